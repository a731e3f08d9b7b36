// `[output] overlay` through the whole program (`lumar render`): off, the frames are those of a
// configuration that never mentions it, bit for bit; on, the setup view is drawn over them —
// a status line at the top left and outlines where the fake camera's tags are — and leaves
// the rest of the picture as it was.
#include <gtest/gtest.h>

#include "output/frame_writer.h"
#include "run_lumar.h"

namespace lumar {
namespace {

namespace fs = std::filesystem;

Image8 renderWith(const fs::path& dir, const std::string& name, const std::string& toml)
{
    std::ofstream(dir / (name + ".toml")) << toml;
    const auto r = test::runLumar({"render", "--config", (dir / (name + ".toml")).string(), "--frames", "2", "--out",
                                   (dir / (name + ".png")).string()},
                                  dir);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return readImage(dir / (name + ".png"), 3);
}

TEST(OverlayRender, OffIsBitIdenticalAndOnDrawsTheSetupViewOverTheFrame)
{
    const fs::path dir = test::scratchDirectory("overlay-render");
    const std::string scene = "[camera]\nwidth = 640\nheight = 360\n";
    const Image8 plain = renderWith(dir, "plain", scene);
    const Image8 off = renderWith(dir, "off", scene + "[output]\noverlay = false\n");
    const Image8 on = renderWith(dir, "on", scene + "[output]\noverlay = true\n");
    ASSERT_EQ(plain.data.size(), size_t(640 * 360 * 3));
    ASSERT_EQ(off.data.size(), plain.data.size());
    ASSERT_EQ(on.data.size(), plain.data.size());
    EXPECT_EQ(off.data, plain.data) << "overlay = false must leave the frames untouched";

    size_t changed = 0, changedInStatus = 0;
    for (int y = 0; y < 360; ++y)
        for (int x = 0; x < 640; ++x) {
            const size_t i = (size_t(y) * 640 + size_t(x)) * 3;
            if (on.data[i] != plain.data[i] || on.data[i + 1] != plain.data[i + 1] ||
                on.data[i + 2] != plain.data[i + 2]) {
                ++changed;
                changedInStatus += (y < 30 && x < 400) ? 1 : 0;
            }
        }
    EXPECT_GT(changedInStatus, 1000u) << "the status line";
    EXPECT_GT(changed, changedInStatus + 100) << "tag outlines beyond the status line";
    EXPECT_LT(changed, size_t(640 * 360) / 5) << "the overlay draws lines and text, not over the whole frame";
    fs::remove_all(dir);
}

} // namespace
} // namespace lumar
