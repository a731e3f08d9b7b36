// [[maps]] and objects placed on maps: parsing, and one check per class of error with the
// exact "FILE:LINE: key:" prefix of the one-line message.
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "config/config.h"
#include "config_fixture.h"
#include "core/error.h"

namespace lumar {
namespace {

namespace fs = std::filesystem;

class MapConfigTest : public test::ConfigFixture {
protected:
    MapConfigTest() : test::ConfigFixture("maps.toml") {}
};

// Lines 1-12.
const std::string kBoard = "[[maps]]\n"
                           "name = \"board\"\n"
                           "[[maps.tags]]\n"
                           "id = 0\n"
                           "size = 0.1\n"
                           "position = [-0.12, 0.12, 0.0]\n"
                           "[[maps.tags]]\n"
                           "id = 1\n"
                           "size = 0.1\n"
                           "position = [0.12, 0.12, 0.0]\n"
                           "rotation = [0.0, 0.0, 90.0]\n"
                           "\n";

TEST_F(MapConfigTest, ReadsMapsAndObjectsOnThem)
{
    const Config c = parse(kBoard + "[[objects]]\nmodel = \"box.glb\"\nmap = \"board\"\n");
    ASSERT_EQ(c.maps.size(), 1u);
    EXPECT_EQ(c.maps[0].name, "board");
    ASSERT_EQ(c.maps[0].tags.size(), 2u);
    EXPECT_EQ(c.maps[0].tags[1].id, 1);
    EXPECT_EQ(c.maps[0].tags[1].size, 0.1);
    EXPECT_EQ(c.maps[0].tags[1].position, glm::dvec3(0.12, 0.12, 0.0));
    EXPECT_EQ(c.maps[0].tags[1].rotationDeg, glm::dvec3(0.0, 0.0, 90.0));
    EXPECT_EQ(c.maps[0].tags[0].rotationDeg, glm::dvec3(0.0));
    ASSERT_EQ(c.objects.size(), 1u);
    EXPECT_EQ(c.objects[0].map, "board");
    // A map tag may also be a marker of the same size.
    EXPECT_NO_THROW(parse("[[markers]]\nid = 1\nsize = 0.1\n" + kBoard));
}

TEST_F(MapConfigTest, DuplicateIdsWithinAndAcrossMaps)
{
    expectError(kBoard + "[[maps.tags]]\nid = 1\nsize = 0.1\n",
                "maps.toml:14: maps[0].tags[2].id: tag 1 is already in a map");
    expectError(kBoard + "[[maps]]\nname = \"other\"\n[[maps.tags]]\nid = 0\nsize = 0.1\n",
                "maps.toml:16: maps[1].tags[0].id: tag 0 is already in a map");
    expectError(kBoard + "[[maps]]\nname = \"board\"\n[[maps.tags]]\nid = 5\nsize = 0.1\n",
                "maps.toml:14: maps[1].name: duplicate map name 'board'");
}

TEST_F(MapConfigTest, MarkerWithAnotherSize)
{
    expectError("[[markers]]\nid = 1\nsize = 0.16\n" + kBoard,
                "maps.toml:12: maps[0].tags[1].size: tag 1 is listed in [[markers]] with size");
}

TEST_F(MapConfigTest, IdsWithinTheFamily)
{
    expectError("[[maps]]\nname = \"b\"\n[[maps.tags]]\nid = 587\nsize = 0.1\n",
                "maps.toml:4: maps[0].tags[0].id: 587 is outside [0, 586]");
    expectError("[tracking]\nfamily = \"tag16h5\"\n[[maps]]\nname = \"b\"\n[[maps.tags]]\nid = 30\nsize = 0.1\n",
                "maps.toml:6: maps[0].tags[0].id: 30 is outside [0, 29]");
    EXPECT_NO_THROW(parse("[tracking]\nfamily = \"tag16h5\"\n[[maps]]\nname = \"b\"\n[[maps.tags]]\nid = 29\n"
                          "size = 0.1\n"));
}

TEST_F(MapConfigTest, RequiredAndBadKeys)
{
    expectError("[[maps]]\n[[maps.tags]]\nid = 0\nsize = 0.1\n", "maps.toml:1: maps[0].name: required key is missing");
    expectError("[[maps]]\nname = \"b\"\n", "maps.toml:1: maps[0].tags: required key is missing");
    expectError("[[maps]]\nname = \"b\"\n[[maps.tags]]\nsize = 0.1\n",
                "maps.toml:3: maps[0].tags[0].id: required key is missing");
    expectError("[[maps]]\nname = \"b\"\n[[maps.tags]]\nid = 0\n",
                "maps.toml:3: maps[0].tags[0].size: required key is missing");
    expectError("[[maps]]\nname = \"b\"\n[[maps.tags]]\nid = 0\nsize = 0.1\nrotation = [1, 2]\n",
                "maps.toml:6: maps[0].tags[0].rotation: expected an array of 3 numbers");
    expectError("[[maps]]\nname = \"b\"\n[[maps.tags]]\nid = 0\nsize = 0.1\nangle = 3\n",
                "maps.toml:6: maps[0].tags[0].angle: unknown key");
}

TEST_F(MapConfigTest, ObjectNamesExactlyOneOfMarkerAndMap)
{
    expectError(kBoard + "[[markers]]\nid = 4\nsize = 0.1\n[[objects]]\nmodel = \"box.glb\"\nmap = \"board\"\n"
                         "marker = 4\n",
                "maps.toml:18: objects[0].map: give either marker or map, not both");
    expectError(kBoard + "[[objects]]\nmodel = \"box.glb\"\nmap = \"table\"\n",
                "maps.toml:15: objects[0].map: map 'table' is not listed in [[maps]]");
    expectError(kBoard + "[[objects]]\nmodel = \"box.glb\"\n", "maps.toml:13: objects[0].marker: required key");
}

// The shipped example's commented [[maps]] block, uncommented, is a valid board of four tags.
TEST_F(MapConfigTest, ShippedExampleMapBlockParses)
{
    const fs::path example = fs::path(LUMAR_SOURCE_DIR) / "daemon/assets/lumar.toml";
    std::ifstream in(example);
    std::string text, line;
    bool inBlock = false;
    while (std::getline(in, line)) {
        if (line == "# [[maps]]")
            inBlock = true;
        else if (line.empty())
            inBlock = false;
        text += (inBlock ? line.substr(2) : line) + "\n";
    }
    const Config c = parseConfig(text, example, example.parent_path());
    ASSERT_EQ(c.maps.size(), 1u);
    EXPECT_EQ(c.maps[0].name, "board");
    EXPECT_EQ(c.maps[0].tags.size(), 4u);
}

} // namespace
} // namespace lumar
