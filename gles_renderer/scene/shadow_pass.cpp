#include "gles_renderer/scene/shadow_pass.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "core/error.h"
#include "gles_renderer/gl/fullscreen_triangle.h"
#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/gl/gpu_texture.h"
#include "gles_renderer/gl/shader_program.h"
#include "gles_renderer/scene/mesh_features.h"
#include "gles_renderer/scene/mesh_pass.h"
#include "gles_renderer/scene/model_pose_upload.h"
#include "gles_renderer/scene/stage_timer.h"
#include "gles_renderer/scene/tile_cover.h"

namespace lumar {
namespace {

// The ellipsoid of the same volume as its bounding box: the inscribed one grown by (6/pi)^(1/3).
constexpr double kEqualVolumeScale = 1.2407009817988;
// A flat model (a quad) still occludes: no semi-axis below this share of the longest.
constexpr double kMinAxisShare = 0.05;
// The casters' depth is pushed away from the light by glPolygonOffset(factor, units): the
// slope term keeps surfaces seen at a grazing angle from shadowing themselves.
constexpr GLfloat kOffsetFactor = 2.0f;
constexpr GLfloat kOffsetUnits = 4.0f;
// Texels kept free around the casters beyond the PCF kernel's radius.
constexpr double kMarginTexels = 2.0;
// phantom_receiver.frag's kOcclusionReach: occluders darken within this many radii.
constexpr double kOcclusionReach = 2.0;
// shadow.glsl's normal offset: the lookups move a point this many texels along its normal
// (shadowParams.z, in metres, for every shader that looks the map up).
constexpr double kNormalOffsetTexels = 1.5;
// The tiles the darkening is culled to (frame pixels; ShadowPass::darkenedRects), and the
// band around each place a shadow or a contact can fall that they include (buffer texels: the
// apply pass upsamples each pixel from the texels around it).
constexpr int kCoverTilePixels = 32;
constexpr double kCoverMarginTexels = 1.5;
// The darkening's tiles are shaded with the union of the labels (what reaches them) of their
// block of kLabelBlockTiles x kLabelBlockTiles tiles: each label its own rectangles and draws,
// and more of them cost more than the terms they save. car.toml, quarter resolution, medians
// of 3 interleaved, the darkening's rasteriser CPU ms: one label 6.3, by tile 5.7 (86 rects),
// blocks of 2 5.3 (59), of 4 5.3 (39), of 8 6.1 (34).
constexpr int kLabelBlockTiles = 2;

bool isCaster(const DrawItem& item)
{
    return !item.phantom;
}

// Sets the winding of front faces for `cameraFromMesh` (see MeshPass); false when the
// transform flattens the mesh to nothing.
bool setFrontFaceFor(const glm::dmat4& cameraFromMesh)
{
    const double determinant = glm::determinant(glm::dmat3(cameraFromMesh));
    if (determinant == 0.0 || !std::isfinite(determinant))
        return false;
    glFrontFace(determinant > 0.0 ? GL_CW : GL_CCW);
    return true;
}

bool finite(const glm::dvec3& v)
{
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The box round `corners` mapped by `transform`, the corners that map to a finite point alone
// (empty, low above high, where none does).
std::pair<glm::dvec3, glm::dvec3> extentOf(const std::array<glm::dvec3, 8>& corners, const glm::dmat4& transform)
{
    constexpr double inf = std::numeric_limits<double>::infinity();
    glm::dvec3 low(inf), high(-inf);
    for (const glm::dvec3& corner : corners) {
        const glm::dvec3 p(transform * glm::dvec4(corner, 1.0));
        if (!finite(p))
            continue;
        low = glm::min(low, p);
        high = glm::max(high, p);
    }
    return {low, high};
}

// The part of the convex polygon `polygon` (a face's (u, v) coordinates) inside the face's
// rectangle [low, high] (Sutherland-Hodgman, one side at a time).
std::vector<glm::dvec2> clipToFace(std::vector<glm::dvec2> polygon, const glm::dvec2& low, const glm::dvec2& high)
{
    for (int side = 0; side < 4 && !polygon.empty(); ++side) {
        const int axis = side / 2;
        const double bound = side % 2 ? high[axis] : low[axis];
        const auto inside = [&](const glm::dvec2& p) { return side % 2 ? p[axis] <= bound : p[axis] >= bound; };
        std::vector<glm::dvec2> kept;
        for (size_t i = 0; i < polygon.size(); ++i) {
            const glm::dvec2& a = polygon[i];
            const glm::dvec2& b = polygon[(i + 1) % polygon.size()];
            if (inside(a))
                kept.push_back(a);
            if (inside(a) != inside(b))
                kept.push_back(a + (b - a) * ((bound - a[axis]) / (b[axis] - a[axis])));
        }
        polygon = std::move(kept);
    }
    return polygon;
}

// Marks the tiles of `cover` that the convex polygon `uv` of the plane x[axis] = plane of a
// model frame (`cameraFromModel`) covers in the window (a projection keeps a convex polygon in
// front of the camera convex); every tile where the polygon reaches behind the camera.
void coverFacePolygon(const glm::dmat4& cameraFromModel, int axis, double plane, std::span<const glm::dvec2> uv,
                      const glm::dmat4& clipFromCamera, int width, int height, double margin, uint32_t label,
                      TileCover& cover)
{
    if (uv.empty())
        return;
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const glm::dmat4 clipFromModel = clipFromCamera * cameraFromModel;
    std::vector<glm::dvec2> window;
    window.reserve(uv.size());
    for (const glm::dvec2& p : uv) {
        glm::dvec4 local(0.0, 0.0, 0.0, 1.0);
        local[axis] = plane;
        local[u] = p.x;
        local[v] = p.y;
        const glm::dvec4 clip = clipFromModel * local;
        if (!(clip.w > 1e-6)) {
            cover.addAll(label);
            return;
        }
        window.emplace_back((clip.x / clip.w * 0.5 + 0.5) * width, (clip.y / clip.w * 0.5 + 0.5) * height);
    }
    cover.addConvex(window, margin, label);
}

// The frame's pixels (a width x height viewport) where the phantoms' depth is read: the
// darkening's rectangles `darkened` (in texels of `scale` x `scale` pixels) and the window
// boxes of the virtual objects (the items that are not phantoms) in front of the camera; the
// whole viewport where a box reaches behind it. Disjoint rectangles of tiles. With
// `outsideDarkened`, the tiles of `darkened` left out (the apply pass writes the depth there).
// The darkening's tiles are the same tiles: kCoverTilePixels / scale texels each.
std::vector<PixelRect> depthRects(const glm::dmat4& clipFromCamera, const std::vector<GpuModel>& models,
                                  std::span<const DrawItem> items, std::span<const PixelRect> darkened, int scale,
                                  int width, int height, bool outsideDarkened)
{
    TileCover cover(width, height, kCoverTilePixels);
    TileCover darkenedCover(width, height, kCoverTilePixels);
    const auto addBox = [](TileCover& to, double x0, double y0, double x1, double y1) {
        const std::array<glm::dvec2, 4> corners{glm::dvec2(x0, y0), glm::dvec2(x1, y0), glm::dvec2(x1, y1),
                                                glm::dvec2(x0, y1)};
        to.addConvex(corners, 0.0);
    };
    // Half a pixel inside: a rectangle's far edges lie on the next tiles' near edges.
    for (const PixelRect& rect : darkened)
        addBox(outsideDarkened ? darkenedCover : cover, rect.x0 * scale + 0.5, rect.y0 * scale + 0.5,
               rect.x1 * scale - 0.5, rect.y1 * scale - 0.5);
    for (const DrawItem& item : items) {
        if (item.phantom)
            continue;
        glm::dvec2 low(std::numeric_limits<double>::infinity()), high(-std::numeric_limits<double>::infinity());
        bool behind = false;
        for (const glm::dvec3& corner : boundsCorners(models[size_t(item.model)], item.cameraFromModel)) {
            const glm::dvec4 clip = clipFromCamera * glm::dvec4(corner, 1.0);
            behind = behind || !(clip.w > 1e-6);
            const glm::dvec2 window((clip.x / clip.w * 0.5 + 0.5) * width, (clip.y / clip.w * 0.5 + 0.5) * height);
            low = glm::min(low, window);
            high = glm::max(high, window);
        }
        if (behind) {
            cover.addAll();
            break;
        }
        // A pixel of margin: rasterised pixels reach half a pixel past the projected outline.
        addBox(cover, low.x - 1.0, low.y - 1.0, high.x + 1.0, high.y + 1.0);
    }
    cover.subtract(darkenedCover);
    return cover.rects();
}

} // namespace

ShadowPass::ShadowPass(const ShadowOptions& options)
    : options_(options), size_(options.enabled ? options.mapSize : 1), frameUniforms_(GlBuffer::create())
{
    if (options_.enabled) {
        GLint maxSize = 0;
        glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSize);
        if (size_ < 1 || size_ > maxSize)
            throw InputError("shadow map size " + std::to_string(size_) + " is outside 1.." + std::to_string(maxSize) +
                             " (GL_MAX_TEXTURE_SIZE)");
        if (options_.receiverScale != 1 && options_.receiverScale != 2 && options_.receiverScale != 4)
            throw InputError("the shadows' receiver scale must be 1, 2 or 4, got " +
                             std::to_string(options_.receiverScale));
        if (!(options_.softness >= 0.0f && options_.softness <= 64.0f))
            throw InputError("shadow softness must be in [0, 64] texels, got " + std::to_string(options_.softness));
    }
    // With a stencil where shadows are on: the dither pattern of glass casters (drawCasters).
    map_ = makeDepthCompareTexture(size_, size_, options_.enabled);
    glBindTexture(GL_TEXTURE_2D, 0);
    checkGlError("creating the shadow map");
    if (!options_.enabled)
        return;

    framebuffer_ = GlFramebuffer::create();
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.name());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_TEXTURE_2D, map_.name(), 0);
    const GLenum none = GL_NONE;
    glDrawBuffers(1, &none);
    glReadBuffer(GL_NONE);
    checkFramebufferComplete("shadow map");
    glBindFramebuffer(GL_FRAMEBUFFER, 0);

    glBindBuffer(GL_UNIFORM_BUFFER, frameUniforms_.name());
    glBufferData(GL_UNIFORM_BUFFER, sizeof(FrameUniforms), nullptr, GL_DYNAMIC_DRAW);
    checkGlError("creating the shadow pass");
}

// Linked at first use: a scene without casters or phantoms pays nothing, and the daemon's
// first frame (its READY) does not wait for two more programs to compile.
void ShadowPass::linkDepthProgram()
{
    if (depthProgram_)
        return;
    depthProgram_ = linkProgram(kDepthOnlyProgram);
    depthCameraFromMeshLocation_ = uniformLocation(depthProgram_, "uCameraFromMesh");
    bindUniformBlock(depthProgram_, "Frame", kFrameBlockBinding);
    // The map's stencil: each texel its threshold in the 4 x 4 Bayer matrix, written once
    // (every texel by exactly one of the 16 draws; the casters' pass clears depth alone).
    const GlProgram dither = linkProgram(kShadowDitherStencilProgram);
    const GLint level = uniformLocation(dither, "uLevel");
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.name());
    glViewport(0, 0, size_, size_);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glEnable(GL_STENCIL_TEST);
    glStencilMask(0xFF);
    glStencilOp(GL_KEEP, GL_KEEP, GL_REPLACE);
    glUseProgram(dither.name());
    for (GLint threshold = 0; threshold < 16; ++threshold) {
        glUniform1i(level, threshold);
        glStencilFunc(GL_ALWAYS, threshold, 0xFF);
        drawFullscreenTriangle();
    }
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    glDisable(GL_STENCIL_TEST);
    checkGlError("writing the shadow map's dither pattern");
}

void ShadowPass::linkReceiverPrograms()
{
    if (darkeningPrograms_[1].program)
        return;
    receiverDepthProgram_ = linkProgram(kPhantomReceiverDepthProgram);
    receiverDepthCameraFromMeshLocation_ = uniformLocation(receiverDepthProgram_, "uCameraFromMesh");
    // The normals feed nothing here: the linker may drop the uniform (-1: glUniform ignores it).
    receiverDepthNormalFromMeshLocation_ = glGetUniformLocation(receiverDepthProgram_.name(), "uNormalFromMesh");
    bindUniformBlock(receiverDepthProgram_, "Frame", kFrameBlockBinding);
    receiverDistanceProgram_ = linkProgram(kPhantomReceiverDistanceProgram);
    receiverDistanceCameraFromMeshLocation_ = uniformLocation(receiverDistanceProgram_, "uCameraFromMesh");
    receiverDistanceNormalFromMeshLocation_ = glGetUniformLocation(receiverDistanceProgram_.name(), "uNormalFromMesh");
    bindUniformBlock(receiverDistanceProgram_, "Frame", kFrameBlockBinding);
    for (int shadow = 0; shadow < 2; ++shadow) {
        DarkeningProgram& darkening = darkeningPrograms_[shadow];
        darkening.program = linkProgram(kPhantomReceiverProgram,
                                        shadow ? "#define RECEIVER_SHADOW 1\n" : "#define RECEIVER_SHADOW 0\n");
        darkening.cameraFromMesh = uniformLocation(darkening.program, "uCameraFromMesh");
        darkening.normalFromMesh = uniformLocation(darkening.program, "uNormalFromMesh");
        darkening.occluderCount = uniformLocation(darkening.program, "uOccluderCount");
        darkening.unitFromCamera = uniformLocation(darkening.program, "uUnitFromCamera");
        darkening.unitNormalFromCamera = uniformLocation(darkening.program, "uUnitNormalFromCamera");
        darkening.occluderReach = uniformLocation(darkening.program, "uOccluderReach");
        bindUniformBlock(darkening.program, "Frame", kFrameBlockBinding);
        glUseProgram(darkening.program.name());
        glUniform1i(uniformLocation(darkening.program, "uDiffuseMap"), GLint(MeshPass::kDiffuseMapUnit));
        if (shadow)
            glUniform1i(uniformLocation(darkening.program, "uShadowMap"), GLint(MeshPass::kShadowMapUnit));
    }
}

void ShadowPass::linkApplyPrograms()
{
    if (applyPrograms_[2].program)
        return;
    const char* const defines[3] = {"#define APPLY_WRITES_DEPTH 0\n", "#define APPLY_WRITES_DEPTH 1\n",
                                    "#define APPLY_WRITES_DEPTH 1\n#define APPLY_ONE_SURFACE 1\n"};
    for (int variant = 0; variant < 3; ++variant) {
        ApplyProgram& apply = applyPrograms_[variant];
        apply.program = linkProgram(kShadowApplyProgram, defines[variant]);
        apply.cameraFromMesh = uniformLocation(apply.program, "uCameraFromMesh");
        apply.normalFromMesh = glGetUniformLocation(apply.program.name(), "uNormalFromMesh");
        apply.texelsPerPixel = uniformLocation(apply.program, "uTexelsPerPixel");
        bindUniformBlock(apply.program, "Frame", kFrameBlockBinding);
        glUseProgram(apply.program.name());
        glUniform1i(uniformLocation(apply.program, "uRatio"), GLint(kRatioUnit));
    }
}

bool ShadowPass::applyCanWriteDepth(const std::vector<GpuModel>& models, std::span<const DrawItem> items)
{
    const DrawItem* phantom = nullptr;
    for (const DrawItem& item : items)
        if (item.phantom && !item.receiverOnly) {
            if (phantom)
                return false;
            phantom = &item;
        }
    if (!phantom)
        return false;
    const GpuModel& model = models[size_t(phantom->model)];
    if (model.pose)
        return false; // its vertices may change with every pose
    for (const GpuPrimitive& primitive : model.primitives)
        if (model.materials[primitive.material].doubleSided)
            return false;
    return model.convex;
}

bool ShadowPass::applyOneSurface(const std::vector<GpuModel>& models, std::span<const DrawItem> items)
{
    return applyCanWriteDepth(models, items) &&
           std::none_of(items.begin(), items.end(), [](const DrawItem& i) { return i.phantom && i.receiverOnly; });
}

void ShadowPass::prepareRatioBuffer(int frameWidth, int frameHeight)
{
    if (ratio_.framebuffer && ratio_.frameWidth == frameWidth && ratio_.frameHeight == frameHeight)
        return;
    // The buffer's texels must tile the frame exactly (its viewport maps the same clip space):
    // a frame whose size the scale does not divide is shaded at the next finer one that does.
    int scale = options_.receiverScale;
    while (scale > 1 && (frameWidth % scale != 0 || frameHeight % scale != 0))
        scale /= 2;
    RatioBuffer buffer;
    buffer.frameWidth = frameWidth;
    buffer.frameHeight = frameHeight;
    buffer.scale = scale;
    const int width = frameWidth / scale, height = frameHeight / scale;
    // RatioBuffer's channels. GL_LINEAR for APPLY_ONE_SURFACE's one filtered lookup (the
    // general filter reads texel by texel: texelFetch ignores it).
    buffer.colour = makeRenderTexture(GL_RGBA8, width, height, GL_LINEAR);
    glBindTexture(GL_TEXTURE_2D, 0);
    buffer.depth = GlRenderbuffer::create();
    glBindRenderbuffer(GL_RENDERBUFFER, buffer.depth.name());
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    buffer.framebuffer = GlFramebuffer::create();
    glBindFramebuffer(GL_FRAMEBUFFER, buffer.framebuffer.name());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, buffer.colour.name(), 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, buffer.depth.name());
    checkFramebufferComplete("shadow darkening buffer");
    checkGlError("creating the shadow darkening buffer");
    ratio_ = std::move(buffer);
}

void ShadowPass::setLight(const DirectionalLight& light)
{
    const double length = glm::length(light.direction);
    if (!(length > 0.0) || !std::isfinite(length))
        throw InputError("the light's direction must be finite and non-zero");
    for (int c = 0; c < 3; ++c)
        if (!(light.color[c] >= 0.0f) || !std::isfinite(light.color[c]))
            throw InputError("the light's colour must be finite and >= 0");
    if (!(light.intensity >= 0.0f) || !std::isfinite(light.intensity))
        throw InputError("the light's intensity must be finite and >= 0");
    light_ = light;
    light_.direction /= length;
    lightSet_ = light.intensity > 0.0f && glm::length(light.color) > 0.0f;
}

void ShadowPass::render(const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                        const glm::dmat3& environmentFromCamera, RenderCpuClock* profile, RenderStats& stats)
{
    mapValid_ = false;
    if (!enabled() || !lightSet_)
        return;
    StageTimer timer(profile, profile != nullptr);
    lightDirection_ = glm::transpose(environmentFromCamera) * light_.direction;
    // The stable frame's origin: the first caster's (a finite one).
    const auto first = std::find_if(items.begin(), items.end(), [](const DrawItem& item) {
        return isCaster(item) && finite(glm::dvec3(item.cameraFromModel[3]));
    });
    if (first != items.end()) {
        glm::dmat4 stableFromCamera(environmentFromCamera);
        stableFromCamera[3] = glm::dvec4(-(environmentFromCamera * glm::dvec3(first->cameraFromModel[3])), 1.0);
        if (fitLightCamera(models, items, stableFromCamera, freshFit_, freshCasters_)) {
            switch (compareMap(freshFit_, freshCasters_, parts_)) {
            case Redraw::All:
                std::swap(fit_, freshFit_);
                std::swap(drawnCasters_, freshCasters_);
                drawnLightDirection_ = light_.direction;
                linkDepthProgram();
                drawCasters(models, items, nullptr);
                drawn_ = true;
                stats.shadowMapDrawn = 1.0;
                break;
            case Redraw::Part:
                // The animated casters' keys and prisms are this frame's; the others' and the
                // fit stay (equal within compareMap's tolerance).
                for (size_t i = 0; i < freshCasters_.size(); ++i)
                    if (freshCasters_[i].poseGeneration != drawnCasters_[i].poseGeneration)
                        drawnCasters_[i] = freshCasters_[i];
                std::swap(fit_.prisms, freshFit_.prisms);
                for (const PixelRect& part : parts_) {
                    drawCasters(models, items, &part);
                    stats.shadowMapDrawn += part.area() / (double(size_) * size_);
                }
                break;
            case Redraw::None:
                break;
            }
            // The map as drawn (this frame or before), seen from this frame's camera.
            lightClipFromCamera_ = fit_.lightClipFromStable * stableFromCamera;
            lightViewFromCamera_ = fit_.lightViewFromStable * stableFromCamera;
            mapValid_ = true;
        }
    }
    if (profile)
        timer.split(stats.shadows);
}

ShadowPass::Redraw ShadowPass::compareMap(const LightFit& fit, const std::vector<CasterKey>& casters,
                                          std::vector<PixelRect>& parts) const
{
    parts.clear();
    if (!drawn_ || light_.direction != drawnLightDirection_ || casters.size() != drawnCasters_.size())
        return Redraw::All;
    // Floating-point noise of poses composed from one marker and the environment's rotation
    // from the same marker: far below a texel (a map of 4096 over 1 cm has 2.4 um texels).
    constexpr double kMetres = 1e-7;
    constexpr double kLinear = 1e-7;
    if (glm::length(fit.centre - fit_.centre) > kMetres || std::abs(fit.side - fit_.side) > kMetres ||
        std::abs(fit.nearZ - fit_.nearZ) > kMetres || std::abs(fit.farZ - fit_.farZ) > kMetres)
        return Redraw::All;
    bool posed = false;
    const auto add = [&parts](PixelRect part) {
        if (part.empty())
            return;
        // Merged with every part it overlaps, until it overlaps none: the parts stay disjoint
        // (each is cleared and drawn whole), and a texel is drawn once.
        for (size_t k = 0; k < parts.size();) {
            if (parts[k].overlaps(part)) {
                part = bounding(part, parts[k]);
                parts.erase(parts.begin() + std::ptrdiff_t(k));
                k = 0;
            } else {
                ++k;
            }
        }
        parts.push_back(part);
    };
    for (size_t i = 0; i < casters.size(); ++i) {
        const CasterKey& a = drawnCasters_[i];
        const CasterKey& b = casters[i];
        if (a.model != b.model)
            return Redraw::All;
        for (int c = 0; c < 3; ++c)
            if (glm::length(glm::dvec3(a.stableFromModel[c] - b.stableFromModel[c])) >
                kLinear * glm::length(glm::dvec3(a.stableFromModel[c])))
                return Redraw::All;
        if (glm::length(glm::dvec3(a.stableFromModel[3] - b.stableFromModel[3])) > kMetres)
            return Redraw::All;
        if (a.poseGeneration == b.poseGeneration)
            continue;
        // Posed where it stands (an animation): its depth changes where it was and where it is;
        // posed by its nodes alone, only where the primitives whose nodes moved were and are.
        posed = true;
        if (!a.primitivePoses.empty() && a.primitivePoses.size() == b.primitivePoses.size()) {
            for (size_t p = 0; p < a.primitivePoses.size(); ++p)
                if (a.primitivePoses[p] != b.primitivePoses[p])
                    add(bounding(texelsOf(a.primitiveBoxes[p].first, a.primitiveBoxes[p].second),
                                 texelsOf(b.primitiveBoxes[p].first, b.primitiveBoxes[p].second)));
        } else {
            add(bounding(texelsOf(a.low, a.high), texelsOf(b.low, b.high)));
        }
    }
    if (!posed)
        return Redraw::None;
    // Most of the map: drawn whole (no scissor, one clear).
    constexpr double kWholeShare = 0.5;
    double area = 0.0;
    for (const PixelRect& part : parts)
        area += part.area();
    if (area > kWholeShare * size_ * size_)
        return Redraw::All;
    return Redraw::Part;
}

PixelRect ShadowPass::texelsOf(const glm::dvec2& low, const glm::dvec2& high) const
{
    if (!(low.x <= high.x && low.y <= high.y))
        return {};
    // The stand-ins drawn stray up to a texel from the model's box (proxyLevelFor), and a
    // triangle covers the texels whose centres it contains.
    constexpr double kMarginTexels = 2.0;
    const auto texel = [&](double v, double centre) { return ((v - centre) / fit_.side + 0.5) * size_; };
    const auto clamp = [&](double t) { return int(std::clamp(t, 0.0, double(size_))); };
    return {clamp(std::floor(texel(low.x, fit_.centre.x) - kMarginTexels)),
            clamp(std::floor(texel(low.y, fit_.centre.y) - kMarginTexels)),
            clamp(std::ceil(texel(high.x, fit_.centre.x) + kMarginTexels)),
            clamp(std::ceil(texel(high.y, fit_.centre.y) + kMarginTexels))};
}

void ShadowPass::describePrimitives(const GpuModel& model, const glm::dmat4& lightViewFromModel, CasterKey& key)
{
    size_t sources = 0;
    for (const GpuPrimitive& primitive : model.primitives)
        sources = std::max(sources, primitive.source + 1);
    constexpr double inf = std::numeric_limits<double>::infinity();
    key.primitivePoses.assign(sources, glm::dmat4(1.0));
    key.primitiveBoxes.assign(sources, {glm::dvec2(inf), glm::dvec2(-inf)});
    for (const GpuPrimitive& primitive : model.primitives) {
        key.primitivePoses[primitive.source] = primitive.modelFromMesh;
        const auto [low, high] =
            extentOf(boxCorners(primitive.boundsMin, primitive.boundsMax, primitive.modelFromMesh), lightViewFromModel);
        key.primitiveBoxes[primitive.source] = {glm::dvec2(low), glm::dvec2(high)};
    }
}

bool ShadowPass::fitLightCamera(const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                                const glm::dmat4& stableFromCamera, LightFit& fit,
                                std::vector<CasterKey>& casters) const
{
    // The light camera's axes are chosen in the environment frame (fixed to the world), so the
    // map's texel grid does not turn with the camera.
    const glm::dvec3 forward = -light_.direction; // the light travels along it
    const glm::dvec3 helper = std::abs(forward.y) < 0.9 ? glm::dvec3(0, 1, 0) : glm::dvec3(1, 0, 0);
    const glm::dvec3 right = glm::normalize(glm::cross(helper, forward));
    const glm::dvec3 up = glm::cross(forward, right);
    glm::dmat4 lightViewFromStable(1.0);
    for (int c = 0; c < 3; ++c) {
        lightViewFromStable[c][0] = right[c];
        lightViewFromStable[c][1] = up[c];
        lightViewFromStable[c][2] = forward[c];
    }
    const glm::dmat4 lightViewFromCamera = lightViewFromStable * stableFromCamera;

    constexpr double inf = std::numeric_limits<double>::infinity();
    glm::dvec3 low(inf), high(-inf);
    double receiversFar = -inf;
    fit.prisms.clear();
    casters.clear();
    for (const DrawItem& item : items) {
        const auto [itemLow, itemHigh] =
            extentOf(boundsCorners(models[size_t(item.model)], item.cameraFromModel), lightViewFromCamera);
        if (isCaster(item)) {
            const GpuModel& model = models[size_t(item.model)];
            CasterKey& key = casters.emplace_back();
            key.model = item.model;
            key.poseGeneration = model.poseGeneration;
            key.stableFromModel = stableFromCamera * item.cameraFromModel;
            if (itemLow.x <= itemHigh.x) {
                key.low = glm::dvec2(itemLow);
                key.high = glm::dvec2(itemHigh);
            }
            // Posed by its nodes alone (nothing skinned or morphed): described by primitive.
            if (model.pose && !model.pose->poser.rig().deforms())
                describePrimitives(model, lightViewFromCamera * item.cameraFromModel, key);
        }
        if (!(itemLow.x <= itemHigh.x))
            continue;
        if (isCaster(item)) {
            low = glm::min(low, itemLow);
            high = glm::max(high, itemHigh);
            fit.prisms.emplace_back(itemLow, itemHigh);
        } else {
            receiversFar = std::max(receiversFar, itemHigh.z);
        }
    }
    if (!(low.x <= high.x))
        return false; // no caster
    // Laterally the map covers the casters alone (plus the kernel's reach): a receiver point
    // outside their footprint seen from the light has no caster between it and the light.
    // In depth it reaches the receivers behind them, whose distance the lookups compare.
    const double extent = std::max({high.x - low.x, high.y - low.y, 1e-4});
    const double margin = std::min(double(options_.softness) + kMarginTexels, 0.25 * size_);
    fit.side = extent * size_ / (size_ - 2.0 * margin);
    fit.texelMetres = fit.side / size_;
    fit.nearZ = low.z - 2.0 * fit.texelMetres;
    fit.farZ = std::max(high.z, receiversFar) + 2.0 * fit.texelMetres;
    fit.centre = 0.5 * (glm::dvec2(low) + glm::dvec2(high));
    // Half a texel of depth, on top of the pass's polygon offset and the lookups' normal offset.
    fit.depthBias = 0.5 * fit.texelMetres / (fit.farZ - fit.nearZ);

    const double side = fit.side, nearZ = fit.nearZ, farZ = fit.farZ;
    glm::dmat4 clipFromLightView(1.0);
    clipFromLightView[0][0] = 2.0 / side;
    clipFromLightView[1][1] = 2.0 / side;
    clipFromLightView[2][2] = 2.0 / (farZ - nearZ);
    clipFromLightView[3] =
        glm::dvec4(-2.0 * fit.centre.x / side, -2.0 * fit.centre.y / side, -2.0 * nearZ / (farZ - nearZ) - 1.0, 1.0);
    fit.lightClipFromStable = clipFromLightView * lightViewFromStable;
    fit.lightViewFromStable = lightViewFromStable;
    // The kernel reaches (softness + 1) texels beyond a caster's outline, from a point the
    // lookups move by up to kNormalOffsetTexels (shadow.glsl's normal offset).
    const double reach = (options_.softness + 1.0 + kNormalOffsetTexels) * fit.texelMetres;
    for (auto& [prismLow, prismHigh] : fit.prisms) {
        prismLow = glm::dvec3(glm::dvec2(prismLow) - reach, nearZ);
        prismHigh = glm::dvec3(glm::dvec2(prismHigh) + reach, farZ);
    }
    return true;
}

void ShadowPass::drawCasters(const std::vector<GpuModel>& models, std::span<const DrawItem> items,
                             const PixelRect* part) const
{
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_.name());
    glViewport(0, 0, size_, size_);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE); // both sides cast: open meshes and double-sided materials too
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    // A part: its texels cleared (the depth alone: the stencil keeps the dither) and drawn
    // again by every caster that reaches into them, with the matrices the rest was drawn with.
    if (part) {
        glEnable(GL_SCISSOR_TEST);
        glScissor(part->x0, part->y0, part->x1 - part->x0, part->y1 - part->y0);
    } else if (!partClearCompiled_) {
        // A part is cleared through the scissor, which Mesa draws as a quad with a shader of
        // its own: cleared once with the first whole map (a texel, cleared again below), that
        // shader is compiled with the first frame's, not at the first frame that redraws a
        // part, when the compiler's code (libLLVM on llvmpipe, ~30 MB) would come back into a
        // full resident set (issue 18, car.toml with bloom, live: peak 132.8-135.8 -> 127.0-127.2
        // MiB; cleared when the pass is made, the compile peaked with the renderer's, 136 MiB).
        glEnable(GL_SCISSOR_TEST);
        glScissor(0, 0, 1, 1);
        glClear(GL_DEPTH_BUFFER_BIT);
        glDisable(GL_SCISSOR_TEST);
        partClearCompiled_ = true;
    }
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(kOffsetFactor, kOffsetUnits);

    FrameUniforms lightFrame;
    lightFrame.clipFromCamera = glm::mat4(fit_.lightClipFromStable); // the casters in the stable frame
    glBindBuffer(GL_UNIFORM_BUFFER, frameUniforms_.name());
    glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof(FrameUniforms), &lightFrame);
    glBindBufferBase(GL_UNIFORM_BUFFER, kFrameBlockBinding, frameUniforms_.name());
    // What primitives without vertex colours or a second uv set read in the cut-out program
    // (their attribute arrays stay disabled), as in MeshPass.
    glVertexAttrib4f(4, 1.0f, 1.0f, 1.0f, 1.0f);
    glVertexAttrib4f(5, 0.0f, 0.0f, 0.0f, 1.0f);
    // Opaque casters first, all with the plain program: it discards nothing, so llvmpipe tests
    // and writes depth before (instead of) shading, and one glUseProgram serves them all. Then
    // glass with the same program through the stencil's dither (below), then the cut-out ones
    // (MASK, BLEND), whose discard leaves the depth write until after their shader: drawn last,
    // their fragments behind an opaque caster fail the depth test before it runs, and the
    // program changes once per kind rather than once per primitive. car.toml's shadows stage,
    // CPU ms a frame, medians of 3 interleaved runs, load 18: every translucent caster through
    // the cut-out shader in draw order 13.0, after the opaque ones 12.1, glass by the stencil
    // 9.8 (another run: the glass drawn as opaque casters 8.0, left out 7.7).
    struct Cutout {
        const GpuPrimitive* primitive;
        const GpuMaterial* material;
        glm::mat4 cameraFromMesh;
    };
    std::vector<Cutout> cutouts, glass;
    glUseProgram(depthProgram_.name());
    size_t caster = 0; // index into drawnCasters_
    for (const DrawItem& item : items) {
        if (!isCaster(item))
            continue;
        const CasterKey& key = drawnCasters_[caster++];
        if (part && !texelsOf(key.low, key.high).overlaps(*part))
            continue;
        const GpuModel& model = models[size_t(item.model)];
        // The simplified stand-in whose error stays within a texel of the map.
        const glm::dvec3 extent = glm::dvec3(model.boundsMax) - glm::dvec3(model.boundsMin);
        const glm::dmat3 linear(key.stableFromModel);
        const double scale = std::max({glm::length(linear[0]), glm::length(linear[1]), glm::length(linear[2])});
        const double texels = scale * std::max({extent.x, extent.y, extent.z}) / fit_.texelMetres;
        for (const GpuPrimitive& primitive : proxyLevelFor(model, texels).primitives) {
            // A part: only the primitives that reach into it, where their boxes are known.
            if (part && primitive.source < key.primitiveBoxes.size() &&
                !texelsOf(key.primitiveBoxes[primitive.source].first, key.primitiveBoxes[primitive.source].second)
                     .overlaps(*part))
                continue;
            // The light's "camera" frame here is the stable frame (fit_.lightClipFromStable).
            const glm::mat4 cameraFromMesh(key.stableFromModel * primitive.modelFromMesh);
            const GpuMaterial& material = model.materials[primitive.material];
            // Glass (not MASK or BLEND): one opacity over the whole surface, kept through the
            // stencil's dither with this program.
            if (material.alphaMode == GltfAlphaMode::Opaque && material.transmissive) {
                glass.push_back({&primitive, &material, cameraFromMesh});
                continue;
            }
            // MASK cut as mesh.frag cuts it; BLEND lets part of the light through.
            if (material.alphaMode == GltfAlphaMode::Mask || isTransparent(material)) {
                cutouts.push_back({&primitive, &material, cameraFromMesh});
                continue;
            }
            glUniformMatrix4fv(depthCameraFromMeshLocation_, 1, GL_FALSE, glm::value_ptr(cameraFromMesh));
            glBindVertexArray(primitive.vertexArray.name());
            glDrawElements(GL_TRIANGLES, primitive.indexCount, primitive.indexType, nullptr);
        }
    }
    if (!glass.empty()) {
        // Of each 4 x 4 block, the texels whose Bayer threshold is below round(16 x opacity),
        // as depth_only.frag's dither keeps them, by the stencil test: the plain program
        // discards nothing, so its depth test stays early.
        glEnable(GL_STENCIL_TEST);
        glStencilMask(0);
        for (const Cutout& c : glass) {
            const GLint kept = std::clamp(GLint(std::floor(16.0f * c.material->shadowOpacity + 0.5f)), 0, 16);
            if (kept == 0)
                continue;
            glStencilFunc(GL_GREATER, kept, 0xFF);
            glUniformMatrix4fv(depthCameraFromMeshLocation_, 1, GL_FALSE, glm::value_ptr(c.cameraFromMesh));
            glBindVertexArray(c.primitive->vertexArray.name());
            glDrawElements(GL_TRIANGLES, c.primitive->indexCount, c.primitive->indexType, nullptr);
        }
        glStencilMask(0xFF);
        glDisable(GL_STENCIL_TEST);
    }
    if (!cutouts.empty()) {
        const auto textured = [](const Cutout& c) {
            return (c.material->features & mesh_feature::kBaseColorTexture) != 0;
        };
        std::stable_partition(cutouts.begin(), cutouts.end(), [&](const Cutout& c) { return !textured(c); });
        glActiveTexture(GL_TEXTURE0 + kCutoutTextureUnit);
        const CutoutProgram* bound = nullptr;
        for (const Cutout& c : cutouts) {
            const CutoutProgram& program = cutoutProgram(textured(c));
            if (bound != &program) {
                glUseProgram(program.program.name());
                bound = &program;
            }
            glBindBufferBase(GL_UNIFORM_BUFFER, kMaterialBlockBinding, c.material->uniforms.name());
            if (textured(c))
                glBindTexture(GL_TEXTURE_2D, c.material->baseColor);
            glUniformMatrix4fv(program.cameraFromMesh, 1, GL_FALSE, glm::value_ptr(c.cameraFromMesh));
            glBindVertexArray(c.primitive->vertexArray.name());
            glDrawElements(GL_TRIANGLES, c.primitive->indexCount, c.primitive->indexType, nullptr);
        }
    }
    glBindVertexArray(0);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glDisable(GL_SCISSOR_TEST);
}

// glTF alphaMode MASK: the surface cut where mesh.frag cuts it; BLEND and transmission:
// dithered by their opacity (depth_only.frag). Without a base colour texture (the car's
// glass) the alpha is the factor alone: a variant without the lookup. Each linked when a
// caster first needs it: a linked program holds about 1.4 MB on llvmpipe, and car.toml
// never needs the textured one.
const ShadowPass::CutoutProgram& ShadowPass::cutoutProgram(bool textured) const
{
    CutoutProgram& cutout = cutoutPrograms_[textured ? 1 : 0];
    if (cutout.program)
        return cutout;
    cutout.program =
        linkProgram(kDepthOnlyProgram, textured ? "#define ALPHA_CUTOUT 1\n#define HAS_BASE_COLOR_TEXTURE 1\n"
                                                : "#define ALPHA_CUTOUT 1\n#define HAS_BASE_COLOR_TEXTURE 0\n");
    cutout.cameraFromMesh = uniformLocation(cutout.program, "uCameraFromMesh");
    bindUniformBlock(cutout.program, "Frame", kFrameBlockBinding);
    bindUniformBlock(cutout.program, "Material", kMaterialBlockBinding);
    if (textured) {
        glUseProgram(cutout.program.name());
        glUniform1i(uniformLocation(cutout.program, "uBaseColor"), GLint(kCutoutTextureUnit));
    }
    return cutout;
}

void ShadowPass::fillView(FrameUniforms& frame, const glm::dmat4& cameraFromView) const
{
    if (!enabled())
        return;
    const glm::dmat3 viewFromCamera = glm::inverse(glm::dmat3(cameraFromView));
    frame.lightClipFromCamera = glm::mat4(lightClipFromCamera_ * cameraFromView);
    frame.lightDirection = glm::vec4(glm::normalize(viewFromCamera * lightDirection_), mapValid_ ? 1.0f : 0.0f);
    frame.lightIrradiance = glm::vec4(light_.color * light_.intensity, lightSet_ ? 1.0f : 0.0f);
    frame.shadowParams = glm::vec4(options_.softness, 1.0f / float(size_),
                                   float(kNormalOffsetTexels * fit_.texelMetres), float(fit_.depthBias));
}

void ShadowPass::setOccluders(const std::vector<GpuModel>& models, std::span<const DrawItem> items)
{
    reachBoxes_.clear();
    auto& [count, unitFromCamera, unitNormalFromCamera, reach] = occluders_;
    count = 0;
    for (const DrawItem& item : items) {
        if (!isCaster(item) || count == kMaxOccluders)
            continue;
        const GpuModel& model = models[size_t(item.model)];
        glm::dvec3 half = 0.5 * kEqualVolumeScale * (glm::dvec3(model.boundsMax) - glm::dvec3(model.boundsMin));
        const double longest = std::max({half.x, half.y, half.z});
        const double determinant = glm::determinant(glm::dmat3(item.cameraFromModel));
        if (!(longest > 0.0) || determinant == 0.0 || !std::isfinite(determinant))
            continue;
        half = glm::max(half, glm::dvec3(kMinAxisShare * longest));
        const glm::dvec3 centre = 0.5 * (glm::dvec3(model.boundsMin) + glm::dvec3(model.boundsMax));
        const glm::dmat4 unitFromModel =
            glm::scale(glm::dmat4(1.0), 1.0 / half) * glm::translate(glm::dmat4(1.0), -centre);
        const glm::dmat4 unit = unitFromModel * glm::inverse(item.cameraFromModel);
        unitFromCamera[size_t(count)] = glm::mat4(unit);
        const glm::dvec3 reachCentre(item.cameraFromModel * glm::dvec4(centre, 1.0));
        const glm::dmat3 linear(item.cameraFromModel);
        const double scale = std::max({glm::length(linear[0]), glm::length(linear[1]), glm::length(linear[2])});
        const double radius = kOcclusionReach * scale * std::max({half.x, half.y, half.z});
        reach[size_t(count)] = glm::vec4(glm::vec3(reachCentre), float(radius * radius));
        reachBoxes_.push_back(glm::inverse(unit));
        unitNormalFromCamera[size_t(count)] = glm::mat3(glm::transpose(glm::inverse(glm::dmat3(unit))));
        ++count;
    }
}

void ShadowPass::useOccluders(const DarkeningProgram& program, uint32_t label) const
{
    Occluders named;
    for (int i = 0; i < occluders_.count; ++i)
        if (label & (1u << i)) {
            const size_t to = size_t(named.count++);
            named.unitFromCamera[to] = occluders_.unitFromCamera[size_t(i)];
            named.unitNormalFromCamera[to] = occluders_.unitNormalFromCamera[size_t(i)];
            named.reach[to] = occluders_.reach[size_t(i)];
        }
    glUniform1i(program.occluderCount, named.count);
    if (named.count > 0) {
        glUniformMatrix4fv(program.unitFromCamera, named.count, GL_FALSE, glm::value_ptr(named.unitFromCamera[0]));
        glUniformMatrix3fv(program.unitNormalFromCamera, named.count, GL_FALSE,
                           glm::value_ptr(named.unitNormalFromCamera[0]));
        glUniform4fv(program.occluderReach, named.count, glm::value_ptr(named.reach[0]));
    }
}

TileCover ShadowPass::darkenedCover(const FrameUniforms& frame, const std::vector<GpuModel>& models,
                                    std::span<const DrawItem> items) const
{
    GLint viewport[4] = {};
    glGetIntegerv(GL_VIEWPORT, viewport);
    const int width = viewport[2], height = viewport[3];
    TileCover cover(width, height, std::max(kCoverTilePixels / ratio_.scale, 1));
    const uint32_t allOccluders = (1u << occluders_.count) - 1u;
    if (!options_.cullReceivers) {
        cover.addAll(allOccluders | kShadowLabel);
        return cover;
    }
    const glm::dmat4 clipFromCamera(frame.clipFromCamera);
    const glm::dmat4 cameraFromLightView = glm::inverse(lightViewFromCamera_);
    // Each face of each receiver's box is a plane: on it a caster's shadow lies inside the
    // section of the caster's prism along the light (the parallelogram where its four long
    // edges meet the plane), and an occluder's contact darkening inside the section of its
    // reach (the ellipsoid kOcclusionReach times its own: an ellipse). Those, cut to the face
    // and projected, mark the tiles to shade. (Their bounding rectangles covered most of a
    // table: the car scene's contact reaches and long evening shadows lie across it.)
    for (const DrawItem& item : items) {
        if (!item.phantom)
            continue;
        const GpuModel& model = models[size_t(item.model)];
        const double determinant = glm::determinant(glm::dmat3(item.cameraFromModel));
        if (determinant == 0.0 || !std::isfinite(determinant))
            continue;
        const glm::dmat4 modelFromCamera = glm::inverse(item.cameraFromModel);
        const glm::dmat3 normalToCamera = glm::transpose(glm::dmat3(modelFromCamera));
        const glm::dvec3 low(model.boundsMin), high(model.boundsMax);
        const glm::dvec3 travel = glm::dmat3(modelFromCamera) * -lightDirection_; // the light's, model frame
        for (int face = 0; face < 6; ++face) {
            const int axis = face / 2, u = (axis + 1) % 3, v = (axis + 2) % 3;
            const double plane = face % 2 ? high[axis] : low[axis];
            glm::dvec3 outward(0.0);
            outward[axis] = face % 2 ? 1.0 : -1.0;
            const glm::dvec2 faceLow(low[u], low[v]), faceHigh(high[u], high[v]);
            const auto add = [&](std::vector<glm::dvec2> polygon, uint32_t label) {
                coverFacePolygon(item.cameraFromModel, axis, plane, clipToFace(std::move(polygon), faceLow, faceHigh),
                                 clipFromCamera, width, height, kCoverMarginTexels, label, cover);
            };
            // A face turned away from the camera is hidden by the others (or culled).
            glm::dvec3 faceCentre = 0.5 * (low + high);
            faceCentre[axis] = plane;
            const glm::dvec3 normal = normalToCamera * outward;
            if (glm::dot(normal, glm::dvec3(item.cameraFromModel * glm::dvec4(faceCentre, 1.0))) >= 0.0)
                continue;
            const bool facesLight = glm::dot(normal, lightDirection_) > 0.0;
            if (mapValid_ && facesLight && std::abs(travel[axis]) > 1e-12)
                for (const auto& [prismLow, prismHigh] : fit_.prisms) {
                    std::vector<glm::dvec2> section;
                    for (const int i : {0, 1, 3, 2}) { // around the prism
                        const glm::dvec3 edge((i & 1) ? prismHigh.x : prismLow.x, (i & 2) ? prismHigh.y : prismLow.y,
                                              prismLow.z);
                        const glm::dvec3 p(modelFromCamera * (cameraFromLightView * glm::dvec4(edge, 1.0)));
                        const glm::dvec3 hit = p + travel * ((plane - p[axis]) / travel[axis]);
                        section.emplace_back(hit[u], hit[v]);
                    }
                    add(std::move(section), kShadowLabel);
                }
            for (size_t occluder = 0; occluder < reachBoxes_.size(); ++occluder) {
                const glm::dmat4& cameraFromUnit = reachBoxes_[occluder];
                // The face's plane in the occluder's unit space: q(a, b) = q0 + a qu + b qv at
                // (u, v) = (a, b). Its points within the reach, |q| < kOcclusionReach, are the
                // ellipse (x - c)^T G (x - c) < r^2 with G = [qu qv]^T [qu qv].
                const glm::dmat4 unitFromModel = glm::inverse(cameraFromUnit) * item.cameraFromModel;
                glm::dvec4 origin(0.0, 0.0, 0.0, 1.0);
                origin[axis] = plane;
                const glm::dvec3 q0(unitFromModel * origin);
                const glm::dvec3 qu(unitFromModel[u]), qv(unitFromModel[v]);
                const glm::dmat2 g(glm::dot(qu, qu), glm::dot(qu, qv), glm::dot(qu, qv), glm::dot(qv, qv));
                const double gDeterminant = glm::determinant(g);
                if (!(gDeterminant > 0.0) || !std::isfinite(gDeterminant))
                    continue;
                const glm::dvec2 centre = -(glm::inverse(g) * glm::dvec2(glm::dot(qu, q0), glm::dot(qv, q0)));
                const glm::dvec3 nearest = q0 + centre.x * qu + centre.y * qv;
                const double r2 = kOcclusionReach * kOcclusionReach - glm::dot(nearest, nearest);
                if (!(r2 > 0.0))
                    continue;
                // G = L L^T (Cholesky): x = c + r L^-T w maps the unit circle onto the ellipse;
                // a polygon circumscribed about the circle onto one about the ellipse.
                const double l11 = std::sqrt(g[0][0]), l21 = g[0][1] / l11;
                const double l22 = std::sqrt(std::max(g[1][1] - l21 * l21, 1e-300));
                const glm::dmat2 fromCircle =
                    std::sqrt(r2) * glm::inverse(glm::transpose(glm::dmat2(l11, l21, 0.0, l22)));
                constexpr int kSides = 16;
                const double grow = 1.0 / std::cos(std::numbers::pi / kSides);
                std::vector<glm::dvec2> ellipse;
                for (int k = 0; k < kSides; ++k) {
                    const double angle = 2.0 * std::numbers::pi * k / kSides;
                    ellipse.push_back(centre + fromCircle * (grow * glm::dvec2(std::cos(angle), std::sin(angle))));
                }
                add(std::move(ellipse), 1u << occluder);
            }
        }
    }
    return cover;
}

void ShadowPass::drawReceivers(const FrameUniforms& frame, const std::vector<GpuModel>& models,
                               std::span<const DrawItem> items, std::span<const IblMaps* const> maps)
{
    if (!enabled() || std::none_of(items.begin(), items.end(), [](const DrawItem& i) { return i.phantom; }))
        return;
    linkReceiverPrograms();
    linkApplyPrograms();
    GLint frameFramebuffer = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &frameFramebuffer);
    GLint viewport[4] = {};
    glGetIntegerv(GL_VIEWPORT, viewport);
    prepareRatioBuffer(viewport[2], viewport[3]);

    glBindBuffer(GL_UNIFORM_BUFFER, frameUniforms_.name());
    glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof(FrameUniforms), &frame);
    glBindBufferBase(GL_UNIFORM_BUFFER, kFrameBlockBinding, frameUniforms_.name());
    setOccluders(models, items);
    glActiveTexture(GL_TEXTURE0 + MeshPass::kShadowMapUnit);
    glBindTexture(GL_TEXTURE_2D, map_.name());

    // The programs that draw the receivers, all with phantom_receiver.vert.
    struct ReceiverProgram {
        const GlProgram* program;
        GLint cameraFromMesh;
        GLint normalFromMesh;
        bool bindsDiffuseMaps;
    };
    const ReceiverProgram depthOnly{&receiverDepthProgram_, receiverDepthCameraFromMeshLocation_,
                                    receiverDepthNormalFromMeshLocation_, false};
    const ReceiverProgram distance{&receiverDistanceProgram_, receiverDistanceCameraFromMeshLocation_,
                                   receiverDistanceNormalFromMeshLocation_, false};
    const auto darkeningWith = [](const DarkeningProgram& program) {
        return ReceiverProgram{&program.program, program.cameraFromMesh, program.normalFromMesh, true};
    };
    const auto applyWith = [](const ApplyProgram& program) {
        return ReceiverProgram{&program.program, program.cameraFromMesh, program.normalFromMesh, false};
    };
    const ReceiverProgram apply = applyWith(applyPrograms_[0]);
    const ReceiverProgram applyWritingDepth = applyWith(applyPrograms_[applyOneSurface(models, items) ? 2 : 1]);
    // receiverOnly: which items; culling: whether single-sided materials hide back faces.
    const auto drawItems = [&](bool receiverOnly, bool culling, const ReceiverProgram& with) {
        glUseProgram(with.program->name());
        for (size_t i = 0; i < items.size(); ++i) {
            const DrawItem& item = items[i];
            if (!item.phantom || item.receiverOnly != receiverOnly)
                continue;
            if (with.bindsDiffuseMaps) {
                glActiveTexture(GL_TEXTURE0 + MeshPass::kDiffuseMapUnit);
                glBindTexture(GL_TEXTURE_2D, maps[i]->diffuse.name()); // a cube atlas
            }
            const GpuModel& model = models[size_t(item.model)];
            for (const GpuPrimitive& primitive : model.primitives) {
                const glm::dmat4 cameraFromMesh = item.cameraFromModel * primitive.modelFromMesh;
                if (!setFrontFaceFor(cameraFromMesh))
                    continue;
                if (culling && !model.materials[primitive.material].doubleSided)
                    glEnable(GL_CULL_FACE);
                else
                    glDisable(GL_CULL_FACE);
                const glm::mat4 cameraFromMeshF(cameraFromMesh);
                const glm::mat3 normalFromMesh(glm::transpose(glm::inverse(glm::dmat3(cameraFromMesh))));
                glUniformMatrix4fv(with.cameraFromMesh, 1, GL_FALSE, glm::value_ptr(cameraFromMeshF));
                glUniformMatrix3fv(with.normalFromMesh, 1, GL_FALSE, glm::value_ptr(normalFromMesh));
                glBindVertexArray(primitive.vertexArray.name());
                glDrawElements(GL_TRIANGLES, primitive.indexCount, primitive.indexType, nullptr);
            }
        }
    };

    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    // 2. The darkening, into the ratio buffer: the phantoms' depth again at its resolution (a
    //    program with the same vertex shader, whose gl_Position is declared invariant: the
    //    shading below meets exactly these depths), with every receiver's distance into the
    //    green and blue channels (the receiver-only surfaces' where no phantom is in front)
    //    and 1 into red and alpha (a receiver is there; RatioBuffer),
    //    then the shading into red, only where something can darken, once per rectangle of a
    //    disjoint cover of those places: elsewhere the ratio is exactly 1. (A table phantom
    //    fills most of the frame, the shadows and contacts a part of it.)
    glBindFramebuffer(GL_FRAMEBUFFER, ratio_.framebuffer.name());
    glViewport(0, 0, ratio_.frameWidth / ratio_.scale, ratio_.frameHeight / ratio_.scale);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    const GLfloat noReceiver[4] = {0.0f, 1.0f, 1.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 0, noReceiver);
    const GLfloat far = 1.0f;
    glClearBufferfv(GL_DEPTH, 0, &far);
    drawItems(false, true, distance);
    glDepthMask(GL_FALSE);
    drawItems(true, false, distance);
    glColorMask(GL_TRUE, GL_FALSE, GL_FALSE, GL_FALSE);
    TileCover cover = darkenedCover(frame, models, items); // in the buffer's texels
    cover.mergeLabels(kLabelBlockTiles);
    const std::vector<PixelRect> rects = cover.rects();
    if (!rects.empty()) {
        glEnable(GL_SCISSOR_TEST);
        glEnable(GL_BLEND);
        glBlendFunc(GL_DST_COLOR, GL_ZERO);
        // Each rectangle with only the occluders that reach it, and the shadow map's lookups
        // only where a prism does (car.toml: 1.4 of its 4 occluders a texel on average, and
        // no shadow on 15 % of the area).
        uint32_t label = 0;
        for (const auto& [rect, rectLabel] : cover.labelledRects()) {
            const DarkeningProgram& program = darkeningPrograms_[(rectLabel & kShadowLabel) ? 1 : 0];
            if (rectLabel != label) {
                glUseProgram(program.program.name());
                useOccluders(program, rectLabel);
                label = rectLabel;
            }
            const ReceiverProgram darkening = darkeningWith(program);
            glScissor(rect.x0, rect.y0, rect.x1 - rect.x0, rect.y1 - rect.y0);
            // The phantoms' darkening, once per texel: only the nearest surface passes GL_EQUAL.
            glDepthFunc(GL_EQUAL);
            drawItems(false, true, darkening);
            // The receiver-only surfaces where no phantom is in front, seen from either side.
            glDepthFunc(GL_LESS);
            drawItems(true, false, darkening);
        }
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDisable(GL_BLEND);
        glDisable(GL_SCISSOR_TEST);
    }
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);

    // 3. In the frame: the phantoms' depth (real surfaces hide the virtual objects drawn
    //    next), then the frame times the darkening. Both after the buffer's passes: one
    //    framebuffer switch fewer, and on llvmpipe a depth meets GL_EQUAL only in the scene
    //    (the run of draws into one framebuffer) that wrote it. Where one phantom alone is
    //    drawn and each pixel can meet it once (applyCanWriteDepth: a table's slab), the
    //    apply pass writes its depth in the darkening's rectangles itself, with GL_LESS,
    //    and the depth pass draws only outside them: the phantom is rasterised once there
    //    instead of twice (car.toml: the receivers' CPU ~2 ms less a frame, bit-identical).
    const bool applyWritesDepth = !rects.empty() && applyCanWriteDepth(models, items);
    glBindFramebuffer(GL_FRAMEBUFFER, GLuint(frameFramebuffer));
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    // Only where a pass reads it: the darkening's rectangles (the apply pass below) and the
    // virtual objects' boxes (MeshPass, next). A table phantom fills most of the frame.
    glEnable(GL_SCISSOR_TEST);
    for (const PixelRect& rect : depthRects(glm::dmat4(frame.clipFromCamera), models, items, rects, ratio_.scale,
                                            viewport[2], viewport[3], applyWritesDepth)) {
        glScissor(viewport[0] + rect.x0, viewport[1] + rect.y0, rect.x1 - rect.x0, rect.y1 - rect.y0);
        drawItems(false, true, depthOnly);
    }
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    if (!rects.empty()) {
        glEnable(GL_SCISSOR_TEST);
        glEnable(GL_BLEND);
        glBlendFunc(GL_DST_COLOR, GL_ZERO);
        // The frame times the darkening, over the same rectangles, drawn over the receivers
        //    at the frame's resolution (against the phantoms' depth) so that each pixel
        //    upsamples the darkening from its own surface (shadow_apply.frag). (Where two
        //    receiver-only surfaces overlap in the image, each applies the buffer's texel.)
        for (const ApplyProgram& program : applyPrograms_) {
            glUseProgram(program.program.name());
            glUniform1f(program.texelsPerPixel, 1.0f / float(ratio_.scale));
        }
        glActiveTexture(GL_TEXTURE0 + kRatioUnit);
        glBindTexture(GL_TEXTURE_2D, ratio_.colour.name());
        const int s = ratio_.scale;
        for (const PixelRect& rect : rects) {
            glScissor(viewport[0] + rect.x0 * s, viewport[1] + rect.y0 * s, (rect.x1 - rect.x0) * s,
                      (rect.y1 - rect.y0) * s);
            if (applyWritesDepth) {
                glDepthFunc(GL_LESS);
                glDepthMask(GL_TRUE);
                drawItems(false, true, applyWritingDepth);
            } else {
                glDepthFunc(GL_EQUAL);
                drawItems(false, true, apply);
            }
            glDepthFunc(GL_LESS);
            glDepthMask(GL_FALSE);
            drawItems(true, false, apply);
        }
        glActiveTexture(GL_TEXTURE0 + kRatioUnit);
        glBindTexture(GL_TEXTURE_2D, 0);
        glDisable(GL_BLEND);
        glDisable(GL_SCISSOR_TEST);
    }
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDisable(GL_CULL_FACE);
    glBindFramebuffer(GL_FRAMEBUFFER, GLuint(frameFramebuffer));
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glBindVertexArray(0);
    glActiveTexture(GL_TEXTURE0);
}

} // namespace lumar
