// The KMS display options a configuration asks for: the board profile's [display] under the
// [output] overrides, and the fallback when this machine has no DRM device.
#include <gtest/gtest.h>

#include "config/board_profile.h"
#include "config/config.h"
#include "gles_renderer/display/drm_device.h"
#include "kms_sink.h"

namespace lumar {
namespace {

TEST(KmsSink, BoardPreferencesUnderOutputOverrides)
{
    Config config = parseConfig("board = \"qemu-virtual-board\"\n[output]\nsink = \"kms\"\n", "test.toml", ".");
    KmsDisplayOptions options = kmsDisplayOptions(config);
    EXPECT_EQ(options.device, "auto");
    EXPECT_EQ(options.drivers, (std::vector<std::string>{"bochs-drm", "virtio_gpu"}));
    EXPECT_EQ(options.output.connector, "auto");
    EXPECT_EQ(options.output.plane, "primary");
    EXPECT_EQ(options.output.mode, "auto");
    EXPECT_FALSE(options.modifiers);
    EXPECT_TRUE(options.finishBeforeFlip); // the board's no-native-fence quirk

    config = parseConfig("board = \"qemu-virtual-board\"\n[output]\nsink = \"kms\"\ndrm_device = \"/dev/dri/card1\"\n"
                         "connector = \"Virtual-2\"\nplane = \"overlay\"\nmode = \"800x600\"\n",
                         "test.toml", ".");
    options = kmsDisplayOptions(config);
    EXPECT_EQ(options.device, "/dev/dri/card1");
    EXPECT_EQ(options.output.connector, "Virtual-2");
    EXPECT_EQ(options.output.plane, "overlay");
    EXPECT_EQ(options.output.mode, "800x600");
    EXPECT_FALSE(options.legacyApi);
    EXPECT_TRUE(kmsDisplayOptions(parseConfig("[output]\nkms_api = \"legacy\"\n", "test.toml", ".")).legacyApi);
    EXPECT_FALSE(options.modifiers); // the board's, no [output] key for it
}

TEST(KmsSink, WithoutABoardAnyDriverAndModifiers)
{
    const KmsDisplayOptions options = kmsDisplayOptions(parseConfig("[output]\nsink = \"kms\"\n", "test.toml", "."));
    EXPECT_TRUE(options.drivers.empty());
    EXPECT_EQ(options.output.connector, "auto");
    EXPECT_EQ(options.output.plane, "primary");
    EXPECT_TRUE(options.modifiers);
    EXPECT_FALSE(options.finishBeforeFlip);
}

TEST(KmsSink, NoDrmDeviceFallsBack)
{
    if (!drmCardNodes().empty())
        GTEST_SKIP() << "this machine has DRM devices; the fallback is tested where there are none";
    EXPECT_EQ(openKmsDisplay(parseConfig("[output]\nsink = \"kms\"\n", "test.toml", ".")), nullptr);
    // A named device that does not exist falls back the same way.
    EXPECT_EQ(
        openKmsDisplay(parseConfig("[output]\nsink = \"kms\"\ndrm_device = \"/dev/dri/card9\"\n", "test.toml", ".")),
        nullptr);
}

} // namespace
} // namespace lumar
