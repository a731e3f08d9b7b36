#include "gles_renderer/assets/environment_map.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include <stb_image.h>

#include "core/error.h"
#include "core/file_bytes.h"
#include "gles_renderer/assets/radiance_hdr_check.h"

namespace lumar {
namespace {

// The cap on an environment map, checked from the header before anything is allocated: at
// most 8192 pixels a side and 4096x2048 pixels in all (a 4k equirectangular map; the shipped
// one is 1k). Decoding needs about 24 bytes a pixel at its peak (stb's float RGB and our copy),
// so the cap is about 200 MB. Issue 16: a 16384x8192 header took 5.3 GB and 12 s before the
// first frame, which a 2 GB appliance does not survive.
constexpr int kMaxHdrSide = 8192;
constexpr uint64_t kMaxHdrPixels = uint64_t(4096) * 2048;
constexpr uintmax_t kMaxHdrFileBytes = uintmax_t(1) << 30;

ImageF decodeHdr(const std::vector<uint8_t>& bytes)
{
    if (bytes.empty() || bytes.size() > size_t(std::numeric_limits<int>::max()) ||
        !stbi_is_hdr_from_memory(bytes.data(), int(bytes.size()))) {
        throw InputError("not a Radiance .hdr image");
    }
    const RadianceImageSize size = readRadianceHeader(bytes);
    if (size.width > kMaxHdrSide || size.height > kMaxHdrSide ||
        uint64_t(size.width) * uint64_t(size.height) > kMaxHdrPixels) {
        throw InputError(std::to_string(size.width) + "x" + std::to_string(size.height) +
                         " is larger than the supported " + std::to_string(kMaxHdrSide) +
                         " pixels a side and 4096x2048 pixels in all");
    }
    checkRadianceStream(bytes);
    int width = 0, height = 0, channelsInFile = 0;
    const std::unique_ptr<float, decltype(&stbi_image_free)> pixels(
        stbi_loadf_from_memory(bytes.data(), int(bytes.size()), &width, &height, &channelsInFile, 3), &stbi_image_free);
    if (!pixels) {
        const char* reason = stbi_failure_reason();
        throw InputError(std::string("cannot decode: ") + (reason ? reason : "unknown stb_image error"));
    }
    if (width != size.width || height != size.height) {
        throw InputError("decoded size differs from the header");
    }
    ImageF image(width, height, 3);
    std::copy(pixels.get(), pixels.get() + image.data.size(), image.data.begin());
    for (size_t i = 0; i < image.data.size(); ++i) {
        if (!std::isfinite(image.data[i])) {
            throw InputError("pixel " + std::to_string(i / 3) + " is not finite");
        }
    }
    return image;
}

// The real SH basis of sh9_reference.json / three.js SphericalHarmonics3, evaluated in T.
template <typename T> std::array<T, 9> basis(T x, T y, T z)
{
    return {T(0.282095),
            T(0.488603) * y,
            T(0.488603) * z,
            T(0.488603) * x,
            T(1.092548) * x * y,
            T(1.092548) * y * z,
            T(0.315392) * (T(3) * z * z - T(1)),
            T(1.092548) * x * z,
            T(0.546274) * (x * x - y * y)};
}

} // namespace

ImageF loadHdrImage(const std::filesystem::path& file)
{
    try {
        return decodeHdr(readFileBytes(file, kMaxHdrFileBytes));
    } catch (const InputError& e) {
        throw InputError(file.string() + ": " + e.what());
    }
}

std::array<float, 9> shBasis(const glm::vec3& unitDirection)
{
    return basis<float>(unitDirection.x, unitDirection.y, unitDirection.z);
}

SH9 projectEquirectSH9(const ImageF& equirect)
{
    if (equirect.channels != 3 || equirect.width < 1 || equirect.height < 1 ||
        equirect.data.size() != size_t(equirect.width) * size_t(equirect.height) * 3) {
        throw InputError("SH projection needs a non-empty 3-channel equirectangular image, got " +
                         std::to_string(equirect.width) + "x" + std::to_string(equirect.height) + "x" +
                         std::to_string(equirect.channels));
    }
    constexpr double pi = std::numbers::pi;
    const int w = equirect.width;
    const int h = equirect.height;

    std::vector<double> cosPhi(static_cast<size_t>(w)), sinPhi(static_cast<size_t>(w));
    for (int c = 0; c < w; ++c) {
        const double phi = ((c + 0.5) / w - 0.5) * 2.0 * pi;
        cosPhi[size_t(c)] = std::cos(phi);
        sinPhi[size_t(c)] = std::sin(phi);
    }

    std::array<glm::dvec3, 9> sum{};
    for (int r = 0; r < h; ++r) {
        const double theta = (r + 0.5) / h * pi;
        const double sinTheta = std::sin(theta);
        const double y = std::cos(theta);
        // The exact solid angle of every pixel of this row: a band of the sphere between
        // two latitudes, split into w equal sectors.
        const double solidAngle = 2.0 * pi / w * (std::cos(r * pi / h) - std::cos((r + 1) * pi / h));
        std::array<glm::dvec3, 9> rowSum{};
        const float* pixel = equirect.row(r);
        for (int c = 0; c < w; ++c, pixel += 3) {
            const glm::dvec3 radiance(pixel[0], pixel[1], pixel[2]);
            const std::array<double, 9> y9 =
                basis<double>(sinTheta * cosPhi[size_t(c)], y, sinTheta * sinPhi[size_t(c)]);
            for (size_t k = 0; k < 9; ++k) {
                rowSum[k] += radiance * y9[k];
            }
        }
        for (size_t k = 0; k < 9; ++k) {
            sum[k] += rowSum[k] * solidAngle;
        }
    }
    SH9 sh;
    for (size_t k = 0; k < 9; ++k) {
        sh[k] = glm::vec3(sum[k]);
    }
    return sh;
}

glm::vec3 irradianceSH9(const SH9& sh, const glm::vec3& unitNormal)
{
    // Ramamoorthi & Hanrahan 2001: the clamped-cosine kernel's SH coefficients per band.
    constexpr float pi = std::numbers::pi_v<float>;
    constexpr std::array<float, 9> bandFactor = {pi,     2 * pi / 3, 2 * pi / 3, 2 * pi / 3, pi / 4,
                                                 pi / 4, pi / 4,     pi / 4,     pi / 4};
    const std::array<float, 9> y = shBasis(unitNormal);
    glm::vec3 irradiance(0.0f);
    for (size_t k = 0; k < 9; ++k) {
        irradiance += bandFactor[k] * y[k] * sh[k];
    }
    return irradiance;
}

} // namespace lumar
