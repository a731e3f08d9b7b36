// Every shipped scene stands its objects upright on their markers: the built-in default,
// daemon/assets/lumar.toml and every daemon/assets/scenes/*.toml (globbed, so a new scene is
// covered without touching this file). Each object's model is loaded as the renderer loads
// it, every vertex is placed with markerFromModel, and the test asserts
//   (a) the lowest vertex lies on the marker plane (z = offset.z, normally 0) within 1 mm;
//   (b) the model's up axis (glTF +Y) maps to the marker's normal (+Z) within 0.5 degrees,
//       unless the object is listed in kTiltedOnPurpose;
//   (c) the object does not reach into a phantom on its marker (the table top below it).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "config/config.h"
#include "core/error.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/assets/gltf_model.h"
#include "object_placement.h"

namespace lumar {
namespace {

namespace fs = std::filesystem;

constexpr double kPlaneToleranceMetres = 1e-3;
constexpr double kUpToleranceDeg = 0.5;
constexpr double kPhantomToleranceMetres = 1e-4; // the car scene's table top is 0.1 mm under the tag

// "scene file name:object name" of objects a scene tilts on purpose with `rotation`
// (none today: every shipped object stands on its base).
const std::set<std::string> kTiltedOnPurpose = {};

struct Scene {
    std::string name;
    Config config;
};

// The built-in default, the documented example, and every scene in daemon/assets/scenes.
// A .toml there that is not a scene must be a material sidecar some scene names.
std::vector<Scene> shippedScenes()
{
    const fs::path assets = fs::path(LUMAR_SOURCE_DIR) / "daemon/assets";
    std::vector<Scene> scenes{{"<built-in>", defaultConfig()}, {"lumar.toml", loadConfig(assets / "lumar.toml")}};
    std::map<fs::path, std::string> notScenes;
    for (const fs::directory_entry& entry : fs::directory_iterator(assets / "scenes")) {
        if (entry.path().extension() != ".toml")
            continue;
        try {
            scenes.push_back({entry.path().filename().string(), loadConfig(entry.path())});
        } catch (const InputError& e) {
            notScenes[fs::weakly_canonical(entry.path())] = e.what();
        }
    }
    for (const Scene& scene : scenes)
        for (const ObjectConfig& object : scene.config.objects)
            if (!object.materials.empty())
                notScenes.erase(fs::weakly_canonical(object.materials));
    for (const auto& [file, error] : notScenes)
        ADD_FAILURE() << file << " is neither a scene nor a sidecar a scene names: " << error;
    std::sort(scenes.begin(), scenes.end(), [](const Scene& a, const Scene& b) { return a.name < b.name; });
    return scenes;
}

GltfModel loadModel(const ObjectConfig& object)
{
    const std::string model = object.model.string();
    return model.starts_with(kBuiltinModelPrefix)
               ? makeBuiltinShape(std::string_view(model).substr(kBuiltinModelPrefix.size()))
               : loadGltfModel(object.model);
}

struct Box {
    glm::dvec3 lo{std::numeric_limits<double>::infinity()};
    glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
    void add(const glm::dvec3& p)
    {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
};

// The model's vertices in the marker frame, as their bounding box.
Box placedVertexBounds(const GltfModel& model, const glm::dmat4& markerFromModel)
{
    Box box;
    for (const GltfPrimitive& primitive : model.primitives) {
        const glm::dmat4 m = markerFromModel * glm::dmat4(primitive.modelFromMesh);
        for (const glm::vec3& p : primitive.positions)
            box.add(glm::dvec3(m * glm::dvec4(glm::dvec3(p), 1.0)));
    }
    return box;
}

// The 8 corners of the model's bounding box in the marker frame, as their bounding box.
Box placedCornerBounds(const GltfModel& model, const glm::dmat4& markerFromModel)
{
    Box box;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec3 p(corner & 1 ? model.boundsMax.x : model.boundsMin.x,
                           corner & 2 ? model.boundsMax.y : model.boundsMin.y,
                           corner & 4 ? model.boundsMax.z : model.boundsMin.z);
        box.add(glm::dvec3(markerFromModel * glm::dvec4(p, 1.0)));
    }
    return box;
}

bool tilted(const ObjectConfig& object)
{
    return object.rotationDeg.x != 0.0 || object.rotationDeg.y != 0.0;
}

TEST(ShippedScenePlacement, EveryObjectStandsUprightOnItsMarker)
{
    const std::vector<Scene> scenes = shippedScenes();
    ASSERT_GE(scenes.size(), 4u); // built-in, lumar.toml, car.toml, mirror_ball.toml at least
    size_t objectsChecked = 0;
    for (const Scene& scene : scenes) {
        for (const ObjectConfig& object : scene.config.objects) {
            const std::string id = scene.name + ":" + object.name;
            SCOPED_TRACE(id);
            const GltfModel model = loadModel(object);
            ASSERT_FALSE(model.primitives.empty());
            const glm::dmat4 m = markerFromModel(object, model.boundsMin, model.boundsMax);
            const Box placed = placedVertexBounds(model, m);

            // (a) On the plane (or on the height its offset asks for). A tilted model is set
            // down by its bounding box's lowest corner: no vertex below the plane, that corner on it.
            const double plane = object.offset.z;
            EXPECT_GE(placed.lo.z, plane - kPlaneToleranceMetres) << "reaches below the marker plane";
            if (tilted(object))
                EXPECT_NEAR(placedCornerBounds(model, m).lo.z, plane, kPlaneToleranceMetres);
            else
                EXPECT_NEAR(placed.lo.z, plane, kPlaneToleranceMetres) << "floats above the marker plane";

            // (b) glTF +Y up along the marker's normal.
            if (!kTiltedOnPurpose.contains(id)) {
                const glm::dvec3 up = glm::normalize(glm::dmat3(m) * glm::dvec3(0, 1, 0));
                const double angleDeg = glm::degrees(std::acos(std::clamp(up.z, -1.0, 1.0)));
                EXPECT_LT(angleDeg, kUpToleranceDeg)
                    << "model up is " << angleDeg << " degrees off the marker normal (rotation = ["
                    << object.rotationDeg.x << ", " << object.rotationDeg.y << ", " << object.rotationDeg.z
                    << "]; turn it about the normal with `heading`)";
            }

            // (c) Clear of the phantoms on its marker: the bounding boxes may touch, not overlap (mesh
            // phantoms are left out: their bounds need the model).
            if (object.map.empty()) {
                for (const PhantomConfig& phantom : scene.config.phantoms) {
                    if (phantom.marker != object.marker || phantom.shape == "mesh")
                        continue;
                    // A plane has no thickness: it lies at its offset's height.
                    const glm::dvec3 extent =
                        phantom.shape == "plane" ? glm::dvec3(phantom.size.x, phantom.size.y, 0.0) : phantom.size;
                    const glm::dvec3 lo = phantom.offset - 0.5 * extent;
                    const glm::dvec3 hi = phantom.offset + 0.5 * extent;
                    const glm::dvec3 overlap = glm::min(hi, placed.hi) - glm::max(lo, placed.lo);
                    const bool intersects = overlap.x > kPhantomToleranceMetres &&
                                            overlap.y > kPhantomToleranceMetres && overlap.z > kPhantomToleranceMetres;
                    EXPECT_FALSE(intersects) << "reaches " << overlap.z * 1000 << " mm into phantom '" << phantom.name
                                             << "' (its top is at z = " << hi.z << " m)";
                }
            }
            ++objectsChecked;
        }
    }
    EXPECT_GE(objectsChecked, 9u);
}

} // namespace
} // namespace lumar
