// PNG stills and the writer factory.
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "output/frame_writer.h"
#include "temp_dir.h"

namespace lumar {
namespace {

using test::TempDir;

Image8 pattern(int width, int height, int channels)
{
    Image8 image(width, height, channels);
    for (size_t i = 0; i < image.data.size(); ++i) {
        image.data[i] = uint8_t((i * 37 + i / 7) % 256);
    }
    return image;
}

TEST(Png, WriteThenReadIsExact)
{
    TempDir dir;
    for (int channels : {1, 3, 4}) {
        const Image8 original = pattern(13, 7, channels);
        const auto file = dir / ("image" + std::to_string(channels) + ".png");
        writePng(file, original);
        const Image8 back = readImage(file, channels);
        EXPECT_EQ(back.width, 13);
        EXPECT_EQ(back.height, 7);
        EXPECT_EQ(back.channels, channels);
        EXPECT_EQ(back.data, original.data) << channels << " channels";
    }
}

TEST(Png, ErrorsNameTheFile)
{
    TempDir dir;
    const auto missing = dir / "missing.png";
    try {
        readImage(missing, 3);
        ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
    }
    const auto unwritable = dir / "no" / "such" / "dir" / "out.png";
    try {
        writePng(unwritable, pattern(2, 2, 3));
        ADD_FAILURE() << "no error";
    } catch (const RuntimeError& e) {
        EXPECT_NE(std::string(e.what()).find(unwritable.string()), std::string::npos) << e.what();
    }
}

TEST(FrameWriter, PngKeepsTheLastFrame)
{
    TempDir dir;
    const auto file = dir / "still.png";
    const Image8 first = pattern(8, 6, 3);
    Image8 last = first;
    last.data[0] = uint8_t(last.data[0] + 1);
    {
        const auto writer = openFrameWriter(file, 30.0);
        writer->write(first);
        writer->write(last);
        EXPECT_FALSE(std::filesystem::exists(file)); // written at finish
        writer->finish();
    }
    EXPECT_EQ(readImage(file, 3).data, last.data);
}

TEST(FrameWriter, DestructorFinishes)
{
    TempDir dir;
    {
        const auto png = openFrameWriter(dir / "a.png", 30.0);
        png->write(pattern(4, 4, 3));
        const auto y4m = openFrameWriter(dir / "a.y4m", 30.0);
        y4m->write(pattern(4, 4, 3));
    }
    EXPECT_TRUE(std::filesystem::exists(dir / "a.png"));
    EXPECT_GT(std::filesystem::file_size(dir / "a.y4m"), 0u);
}

TEST(FrameWriter, ChoosesByExtension)
{
    TempDir dir;
    EXPECT_THROW(openFrameWriter(dir / "out.bmp", 30.0), InputError);
    EXPECT_THROW(openFrameWriter(dir / "out", 30.0), InputError);
    EXPECT_NO_THROW(openFrameWriter(dir / "OUT.PNG", 30.0));
    EXPECT_THROW(openFrameWriter(dir / "missing" / "out.y4m", 30.0), RuntimeError);
}

} // namespace
} // namespace lumar
