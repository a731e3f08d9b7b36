// Image-folder playback and the source factory.
#include <string>

#include <gtest/gtest.h>

#include "capture/factory/capture_factory.h"
#include "capture/image_folder_source.h"
#include "core/error.h"
#include "output/frame_writer.h"
#include "temp_dir.h"

namespace lumar {
namespace {

using test::TempDir;
using test::writeFile;

Image8 solid(int width, int height, uint8_t r, uint8_t g, uint8_t b)
{
    Image8 image(width, height, 3);
    for (int i = 0; i < width * height; ++i) {
        image.data[size_t(3 * i)] = r;
        image.data[size_t(3 * i + 1)] = g;
        image.data[size_t(3 * i + 2)] = b;
    }
    return image;
}

CameraConfig folderConfig(const std::filesystem::path& folder, bool loop)
{
    CameraConfig config;
    config.source = "images";
    config.path = folder;
    config.loop = loop;
    config.fps = 10.0;
    return config;
}

TEST(ImageFolderSource, PlaysImagesInNameOrderAndLoops)
{
    TempDir dir;
    writePng(dir / "b.png", solid(6, 4, 0, 0, 255));
    writePng(dir / "a.PNG", solid(6, 4, 255, 0, 0)); // extensions match in any case
    writeFile(dir / "notes.txt", "not an image");
    ImageFolderSource source(folderConfig(dir.path(), true));
    EXPECT_EQ(source.width(), 6);
    EXPECT_EQ(source.height(), 4);
    EXPECT_DOUBLE_EQ(source.fps(), 10.0);
    ASSERT_EQ(source.files().size(), 2u);

    Frame frame;
    const uint8_t expectedRed[] = {255, 0, 255, 0};
    for (int k = 0; k < 4; ++k) {
        ASSERT_TRUE(source.next(frame));
        EXPECT_EQ(frame.sequence, uint64_t(k));
        EXPECT_EQ(frame.timestampNs, int64_t(k) * 100'000'000);
        EXPECT_EQ(frame.rgb.data[0], expectedRed[k]) << "frame " << k;
        // BT.601 luma of pure red is round(0.299 · 255) = 76, of pure blue round(0.114 · 255) = 29.
        EXPECT_EQ(frame.luma.data[0], expectedRed[k] ? 76 : 29) << "frame " << k;
    }
}

TEST(ImageFolderSource, StopsAtTheEndWithoutLoop)
{
    TempDir dir;
    writePng(dir / "0001.png", solid(2, 2, 1, 2, 3));
    writePng(dir / "0002.png", solid(2, 2, 4, 5, 6));
    ImageFolderSource source(folderConfig(dir.path(), false));
    Frame frame;
    EXPECT_TRUE(source.next(frame));
    EXPECT_TRUE(source.next(frame));
    EXPECT_EQ(frame.rgb.data[0], 4);
    EXPECT_FALSE(source.next(frame));
}

TEST(ImageFolderSource, MixedSizesAreAnInputErrorNamingTheFile)
{
    TempDir dir;
    writePng(dir / "a.png", solid(6, 4, 0, 0, 0));
    writePng(dir / "b.png", solid(8, 4, 0, 0, 0));
    try {
        ImageFolderSource source(folderConfig(dir.path(), true));
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find((dir / "b.png").string()), std::string::npos) << message;
        EXPECT_NE(message.find("8x4"), std::string::npos) << message;
    }
}

TEST(ImageFolderSource, BadFoldersAndFilesAreInputErrors)
{
    TempDir dir;
    EXPECT_THROW(ImageFolderSource(folderConfig(dir / "absent", true)), InputError);
    EXPECT_THROW(ImageFolderSource(folderConfig(dir.path(), true)), InputError); // empty
    writeFile(dir / "broken.png", "this is no PNG");
    try {
        ImageFolderSource source(folderConfig(dir.path(), true));
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find((dir / "broken.png").string()), std::string::npos) << e.what();
    }
}

TEST(OpenCaptureSource, ChoosesTheSourceTheConfigNames)
{
    TempDir dir;
    writePng(dir / "only.png", solid(10, 8, 9, 9, 9));
    const auto images = openCaptureSource(folderConfig(dir.path(), true));
    EXPECT_EQ(images->width(), 10);

    CameraConfig fake;
    fake.width = 64;
    fake.height = 48;
    const auto fakeSource = openCaptureSource(fake);
    EXPECT_EQ(fakeSource->width(), 64);

    CameraConfig y4m;
    y4m.source = "y4m";
    y4m.path = dir / "missing.y4m";
    EXPECT_THROW(openCaptureSource(y4m), InputError);

    CameraConfig unknown;
    unknown.source = "v4l3";
    try {
        openCaptureSource(unknown);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("camera.source: unknown source 'v4l3'"), std::string::npos) << e.what();
    }
}

} // namespace
} // namespace lumar
