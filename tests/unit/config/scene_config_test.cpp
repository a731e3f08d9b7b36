// Configuration of the paper's rendering: [rendering] (environment-map policy and size),
// objects' Lafortune materials (preset, sidecar) and built-in shapes, and [[phantoms]];
// each error with its exact "FILE:LINE: key:" prefix. The shipped demo scenes parse.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "config/config.h"
#include "config_fixture.h"
#include "core/error.h"

namespace lumar {
namespace {

namespace fs = std::filesystem;

class SceneConfigTest : public test::ConfigFixture {};

const std::string kMarker = "[[markers]]\nid = 0\nsize = 0.16\n";

TEST_F(SceneConfigTest, RenderingDefaultsAndValues)
{
    const Config defaults = parse("");
    EXPECT_EQ(defaults.rendering.environmentMaps, "auto");
    EXPECT_EQ(defaults.rendering.environmentMapSize, 64);
    EXPECT_TRUE(defaults.rendering.phantomsShowCamera);
    EXPECT_FALSE(parse("[rendering]\nphantoms_show_camera = false\n").rendering.phantomsShowCamera);
    const Config c = parse("[rendering]\nenvironment_maps = \"budget\"\nenvironment_map_every = 3\n"
                           "environment_map_budget_ms = 5.5\nenvironment_map_size = 128\n");
    EXPECT_EQ(c.rendering.environmentMaps, "budget");
    EXPECT_EQ(c.rendering.environmentMapEvery, 3);
    EXPECT_DOUBLE_EQ(c.rendering.environmentMapBudgetMs, 5.5);
    EXPECT_EQ(c.rendering.environmentMapSize, 128);
}

TEST_F(SceneConfigTest, RenderingErrorsNameTheLine)
{
    expectError("[rendering]\nenvironment_maps = \"sometimes\"\n", "test.toml:2: rendering.environment_maps:");
    expectError("[rendering]\n\nenvironment_map_size = 100\n", "test.toml:3: rendering.environment_map_size:");
    expectError("[rendering]\nenvironment_map_size = 512\n", "test.toml:2: rendering.environment_map_size:");
    expectError("[rendering]\nenvironment_map_budget_ms = 0\n", "test.toml:2: rendering.environment_map_budget_ms:");
    expectError("[rendering]\nenvironment_map_every = 0\n", "test.toml:2: rendering.environment_map_every:");
    expectError("[rendering]\nshadows = true\n", "test.toml:2: rendering.shadows: unknown key");
}

TEST_F(SceneConfigTest, ObjectsTakeBuiltInShapesPresetsAndSidecars)
{
    std::ofstream(dir_ / "box.materials.toml") << "[material.\"*\"]\npreset = \"chrome\"\n";
    const Config c = parse(kMarker + "[[objects]]\nmodel = \"builtin:sphere\"\nmarker = 0\nmaterial = \"chrome\"\n" +
                           "[[objects]]\nmodel = \"box.glb\"\nmarker = 0\nmaterials = \"box.materials.toml\"\n");
    ASSERT_EQ(c.objects.size(), 2u);
    EXPECT_EQ(c.objects[0].model, fs::path("builtin:sphere"));
    EXPECT_EQ(c.objects[0].material, "chrome");
    EXPECT_EQ(c.objects[1].materials, dir_ / "box.materials.toml");
}

TEST_F(SceneConfigTest, ObjectMaterialErrorsNameTheLine)
{
    expectError(kMarker + "[[objects]]\nmodel = \"builtin:teapot\"\nmarker = 0\n", "test.toml:4: objects[0].model:");
    expectError(kMarker + "[[objects]]\nmodel = \"box.glb\"\nmarker = 0\nmaterial = \"velvet\"\n",
                "test.toml:4: objects[0].material:");
    expectError(kMarker + "[[objects]]\nmodel = \"box.glb\"\nmarker = 0\nmaterials = \"none.toml\"\n",
                "test.toml:7: objects[0].materials:");
    // A broken sidecar reports its own file and line.
    std::ofstream(dir_ / "bad.toml") << "[material.\"*\"]\n\npreset = \"unobtainium\"\n";
    expectError(kMarker + "[[objects]]\nmodel = \"box.glb\"\nmarker = 0\nmaterials = \"bad.toml\"\n",
                (dir_ / "bad.toml").string() + ":3:");
}

TEST_F(SceneConfigTest, PhantomsAndTheirErrors)
{
    const Config c = parse(kMarker + "[[phantoms]]\nname = \"table\"\nmarker = 0\nsize = [1.2, 0.8, 0.02]\n"
                                     "offset = [0.0, 0.0, -0.01]\ncolor = [0.4, 0.3, 0.2]\n");
    ASSERT_EQ(c.phantoms.size(), 1u);
    EXPECT_EQ(c.phantoms[0].name, "table");
    EXPECT_DOUBLE_EQ(c.phantoms[0].size.x, 1.2);
    EXPECT_DOUBLE_EQ(c.phantoms[0].offset.z, -0.01);
    EXPECT_DOUBLE_EQ(c.phantoms[0].color.g, 0.3);

    expectError(kMarker + "[[phantoms]]\nmarker = 0\n", "test.toml:4: phantoms[0].size:");
    expectError(kMarker + "[[phantoms]]\nmarker = 7\nsize = [1, 1, 1]\n", "test.toml:4: phantoms[0].marker:");
    expectError(kMarker + "[[phantoms]]\nmarker = 0\nsize = [1, 0, 1]\n", "test.toml:4: phantoms[0].size:");
    expectError(kMarker + "[[phantoms]]\nmarker = 0\nsize = [1, 1, 1]\ncolor = [2, 0, 0]\n",
                "test.toml:4: phantoms[0].color:");
}

TEST_F(SceneConfigTest, PhantomShapes)
{
    const std::string head = kMarker + "[[phantoms]]\nmarker = 0\n";
    const Config box = parse(head + "size = [0.2, 0.3, 0.4]\n");
    EXPECT_EQ(box.phantoms[0].shape, "box");
    EXPECT_EQ(box.phantoms[0].mesh, nullptr);

    const Config plane = parse(head + "shape = \"plane\"\nsize = [1.2, 0.8]\nheading = 30\n");
    EXPECT_EQ(plane.phantoms[0].shape, "plane");
    EXPECT_DOUBLE_EQ(plane.phantoms[0].size.x, 1.2);
    EXPECT_DOUBLE_EQ(plane.phantoms[0].size.y, 0.8);
    EXPECT_DOUBLE_EQ(plane.phantoms[0].headingDeg, 30.0);
    // A third side is accepted and unused, even zero.
    EXPECT_EQ(parse(head + "shape = \"plane\"\nsize = [1.2, 0.8, 0]\n").phantoms[0].shape, "plane");

    const Config cylinder = parse(head + "shape = \"cylinder\"\nsize = [0.08, 0.08, 0.1]\n");
    EXPECT_EQ(cylinder.phantoms[0].shape, "cylinder");
    EXPECT_DOUBLE_EQ(cylinder.phantoms[0].size.z, 0.1);

    const Config mesh = parse(head + "shape = \"mesh\"\nmodel = \"box.glb\"\nsize = 0.3\noffset = [0.1, 0, 0]\n");
    ASSERT_EQ(mesh.phantoms.size(), 1u);
    EXPECT_EQ(mesh.phantoms[0].model, dir_ / "box.glb");
    ASSERT_NE(mesh.phantoms[0].mesh, nullptr);
    EXPECT_FALSE(mesh.phantoms[0].mesh->primitives.empty());
    EXPECT_DOUBLE_EQ(mesh.phantoms[0].size.x, 0.3);
    const Config builtin = parse(head + "shape = \"mesh\"\nmodel = \"builtin:sphere\"\n");
    ASSERT_NE(builtin.phantoms[0].mesh, nullptr);
    EXPECT_EQ(builtin.phantoms[0].size.x, 0.0); // as authored
}

TEST_F(SceneConfigTest, PhantomShapeErrorsNameFileLineAndKey)
{
    const std::string head = kMarker + "[[phantoms]]\nmarker = 0\n";
    expectError(head + "shape = \"cone\"\nsize = [1, 1, 1]\n",
                "test.toml:6: phantoms[0].shape: 'cone' is not one of box, plane, cylinder, mesh");
    expectError(head + "shape = \"mesh\"\nsize = 0.3\n", "test.toml:4: phantoms[0].model: required key is missing");
    expectError(head + "shape = \"mesh\"\nmodel = \"missing.glb\"\n", "test.toml:7: phantoms[0].model:");
    expectError(head + "shape = \"mesh\"\nmodel = \"builtin:teapot\"\n", "test.toml:7: phantoms[0].model:");
    expectError(head + "shape = \"mesh\"\nmodel = \"box.glb\"\nsize = [1, 1, 1]\n",
                "test.toml:8: phantoms[0].size: expected a number");
    expectError(head + "size = [1, 1, 1]\nmodel = \"box.glb\"\n", "test.toml:7: phantoms[0].model: only a phantom");
    expectError(head + "size = [1, 1]\n", "test.toml:6: phantoms[0].size: expected an array of 3 numbers");
    expectError(head + "shape = \"cylinder\"\nsize = [0.1, 0.1, 0]\n", "test.toml:4: phantoms[0].size:");
    expectError(kMarker + "[[phantoms]]\nmarker = 3\nshape = \"plane\"\nsize = [1, 1]\n",
                "test.toml:4: phantoms[0].marker:");
    // A broken glTF file: the config's line and key, then the loader's "FILE: what".
    {
        std::ofstream broken(dir_ / "broken.glb", std::ios::binary);
        broken << "glTF this is not";
    }
    const std::string message =
        expectError(head + "shape = \"mesh\"\nmodel = \"broken.glb\"\n", "test.toml:7: phantoms[0].model: ");
    EXPECT_NE(message.find("broken.glb"), std::string::npos) << message;
}

TEST_F(SceneConfigTest, ShippedDemoScenesParse)
{
    for (const char* scene : {"car.toml", "mirror_ball.toml"}) {
        SCOPED_TRACE(scene);
        const Config c = loadConfig(fs::path(LUMAR_SOURCE_DIR) / "daemon/assets/scenes" / scene);
        EXPECT_GE(c.objects.size(), 3u);
        EXPECT_EQ(c.phantoms.size(), 1u);
    }
}

} // namespace
} // namespace lumar
