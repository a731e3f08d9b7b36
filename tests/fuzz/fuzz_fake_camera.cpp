// The fake camera's scene as a configuration describes it ([camera] fps/noise/exposure/seed,
// [[camera.fake_tags]], [[camera.fake_objects]] with their shapes, sizes, offsets, colours and
// textures, [environment]): parsed and validated as `lumar run` does, then the fake camera's
// own checks and its trajectory over the scene's tags (the camera's pose at a few times).
// The camera itself is not built: it bakes the table's texture, 12 s an input under ASan on a
// loaded machine (libFuzzer's timeout), whatever the input.
#include "capture/fake_camera.h"
#include "capture/fake_trajectory.h"
#include "config/config.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::filesystem::path baseDir = LUMAR_FUZZ_ASSET_DIR;
    (void)lumar::fuzz::scratchDir();
    return lumar::fuzz::expectInputErrorOnly([&] {
        const lumar::Config config =
            lumar::parseConfig(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.toml", baseDir);
        if (config.camera.source != "fake")
            return;
        lumar::FakeCamera::validateScene(config.camera);
        const lumar::FakeTrajectory trajectory(config.camera.fakeTags);
        for (double seconds : {0.0, 1.0 / config.camera.fps, 1e6})
            (void)trajectory.cameraFromWorld(seconds);
    });
}
