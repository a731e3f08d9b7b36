#include "capture/fake_camera.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <mutex>
#include <optional>
#include <set>
#include <string>

#include <stb_image.h>

#include "capture/colour_conversion.h"
#include "capture/convex_polygon.h"
#include "capture/environment_cube.h"
#include "capture/fake_objects.h"
#include "capture/fake_scene_shading.h"
#include "capture/fake_trajectory.h"
#include "capture/lazy_texels.h"
#include "capture/packed_buffer.h"
#include "capture/sensor_noise.h"
#include "capture/srgb_encoding.h"
#include "capture/table_irradiance.h"
#include "capture/table_texture.h"
#include "capture/tag36h11_pattern.h"
#include "core/environment_frame.h"
#include "core/error.h"
#include "core/log.h"
#include "gles_renderer/assets/environment_map.h"

namespace lumar {
namespace {

// Rays per pixel along each axis, box-filtered: 2 × 2 anti-aliases the tag edges enough for
// sub-pixel corner accuracy (see the round-trip test) within the 30 fps budget.
constexpr int kSamplesPerAxis = 2;
static_assert(kSamplesPerAxis * kSamplesPerAxis <= fake_scene::kMaxRaysPerSum, "packed sums would overflow");
// Ray positions inside a pixel, in pixels from its centre: a regular grid.
constexpr std::array<float, kSamplesPerAxis> kSampleOffsets = [] {
    std::array<float, kSamplesPerAxis> offsets{};
    for (int i = 0; i < kSamplesPerAxis; ++i) {
        offsets[size_t(i)] = (float(i) + 0.5f) / kSamplesPerAxis - 0.5f;
    }
    return offsets;
}();
// Rays are located on the table a chunk of pixels at a time, in a branch-free loop the
// compiler vectorizes; only rays off the plain table (tags, edges, floor) are shaded one by one.
constexpr int kChunkPixels = 128;
constexpr int kChunkRays = kChunkPixels * kSamplesPerAxis;
constexpr int kMaxDimension = 16384;
// Floor shading levels out to the walls (see Impl::floorLevels).
constexpr int kFloorLevels = 2048;
constexpr float kFloorLevelsPerSquareMetre = float(kFloorLevels) / (fake_scene::kRoomRadius * fake_scene::kRoomRadius);
constexpr int kMinDimension = 16;
// Bounds tag sizes and positions, metres: it bounds the camera's distance and so keeps
// every coordinate the ray loops compute far inside float and int range.
constexpr double kMaxSceneExtent = 10.0;
constexpr float kHalfCells = 0.5f * kTag36h11TotalCells;

// What locateRays() found for a ray that is not on plain table: shade it in full, test the
// objects first, or background entry b at kFirstBackground − b.
constexpr int32_t kShadeRay = -1;
constexpr int32_t kObjectRay = -2;
constexpr int32_t kFirstBackground = -3;

// Where the rays of one chunk of one sub-row hit the table plane.
struct RayChunk {
    int32_t texelIndex[kChunkRays]; // a table texel, or one of the codes below
    float x[kChunkRays];
    float y[kChunkRays];
};

// A tag lying on the table, ready for per-ray lookups.
struct TagSurface {
    float centreX = 0.0f;
    float centreY = 0.0f;
    float halfOuter = 0.0f; // half the side of the white frame's outer edge
    float cellsPerMetre = 0.0f;
    std::array<float, kTag36h11TotalCells * kTag36h11TotalCells> codeValues{};
};

// Under an environment map the tag's print is paper and ink with the albedo their room code
// values stand for (sRGB-decoded): 0.81 and 0.011.
const float kPaperAlbedo = float(srgbDecode(fake_scene::kPaperWhite / 255.0));
const float kInkAlbedo = float(srgbDecode(fake_scene::kInkBlack / 255.0));

// Objects in the plain room: lit mostly from above, as by the room's lamp and pale walls
// (a white top shows about what the table's brightest texels do).
glm::vec3 roomLight(const glm::vec3& normal)
{
    return glm::vec3(0.8f + 0.2f * normal.z);
}

// Where an object may be on screen in one frame: the convex hull of its outline's projection
// (pixels), between rows y0 and y1; `whole`: anywhere (a point behind the camera).
struct ScreenOutline {
    float y0 = 0.0f;
    float y1 = 0.0f;
    bool whole = false;
    std::vector<glm::vec2> hull;
};
// A sub-row's share of an outline: rays with x0 <= u <= x1 may hit the object.
struct ScreenSpan {
    float x0 = 0.0f;
    float x1 = -1.0f;
};
// A ray this close to an outline (pixels) is tested against the object too: a margin for
// float rounding, wider than the rounding by far.
constexpr float kOutlineMargin = 1.0f;

void validateObjects(const CameraConfig& config)
{
    for (size_t i = 0; i < config.fakeObjects.size(); ++i) {
        const FakeObjectConfig& object = config.fakeObjects[i];
        const std::string where = "camera.fake_objects[" + std::to_string(i) + "].";
        if (object.shape != "box" && object.shape != "cylinder") {
            throw InputError(where + "shape: '" + object.shape + "' is not one of box, cylinder");
        }
        bool known = false;
        for (const FakeTagConfig& tag : config.fakeTags) {
            known = known || tag.id == object.tag;
        }
        if (!known) {
            throw InputError(where + "tag: tag " + std::to_string(object.tag) + " is not in camera.fake_tags");
        }
        for (int a = 0; a < 3; ++a) {
            if (!(object.size[a] > 0.0) || !(object.size[a] <= kMaxSceneExtent)) {
                throw InputError(where + "size: each side must be positive and at most 10 m");
            }
        }
        if (object.shape == "cylinder" && object.size.x != object.size.y) {
            throw InputError(where + "size: a cylinder's x and y are its diameter and must be equal");
        }
        if (!(std::abs(object.offset.x) <= kMaxSceneExtent) || !(std::abs(object.offset.y) <= kMaxSceneExtent)) {
            throw InputError(where + "offset: must be within 10 m of the tag");
        }
        if (!std::isfinite(object.headingDeg)) {
            throw InputError(where + "heading: must be finite");
        }
        for (int c = 0; c < 3; ++c) {
            if (!(object.color[c] >= 0.0 && object.color[c] <= 1.0)) {
                throw InputError(where + "color: each channel must be in [0, 1]");
            }
        }
    }
}

void validate(const CameraConfig& config)
{
    if (config.width < kMinDimension || config.width > kMaxDimension || config.height < kMinDimension ||
        config.height > kMaxDimension) {
        throw InputError("camera.width/height: the fake camera renders between 16x16 and 16384x16384, got " +
                         std::to_string(config.width) + "x" + std::to_string(config.height));
    }
    if (!(config.fps > 0.0) || !std::isfinite(config.fps)) {
        throw InputError("camera.fps: must be positive, got " + std::to_string(config.fps));
    }
    if (!(config.noiseSigma >= 0.0) || !std::isfinite(config.noiseSigma)) {
        throw InputError("camera.noise_sigma: must be zero or positive, got " + std::to_string(config.noiseSigma));
    }
    if (!(config.exposure > 0.0) || !std::isfinite(config.exposure)) {
        throw InputError("camera.exposure: must be positive and finite, got " + std::to_string(config.exposure));
    }
    if (!(config.fakeEnvironmentIntensity >= 0.0) || !std::isfinite(config.fakeEnvironmentIntensity)) {
        throw InputError("environment.intensity: must be zero or positive, got " +
                         std::to_string(config.fakeEnvironmentIntensity));
    }
    if (config.fakeTags.empty()) {
        throw InputError("camera.fake_tags: no tags (the fake scene needs at least one)");
    }
    std::set<int> ids;
    const int codes = tag36h11CodeCount();
    for (size_t i = 0; i < config.fakeTags.size(); ++i) {
        const FakeTagConfig& tag = config.fakeTags[i];
        const std::string where = "camera.fake_tags[" + std::to_string(i) + "]: ";
        if (tag.id < 0 || tag.id >= codes) {
            throw InputError(where + "id " + std::to_string(tag.id) + " has no tag36h11 code (valid ids are 0.." +
                             std::to_string(codes - 1) + ")");
        }
        if (!ids.insert(tag.id).second) {
            throw InputError(where + "duplicate id " + std::to_string(tag.id));
        }
        if (!(tag.size > 0.0) || !(tag.size <= kMaxSceneExtent)) {
            throw InputError(where + "size must be positive and at most 10 m, got " + std::to_string(tag.size));
        }
        if (!(std::abs(tag.position.x) <= kMaxSceneExtent) || !(std::abs(tag.position.y) <= kMaxSceneExtent)) {
            throw InputError(where + "position must be within 10 m of the table's centre");
        }
    }
    validateObjects(config);
}

TagSurface makeTagSurface(const FakeTagConfig& tag)
{
    TagSurface surface;
    surface.centreX = float(tag.position.x);
    surface.centreY = float(tag.position.y);
    const double cell = tag.size / kTag36h11BorderCells;
    surface.halfOuter = float(0.5 * kTag36h11TotalCells * cell);
    surface.cellsPerMetre = float(1.0 / cell);
    const TagPattern pattern = tag36h11Pattern(tag.id);
    for (size_t i = 0; i < pattern.size(); ++i) {
        surface.codeValues[i] = pattern[i] ? fake_scene::kPaperWhite : fake_scene::kInkBlack;
    }
    return surface;
}

// An object's texture as linear albedo (sRGB-decoded), 3 channels.
ImageF loadTexture(const std::filesystem::path& file, const SrgbEncoder& encoder)
{
    int width = 0;
    int height = 0;
    int channels = 0;
    stbi_uc* pixels = stbi_load(file.c_str(), &width, &height, &channels, 3);
    if (pixels == nullptr) {
        const char* reason = stbi_failure_reason();
        throw InputError(file.string() + ": cannot read the texture: " + (reason ? reason : "unknown reason"));
    }
    ImageF albedo(width, height, 3);
    for (size_t i = 0; i < albedo.data.size(); ++i) {
        albedo.data[i] = encoder.linear(pixels[i]);
    }
    stbi_image_free(pixels);
    return albedo;
}

uint8_t toByte(float v)
{
    // Round half up; the clamp keeps noise from wrapping.
    const int i = int(v + 0.5f);
    return uint8_t(i < 0 ? 0 : (i > 255 ? 255 : i));
}

// The table texel index under table point (x, y), |x|, |y| <= kTableHalfSize.
size_t tableTexelIndex(float x, float y)
{
    constexpr int last = TableTexture::kResolution - 1;
    const int tx = std::clamp(int((x + fake_scene::kTableHalfSize) * TableTexture::kTexelsPerMetre), 0, last);
    const int ty = std::clamp(int((y + fake_scene::kTableHalfSize) * TableTexture::kTexelsPerMetre), 0, last);
    return size_t(ty) * TableTexture::kResolution + size_t(tx);
}

// The cube tiles a frame from `eye` may read: those its view may reach, less those the table
// hides whole (a ray that meets the table reads the table, not the cube). The table's cone
// is taken 1 mm smaller all round: a ray at its very edge may go either way.
bool cubeTileMayBeRead(const EnvironmentCube& cube, int tile, const ViewCone& view, const glm::vec3& eye)
{
    if (!cube.tileMayBeSeen(tile, view)) {
        return false;
    }
    if (eye.z <= 0.0f) {
        return true;
    }
    const float h = fake_scene::kTableHalfSize - 1e-3f;
    const ViewCone table = ViewCone::spannedBy({glm::vec3(-h, -h, 0.0f) - eye, glm::vec3(h, -h, 0.0f) - eye,
                                                glm::vec3(h, h, 0.0f) - eye, glm::vec3(-h, h, 0.0f) - eye});
    return !cube.tileWithin(tile, table);
}

} // namespace

struct FakeCamera::Impl {
    // What depends on the exposure, re-made when it changes (Impl::expose).
    struct Exposed {
        double exposure = 1.0;
        PackedBuffer ownTable;
        const fake_scene::PackedRgb* table = nullptr; // the lit table texels
        // Room: the floor levels.
        PackedBuffer background;
        // Environment: the environment cube's texels, baked as frames first look at them.
        std::optional<LazyTexels> cubeTexels;
        // Room: code value -> code value at this exposure; identity at 1.
        std::array<uint8_t, 256> remap{};
        bool remapIsIdentity = true;
        // Environment: the tags' print where no object shades it, and for each tag that an
        // object's shadow reaches, its paper and ink lit texel by texel (the table's texels).
        fake_scene::PackedRgb paper = 0;
        fake_scene::PackedRgb ink = 0;
        struct LitTag {
            int x0 = 0; // the first table texel covered
            int y0 = 0;
            int size = 0;       // texels a side; 0: lit evenly (paper, ink)
            PackedBuffer codes; // ink, paper for texel (i, j) at 2 (j · size + i)
        };
        std::vector<LitTag> litTags;
        // Per object and face: the white radiance times the exposure, and for a coloured
        // object the packed colour (the cylinder's side is shaded per ray).
        std::vector<std::array<glm::vec3, FakeObject::kFaces>> faceLight;
        std::vector<std::array<fake_scene::PackedRgb, FakeObject::kFaces>> faceCodes;

        [[nodiscard]] fake_scene::PackedRgb remapped(fake_scene::PackedRgb p) const
        {
            if (remapIsIdentity) {
                return p;
            }
            using fake_scene::kLaneBits;
            using fake_scene::kLaneMask;
            return uint32_t(remap[p & kLaneMask]) | (uint32_t(remap[(p >> kLaneBits) & kLaneMask]) << kLaneBits) |
                   (uint32_t(remap[p >> (2 * kLaneBits)]) << (2 * kLaneBits));
        }
    };

    CameraConfig config;
    CameraIntrinsics intrinsics;
    FakeTrajectory trajectory;
    bool environment = false; // an environment map surrounds and lights the table
    // Room only: the table lit by the lamp, kept for every frame. Under an environment map the
    // wood's albedo is only needed to light the table (Exposed::ownTable), a row at a time from
    // its generators: the whole albedo table (16.8 MB) is never held.
    std::optional<TableTexture> table;
    std::optional<TableWood> wood; // environment only
    SensorNoise noise;
    SrgbEncoder encoder;
    std::vector<TagSurface> tags;
    // The tags' union bounding box: most rays miss every tag after one test.
    float tagsMinX = 0.0f, tagsMaxX = 0.0f, tagsMinY = 0.0f, tagsMaxY = 0.0f;
    // The floor's colour at squared distance (level + 0.5) / kFloorLevelsPerSquareMetre: the
    // floor is smooth, so a table lookup is indistinguishable from shading each ray.
    std::array<fake_scene::PackedRgb, kFloorLevels> floorLevels{};
    // Environment only.
    std::optional<EnvironmentCube> cube;
    SH9 sh{}; // the map's SH, intensity applied
    glm::mat3 environmentFromWorld{1.0f};
    std::optional<TableIrradiance> light;
    std::vector<FakeObject> objects;
    std::vector<glm::vec3> objectAlbedo; // linear; unused for a textured object
    // Environment: the views of the frames of one period of the trajectory, whose cube tiles
    // are baked with each exposure, so frames rendered in order bake none themselves.
    struct OrbitView {
        ViewCone view;
        glm::vec3 eye{0.0f};
    };
    std::vector<OrbitView> orbitViews;
    std::vector<ImageF> objectTextures; // linear albedo; empty for a coloured object

    std::atomic<double> requestedExposure{1.0};
    mutable std::mutex exposedMutex;
    mutable std::shared_ptr<const Exposed> exposed;
    uint64_t nextSequence = 0;

    explicit Impl(const CameraConfig& c)
        : config(c), intrinsics(defaultIntrinsics(c.width, c.height)), trajectory(c.fakeTags),
          environment(!c.fakeEnvironment.empty()), noise(c.noiseSigma), requestedExposure(c.exposure)
    {
        for (int level = 0; level < kFloorLevels; ++level) {
            const float radiusSquared = (float(level) + 0.5f) / kFloorLevelsPerSquareMetre;
            floorLevels[size_t(level)] = fake_scene::packRgb(fake_scene::floorColour(radiusSquared));
        }
        if (!environment) {
            table.emplace(c.seed, true);
        } else {
            wood.emplace(c.seed);
        }
        tagsMinX = tagsMinY = INFINITY;
        tagsMaxX = tagsMaxY = -INFINITY;
        for (const auto& tag : c.fakeTags) {
            const TagSurface& s = tags.emplace_back(makeTagSurface(tag));
            tagsMinX = std::min(tagsMinX, s.centreX - s.halfOuter);
            tagsMaxX = std::max(tagsMaxX, s.centreX + s.halfOuter);
            tagsMinY = std::min(tagsMinY, s.centreY - s.halfOuter);
            tagsMaxY = std::max(tagsMaxY, s.centreY + s.halfOuter);
        }
        for (const FakeObjectConfig& object : c.fakeObjects) {
            glm::dvec2 tagPosition(0.0);
            for (const FakeTagConfig& tag : c.fakeTags) {
                tagPosition = tag.id == object.tag ? tag.position : tagPosition;
            }
            objects.emplace_back(object, tagPosition);
            objectAlbedo.emplace_back(object.color);
            objectTextures.push_back(object.texture.empty() ? ImageF{} : loadTexture(object.texture, encoder));
        }
        if (environment) {
            ImageF map = loadHdrImage(c.fakeEnvironment);
            // The cube keeps the map as loaded (compactly) and applies the intensity itself.
            cube.emplace(map, float(c.fakeEnvironmentIntensity), EnvironmentCube::log2SizeFor(intrinsics.fx));
            for (float& v : map.data) {
                v = std::max(v, 0.0f) * float(c.fakeEnvironmentIntensity);
            }
            sh = projectEquirectSH9(map);
            environmentFromWorld = glm::mat3(environmentFromMarker());
            light.emplace(whiteRadiance(glm::vec3(0.0f, 0.0f, 1.0f)), map, objects);
            // The trajectory repeats every kPeriodSeconds: at 30 fps, 360 frames.
            const int periodFrames = int(std::min(std::ceil(FakeTrajectory::kPeriodSeconds * c.fps), 3600.0));
            for (int k = 0; k < periodFrames; ++k) {
                const Pose pose = trajectory.cameraFromWorld(double(k) / c.fps);
                const glm::dmat3 worldFromCamera = glm::transpose(pose.R);
                orbitViews.push_back({frameView(worldFromCamera), glm::vec3(-(worldFromCamera * pose.t))});
            }
        }
        exposed = expose(c.exposure);
    }

    // The radiance of a white (albedo 1) diffuse surface facing world direction `normal`:
    // E(n)/π from the map's SH (as the renderer lights virtual objects), or the room's light.
    [[nodiscard]] glm::vec3 whiteRadiance(const glm::vec3& normal) const
    {
        if (!environment) {
            return roomLight(normal);
        }
        constexpr float kInvPi = 0.318309886f;
        return glm::max(irradianceSH9(sh, environmentFromWorld * normal) * kInvPi, glm::vec3(0.0f));
    }

    // Everything that depends on the exposure, lit at `exposure`.
    [[nodiscard]] std::shared_ptr<const Exposed> expose(double exposure) const
    {
        auto out = std::make_shared<Exposed>();
        out->exposure = exposure;
        const float e = float(exposure);
        for (size_t k = 0; k < objects.size(); ++k) {
            auto& faceLight = out->faceLight.emplace_back();
            auto& codes = out->faceCodes.emplace_back();
            for (int face = 0; face < FakeObject::kFaces; ++face) {
                faceLight[size_t(face)] = e * whiteRadiance(objects[k].faceNormal(face));
                codes[size_t(face)] = encoder.pack(objectAlbedo[k] * faceLight[size_t(face)]);
            }
        }
        if (!environment) {
            for (int c = 0; c < 256; ++c) {
                out->remap[size_t(c)] =
                    uint8_t(std::lround(255.0 * srgbEncode(std::clamp(exposure * srgbDecode(c / 255.0), 0.0, 1.0))));
                out->remapIsIdentity = out->remapIsIdentity && out->remap[size_t(c)] == c;
            }
            out->background = allocatePacked(kFloorLevels);
            for (size_t i = 0; i < kFloorLevels; ++i) {
                out->background[i] = out->remapped(floorLevels[i]);
            }
            if (out->remapIsIdentity) {
                out->table = table->texels();
                return out;
            }
            const size_t count = size_t(TableTexture::kResolution) * TableTexture::kResolution;
            out->ownTable = allocatePacked(count);
            for (size_t i = 0; i < count; ++i) {
                out->ownTable[i] = out->remapped(table->texels()[i]);
            }
            out->table = out->ownTable.get();
            return out;
        }
        const glm::vec3 open = e * light->unoccluded();
        out->paper = encoder.pack(kPaperAlbedo * open);
        out->ink = encoder.pack(kInkAlbedo * open);
        for (const TagSurface& tag : tags) {
            out->litTags.push_back(lightTag(tag, e));
        }
        out->cubeTexels.emplace(
            cube->texelCount(), cube->tileCount(),
            [this, e](int tile, fake_scene::PackedRgb* texels) { cube->bakeTile(tile, e, encoder, texels); });
        // Baked now, the tiles the orbit's frames will read (7 % of the cube at 1280x720): the
        // frames then only test their view (~0.05 ms); a frame off the orbit (a sequence that
        // is not a whole frame of a period at another fps) bakes what it needs itself.
        out->cubeTexels->prepare([&](int tile) {
            return std::any_of(orbitViews.begin(), orbitViews.end(),
                               [&](const OrbitView& o) { return cubeTileMayBeRead(*cube, tile, o.view, o.eye); });
        });
        out->ownTable = lightTable(e);
        out->table = out->ownTable.get();
        return out;
    }

    // The table's texels at exposure e: albedo × W(x, y) × e, encoded. Where no object shades
    // the table W is constant, so a texel is three 256-entry lookups.
    [[nodiscard]] PackedBuffer lightTable(float e) const
    {
        constexpr int n = TableTexture::kResolution;
        const glm::vec3 open = e * light->unoccluded();
        std::array<std::array<uint32_t, 256>, 3> openCodes{};
        for (int c = 0; c < 256; ++c) {
            for (int ch = 0; ch < 3; ++ch) {
                openCodes[size_t(ch)][size_t(c)] = encoder.code(encoder.linear(uint32_t(c)) * open[ch])
                                                   << (ch * fake_scene::kLaneBits);
            }
        }
        PackedBuffer lit = allocatePacked(size_t(n) * n);
        const float metresPerTexel = 1.0f / TableTexture::kTexelsPerMetre;
        using fake_scene::kLaneBits;
        using fake_scene::kLaneMask;
        std::vector<fake_scene::PackedRgb> albedo(n);
        for (int ty = 0; ty < n; ++ty) {
            wood->row(ty, 0, n, false, albedo.data());
            const float y = -fake_scene::kTableHalfSize + (float(ty) + 0.5f) * metresPerTexel;
            for (int tx = 0; tx < n; ++tx) {
                const size_t i = size_t(ty) * n + size_t(tx);
                const fake_scene::PackedRgb a = albedo[size_t(tx)];
                const float x = -fake_scene::kTableHalfSize + (float(tx) + 0.5f) * metresPerTexel;
                if (!light->shadowed(x, y)) {
                    lit[i] = openCodes[0][a & kLaneMask] | openCodes[1][(a >> kLaneBits) & kLaneMask] |
                             openCodes[2][a >> (2 * kLaneBits)];
                } else {
                    lit[i] = encoder.pack(encoder.unpackLinear(a) * (e * light->at(x, y)));
                }
            }
        }
        return lit;
    }

    // A tag's print lit at exposure e, texel by texel where a shadow reaches it.
    [[nodiscard]] Exposed::LitTag lightTag(const TagSurface& tag, float e) const
    {
        Exposed::LitTag lit;
        // 1024 texels (0.6 m) at most: a larger tag is shaded ray by ray in its shadows.
        constexpr int kMaxSize = 1024;
        constexpr float k = TableTexture::kTexelsPerMetre;
        const float h = fake_scene::kTableHalfSize;
        const int x0 = int(std::floor((tag.centreX - tag.halfOuter + h) * k));
        const int y0 = int(std::floor((tag.centreY - tag.halfOuter + h) * k));
        const int size = int(std::ceil(2.0f * tag.halfOuter * k)) + 2;
        bool shadowed = false;
        const float step = 0.5f / TableIrradiance::kCellsPerMetre;
        for (float y = tag.centreY - tag.halfOuter; y <= tag.centreY + tag.halfOuter + step && !shadowed; y += step) {
            for (float x = tag.centreX - tag.halfOuter; x <= tag.centreX + tag.halfOuter + step; x += step) {
                shadowed = shadowed || light->shadowed(x, y);
            }
        }
        if (!shadowed || size > kMaxSize) {
            return lit;
        }
        lit.x0 = x0;
        lit.y0 = y0;
        lit.size = size;
        lit.codes = allocatePacked(2 * size_t(size) * size_t(size));
        for (int j = 0; j < size; ++j) {
            const float y = (float(y0 + j) + 0.5f) / k - h;
            for (int i = 0; i < size; ++i) {
                const float x = (float(x0 + i) + 0.5f) / k - h;
                const glm::vec3 w = e * light->at(x, y);
                lit.codes[2 * (size_t(j) * size_t(size) + size_t(i))] = encoder.pack(kInkAlbedo * w);
                lit.codes[2 * (size_t(j) * size_t(size) + size_t(i)) + 1] = encoder.pack(kPaperAlbedo * w);
            }
        }
        return lit;
    }

    // The exposed state for the next frame, re-lit first if the exposure changed.
    [[nodiscard]] std::shared_ptr<const Exposed> current() const
    {
        const std::lock_guard lock(exposedMutex);
        const double wanted = requestedExposure.load();
        if (exposed->exposure != wanted) {
            exposed = expose(wanted);
        }
        return exposed;
    }

    // Locates kChunkRays rays along one sub-row, directions base + (u0 + i·du) · step: the
    // texel index of each ray that lands on plain table, kFirstBackground − b for background
    // entry b (the room's floor levels, or the environment cube), kObjectRay where the ray may
    // hit an object (within `spans`), or kShadeRay where it needs full shading (a tag, a room's
    // wall). Every loop is branch-free so it vectorizes.
    template <bool kEnvironment>
    void locateRays(const glm::vec3& eye, const glm::vec3& base, const glm::vec3& step, float u0, float du,
                    const std::vector<ScreenSpan>& spans, RayChunk& chunk) const
    {
        // Rays closer to horizontal than this are left to shade() (room) or to the cube
        // (environment): clamping dz keeps every value finite, and with the scene bounded
        // (kMaxSceneExtent) small enough for the integer conversions below. Such rays never
        // reach the table or the nearby floor (the camera is at least 0.3 m up).
        constexpr float kShallowest = -1e-3f;
        constexpr float kSize = float(TableTexture::kResolution);
        constexpr float kScale = TableTexture::kTexelsPerMetre;
        int offTable = 0;
        for (int i = 0; i < kChunkRays; ++i) {
            const float u = u0 + float(i) * du;
            const float dx = base.x + u * step.x;
            const float dy = base.y + u * step.y;
            const float dz = base.z + u * step.z;
            const bool down = dz < kShallowest;
            const float t = -eye.z / std::min(dz, kShallowest);
            const float x = eye.x + t * dx;
            const float y = eye.y + t * dy;
            // Texel coordinates: the table is [0, kSize)², so int() below stays in range.
            const float fx = (x + fake_scene::kTableHalfSize) * kScale;
            const float fy = (y + fake_scene::kTableHalfSize) * kScale;
            const bool onTable = down & (fx >= 0.0f) & (fx < kSize) & (fy >= 0.0f) & (fy < kSize);
            const int index = int(fy) * TableTexture::kResolution + int(fx);
            if constexpr (kEnvironment) {
                chunk.texelIndex[i] = onTable ? index : kShadeRay;
                offTable += onTable ? 0 : 1;
            } else {
                // Past the table's edge: the floor, lit as a function of the squared distance.
                const float tFloor = (fake_scene::kFloorZ - eye.z) / std::min(dz, kShallowest);
                const float gx = eye.x + tFloor * dx;
                const float gy = eye.y + tFloor * dy;
                const float level = (gx * gx + gy * gy) * kFloorLevelsPerSquareMetre;
                const bool onFloor = down & (level < float(kFloorLevels));
                const int floorCode = kFirstBackground - int(std::min(level, float(kFloorLevels - 1)));
                chunk.texelIndex[i] = onTable ? index : (onFloor ? floorCode : kShadeRay);
            }
            chunk.x[i] = x;
            chunk.y[i] = y;
        }
        if constexpr (kEnvironment) {
            // Only chunks that reach past the table's edge look up the cube.
            if (offTable != 0) {
                const int log2Size = cube->log2Size();
                for (int i = 0; i < kChunkRays; ++i) {
                    const float u = u0 + float(i) * du;
                    const int32_t texel =
                        EnvironmentCube::index(base.x + u * step.x, base.y + u * step.y, base.z + u * step.z, log2Size);
                    chunk.texelIndex[i] = chunk.texelIndex[i] >= 0 ? chunk.texelIndex[i] : kFirstBackground - texel;
                }
            }
        }
        for (const TagSurface& tag : tags) {
            // Locals, so the compiler knows the stores below cannot change them.
            const float cx = tag.centreX;
            const float cy = tag.centreY;
            const float half = tag.halfOuter;
            for (int i = 0; i < kChunkRays; ++i) {
                const bool inside = (std::abs(chunk.x[i] - cx) < half) & (std::abs(chunk.y[i] - cy) < half);
                chunk.texelIndex[i] = inside ? kShadeRay : chunk.texelIndex[i];
            }
        }
        for (const ScreenSpan& span : spans) {
            const float x0 = span.x0;
            const float x1 = span.x1;
            if (x1 < u0 || x0 > u0 + float(kChunkRays) * du) {
                continue;
            }
            for (int i = 0; i < kChunkRays; ++i) {
                const float u = u0 + float(i) * du;
                chunk.texelIndex[i] = (u >= x0) & (u <= x1) ? kObjectRay : chunk.texelIndex[i];
            }
        }
    }

    // The colour of an object where a ray hit it.
    [[nodiscard]] fake_scene::PackedRgb shadeObject(const Exposed& ex, const FakeObjectHit& hit) const
    {
        const FakeObject& object = objects[size_t(hit.object)];
        const ImageF& texture = objectTextures[size_t(hit.object)];
        const bool curved = object.isCylinder() && hit.face == FakeObject::kSide;
        if (texture.empty() && !curved) {
            return ex.faceCodes[size_t(hit.object)][size_t(hit.face)];
        }
        const glm::vec3 lightHere = curved ? float(ex.exposure) * whiteRadiance(object.normal(hit))
                                           : ex.faceLight[size_t(hit.object)][size_t(hit.face)];
        glm::vec3 albedo = objectAlbedo[size_t(hit.object)];
        if (!texture.empty()) {
            const glm::vec2 uv = object.uv(hit);
            const int x = std::min(int(uv.x * float(texture.width)), texture.width - 1);
            const int y = std::min(int(uv.y * float(texture.height)), texture.height - 1);
            const float* t = texture.at(x, y);
            albedo = glm::vec3(t[0], t[1], t[2]);
        }
        return encoder.pack(albedo * lightHere);
    }

    // The colour seen along world-space ray direction d from `eye` where it may hit an object.
    template <bool kEnvironment>
    [[nodiscard]] fake_scene::PackedRgb shadeNearObjects(const Exposed& ex, const glm::vec3& eye,
                                                         const glm::vec3& d) const
    {
        FakeObjectHit hit;
        for (size_t k = 0; k < objects.size(); ++k) {
            if (objects[k].intersect(eye, d, hit)) {
                hit.object = int(k);
            }
        }
        if (hit.object >= 0) {
            return shadeObject(ex, hit);
        }
        return shade<kEnvironment>(ex, eye, d.x, d.y, d.z);
    }

    // The colour seen along world-space ray direction d from `eye`, objects aside. Always
    // inlined: it runs for every ray that locateRays() could not resolve.
    template <bool kEnvironment>
    [[nodiscard]] [[gnu::always_inline]] inline fake_scene::PackedRgb shade(const Exposed& ex, const glm::vec3& eye,
                                                                            float dx, float dy, float dz) const
    {
        using namespace fake_scene;
        if (dz >= 0.0f) {
            if constexpr (kEnvironment) {
                return ex.cubeTexels->texels()[size_t(EnvironmentCube::index(dx, dy, dz, cube->log2Size()))];
            } else {
                return ex.remapped(packRgb(wallColour(dz / std::sqrt(dx * dx + dy * dy + dz * dz))));
            }
        }
        const float s = -eye.z / dz;
        const float x = eye.x + s * dx;
        const float y = eye.y + s * dy;
        if (x >= tagsMinX && x <= tagsMaxX && y >= tagsMinY && y <= tagsMaxY) {
            for (const TagSurface& tag : tags) {
                const float u = x - tag.centreX;
                const float v = y - tag.centreY;
                if (std::abs(u) < tag.halfOuter && std::abs(v) < tag.halfOuter) {
                    // Column 0 lies along the tag's −x edge, row 0 along its +y edge.
                    const int col = std::clamp(int(u * tag.cellsPerMetre + kHalfCells), 0, kTag36h11TotalCells - 1);
                    const int row = std::clamp(int(kHalfCells - v * tag.cellsPerMetre), 0, kTag36h11TotalCells - 1);
                    const float code = tag.codeValues[size_t(row * kTag36h11TotalCells + col)];
                    if constexpr (kEnvironment) {
                        const bool paper = code == kPaperWhite;
                        const Exposed::LitTag& lit = ex.litTags[size_t(&tag - tags.data())];
                        if (lit.size > 0) {
                            const int last = lit.size - 1;
                            const int i =
                                std::clamp(int((x + kTableHalfSize) * TableTexture::kTexelsPerMetre) - lit.x0, 0, last);
                            const int j =
                                std::clamp(int((y + kTableHalfSize) * TableTexture::kTexelsPerMetre) - lit.y0, 0, last);
                            return lit.codes[2 * (size_t(j) * size_t(lit.size) + size_t(i)) + (paper ? 1 : 0)];
                        }
                        if (light->shadowed(x, y)) { // a tag too large to bake
                            return encoder.pack((paper ? kPaperAlbedo : kInkAlbedo) * float(ex.exposure) *
                                                light->at(x, y));
                        }
                        return paper ? ex.paper : ex.ink;
                    } else {
                        return ex.remapped(packGrey(code * tableLighting(x, y)));
                    }
                }
            }
        }
        if (std::abs(x) <= kTableHalfSize && std::abs(y) <= kTableHalfSize) {
            return ex.table[tableTexelIndex(x, y)];
        }
        if constexpr (kEnvironment) {
            return ex.cubeTexels->texels()[size_t(EnvironmentCube::index(dx, dy, dz, cube->log2Size()))];
        } else {
            // Past the table's edge the ray goes on down to the floor, or to a wall far away.
            const float sf = (kFloorZ - eye.z) / dz;
            const float fx = eye.x + sf * dx;
            const float fy = eye.y + sf * dy;
            const float radiusSquared = fx * fx + fy * fy;
            if (radiusSquared >= kRoomRadius * kRoomRadius) {
                return ex.remapped(packRgb(wallColour(dz / std::sqrt(dx * dx + dy * dy + dz * dz))));
            }
            return ex.remapped(packRgb(floorColour(radiusSquared)));
        }
    }

    // One frame's rays: the world direction through pixel (u, v) is
    // rowBase(v) + u · stepU, so a ray costs three multiply-adds and one division.
    struct FrameRays {
        glm::vec3 eye{0.0f};
        glm::vec3 stepU{0.0f};
        glm::dmat3 worldFromCamera{1.0};
        const CameraIntrinsics* intrinsics = nullptr;
        std::vector<ScreenOutline> objectOutlines; // where rays may hit an object

        [[nodiscard]] glm::vec3 rowBase(double v) const
        {
            const CameraIntrinsics& k = *intrinsics;
            return glm::vec3(worldFromCamera[1] * ((v - k.cy) / k.fy) + worldFromCamera[2] -
                             worldFromCamera[0] * (k.cx / k.fx));
        }
    };

    // Every direction a ray of a frame may take, from its camera's orientation: the rays run
    // from pixel centre -0.25 to width - 0.75 (kSampleOffsets), and a margin of pixels covers
    // the rounding of their float directions many times over.
    [[nodiscard]] ViewCone frameView(const glm::dmat3& worldFromCamera) const
    {
        constexpr double kMargin = 2.0;
        const double u0 = -kMargin;
        const double u1 = double(config.width - 1) + kMargin;
        const double v0 = -kMargin;
        const double v1 = double(config.height - 1) + kMargin;
        const auto direction = [&](double u, double v) {
            const CameraIntrinsics& k = intrinsics;
            return glm::vec3(worldFromCamera * glm::dvec3((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0));
        };
        return ViewCone::spannedBy({direction(u0, v0), direction(u1, v0), direction(u1, v1), direction(u0, v1)});
    }

    // Where on screen each object may be in a frame: its outline points projected (a pixel
    // wider all round when used), or the whole image if one is behind the camera.
    [[nodiscard]] std::vector<ScreenOutline> objectOutlines(const Pose& cameraFromWorld) const
    {
        std::vector<ScreenOutline> outlines;
        for (const FakeObject& object : objects) {
            ScreenOutline outline;
            std::vector<glm::vec2> projected;
            for (const glm::vec3& point : object.hullPoints()) {
                const glm::dvec3 p = cameraFromWorld.apply(glm::dvec3(point));
                if (p.z < 1e-3) {
                    outline.whole = true;
                    break;
                }
                projected.push_back(glm::vec2(intrinsics.project(p)));
            }
            if (outline.whole) {
                outline.y0 = -INFINITY;
                outline.y1 = INFINITY;
            } else {
                outline.hull = convexHull(std::move(projected));
                outline.y0 = INFINITY;
                outline.y1 = -INFINITY;
                for (const glm::vec2& p : outline.hull) {
                    outline.y0 = std::min(outline.y0, p.y);
                    outline.y1 = std::max(outline.y1, p.y);
                }
            }
            if (outline.y1 + kOutlineMargin >= -1.0f && outline.y0 - kOutlineMargin <= float(config.height)) {
                outlines.push_back(std::move(outline));
            }
        }
        return outlines;
    }

    // The outlines' spans on the sub-row at image row v.
    void outlineSpans(const std::vector<ScreenOutline>& outlines, float v, std::vector<ScreenSpan>& spans) const
    {
        spans.clear();
        for (const ScreenOutline& outline : outlines) {
            if (v < outline.y0 - kOutlineMargin || v > outline.y1 + kOutlineMargin) {
                continue;
            }
            if (outline.whole) {
                spans.push_back({-INFINITY, INFINITY});
                continue;
            }
            // Rows within the margin above or below take the nearest row's span.
            const glm::vec2 span = convexSpanAt(outline.hull, std::clamp(v, outline.y0, outline.y1));
            if (span.x <= span.y) {
                spans.push_back({span.x - kOutlineMargin, span.y + kOutlineMargin});
            }
        }
    }

    // Renders image row y: kSamplesPerAxis² rays per pixel, box-filtered, plus noise.
    template <bool kEnvironment>
    void renderRow(const Exposed& ex, const FrameRays& rays, uint64_t sequence, int y, uint8_t* rgbOut,
                   uint8_t* lumaOut, std::array<std::vector<ScreenSpan>, kSamplesPerAxis>& spans) const
    {
        constexpr int samples = kSamplesPerAxis * kSamplesPerAxis;
        constexpr float scale = 1.0f / samples;
        glm::vec3 bases[kSamplesPerAxis];
        for (int sy = 0; sy < kSamplesPerAxis; ++sy) {
            bases[sy] = rays.rowBase(double(y) + double(kSampleOffsets[sy]));
            outlineSpans(rays.objectOutlines, float(y) + kSampleOffsets[sy], spans[size_t(sy)]);
        }
        SplitMix64 rng = SensorNoise::rowGenerator(config.seed, sequence, y);
        const fake_scene::PackedRgb* texels = ex.table;
        const fake_scene::PackedRgb* background = kEnvironment ? ex.cubeTexels->texels() : ex.background.get();
        RayChunk chunks[kSamplesPerAxis];
        for (int x0 = 0; x0 < config.width; x0 += kChunkPixels) {
            for (int sy = 0; sy < kSamplesPerAxis; ++sy) {
                locateRays<kEnvironment>(rays.eye, bases[sy], rays.stepU, float(x0) + kSampleOffsets[0],
                                         1.0f / kSamplesPerAxis, spans[size_t(sy)], chunks[sy]);
            }
            const int x1 = std::min(x0 + kChunkPixels, config.width);
            for (int x = x0; x < x1; ++x) {
                fake_scene::PackedRgb sum = 0;
#pragma GCC unroll 4
                for (int sy = 0; sy < kSamplesPerAxis; ++sy) {
#pragma GCC unroll 4
                    for (int sx = 0; sx < kSamplesPerAxis; ++sx) {
                        const int32_t index = chunks[sy].texelIndex[(x - x0) * kSamplesPerAxis + sx];
                        if (index >= 0) {
                            sum += texels[index];
                        } else if (index <= kFirstBackground) {
                            sum += background[size_t(kFirstBackground - index)];
                        } else {
                            const glm::vec3 d = bases[sy] + (float(x) + kSampleOffsets[sx]) * rays.stepU;
                            sum += index == kShadeRay ? shade<kEnvironment>(ex, rays.eye, d.x, d.y, d.z)
                                                      : shadeNearObjects<kEnvironment>(ex, rays.eye, d);
                        }
                    }
                }
                float nr = 0.0f;
                float ng = 0.0f;
                float nb = 0.0f;
                noise.sampleRgb(rng, nr, ng, nb);
                const uint8_t r = toByte(float(sum & fake_scene::kLaneMask) * scale + nr);
                const uint8_t g = toByte(float((sum >> fake_scene::kLaneBits) & fake_scene::kLaneMask) * scale + ng);
                const uint8_t b = toByte(float(sum >> (2 * fake_scene::kLaneBits)) * scale + nb);
                rgbOut[3 * x] = r;
                rgbOut[3 * x + 1] = g;
                rgbOut[3 * x + 2] = b;
                lumaOut[x] = bt601Luma(r, g, b);
            }
        }
    }
};

FakeCamera::FakeCamera(const CameraConfig& config)
{
    validate(config);
    impl_ = std::make_unique<Impl>(config);
    LUMAR_LOG(Capture, Info) << "fake camera " << config.width << "x" << config.height << " at " << config.fps
                             << " fps, " << config.fakeTags.size() << " tag(s), " << config.fakeObjects.size()
                             << " object(s), "
                             << (config.fakeEnvironment.empty() ? std::string("plain room")
                                                                : config.fakeEnvironment.filename().string())
                             << ", exposure " << config.exposure << ", seed " << config.seed;
}

void FakeCamera::validateScene(const CameraConfig& config)
{
    validate(config);
}

FakeCamera::~FakeCamera() = default;

bool FakeCamera::next(Frame& frame)
{
    render(impl_->nextSequence, frame);
    ++impl_->nextSequence;
    return true;
}

int FakeCamera::width() const
{
    return impl_->config.width;
}

int FakeCamera::height() const
{
    return impl_->config.height;
}

double FakeCamera::fps() const
{
    return impl_->config.fps;
}

const CameraIntrinsics& FakeCamera::intrinsics() const
{
    return impl_->intrinsics;
}

void FakeCamera::setExposure(double exposure)
{
    if (!(exposure > 0.0) || !std::isfinite(exposure)) {
        throw InputError("camera.exposure: must be positive and finite, got " + std::to_string(exposure));
    }
    impl_->requestedExposure.store(exposure);
}

double FakeCamera::exposure() const
{
    return impl_->requestedExposure.load();
}

Pose FakeCamera::cameraFromWorld(uint64_t sequence) const
{
    return impl_->trajectory.cameraFromWorld(double(sequence) / impl_->config.fps);
}

std::vector<TagGroundTruth> FakeCamera::groundTruth(uint64_t sequence) const
{
    const Pose camera = cameraFromWorld(sequence);
    std::vector<TagGroundTruth> truths;
    truths.reserve(impl_->config.fakeTags.size());
    for (const FakeTagConfig& tag : impl_->config.fakeTags) {
        // The marker frame is the world frame moved to the tag's centre.
        const Pose worldFromMarker{glm::dmat3(1.0), glm::dvec3(tag.position, 0.0)};
        truths.push_back({tag.id, tag.size, camera * worldFromMarker});
    }
    return truths;
}

void FakeCamera::render(uint64_t sequence, Frame& frame) const
{
    const Impl& s = *impl_;
    const std::shared_ptr<const Impl::Exposed> exposed = s.current();
    frame.rgb.reshape(s.config.width, s.config.height, 3);
    frame.luma.reshape(s.config.width, s.config.height, 1);
    frame.sequence = sequence;
    frame.timestampNs = int64_t(double(sequence) * 1e9 / s.config.fps + 0.5);

    const Pose cameraPose = cameraFromWorld(sequence);
    const glm::dmat3 worldFromCamera = glm::transpose(cameraPose.R);
    const CameraIntrinsics& k = s.intrinsics;
    Impl::FrameRays rays;
    rays.eye = glm::vec3(-(worldFromCamera * cameraPose.t));
    rays.worldFromCamera = worldFromCamera;
    rays.intrinsics = &k;
    rays.stepU = glm::vec3(worldFromCamera[0] / k.fx);
    rays.objectOutlines = s.objectOutlines(cameraPose);
    if (s.environment) {
        // The texels this frame may read, baked first where no earlier frame needed them.
        const ViewCone view = s.frameView(worldFromCamera);
        exposed->cubeTexels->prepare([&](int tile) { return cubeTileMayBeRead(*s.cube, tile, view, rays.eye); });
    }
    std::array<std::vector<ScreenSpan>, kSamplesPerAxis> spans;
    for (int y = 0; y < s.config.height; ++y) {
        if (s.environment) {
            s.renderRow<true>(*exposed, rays, sequence, y, frame.rgb.row(y), frame.luma.row(y), spans);
        } else {
            s.renderRow<false>(*exposed, rays, sequence, y, frame.rgb.row(y), frame.luma.row(y), spans);
        }
    }
}

} // namespace lumar
