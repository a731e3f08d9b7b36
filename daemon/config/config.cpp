// Parsing and validation of lumar's TOML configuration (config.h): one function per section,
// each reading its keys through a TableReader that rejects unknown keys and bad values.
#include "config/config.h"

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <set>

#include <stb_image.h>

#include "config/material_sidecar.h"
#include "config/toml_parse.h"
#include "config/toml_reader.h"
#include "core/error.h"
#include "core/log.h"
#include "gles_renderer/assets/builtin_shapes.h"
#include "gles_renderer/assets/gltf_model.h"
#include "gles_renderer/assets/lafortune_material.h"

namespace lumar {
namespace {

using config_detail::TableReader;
using Expect = TableReader::Expect;

constexpr int kTag36h11Codes = 587;
// Bounds on placement numbers (issue 16: offsets of 1e308 and rotations of 1e300 were
// accepted and became infinities and meaningless angles in the pose maths). An object or
// phantom sits within 100 m of its marker (the map's own bound); angles are degrees, one turn
// either way.
constexpr double kMaxOffsetMetres = 100.0;
constexpr double kMaxDegrees = 360.0;

struct Context {
    std::string fileName;
    std::filesystem::path baseDir;
};

// Reads the elements of an array of tables, one TableReader each ("objects[2]").
template <typename Fn> void forEachTable(TableReader& parent, std::string_view key, Fn&& fn)
{
    const toml::array* array = parent.arrayOfTables(key);
    if (!array)
        return;
    for (size_t i = 0; i < array->size(); ++i) {
        TableReader r(*array->get(i)->as_table(), parent.keyName(key) + "[" + std::to_string(i) + "]",
                      parent.fileName());
        fn(r, array->get(i));
        r.finish();
    }
}

// A key that holds either the string "auto" (stored as CameraControlsConfig::kAuto) or an
// integer within [min, max].
void autoOrInteger(TableReader& r, std::string_view key, std::optional<int>& out, long long min, long long max)
{
    const toml::node* node = r.node(key);
    if (node == nullptr)
        return;
    if (node->is_string()) {
        std::string text;
        r.oneOf(key, text, {"auto"});
        out = CameraControlsConfig::kAuto;
        return;
    }
    int value = 0;
    if (!node->is_integer())
        r.fail(node, key, "expected \"auto\" or an integer");
    r.integer(key, value, min, max);
    out = value;
}

void readCameraControls(TableReader& camera, CameraControlsConfig& controls)
{
    const toml::table* table = camera.table("controls");
    if (!table)
        return;
    TableReader r(*table, camera.keyName("controls"), camera.fileName());
    autoOrInteger(r, "exposure_us", controls.exposureUs, 1, 10'000'000);
    if (r.has("gain")) {
        int gain = 0;
        r.integer("gain", gain, 0, 1'000'000);
        controls.gain = gain;
    }
    autoOrInteger(r, "white_balance_k", controls.whiteBalanceK, 1000, 20000);
    if (r.has("power_line_hz")) {
        int hz = 0;
        r.integer("power_line_hz", hz, 0, 60);
        if (hz != 0 && hz != 50 && hz != 60)
            r.fail(r.node("power_line_hz"), "power_line_hz", std::to_string(hz) + " must be 0 (off), 50 or 60");
        controls.powerLineHz = hz;
    }
    r.finish();
}

// A texture must be an image stb can read (its header is checked here, the pixels when the
// fake camera starts).
void checkTextureFile(TableReader& r, const std::filesystem::path& file)
{
    constexpr int kMaxTextureSide = 16384;
    int width = 0, height = 0, components = 0;
    if (!stbi_info(file.c_str(), &width, &height, &components)) {
        const char* reason = stbi_failure_reason();
        r.fail(r.node("texture"), "texture",
               file.string() + ": cannot read: " + (reason ? reason : "not a PNG or JPEG image"));
    }
    if (width > kMaxTextureSide || height > kMaxTextureSide)
        r.fail(r.node("texture"), "texture",
               file.string() + ": " + std::to_string(width) + "x" + std::to_string(height) +
                   " is larger than 16384 pixels a side");
}

// [[camera.fake_objects]], after the fake tags they stand on.
void readFakeObjects(TableReader& camera, CameraConfig& config, const Context& ctx)
{
    forEachTable(camera, "fake_objects", [&](TableReader& t, const toml::node* node) {
        FakeObjectConfig object;
        t.oneOf("shape", object.shape, {"box", "cylinder"});
        if (!t.has("tag"))
            t.failMissing("tag");
        t.integer("tag", object.tag, 0, kTag36h11Codes - 1);
        bool known = false;
        for (const FakeTagConfig& tag : config.fakeTags)
            known = known || tag.id == object.tag;
        if (!known)
            t.fail(t.node("tag"), "tag", "tag " + std::to_string(object.tag) + " is not in camera.fake_tags");
        if (!t.has("size"))
            t.failMissing("size");
        t.vec3("size", object.size);
        for (int i = 0; i < 3; ++i)
            if (!(object.size[i] > 0.0 && object.size[i] <= 2.0))
                t.fail(t.node("size"), "size", "each side must be in (0, 2] metres");
        if (object.shape == "cylinder" && object.size.x != object.size.y)
            t.fail(t.node("size"), "size", "a cylinder's x and y are its diameter and must be equal");
        t.vec2("offset", object.offset, 2.0);
        t.number("heading", object.headingDeg, -360.0, 360.0);
        if (t.has("color") && t.has("texture"))
            t.fail(t.node("texture"), "texture", "give either color or texture, not both");
        if (!t.has("color") && !t.has("texture"))
            t.fail(node, "color", "missing: give color (linear albedo) or texture (an image)");
        t.vec3("color", object.color);
        for (int c = 0; c < 3; ++c)
            if (!(object.color[c] >= 0.0 && object.color[c] <= 1.0))
                t.fail(t.node("color"), "color", "each channel must be in [0, 1]");
        t.path("texture", object.texture, ctx.baseDir, Expect::File);
        if (!object.texture.empty())
            checkTextureFile(t, object.texture);
        config.fakeObjects.push_back(object);
    });
}

void readCamera(TableReader& root, CameraConfig& camera, const Context& ctx)
{
    const toml::table* table = root.table("camera");
    if (!table)
        return;
    TableReader r(*table, "camera", ctx.fileName);
    r.oneOf("source", camera.source, {"fake", "y4m", "images", "v4l2", "libcamera"});
    r.string("device", camera.device);
    if (camera.device.empty())
        r.fail(r.node("device"), "device", "must not be empty");
    r.integer("timeout_ms", camera.timeoutMs, 50, 60000);
    r.integer("buffers", camera.buffers, 2, 32);
    r.oneOf("format", camera.format, {"auto", "nv12", "yuyv", "mjpeg", "grey"});
    r.oneOf("convert", camera.convert, {"auto", "gpu", "cpu"});
    r.oneOf("zero_copy", camera.zeroCopy, {"auto", "off"});
    readCameraControls(r, camera.controls);
    r.integer("width", camera.width, 16, 8192);
    r.checkEven("width", camera.width);
    r.integer("height", camera.height, 16, 8192);
    r.checkEven("height", camera.height);
    r.number("fps", camera.fps, 0.0, 240.0, true);
    r.boolean("loop", camera.loop);
    r.unsignedInteger("seed", camera.seed);
    r.number("noise", camera.noiseSigma, 0.0, 50.0);
    r.path("calibration", camera.calibration, ctx.baseDir, Expect::File);
    const bool fromFile = camera.source == "y4m" || camera.source == "images";
    r.path("path", camera.path, ctx.baseDir, camera.source == "images" ? Expect::Directory : Expect::File);
    if (fromFile && camera.path.empty())
        r.failMissing("path");

    if (r.has("fake_tags")) {
        camera.fakeTags.clear();
        std::set<int> ids;
        forEachTable(r, "fake_tags", [&](TableReader& t, const toml::node* node) {
            FakeTagConfig tag;
            if (!t.has("id"))
                t.failMissing("id");
            t.integer("id", tag.id, 0, kTag36h11Codes - 1);
            t.number("size", tag.size, 0.005, 2.0, true);
            t.vec2("position", tag.position, 0.5);
            if (!ids.insert(tag.id).second)
                t.fail(node, "id", "duplicate fake tag id " + std::to_string(tag.id));
            camera.fakeTags.push_back(tag);
        });
    }
    readFakeObjects(r, camera, ctx);
    r.number("exposure", camera.exposure, 0.0, 1e6, true);
    r.finish();
}

void readTracking(TableReader& root, TrackingConfig& tracking, const Context& ctx)
{
    const toml::table* table = root.table("tracking");
    if (!table)
        return;
    TableReader r(*table, "tracking", ctx.fileName);
    r.oneOf("family", tracking.family,
            {"tag36h11", "tag25h9", "tag16h5", "tagCircle21h7", "tagCircle49h12", "tagStandard41h12",
             "tagStandard52h13", "tagCustom48h12"});
    r.number("quad_decimate", tracking.quadDecimate, 1.0, 8.0);
    r.number("quad_sigma", tracking.quadSigma, 0.0, 5.0);
    r.boolean("refine_edges", tracking.refineEdges);
    r.number("decode_sharpening", tracking.decodeSharpening, 0.0, 5.0);
    r.integer("threads", tracking.threads, 1, 64);
    r.boolean("roi", tracking.roi);
    r.integer("full_frame_every", tracking.fullFrameEvery, 1, 1000);
    r.integer("coarse_every", tracking.coarseEvery, 0, 1000);
    r.number("coarse_decimate", tracking.coarseDecimate, 1.0, 16.0);
    r.integer("max_bit_errors", tracking.maxBitErrors, 0, 2);
    r.boolean("filter", tracking.filter);
    r.number("filter_min_cutoff", tracking.filterMinCutoffHz, 0.0, 100.0, true);
    r.number("filter_beta", tracking.filterBeta, 0.0, 1000.0);
    r.number("filter_rotation_min_cutoff", tracking.filterRotationMinCutoffHz, 0.0, 100.0, true);
    r.number("filter_rotation_beta", tracking.filterRotationBeta, 0.0, 1000.0);
    r.finish();
}

void readMarkers(TableReader& root, std::vector<MarkerConfig>& markers)
{
    std::set<int> ids;
    forEachTable(root, "markers", [&](TableReader& r, const toml::node* node) {
        MarkerConfig marker;
        if (!r.has("id"))
            r.failMissing("id");
        r.integer("id", marker.id, 0, 1 << 20);
        if (!r.has("size"))
            r.failMissing("size");
        r.number("size", marker.size, 0.005, 2.0, true);
        if (!ids.insert(marker.id).second)
            r.fail(node, "id", "duplicate marker id " + std::to_string(marker.id));
        markers.push_back(marker);
    });
}

// Codes in each tag family (the libraries' ncodes): valid tag ids are 0..count-1.
int tagFamilyCodeCount(std::string_view family)
{
    static constexpr std::pair<std::string_view, int> kCounts[] = {
        {"tag36h11", kTag36h11Codes}, {"tag25h9", 35},           {"tag16h5", 30},
        {"tagCircle21h7", 38},        {"tagCircle49h12", 65535}, {"tagStandard41h12", 2115},
        {"tagStandard52h13", 48714},  {"tagCustom48h12", 42211}};
    for (const auto& [name, count] : kCounts)
        if (name == family)
            return count;
    return 1 << 20; // unreachable: readTracking accepts only the families above
}

// [[maps]] with their [[maps.tags]]. A tag id belongs to one map at most (the tracker could
// not tell which map a detection belongs to otherwise), and a tag that is also a marker must
// have the marker's size (one detection gets one per-tag pose).
void readMaps(TableReader& root, std::vector<MapConfig>& maps, const std::vector<MarkerConfig>& markers,
              const std::string& family)
{
    const int codes = tagFamilyCodeCount(family);
    std::set<std::string> names;
    std::set<int> ids;
    forEachTable(root, "maps", [&](TableReader& r, const toml::node* node) {
        MapConfig map;
        if (!r.has("name"))
            r.failMissing("name");
        r.string("name", map.name);
        if (map.name.empty())
            r.fail(r.node("name"), "name", "must not be empty");
        if (!names.insert(map.name).second)
            r.fail(r.node("name"), "name", "duplicate map name '" + map.name + "'");
        if (!r.has("tags"))
            r.failMissing("tags");
        forEachTable(r, "tags", [&](TableReader& t, const toml::node*) {
            MapTagConfig tag;
            if (!t.has("id"))
                t.failMissing("id");
            t.integer("id", tag.id, 0, codes - 1);
            if (!t.has("size"))
                t.failMissing("size");
            t.number("size", tag.size, 0.005, 2.0, true);
            t.vec3("position", tag.position, 100.0);
            if (glm::length(tag.position) > 100.0)
                t.fail(t.node("position"), "position", "must be within 100 metres of the map's origin");
            t.vec3("rotation", tag.rotationDeg, kMaxDegrees);
            if (!ids.insert(tag.id).second)
                t.fail(t.node("id"), "id", "tag " + std::to_string(tag.id) + " is already in a map");
            for (const MarkerConfig& m : markers)
                if (m.id == tag.id && m.size != tag.size)
                    t.fail(t.node("size"), "size",
                           "tag " + std::to_string(tag.id) + " is listed in [[markers]] with size " +
                               std::to_string(m.size) + ", not " + std::to_string(tag.size));
            map.tags.push_back(tag);
        });
        if (map.tags.empty())
            r.fail(node, "tags", "a map needs at least one tag");
        maps.push_back(map);
    });
}

// [[objects]] animation = "name" | index | "all" | "none", loop, speed. Names are checked
// against the model when it is loaded (app/object_animation.h) and by check-config.
void readObjectAnimation(TableReader& r, ObjectConfig& object)
{
    if (const toml::node* node = r.node("animation"))
        object.animationLine = int(node->source().begin.line);
    if (const toml::node* node = r.node("animation"); node && node->is_integer()) {
        r.integer("animation", object.animationIndex, 0, 1 << 20);
    } else {
        r.string("animation", object.animation);
        if (node && object.animation.empty())
            r.fail(node, "animation", "must name an animation, or be an index, \"all\" or \"none\"");
    }
    r.boolean("loop", object.loop);
    r.number("speed", object.speed, 0.0, 1000.0);
}

void readObjects(TableReader& root, std::vector<ObjectConfig>& objects, const std::vector<MarkerConfig>& markers,
                 const std::vector<MapConfig>& maps, const Context& ctx)
{
    std::set<std::string> names;
    forEachTable(root, "objects", [&](TableReader& r, const toml::node* node) {
        ObjectConfig object;
        object.name = "object" + std::to_string(objects.size());
        r.string("name", object.name);
        if (object.name.empty())
            r.fail(node, "name", "must not be empty");
        if (!names.insert(object.name).second)
            r.fail(node, "name", "duplicate object name '" + object.name + "'");
        if (!r.has("model"))
            r.failMissing("model");
        std::string model;
        r.string("model", model);
        if (model.starts_with(kBuiltinModelPrefix)) {
            if (!isBuiltinShape(model.substr(kBuiltinModelPrefix.size())))
                r.fail(node, "model", "'" + model + "' is not a built-in shape (builtin:sphere, builtin:cube)");
            object.model = model;
        } else {
            r.path("model", object.model, ctx.baseDir, Expect::File);
            const auto extension = object.model.extension();
            if (extension != ".gltf" && extension != ".glb")
                r.fail(node, "model", object.model.string() + ": expected a .gltf or .glb file");
        }
        r.path("materials", object.materials, ctx.baseDir, Expect::File);
        if (!object.materials.empty())
            object.materialOverrides = loadMaterialSidecar(object.materials); // reports its own FILE:LINE errors
        r.string("material", object.material);
        if (!object.material.empty() && !materialPreset(object.material)) {
            std::string known;
            for (const std::string_view name : materialPresetNames())
                known += (known.empty() ? "" : ", ") + std::string(name);
            r.fail(node, "material", "'" + object.material + "' is not a material preset (" + known + ")");
        }
        if (r.has("map")) {
            if (r.has("marker"))
                r.fail(r.node("map"), "map", "give either marker or map, not both");
            r.string("map", object.map);
            bool known = false;
            for (const MapConfig& m : maps)
                known = known || m.name == object.map;
            if (!known)
                r.fail(r.node("map"), "map", "map '" + object.map + "' is not listed in [[maps]]");
        } else {
            if (!r.has("marker"))
                r.failMissing("marker");
            r.integer("marker", object.marker, 0, 1 << 20);
            bool known = false;
            for (const MarkerConfig& m : markers)
                known = known || m.id == object.marker;
            if (!known)
                r.fail(node, "marker", "marker " + std::to_string(object.marker) + " is not listed in [[markers]]");
        }
        r.vec3("offset", object.offset, kMaxOffsetMetres);
        r.number("heading", object.headingDeg, -360.0, 360.0);
        r.vec3("rotation", object.rotationDeg, kMaxDegrees);
        r.number("scale", object.scale, 0.0, 1e6, true);
        r.number("size", object.size, 0.0, 1e3, true);
        readObjectAnimation(r, object);
        objects.push_back(object);
    });
}

// A phantom's `size`: three sides, two for a plane (a third is accepted and unused), or the
// longest side of a mesh.
void readPhantomSize(TableReader& r, const toml::node* table, PhantomConfig& phantom)
{
    const toml::node* node = r.node("size");
    if (phantom.shape == "mesh") {
        double longest = 0.0;
        r.number("size", longest, 0.0, 100.0, true);
        phantom.size = glm::dvec3(longest);
        return;
    }
    if (!node)
        r.failMissing("size");
    const toml::array* array = node->as_array();
    if (phantom.shape == "plane" && array && array->size() == 2) {
        glm::dvec2 sides(0.0);
        r.vec2("size", sides, 100.0);
        phantom.size = glm::dvec3(sides, 1.0);
    } else {
        r.vec3("size", phantom.size);
    }
    const bool flat = phantom.shape == "plane"; // its z is unused
    if (!(phantom.size.x > 0 && phantom.size.y > 0 && (flat || phantom.size.z > 0) && phantom.size.x < 100 &&
          phantom.size.y < 100 && phantom.size.z < 100))
        r.fail(table, "size", "each side must be in (0, 100) metres");
}

// A mesh phantom's model: read now, so a missing or broken file is reported against the key
// that names it (by `lumar check-config` and on reload, which then keeps the last good scene).
void readPhantomModel(TableReader& r, PhantomConfig& phantom, const Context& ctx)
{
    const toml::node* node = r.node("model");
    if (phantom.shape != "mesh") {
        if (node)
            r.fail(node, "model", "only a phantom with shape = \"mesh\" has a model");
        return;
    }
    if (!node)
        r.failMissing("model");
    std::string model;
    r.string("model", model);
    try {
        if (model.starts_with(kBuiltinModelPrefix)) {
            if (!isBuiltinShape(model.substr(kBuiltinModelPrefix.size())))
                r.fail(node, "model", "'" + model + "' is not a built-in shape (builtin:sphere, builtin:cube)");
            phantom.model = model;
            phantom.mesh =
                std::make_shared<const GltfModel>(makeBuiltinShape(model.substr(kBuiltinModelPrefix.size())));
            return;
        }
        r.path("model", phantom.model, ctx.baseDir, Expect::File);
        const auto extension = phantom.model.extension();
        if (extension != ".gltf" && extension != ".glb")
            r.fail(node, "model", phantom.model.string() + ": expected a .gltf or .glb file");
        phantom.mesh = std::make_shared<const GltfModel>(loadGltfModel(phantom.model));
    } catch (const InputError& e) {
        const std::string what = e.what();
        if (what.starts_with(ctx.fileName + ":"))
            throw;                   // already this file's line and key
        r.fail(node, "model", what); // the glTF loader's "FILE: what is wrong"
    }
}

void readPhantoms(TableReader& root, std::vector<PhantomConfig>& phantoms, const std::vector<MarkerConfig>& markers,
                  const Context& ctx)
{
    std::set<std::string> names;
    forEachTable(root, "phantoms", [&](TableReader& r, const toml::node* node) {
        PhantomConfig phantom;
        phantom.name = "phantom" + std::to_string(phantoms.size());
        r.string("name", phantom.name);
        if (!names.insert(phantom.name).second)
            r.fail(node, "name", "duplicate phantom name '" + phantom.name + "'");
        if (!r.has("marker"))
            r.failMissing("marker");
        r.integer("marker", phantom.marker, 0, 1 << 20);
        bool known = false;
        for (const MarkerConfig& m : markers)
            known = known || m.id == phantom.marker;
        if (!known)
            r.fail(node, "marker", "marker " + std::to_string(phantom.marker) + " is not listed in [[markers]]");
        r.oneOf("shape", phantom.shape, {"box", "plane", "cylinder", "mesh"});
        readPhantomSize(r, node, phantom);
        readPhantomModel(r, phantom, ctx);
        r.vec3("offset", phantom.offset, kMaxOffsetMetres);
        r.number("heading", phantom.headingDeg, -360.0, 360.0);
        r.vec3("color", phantom.color);
        for (int c = 0; c < 3; ++c)
            if (!(phantom.color[c] >= 0.0 && phantom.color[c] <= 1.0))
                r.fail(node, "color", "each channel must be in [0, 1]");
        phantoms.push_back(phantom);
    });
}

void readEnvironment(TableReader& root, EnvironmentConfig& environment, const Context& ctx)
{
    const toml::table* table = root.table("environment");
    if (!table)
        return;
    TableReader r(*table, "environment", ctx.fileName);
    r.path("hdr", environment.hdr, ctx.baseDir, Expect::File);
    r.number("intensity", environment.intensity, 0.0, 100.0);
    r.oneOf("source", environment.source, {"hdr", "camera", "camera+hdr"});
    if (environment.source == "camera+hdr" && environment.hdr.empty())
        r.fail(table->get("source"), "source",
               "\"camera+hdr\" fills what the camera has not seen from an hdr: set hdr");
    r.boolean("match_exposure", environment.matchExposure);
    r.finish();
}

void readLights(TableReader& root, std::vector<LightConfig>& lights)
{
    forEachTable(root, "lights", [&](TableReader& r, const toml::node*) {
        LightConfig light;
        r.oneOf("type", light.type, {"directional"});
        if (!r.has("direction"))
            r.failMissing("direction");
        r.vec3("direction", light.direction, 1e6);
        if (!(glm::length(light.direction) > 1e-9))
            r.fail(r.node("direction"), "direction", "must not be zero");
        light.direction = glm::normalize(light.direction);
        r.vec3("color", light.color);
        for (int c = 0; c < 3; ++c)
            if (!(light.color[c] >= 0.0 && light.color[c] <= 1.0))
                r.fail(r.node("color"), "color", "each channel must be in [0, 1]");
        r.number("intensity", light.intensity, 0.0, 1e6);
        r.boolean("shadow", light.shadow);
        lights.push_back(light);
    });
}

void readShadows(TableReader& root, ShadowsConfig& shadows)
{
    const toml::table* table = root.table("shadows");
    if (!table)
        return;
    TableReader r(*table, "shadows", root.fileName());
    r.boolean("enabled", shadows.enabled);
    r.integer("map_size", shadows.mapSize, 256, 4096);
    if ((shadows.mapSize & (shadows.mapSize - 1)) != 0)
        r.fail(r.node("map_size"), "map_size", std::to_string(shadows.mapSize) + " is not a power of two");
    r.number("softness", shadows.softness, 0.0, 16.0);
    r.oneOf("resolution", shadows.resolution, {"full", "half", "quarter"});
    r.boolean("ground", shadows.ground);
    r.finish();
}

void readLens(TableReader& rendering, LensConfig& lens)
{
    const toml::table* table = rendering.table("lens");
    if (!table)
        return;
    TableReader r(*table, "rendering.lens", rendering.fileName());
    r.boolean("enabled", lens.enabled);
    r.number("threshold", lens.threshold, 0.0, 1000.0);
    r.boolean("bloom", lens.bloom);
    r.number("bloom_intensity", lens.bloomIntensity, 0.0, 16.0);
    r.number("bloom_radius", lens.bloomRadius, 2.0, 1024.0);
    r.boolean("glare", lens.glare);
    r.integer("glare_streaks", lens.glareStreaks, 2, 16);
    r.number("glare_length", lens.glareLength, 4.0, 1024.0);
    r.number("glare_intensity", lens.glareIntensity, 0.0, 16.0);
    r.number("glare_angle", lens.glareAngle, -360.0, 360.0);
    r.finish();
}

void readRendering(TableReader& root, RenderingConfig& rendering, const Context& ctx)
{
    const toml::table* table = root.table("rendering");
    if (!table)
        return;
    TableReader r(*table, "rendering", ctx.fileName);
    r.oneOf("environment_maps", rendering.environmentMaps,
            {"auto", "every_frame", "every_k", "budget", "on_change", "off"});
    r.integer("environment_map_every", rendering.environmentMapEvery, 1, 1000);
    r.number("environment_map_budget_ms", rendering.environmentMapBudgetMs, 0.0, 1000.0, true);
    r.integer("environment_map_size", rendering.environmentMapSize, 16, 256);
    r.boolean("phantoms_show_camera", rendering.phantomsShowCamera);
    readLens(r, rendering.lens);
    const int size = rendering.environmentMapSize;
    if ((size & (size - 1)) != 0)
        r.fail(table->get("environment_map_size"), "environment_map_size",
               std::to_string(size) + " is not a power of two");
    r.finish();
}

// "WIDTHxHEIGHT", both sides in 1..16384 (issue 16: sscanf's %d read "4294967297x1" as 1x1
// by overflowing). from_chars reports overflow instead, and takes no sign or blank.
bool parseModeSize(std::string_view mode)
{
    constexpr int kMaxModeSide = 16384;
    const size_t x = mode.find('x');
    if (x == std::string_view::npos)
        return false;
    const auto side = [](std::string_view text) {
        int value = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        return ec == std::errc() && end == text.data() + text.size() && !text.empty() && value >= 1 &&
                       value <= kMaxModeSide
                   ? value
                   : 0;
    };
    return side(mode.substr(0, x)) != 0 && side(mode.substr(x + 1)) != 0;
}

void readOutput(TableReader& root, OutputConfig& output, const Context& ctx)
{
    const toml::table* table = root.table("output");
    if (!table)
        return;
    TableReader r(*table, "output", ctx.fileName);
    r.oneOf("sink", output.sink, {"headless", "kms", "window", "none"});
    r.string("drm_device", output.drmDevice);
    if (output.drmDevice != "auto" && !output.drmDevice.starts_with("/dev/"))
        r.fail(table->get("drm_device"), "drm_device", "expected \"auto\" or a /dev/dri/card* path");
    r.string("connector", output.connector);
    r.oneOf("plane", output.plane, {"auto", "primary", "overlay"});
    r.string("mode", output.mode);
    r.oneOf("kms_api", output.kmsApi, {"auto", "legacy"});
    if (output.mode != "auto" && !parseModeSize(output.mode))
        r.fail(table->get("mode"), "mode", "expected \"auto\" or WIDTHxHEIGHT with sides 1..16384, e.g. \"1920x1080\"");
    r.path("path", output.path, ctx.baseDir, Expect::Parent);
    const auto extension = output.path.extension();
    if (!output.path.empty() && extension != ".png" && extension != ".y4m")
        r.fail(table->get("path"), "path", output.path.string() + ": expected a .png or .y4m file");
    r.path("status_path", output.statusPath, ctx.baseDir, Expect::Parent);
    r.boolean("overlay", output.overlay);
    r.finish();
}

// `board = "x86-uvc"` (a shipped profile) or a path to a board file: the profile's camera
// values become the defaults that the [camera] table then overrides.
void readBoardProfile(TableReader& root, Config& config, const Context& ctx)
{
    if (!root.has("board"))
        return;
    std::string name;
    root.string("board", name);
    if (name.empty())
        root.fail(root.node("board"), "board", "must not be empty");
    const std::filesystem::path file = resolveBoardProfile(name, ctx.baseDir);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) {
        std::string shipped;
        for (const std::string& board : shippedBoardNames())
            shipped += (shipped.empty() ? "" : ", ") + board;
        root.fail(root.node("board"), "board", "no board profile " + file.string() + " (shipped: " + shipped + ")");
    }
    config.board = loadBoardProfile(file); // reports its own FILE:LINE errors
    applyBoardCameraDefaults(*config.board, config.camera);
}

void readLogLevel(TableReader& root, std::string& level)
{
    root.string("log_level", level);
    std::string_view spec = level;
    while (!spec.empty()) {
        const size_t comma = spec.find(',');
        const std::string_view item = spec.substr(0, comma);
        spec = comma == std::string_view::npos ? std::string_view{} : spec.substr(comma + 1);
        const size_t colon = item.find(':');
        log::Level parsed{};
        if (!log::parseLevel(colon == std::string_view::npos ? item : item.substr(colon + 1), parsed))
            root.fail(nullptr, "log_level", "'" + level + "' is not a level spec (e.g. info, or capture:debug,*:warn)");
    }
}

} // namespace

double Config::markerSize(int id) const
{
    for (const MarkerConfig& m : markers)
        if (m.id == id)
            return m.size;
    return 0.0;
}

Config parseConfig(std::string_view text, const std::filesystem::path& fileName, const std::filesystem::path& baseDir)
{
    const Context ctx{fileName.string(), baseDir};
    const toml::table root = parseToml(text, ctx.fileName);

    Config config;
    config.sourceFile = fileName;
    TableReader r(root, "", ctx.fileName);
    readLogLevel(r, config.logLevel);
    readBoardProfile(r, config, ctx);
    readCamera(r, config.camera, ctx);
    readTracking(r, config.tracking, ctx);
    readMarkers(r, config.markers);
    readMaps(r, config.maps, config.markers, config.tracking.family);
    readObjects(r, config.objects, config.markers, config.maps, ctx);
    readPhantoms(r, config.phantoms, config.markers, ctx);
    readEnvironment(r, config.environment, ctx);
    readLights(r, config.lights);
    readShadows(r, config.shadows);
    if (config.camera.source == "fake") {
        config.camera.fakeEnvironment = config.environment.hdr;
        config.camera.fakeEnvironmentIntensity = config.environment.intensity;
    }
    readRendering(r, config.rendering, ctx);
    readOutput(r, config.output, ctx);
    r.finish();
    return config;
}

Config loadConfig(const std::filesystem::path& file)
{
    std::error_code ec;
    if (std::filesystem::is_directory(file, ec))
        throw InputError(file.string() + ": cannot read: is a directory");
    // A configuration is a few kilobytes; a larger file is not one (and would be read whole).
    constexpr uintmax_t kMaxConfigBytes = uintmax_t(1) << 20;
    if (const uintmax_t size = std::filesystem::file_size(file, ec); !ec && size > kMaxConfigBytes)
        throw InputError(file.string() + ": cannot read: the file is larger than 1 MiB");
    std::ifstream in(file, std::ios::binary);
    if (!in)
        throw InputError(file.string() + ": cannot read: " + std::strerror(errno));
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    if (in.bad())
        throw InputError(file.string() + ": cannot read: I/O error");
    const std::filesystem::path base = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
    Config config = parseConfig(text, file, base);
    LUMAR_LOG(Config, Debug) << "loaded " << file.string();
    return config;
}

} // namespace lumar
