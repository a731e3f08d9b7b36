#include "capture/fake_camera.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>

#include "capture/colour_conversion.h"
#include "capture/fake_scene_shading.h"
#include "capture/fake_trajectory.h"
#include "capture/sensor_noise.h"
#include "capture/table_texture.h"
#include "capture/tag36h11_pattern.h"
#include "core/error.h"
#include "core/log.h"

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

// Where the rays of one chunk of one sub-row hit the table plane.
struct RayChunk {
    int32_t texelIndex[kChunkRays]; // −1: shade the ray in full
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

uint8_t toByte(float v)
{
    // Round half up; the clamp keeps noise from wrapping.
    const int i = int(v + 0.5f);
    return uint8_t(i < 0 ? 0 : (i > 255 ? 255 : i));
}

} // namespace

struct FakeCamera::Impl {
    CameraConfig config;
    CameraIntrinsics intrinsics;
    FakeTrajectory trajectory;
    TableTexture table;
    SensorNoise noise;
    std::vector<TagSurface> tags;
    // The tags' union bounding box: most rays miss every tag after one test.
    float tagsMinX = 0.0f, tagsMaxX = 0.0f, tagsMinY = 0.0f, tagsMaxY = 0.0f;
    // The floor's colour at squared distance (level + 0.5) / kFloorLevelsPerSquareMetre: the
    // floor is smooth, so a table lookup is indistinguishable from shading each ray.
    std::array<fake_scene::PackedRgb, kFloorLevels> floorLevels{};
    uint64_t nextSequence = 0;

    explicit Impl(const CameraConfig& c)
        : config(c), intrinsics(defaultIntrinsics(c.width, c.height)), trajectory(c.fakeTags), table(c.seed),
          noise(c.noiseSigma)
    {
        for (int level = 0; level < kFloorLevels; ++level) {
            const float radiusSquared = (float(level) + 0.5f) / kFloorLevelsPerSquareMetre;
            floorLevels[size_t(level)] = fake_scene::packRgb(fake_scene::floorColour(radiusSquared));
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
    }

    // Locates kChunkRays rays along one sub-row, directions base + (u0 + i·du) · step: the
    // texel index of each ray that lands on plain table, −2 − level for the floor (see
    // floorLevels), or −1 where the ray needs full shading (a tag, a wall). Every loop is
    // branch-free so it vectorizes.
    void locateTableRays(const glm::vec3& eye, const glm::vec3& base, const glm::vec3& step, float u0, float du,
                         RayChunk& chunk) const
    {
        // Rays closer to horizontal than this are left to shade(): clamping dz keeps every
        // value finite, and with the scene bounded (kMaxSceneExtent) small enough for the
        // integer conversions below. Such rays never reach the table or the nearby floor
        // (the camera is at least 0.3 m up), so shade() rarely sees them.
        constexpr float kShallowest = -1e-3f;
        constexpr float kSize = float(TableTexture::kResolution);
        constexpr float kScale = TableTexture::kTexelsPerMetre;
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
            // Past the table's edge: the floor, lit as a function of the squared distance.
            const float tFloor = (fake_scene::kFloorZ - eye.z) / std::min(dz, kShallowest);
            const float gx = eye.x + tFloor * dx;
            const float gy = eye.y + tFloor * dy;
            const float level = (gx * gx + gy * gy) * kFloorLevelsPerSquareMetre;
            const bool onFloor = down & (level < float(kFloorLevels));
            const int floorCode = -2 - int(std::min(level, float(kFloorLevels - 1)));
            chunk.texelIndex[i] = onTable ? index : (onFloor ? floorCode : -1);
            chunk.x[i] = x;
            chunk.y[i] = y;
        }
        for (const TagSurface& tag : tags) {
            // Locals, so the compiler knows the stores below cannot change them.
            const float cx = tag.centreX;
            const float cy = tag.centreY;
            const float half = tag.halfOuter;
            for (int i = 0; i < kChunkRays; ++i) {
                const bool inside = (std::abs(chunk.x[i] - cx) < half) & (std::abs(chunk.y[i] - cy) < half);
                chunk.texelIndex[i] = inside ? -1 : chunk.texelIndex[i];
            }
        }
    }

    // The colour seen along world-space ray direction d from `eye`. Always inlined: it runs
    // for every ray, 3.7 million times per 720p frame.
    [[nodiscard]] [[gnu::always_inline]] inline fake_scene::PackedRgb shade(const glm::vec3& eye, float dx, float dy,
                                                                            float dz) const
    {
        using namespace fake_scene;
        if (dz >= 0.0f) {
            return packRgb(wallColour(dz / std::sqrt(dx * dx + dy * dy + dz * dz)));
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
                    return packGrey(tag.codeValues[size_t(row * kTag36h11TotalCells + col)] * tableLighting(x, y));
                }
            }
        }
        if (std::abs(x) <= kTableHalfSize && std::abs(y) <= kTableHalfSize) {
            return table.at(x, y);
        }
        // Past the table's edge the ray goes on down to the floor, or to a wall far away.
        const float sf = (kFloorZ - eye.z) / dz;
        const float fx = eye.x + sf * dx;
        const float fy = eye.y + sf * dy;
        const float radiusSquared = fx * fx + fy * fy;
        if (radiusSquared >= kRoomRadius * kRoomRadius) {
            return packRgb(wallColour(dz / std::sqrt(dx * dx + dy * dy + dz * dz)));
        }
        return packRgb(floorColour(radiusSquared));
    }

    // One frame's rays: the world direction through pixel (u, v) is
    // rowBase(v) + u · stepU, so a ray costs three multiply-adds and one division.
    struct FrameRays {
        glm::vec3 eye{0.0f};
        glm::vec3 stepU{0.0f};
        glm::dmat3 worldFromCamera{1.0};
        const CameraIntrinsics* intrinsics = nullptr;

        [[nodiscard]] glm::vec3 rowBase(double v) const
        {
            const CameraIntrinsics& k = *intrinsics;
            return glm::vec3(worldFromCamera[1] * ((v - k.cy) / k.fy) + worldFromCamera[2] -
                             worldFromCamera[0] * (k.cx / k.fx));
        }
    };

    // Renders image row y: kSamplesPerAxis² rays per pixel, box-filtered, plus noise.
    void renderRow(const FrameRays& rays, uint64_t sequence, int y, uint8_t* rgbOut, uint8_t* lumaOut) const
    {
        constexpr int samples = kSamplesPerAxis * kSamplesPerAxis;
        constexpr float scale = 1.0f / samples;
        glm::vec3 bases[kSamplesPerAxis];
        for (int sy = 0; sy < kSamplesPerAxis; ++sy) {
            bases[sy] = rays.rowBase(double(y) + double(kSampleOffsets[sy]));
        }
        SplitMix64 rng = SensorNoise::rowGenerator(config.seed, sequence, y);
        const fake_scene::PackedRgb* texels = table.texels();
        RayChunk chunks[kSamplesPerAxis];
        for (int x0 = 0; x0 < config.width; x0 += kChunkPixels) {
            for (int sy = 0; sy < kSamplesPerAxis; ++sy) {
                locateTableRays(rays.eye, bases[sy], rays.stepU, float(x0) + kSampleOffsets[0], 1.0f / kSamplesPerAxis,
                                chunks[sy]);
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
                        } else if (index <= -2) {
                            sum += floorLevels[size_t(-2 - index)];
                        } else {
                            const glm::vec3 d = bases[sy] + (float(x) + kSampleOffsets[sx]) * rays.stepU;
                            sum += shade(rays.eye, d.x, d.y, d.z);
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
                             << " fps, " << config.fakeTags.size() << " tag(s), seed " << config.seed;
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
    for (int y = 0; y < s.config.height; ++y) {
        s.renderRow(rays, sequence, y, frame.rgb.row(y), frame.luma.row(y));
    }
}

} // namespace lumar
