// The built-in configuration (what `lumar render` and `lumar run` use without --config) and
// the directory the shipped assets it names are found in.
#include <cstdlib>

#include <unistd.h>

#include "config/config.h"

namespace lumar {
namespace {

// Kept equal to daemon/assets/lumar.toml (a test compares the two).
constexpr std::string_view kDefaultConfig = R"toml(
log_level = "info"

[camera]
source = "fake"
width = 1280
height = 720
fps = 30.0
loop = true
calibration = "calibration/fake_camera_1280x720.yaml"
seed = 1
noise = 2.0
exposure = 1.0

[[camera.fake_tags]]
id = 0
size = 0.16
position = [0.0, 0.0]

[[camera.fake_objects]]
shape = "box"
tag = 0
size = [0.08, 0.08, 0.1]
offset = [0.0, 0.2]
heading = 20.0
color = [0.6, 0.12, 0.06]

[tracking]
family = "tag36h11"
quad_decimate = 2.0
quad_sigma = 0.0
refine_edges = true
decode_sharpening = 0.25
threads = 2
roi = true
full_frame_every = 10
coarse_every = 3
coarse_decimate = 4.0
max_bit_errors = 2
filter = true
filter_min_cutoff = 0.3
filter_beta = 40.0
filter_rotation_min_cutoff = 0.3
filter_rotation_beta = 8.0

[[markers]]
id = 0
size = 0.16

[[objects]]
name = "truck"
model = "models/CesiumMilkTruck.glb"
marker = 0
offset = [0.0, 0.0, 0.0]
heading = 0.0
rotation = [0.0, 0.0, 0.0]
size = 0.2

[environment]
hdr = "env/venice_sunset_1k.hdr"
intensity = 1.0
source = "hdr"
match_exposure = true

[rendering]
environment_maps = "auto"
environment_map_every = 2
environment_map_budget_ms = 8.0
environment_map_size = 64
phantoms_show_camera = true

[rendering.lens]
enabled = false
threshold = 1.0
bloom = true
bloom_intensity = 0.5
bloom_radius = 32.0
glare = false
glare_streaks = 4
glare_length = 96.0
glare_intensity = 0.3
glare_angle = 0.0

[output]
sink = "headless"
)toml";

bool isDirectory(const std::filesystem::path& p)
{
    std::error_code ec;
    return std::filesystem::is_directory(p, ec);
}

} // namespace

std::string_view defaultConfigText()
{
    return kDefaultConfig;
}

Config defaultConfig()
{
    return parseConfig(kDefaultConfig, "<built-in>", assetDirectory());
}

std::filesystem::path assetDirectory()
{
    if (const char* env = std::getenv("LUMAR_ASSET_DIR"); env && isDirectory(env))
        return env;
    std::error_code ec;
    const auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        auto installed = exe.parent_path().parent_path() / "share" / "lumar";
        if (isDirectory(installed))
            return installed;
    }
    if (isDirectory(LUMAR_INSTALL_ASSET_DIR))
        return LUMAR_INSTALL_ASSET_DIR;
    return std::filesystem::path(LUMAR_SOURCE_ASSET_DIR).lexically_normal();
}

} // namespace lumar
