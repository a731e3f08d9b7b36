// sh_error_table: prints a markdown table of the SH9 projection error (sh9RelativeError:
// max |c − c_ref| / max |c_ref| over the 27 numbers) against the sample count for the
// paper's uniform sets (stratified, seed 1; spherical Fibonacci) and for King's per-texel
// walk on cubes made from the environment, for the four test environments.
//
//   sh_error_table [path/to/venice_sunset_1k.hdr]
//
// References: the closed forms of sh_test_environments.h; for the .hdr (bilinear lookup of
// the equirect), a brute-force Gauss–Legendre quadrature with 2048×4096 nodes.
#include <array>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gles_renderer/assets/environment_map.h"
#include "gles_renderer/ibl/cube_map.h"
#include "gles_renderer/ibl/sh_projection.h"
#include "gles_renderer/ibl/sphere_samples.h"
#include "unit/render/sh_test_environments.h"

namespace {

using namespace lumar;

struct Column {
    std::string name;
    RadianceFunction radiance;
    SH9 reference;
    std::shared_ptr<const ImageF> equirect; // the .hdr only: its cubes come from cubeFromEquirect
};

std::vector<Column> columns(const std::filesystem::path& hdr)
{
    std::vector<Column> result;
    for (const test::ShEnvironment& e :
         {test::constantEnvironment(), test::peakedLobeEnvironment(), test::cosineLobeEnvironment()}) {
        result.push_back({e.name, e.radiance, e.closedForm, nullptr});
        std::printf("<!-- %s: brute force (512 nodes) vs closed form: %.2e -->\n", e.name.c_str(),
                    sh9RelativeError(projectSH9BruteForce(e.radiance, 512), e.closedForm));
    }
    std::error_code ec;
    if (std::filesystem::exists(hdr, ec)) {
        const auto image = std::make_shared<const ImageF>(loadHdrImage(hdr));
        const RadianceFunction radiance = [image](glm::vec3 d) { return sampleEquirectBilinear(*image, d); };
        const SH9 reference = projectSH9BruteForce(radiance, 2048);
        std::printf("<!-- venice: brute force 1024 vs 2048 nodes: %.2e; vs per-pixel projectEquirectSH9: %.2e -->\n",
                    sh9RelativeError(projectSH9BruteForce(radiance, 1024), reference),
                    sh9RelativeError(projectEquirectSH9(*image), reference));
        result.push_back({"venice_sunset_1k.hdr", radiance, reference, image});
    } else {
        std::printf("<!-- %s is absent: no .hdr column -->\n", hdr.string().c_str());
    }
    return result;
}

// N = 64 … 65536 as asked, then larger sets that show what the .hdr's sun needs.
constexpr std::array<int, 9> kGridSides = {8, 16, 32, 64, 128, 256, 512, 1024, 2048};
constexpr std::array<int, 7> kCubeSizes = {8, 16, 32, 64, 128, 256, 512};

void printRow(const std::string& label, const std::vector<Column>& cols,
              const std::function<SH9(const Column&)>& project)
{
    std::printf("| %s |", label.c_str());
    for (const Column& c : cols) {
        std::printf(" %.2e |", sh9RelativeError(project(c), c.reference));
    }
    std::printf("\n");
}

void printTable(const std::vector<Column>& cols)
{
    std::printf("\n| method | N |");
    for (const Column& c : cols) {
        std::printf(" %s |", c.name.c_str());
    }
    std::printf("\n|---|---|");
    for (size_t i = 0; i < cols.size(); ++i) {
        std::printf("---|");
    }
    std::printf("\n");
    for (const int side : kGridSides) {
        const std::vector<glm::vec3> samples = stratifiedSphereSamples(side, 1);
        printRow("stratified | " + std::to_string(side * side), cols,
                 [&](const Column& c) { return projectSH9Uniform(samples, c.radiance); });
    }
    for (const int side : kGridSides) {
        const std::vector<glm::vec3> samples = fibonacciSphereSamples(side * side);
        printRow("Fibonacci | " + std::to_string(side * side), cols,
                 [&](const Column& c) { return projectSH9Uniform(samples, c.radiance); });
    }
    for (const int size : kCubeSizes) {
        printRow("King cube " + std::to_string(size) + "² | " + std::to_string(6 * size * size), cols,
                 [&](const Column& c) {
                     return projectCubeSH9King(c.equirect ? cubeFromEquirect(*c.equirect, size)
                                                          : cubeFromFunction(size, c.radiance));
                 });
    }
}

} // namespace

int main(int argc, char** argv)
{
    try {
        const std::filesystem::path hdr =
            argc > 1 ? std::filesystem::path(argv[1])
                     : std::filesystem::path(LUMAR_SHARED_DATA_DIR) / "env/venice_sunset_1k.hdr";
        printTable(columns(hdr));
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sh_error_table: %s\n", e.what());
        return 2;
    }
}
