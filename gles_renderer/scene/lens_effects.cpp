#include "gles_renderer/scene/lens_effects.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <numbers>
#include <string>

#include "core/error.h"
#include "gles_renderer/gl/fullscreen_triangle.h"
#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/gl/gpu_texture.h"
#include "gles_renderer/gl/shader_program.h"
#include "gles_renderer/scene/tile_cover.h"

namespace lumar {
namespace {

constexpr ProgramSources kLensDownsampleProgram{"fullscreen.vert", "lens_downsample.frag"};
constexpr ProgramSources kLensUpsampleProgram{"fullscreen.vert", "lens_upsample.frag"};
constexpr ProgramSources kLensGlareProgram{"fullscreen.vert", "lens_glare.frag"};
constexpr ProgramSources kLensCompositeProgram{"fullscreen.vert", "lens_composite.frag"};

// lens_glare.frag's array sizes.
constexpr int kMaxStreaks = 16;
constexpr int kMaxSamples = 32;
// The glare is gathered at an eighth of the frame's size (pyramid level 2): at a quarter, its
// 68 samples a texel took 85 ms of a 245 ms frame (the demo truck, 1280x720, llvmpipe, load 7).
constexpr int kGlareLevel = 2;
constexpr int kGlareScale = 8;
// Glare samples are this many texels apart at most: bilinear filtering fills the gaps of a
// ray wider than a texel (RGBM: nearest texels, a dotted ray beyond one texel).
constexpr float kGlareSampleSpacing = 2.0f;
// A ray's weights fall off as exp(-kGlareFalloff t), t from 0 at the bright spot to 1 at the
// configured length (where it is e^-4 = 2 % of its start).
constexpr float kGlareFalloff = 4.0f;
constexpr int kMaxBloomLevels = 8;
// Culled effects are drawn in tiles of this many pixels: the larger, the fewer draws and the
// more pixels drawn for nothing around each bright spot.
constexpr int kCullTile = 32;
// Culled passes draw this many texels past what the next pass reads of them: each step up the
// pyramid, the glare and the composite read their source bilinearly, one texel round its
// footprint.
constexpr int kCullMargin = 2;
// lens_composite.frag's kNothing: the least light the effects add to a pixel they change.
constexpr float kCompositeNothing = 1e-5f;

// The texels of a level of `scale` pixels each that cover `pixels`, grown by kCullMargin.
PixelRect levelTexels(const PixelRect& pixels, int scale)
{
    return {pixels.x0 / scale - kCullMargin, pixels.y0 / scale - kCullMargin,
            (pixels.x1 + scale - 1) / scale + kCullMargin, (pixels.y1 + scale - 1) / scale + kCullMargin};
}

void checkOptions(const LensOptions& o)
{
    const auto check = [](bool ok, const std::string& what) {
        if (!ok)
            throw InputError("lens effects: " + what);
    };
    check(std::isfinite(o.threshold) && o.threshold >= 0.0f, "threshold must be finite and >= 0");
    check(std::isfinite(o.bloomIntensity) && o.bloomIntensity >= 0.0f && o.bloomIntensity <= 16.0f,
          "bloom intensity must be within [0, 16]");
    check(std::isfinite(o.bloomRadius) && o.bloomRadius >= 2.0f && o.bloomRadius <= 1024.0f,
          "bloom radius must be within [2, 1024] pixels");
    check(o.glareStreaks >= 2 && o.glareStreaks <= kMaxStreaks, "glare streaks must be within [2, 16]");
    check(std::isfinite(o.glareLength) && o.glareLength >= 4.0f && o.glareLength <= 1024.0f,
          "glare length must be within [4, 1024] pixels");
    check(std::isfinite(o.glareIntensity) && o.glareIntensity >= 0.0f && o.glareIntensity <= 16.0f,
          "glare intensity must be within [0, 16]");
    check(std::isfinite(o.glareAngle), "glare angle must be finite");
}

// Whether GL runs on the CPU (LensImageFormat::Auto).
bool softwareRasteriser()
{
    const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const std::string renderer = name ? name : "";
    return renderer.find("llvmpipe") != std::string::npos || renderer.find("softpipe") != std::string::npos ||
           renderer.find("swrast") != std::string::npos;
}

std::string rgbmDefine(bool rgbm)
{
    return std::string("#define LENS_RGBM ") + (rgbm ? "1" : "0") + "\n";
}

std::string sourceRgbmDefine(bool rgbm)
{
    return std::string("#define LENS_SOURCE_RGBM ") + (rgbm ? "1" : "0") + "\n";
}

void bindTexture(GLint unit, GLuint texture)
{
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    glBindTexture(GL_TEXTURE_2D, texture);
}

} // namespace

LensEffects::LensEffects(const RenderTarget& target, const LensOptions& options, bool rgbm)
    : options_(options), radianceRgbm_(rgbm), rgbm_(rgbm || options.images == LensImageFormat::Rgbm ||
                                                    (options.images == LensImageFormat::Auto && softwareRasteriser())),
      culled_(options.culling == LensCulling::Culled || (options.culling == LensCulling::Auto && softwareRasteriser())),
      // The composite then reads the frame where it writes it: no copy of the frame (3.5 MiB
      // at 1280x720) nor the blit into it. Multisampled, the fetch would read each sample.
      fetch_(target.samples() == 1 && hasGlExtension("GL_EXT_shader_framebuffer_fetch")), width_(target.width()),
      height_(target.height()), samples_(target.samples()), targetFramebuffer_(target.drawFramebuffer())
{
    checkOptions(options_);
    // Packed float (32 bits a texel) where it renders: half RGBA16F's memory (3.5 MiB at
    // 1280x720) and its bandwidth in the frame's shading, still blendable (the blend's alpha
    // is the fragment's) and within 3 % of the radiance, which only feeds the glow.
    radianceFormat_ = radianceRgbm_                                 ? GL_RGBA8
                      : hasGlExtension("GL_EXT_color_buffer_float") ? GL_R11F_G11F_B10F
                                                                    : GL_RGBA16F;
    radiance_ = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, radiance_.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, radianceFormat_, width_, height_);
    glBindFramebuffer(GL_FRAMEBUFFER, targetFramebuffer_);
    if (samples_ > 1) {
        multisampledRadiance_ = GlRenderbuffer::create();
        glBindRenderbuffer(GL_RENDERBUFFER, multisampledRadiance_.name());
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, radianceFormat_, width_, height_);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, multisampledRadiance_.name());
    } else {
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, radiance_.name(), 0);
    }
    endVirtual(); // attachment 1 stays out of every other pass
    checkFramebufferComplete("the frame with the lens effects' radiance image");
    radianceFramebuffer_ = GlFramebuffer::create();
    glBindFramebuffer(GL_FRAMEBUFFER, radianceFramebuffer_.name());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, radiance_.name(), 0);
    checkFramebufferComplete("the lens effects' radiance image");
    // Culled, the bright image is the radiance halved on the CPU where the radiance reads back
    // as it is stored (packed floats): no bright pass, which on llvmpipe fetched four texels
    // (unpacked one by one) for each of the bright image's (car.toml with bloom: 1.3 ms of
    // wall time for the pass against 0.4 ms for the read and the halving).
    if (culled_ && radianceFormat_ == GL_R11F_G11F_B10F) {
        GLint readFormat = 0, readType = 0;
        glGetIntegerv(GL_IMPLEMENTATION_COLOR_READ_FORMAT, &readFormat);
        glGetIntegerv(GL_IMPLEMENTATION_COLOR_READ_TYPE, &readType);
        readsRadiance_ = readFormat == GL_RGB && readType == GL_UNSIGNED_INT_10F_11F_11F_REV;
    }

    // The pyramid: levels whose texels are 2, 4, ... output pixels, the coarsest no wider
    // than the radius; the glare reads level kGlareLevel and needs it.
    bloomLevels_ = std::clamp(int(std::floor(std::log2(options_.bloomRadius))), 1, kMaxBloomLevels);
    const int levels = std::max(options_.bloom ? bloomLevels_ : 0, options_.glare ? kGlareLevel + 1 : 0);
    int w = width_, h = height_;
    for (int k = 0; k < levels && (w > 1 || h > 1); ++k) {
        w = (w + 1) / 2;
        h = (h + 1) / 2;
        levelSizes_.emplace_back(w, h);
    }
    bloomLevels_ = std::min(bloomLevels_, int(levelSizes_.size()));
    glare_ = options_.glare && levelSizes_.size() > size_t(kGlareLevel);
    const bool bloom = options_.bloom && bloomLevels_ > 0;
    if (culled_) {
        // The bright pass's image alone is GL's; the bloom and the glare come back from the
        // CPU as float images (RGB16F filters on every GLES 3), sampled once per pixel.
        if (!levelSizes_.empty() && !readsRadiance_)
            down_.push_back(makeLevel(levelSizes_[0].x, levelSizes_[0].y));
        cpuLevels_.resize(levelSizes_.size());
        cpuUp_.resize(levelSizes_.size());
        if (bloom) {
            bloomUpload_ = makeRenderTexture(GL_RGB16F, levelSizes_[0].x, levelSizes_[0].y, GL_LINEAR);
        }
        if (glare_)
            glareUpload_ =
                makeRenderTexture(GL_RGB16F, levelSizes_[kGlareLevel].x, levelSizes_[kGlareLevel].y, GL_LINEAR);
    } else {
        for (size_t k = 0; k < levelSizes_.size(); ++k) {
            down_.push_back(makeLevel(levelSizes_[k].x, levelSizes_[k].y));
            up_.push_back(options_.bloom && int(k) + 1 < bloomLevels_ ? makeLevel(levelSizes_[k].x, levelSizes_[k].y)
                                                                      : Level{});
        }
        if (glare_)
            glareLevel_ = makeLevel(levelSizes_[kGlareLevel].x, levelSizes_[kGlareLevel].y);
    }
    if (!fetch_) {
        frameCopy_.width = width_;
        frameCopy_.height = height_;
        frameCopy_.texture = GlTexture::create();
        glBindTexture(GL_TEXTURE_2D, frameCopy_.texture.name());
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width_, height_);
        frameCopy_.framebuffer = GlFramebuffer::create();
        glBindFramebuffer(GL_FRAMEBUFFER, frameCopy_.framebuffer.name());
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, frameCopy_.texture.name(), 0);
        checkFramebufferComplete("the lens effects' copy of the frame");
    }

    // The image formats and the effects that are on are compiled into the programs: on
    // llvmpipe a branch on a uniform runs both sides, and the composite read the bloom and
    // the glare both ways (bilinear and texel by texel) whichever was on (issue 18: the car
    // scene with bloom on llvmpipe: post 27.7 -> 21.7 ms of CPU).
    const std::string formatDefine = rgbmDefine(rgbm_);
    if (!readsRadiance_) {
        downsample_ = linkProgram(kLensDownsampleProgram, formatDefine + sourceRgbmDefine(rgbm_));
        if (radianceRgbm_ != rgbm_)
            brightPass_ = linkProgram(kLensDownsampleProgram, formatDefine + sourceRgbmDefine(radianceRgbm_));
    }
    for (const GlProgram* program : {&downsample_, &brightPass_}) {
        if (!*program)
            continue;
        glUseProgram(program->name());
        glUniform1i(uniformLocation(*program, "uSource"), 0);
    }
    if (!culled_ && options_.bloom && bloomLevels_ > 1) {
        upsample_ = linkProgram(kLensUpsampleProgram, formatDefine);
        glUseProgram(upsample_.name());
        glUniform1i(uniformLocation(upsample_, "uLevel"), 0);
        glUniform1i(uniformLocation(upsample_, "uCoarser"), 1);
    }
    // Culled, the composite reads the CPU's float images.
    composite_ =
        linkProgram(kLensCompositeProgram, rgbmDefine(rgbm_ && !culled_) + "#define LENS_BLOOM " + (bloom ? "1" : "0") +
                                               "\n#define LENS_GLARE " + (glare_ ? "1" : "0") +
                                               "\n#define LENS_FETCH " + (fetch_ ? "1" : "0") + "\n");
    glUseProgram(composite_.name());
    if (!fetch_)
        glUniform1i(uniformLocation(composite_, "uFrame"), 0);
    glUniform1i(optionalUniformLocation(composite_, "uBloom"), 1);
    glUniform1i(optionalUniformLocation(composite_, "uGlare"), 2);
    glUniform1f(optionalUniformLocation(composite_, "uGlareScale"), 1.0f / float(kGlareScale));
    glUniform2f(optionalUniformLocation(composite_, "uIntensity"), bloom ? options_.bloomIntensity : 0.0f,
                glare_ ? options_.glareIntensity : 0.0f);

    if (glare_) {
        // Rays in the glare's texels; the frame's texel rows run down the image, like the
        // angle's +y.
        const float length = options_.glareLength / float(kGlareScale);
        const int samples = std::clamp(int(std::ceil(length / kGlareSampleSpacing)) + 1, 2, kMaxSamples);
        const float step = length / float(samples - 1);
        const double first = double(options_.glareAngle) * std::numbers::pi / 180.0;
        for (int s = 0; s < options_.glareStreaks; ++s) {
            const double angle = first + 2.0 * std::numbers::pi * s / options_.glareStreaks;
            // lens_glare.frag gathers from behind (p - step i): a bright texel's light moves
            // along the step.
            glareSteps_.emplace_back(float(std::cos(angle) * step), float(std::sin(angle) * step));
        }
        double total = 0.0;
        for (int i = 0; i < samples; ++i) {
            glareWeights_.push_back(float(std::exp(-kGlareFalloff * i / double(samples - 1))));
            total += glareWeights_.back() * options_.glareStreaks; // the centre is shared: counted as in the shader
        }
        for (float& weight : glareWeights_)
            weight = float(weight / total);
        if (!culled_) {
            std::array<GLfloat, 2 * kMaxStreaks> steps{};
            for (size_t s = 0; s < glareSteps_.size(); ++s) {
                steps[2 * s] = glareSteps_[s].x;
                steps[2 * s + 1] = glareSteps_[s].y;
            }
            std::array<GLfloat, kMaxSamples> weights{};
            std::copy(glareWeights_.begin(), glareWeights_.end(), weights.begin());
            glareProgram_ = linkProgram(kLensGlareProgram, formatDefine);
            glUseProgram(glareProgram_.name());
            glUniform1i(uniformLocation(glareProgram_, "uSource"), 0);
            glUniform2fv(uniformLocation(glareProgram_, "uSteps"), kMaxStreaks, steps.data());
            glUniform1i(uniformLocation(glareProgram_, "uStreaks"), options_.glareStreaks);
            glUniform1i(uniformLocation(glareProgram_, "uSamples"), samples);
            glUniform1fv(uniformLocation(glareProgram_, "uWeights"), kMaxSamples, weights.data());
        }
    }
    glUseProgram(0);
    checkGlError("creating the lens effects");
}

LensEffects::Level LensEffects::makeLevel(int width, int height) const
{
    Level level;
    level.width = width;
    level.height = height;
    // The glare filters float levels bilinearly; every other read is texelFetch.
    level.texture = makeRenderTexture(rgbm_ ? GL_RGBA8 : GL_RGBA16F, width, height, rgbm_ ? GL_NEAREST : GL_LINEAR);
    level.framebuffer = GlFramebuffer::create();
    glBindFramebuffer(GL_FRAMEBUFFER, level.framebuffer.name());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, level.texture.name(), 0);
    checkFramebufferComplete("a lens-effect image");
    return level;
}

void LensEffects::beginVirtual() const
{
    const GLenum both[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, both);
    const GLfloat zero[] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearBufferfv(GL_COLOR, 1, zero);
}

void LensEffects::endVirtual() const
{
    const GLenum first[] = {GL_COLOR_ATTACHMENT0, GL_NONE};
    glDrawBuffers(2, first);
}

void LensEffects::blendingVirtual(bool blending) const
{
    if (!radianceRgbm_)
        return;
    const GLenum first[] = {GL_COLOR_ATTACHMENT0, GL_NONE};
    const GLenum both[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, blending ? first : both);
}

void LensEffects::drawInto(Level& level, const PixelRect& texels)
{
    const PixelRect drawn = intersection(texels, {0, 0, level.width, level.height});
    glBindFramebuffer(GL_FRAMEBUFFER, level.framebuffer.name());
    glViewport(0, 0, level.width, level.height);
    if (drawn.empty())
        return;
    const bool scissored = drawn.x0 > 0 || drawn.y0 > 0 || drawn.x1 < level.width || drawn.y1 < level.height;
    if (scissored) {
        glEnable(GL_SCISSOR_TEST);
        glScissor(drawn.x0, drawn.y0, drawn.x1 - drawn.x0, drawn.y1 - drawn.y0);
    }
    drawFullscreenTriangle();
    if (scissored)
        glDisable(GL_SCISSOR_TEST);
}

int LensEffects::reachPixels() const
{
    // Bloom: a bright pixel's coarsest texel (2^levels pixels) reaches 2^levels - 1 pixels past
    // it, every step up the pyramid one texel of that step further (2^levels - 2 in all) and
    // the composite's bilinear read 2 more. Glare: the rays.
    const int bloom = options_.bloom ? 2 << bloomLevels_ : 0;
    const int glare = glare_ ? int(std::ceil(options_.glareLength)) + 2 * kGlareScale : 0;
    return std::max(bloom, glare) + 4;
}

void LensEffects::readLevel(const Level& level, const PixelRect& texels, RadianceRegion& region,
                            std::vector<uint8_t>& bytes) const
{
    region.reset(level.width, level.height, texels);
    const PixelRect& held = region.texels();
    if (held.empty())
        return;
    const int w = held.x1 - held.x0, h = held.y1 - held.y0;
    const size_t count = size_t(w) * size_t(h);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, level.framebuffer.name());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    if (rgbm_) {
        bytes.resize(count * 4);
        glReadPixels(held.x0, held.y0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
        // rgbm.glsl's decoding.
        constexpr float kRgbmRange = 16.0f;
        for (int y = 0; y < h; ++y) {
            const uint8_t* in = &bytes[size_t(y) * size_t(w) * 4];
            float* out = region.row(held.y0 + y);
            for (int x = 0; x < w; ++x, in += 4, out += 3) {
                if ((in[0] | in[1] | in[2]) == 0)
                    continue; // the bright image's most: the region is zero already
                const float scale = float(in[3]) / 255.0f * kRgbmRange;
                for (int c = 0; c < 3; ++c)
                    out[c] = float(in[c]) / 255.0f * scale;
            }
        }
    } else {
        bytes.resize(count * 4 * sizeof(float));
        glReadPixels(held.x0, held.y0, w, h, GL_RGBA, GL_FLOAT, bytes.data());
        for (int y = 0; y < h; ++y) {
            float* out = region.row(held.y0 + y);
            for (int x = 0; x < w; ++x, out += 3) {
                float rgba[4];
                std::memcpy(rgba, &bytes[((size_t(y) * size_t(w) + size_t(x)) * 4) * sizeof(float)], sizeof rgba);
                std::copy_n(rgba, 3, out);
            }
        }
    }
    checkGlError("reading a lens-effect image");
}

void LensEffects::readRadianceHalved(const PixelRect& sourceBounds)
{
    RadianceRegion& region = cpuLevels_[0];
    region.reset(levelSizes_[0].x, levelSizes_[0].y, levelTexels(sourceBounds, 2));
    const PixelRect& texels = region.texels();
    if (texels.empty())
        return;
    // Waits for the rasteriser: the frame's shading.
    const PixelRect pixels =
        intersection({2 * texels.x0, 2 * texels.y0, 2 * texels.x1, 2 * texels.y1}, {0, 0, width_, height_});
    const int w = pixels.x1 - pixels.x0, h = pixels.y1 - pixels.y0;
    packedRadiance_.resize(size_t(w) * size_t(h));
    glBindFramebuffer(GL_READ_FRAMEBUFFER, radianceFramebuffer_.name());
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(pixels.x0, pixels.y0, w, h, GL_RGB, GL_UNSIGNED_INT_10F_11F_11F_REV, packedRadiance_.data());
    checkGlError("reading the lens effects' radiance");
    // lens_downsample.frag: a quarter of the 2 x 2 pixels under each texel. Most pixels hold
    // no light above the threshold: 0 bits.
    for (int y = 0; y < h; ++y) {
        const uint32_t* in = &packedRadiance_[size_t(y) * size_t(w)];
        float* row = region.row((pixels.y0 + y) / 2);
        for (int x = 0; x < w; ++x) {
            if (in[x] == 0)
                continue;
            const glm::vec3 radiance = unpackR11G11B10F(in[x]);
            float* out = row + size_t((pixels.x0 + x) / 2 - texels.x0) * 3;
            out[0] += 0.25f * radiance.r;
            out[1] += 0.25f * radiance.g;
            out[2] += 0.25f * radiance.b;
        }
    }
}

std::vector<PixelRect> LensEffects::litTiles(const PixelRect& area) const
{
    // A tile beyond reach of the bright image's lit texels gets nothing.
    const RadianceRegion& bright = cpuLevels_[0];
    const PixelRect& texels = bright.texels();
    TileCover tiles(width_, height_, kCullTile);
    std::vector<uint8_t> litTile(size_t(tiles.columns()) * size_t(tiles.rows()));
    bool any = false;
    for (int y = texels.y0; y < texels.y1; ++y) {
        const float* texel = bright.row(y);
        for (int x = texels.x0; x < texels.x1; ++x, texel += 3)
            if (texel[0] > 0.0f || texel[1] > 0.0f || texel[2] > 0.0f) {
                litTile[size_t(std::min(y * 2 / kCullTile, tiles.rows() - 1)) * size_t(tiles.columns()) +
                        size_t(std::min(x * 2 / kCullTile, tiles.columns() - 1))] = 1;
                any = true;
            }
    }
    if (!any)
        return {};
    const double reach = reachPixels();
    for (int row = 0; row < tiles.rows(); ++row)
        for (int column = 0; column < tiles.columns(); ++column)
            if (litTile[size_t(row) * size_t(tiles.columns()) + size_t(column)]) {
                const double x0 = column * kCullTile, y0 = row * kCullTile;
                const std::array<glm::dvec2, 4> square{glm::dvec2(x0, y0), glm::dvec2(x0 + kCullTile, y0),
                                                       glm::dvec2(x0 + kCullTile, y0 + kCullTile),
                                                       glm::dvec2(x0, y0 + kCullTile)};
                tiles.addConvex(square, reach);
            }
    std::vector<PixelRect> rects;
    for (const PixelRect& rect : tiles.rects()) {
        const PixelRect inside = intersection(rect, area);
        if (!inside.empty())
            rects.push_back(inside);
    }
    return rects;
}

LensEffects::Area LensEffects::area(std::span<const GpuModel> models, std::span<const DrawItem> items,
                                    const glm::mat4& clipFromCamera) const
{
    const PixelRect frame{0, 0, width_, height_};
    const int margin = reachPixels();
    Area area;
    std::vector<PixelRect> sources;
    for (const DrawItem& item : items) {
        if (item.phantom)
            continue;
        const GpuModel& model = models[size_t(item.model)];
        const glm::dmat4 clipFromModel = glm::dmat4(clipFromCamera) * item.cameraFromModel;
        PixelRect rect;
        bool behind = false;
        for (int corner = 0; corner < 8 && !behind; ++corner) {
            const glm::dvec3 local((corner & 1) ? model.boundsMax.x : model.boundsMin.x,
                                   (corner & 2) ? model.boundsMax.y : model.boundsMin.y,
                                   (corner & 4) ? model.boundsMax.z : model.boundsMin.z);
            const glm::dvec4 clip = clipFromModel * glm::dvec4(local, 1.0);
            if (!(clip.w > 1e-6)) {
                behind = true; // reaches behind the camera: anywhere
                break;
            }
            const double x = (clip.x / clip.w * 0.5 + 0.5) * width_, y = (clip.y / clip.w * 0.5 + 0.5) * height_;
            const PixelRect pixel{int(std::floor(std::clamp(x, -1e6, 1e6))), int(std::floor(std::clamp(y, -1e6, 1e6))),
                                  int(std::ceil(std::clamp(x, -1e6, 1e6))), int(std::ceil(std::clamp(y, -1e6, 1e6)))};
            rect = bounding(rect, PixelRect{pixel.x0, pixel.y0, std::max(pixel.x1, pixel.x0 + 1),
                                            std::max(pixel.y1, pixel.y0 + 1)});
        }
        const PixelRect source = behind ? frame : intersection(rect, frame);
        if (!source.empty())
            sources.push_back(source);
        area.reach = bounding(
            area.reach,
            behind ? frame
                   : intersection({rect.x0 - margin, rect.y0 - margin, rect.x1 + margin, rect.y1 + margin}, frame));
    }
    if (area.reach.empty())
        return {};
    area.sources = disjointCover(sources);
    return area;
}

void LensEffects::copyFrame(const RenderTarget& target, const PixelRect& area)
{
    target.resolveColour();
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target.readFramebuffer());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, frameCopy_.framebuffer.name());
    glBlitFramebuffer(area.x0, area.y0, area.x1, area.y1, area.x0, area.y0, area.x1, area.y1, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
}

void LensEffects::apply(const RenderTarget& target, const Area& area)
{
    if (area.reach.empty())
        return;
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    if (samples_ > 1) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, targetFramebuffer_);
        glReadBuffer(GL_COLOR_ATTACHMENT1);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, radianceFramebuffer_.name());
        glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
    }
    if (culled_)
        applyCulled(target, area);
    else
        applyWhole(target, area.reach);
    target.bindForDrawing();
    glUseProgram(0);
    glActiveTexture(GL_TEXTURE0);
    checkGlError("drawing the lens effects");
}

void LensEffects::applyWhole(const RenderTarget& target, const PixelRect& reach)
{
    constexpr PixelRect kEverything{0, 0, 1 << 30, 1 << 30};
    for (size_t k = 0; k < down_.size(); ++k) {
        // The radiance holds only the light above the threshold (mesh.frag): the first step
        // is a plain downsample too, in the radiance's format where it differs.
        if (k <= 1)
            glUseProgram((k == 0 && brightPass_ ? brightPass_ : downsample_).name());
        bindTexture(0, k == 0 ? radiance_.name() : down_[k - 1].texture.name());
        drawInto(down_[k], kEverything);
    }
    // Bloom: up from the coarsest level, each level's share 1 / (levels from it down).
    if (options_.bloom && bloomLevels_ > 1) {
        glUseProgram(upsample_.name());
        const GLint weight = uniformLocation(upsample_, "uWeight");
        for (int k = bloomLevels_ - 2; k >= 0; --k) {
            bindTexture(0, down_[size_t(k)].texture.name());
            bindTexture(1, k + 2 == bloomLevels_ ? down_[size_t(k + 1)].texture.name()
                                                 : up_[size_t(k + 1)].texture.name());
            glUniform1f(weight, 1.0f / float(bloomLevels_ - k));
            drawInto(up_[size_t(k)], kEverything);
        }
    }
    if (glare_) {
        glUseProgram(glareProgram_.name());
        bindTexture(0, down_[kGlareLevel].texture.name());
        drawInto(glareLevel_, kEverything);
    }
    const GLuint bloom = !options_.bloom || down_.empty() ? 0
                         : bloomLevels_ > 1               ? up_[0].texture.name()
                                                          : down_[0].texture.name();
    const PixelRect tiles[] = {reach};
    composite(target, tiles, reach, bloom, glareLevel_.texture.name());
}

void LensEffects::applyCulled(const RenderTarget& target, const Area& area)
{
    if (levelSizes_.empty())
        return;
    PixelRect sourceBounds;
    for (const PixelRect& source : area.sources)
        sourceBounds = bounding(sourceBounds, source);
    if (readsRadiance_) {
        readRadianceHalved(sourceBounds);
    } else {
        // The bright pass, cleared and drawn over the sources only: the radiance is 0
        // elsewhere, so the image is whole. Between the objects and round them lie most of the
        // texels within reach (car.toml: the four objects' bounds hold 247k of its 575k pixels).
        glUseProgram((brightPass_ ? brightPass_ : downsample_).name());
        bindTexture(0, radiance_.name());
        glBindFramebuffer(GL_FRAMEBUFFER, down_[0].framebuffer.name());
        const GLfloat zero[] = {0.0f, 0.0f, 0.0f, 0.0f};
        glClearBufferfv(GL_COLOR, 0, zero);
        glViewport(0, 0, down_[0].width, down_[0].height);
        glEnable(GL_SCISSOR_TEST);
        for (const PixelRect& source : area.sources) {
            const PixelRect texels = intersection(levelTexels(source, 2), {0, 0, down_[0].width, down_[0].height});
            if (texels.empty())
                continue;
            glScissor(texels.x0, texels.y0, texels.x1 - texels.x0, texels.y1 - texels.y0);
            drawFullscreenTriangle();
        }
        glDisable(GL_SCISSOR_TEST);
        // The bright pass's image is where all of the effects' light comes from; only the
        // texels under the sources can be lit. The read waits for the rasteriser.
        readLevel(down_[0], levelTexels(sourceBounds, 2), cpuLevels_[0], brightBytes_);
    }

    const std::vector<PixelRect> tiles = litTiles(area.reach);
    PixelRect bounds;
    for (const PixelRect& tile : tiles)
        bounds = bounding(bounds, tile);
    for (RadianceRegion& level : cpuUp_)
        level.reset(0, 0, {});
    cpuGlare_.reset(0, 0, {});
    if (bounds.empty())
        return;
    // Down the pyramid under the sources (0 beyond them, as the bright image is), up it and the
    // glare within reach of the tiles: each step reads its source one texel round its
    // footprint, inside the kCullMargin texels every region has to spare.
    for (size_t k = 1; k < cpuLevels_.size(); ++k) {
        cpuLevels_[k].reset(levelSizes_[k].x, levelSizes_[k].y, levelTexels(sourceBounds, 2 << k));
        inBands(cpuLevels_[k].texels(),
                [&](const PixelRect& band) { downsampleRegion(cpuLevels_[k - 1], cpuLevels_[k], band); });
    }
    // Up the pyramid to its second level over the bounds, the glare there too (both small);
    // the finest level, the bloom itself, only where the composite will draw.
    const bool bloom = options_.bloom && bloomLevels_ > 0;
    if (bloom)
        for (int k = bloomLevels_ - 2; k >= 1; --k) {
            RadianceRegion& up = cpuUp_[size_t(k)];
            up.reset(levelSizes_[size_t(k)].x, levelSizes_[size_t(k)].y, levelTexels(bounds, 2 << k));
            inBands(up.texels(), [&](const PixelRect& band) {
                upsampleRegion(cpuLevels_[size_t(k)], cpuCoarser(k), 1.0f / float(bloomLevels_ - k), up, band);
            });
        }
    if (glare_) {
        cpuGlare_.reset(levelSizes_[kGlareLevel].x, levelSizes_[kGlareLevel].y, levelTexels(bounds, kGlareScale));
        inBands(cpuGlare_.texels(), [&](const PixelRect& band) {
            gatherGlareRegion(cpuLevels_[kGlareLevel], glareSteps_, glareWeights_, cpuGlare_, band);
        });
    }
    const std::vector<PixelRect> reached = reachedTiles(tiles);
    PixelRect reachedBounds;
    for (const PixelRect& rect : reached)
        reachedBounds = bounding(reachedBounds, rect);
    if (bloom && bloomLevels_ > 1) {
        RadianceRegion& up = cpuUp_[0];
        up.reset(levelSizes_[0].x, levelSizes_[0].y, levelTexels(reachedBounds, 2));
        // Each band upsamples the rectangles' rows within it (the rectangles are disjoint).
        inBands(up.texels(), [&](const PixelRect& band) {
            for (const PixelRect& rect : reached)
                upsampleRegion(cpuLevels_[0], cpuCoarser(0), 1.0f / float(bloomLevels_), up,
                               intersection(levelTexels(rect, 2), band));
        });
    }
    // Uploaded where the composite reads them: its rectangles' texels, one round their
    // footprint (what the bilinear reads take).
    const auto upload = [&reached](GLuint texture, const RadianceRegion& region, int scale) {
        const PixelRect& held = region.texels();
        glBindTexture(GL_TEXTURE_2D, texture);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, held.x1 - held.x0);
        for (const PixelRect& rect : reached) {
            const PixelRect texels = intersection(levelTexels(rect, scale), held);
            if (texels.empty())
                continue;
            glTexSubImage2D(GL_TEXTURE_2D, 0, texels.x0, texels.y0, texels.x1 - texels.x0, texels.y1 - texels.y0,
                            GL_RGB, GL_FLOAT, region.row(texels.y0) + size_t(texels.x0 - held.x0) * 3);
        }
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    };
    if (bloom)
        upload(bloomUpload_.name(), cpuBloom(), 2);
    if (glare_)
        upload(glareUpload_.name(), cpuGlare_, kGlareScale);
    checkGlError("uploading the lens effects");
    composite(target, reached, bounds, bloomUpload_.name(), glareUpload_.name());
}

void LensEffects::inBands(const PixelRect& texels, const std::function<void(const PixelRect&)>& work) const
{
    // Fewer rows cost less than handing half of them over (a wake-up and a wait, ~20 us).
    constexpr int kMinRowsToSplit = 16;
    if (helper_ == nullptr || texels.y1 - texels.y0 < kMinRowsToSplit) {
        work(texels);
        return;
    }
    const int middle = texels.y0 + (texels.y1 - texels.y0) / 2;
    const PixelRect top{texels.x0, texels.y0, texels.x1, middle}, bottom{texels.x0, middle, texels.x1, texels.y1};
    helper_->runAlongside([&] { work(top); }, [&] { work(bottom); });
}

const RadianceRegion& LensEffects::cpuCoarser(int level) const
{
    return level + 2 == bloomLevels_ ? cpuLevels_[size_t(level + 1)] : cpuUp_[size_t(level + 1)];
}

const RadianceRegion& LensEffects::cpuBloom() const
{
    return bloomLevels_ > 1 ? cpuUp_[0] : cpuLevels_[0];
}

std::vector<PixelRect> LensEffects::reachedTiles(std::span<const PixelRect> candidates) const
{
    // The reach bounds the effects of the brightest light; most highlights' blooms fade below
    // what the composite keeps (kCompositeNothing) well within it: in the car scene with bloom,
    // 50k of the 190k pixels within reach. A bilinear read is never above the largest texel it
    // reads, so a tile whose texels (one round its footprint) stay below is left out.
    // The bloom's finest level is not computed yet: it mixes the bright image (weight w) and
    // the next level doubled (1 - w), each no more than its largest texel under the tile.
    const bool bloomOn = options_.bloom && bloomLevels_ > 0;
    const RadianceRegion* bright = bloomOn ? &cpuLevels_[0] : nullptr;
    const RadianceRegion* coarser = bloomOn && bloomLevels_ > 1 ? &cpuCoarser(0) : nullptr;
    const float brightWeight = bloomLevels_ > 1 ? 1.0f / float(bloomLevels_) : 1.0f;
    const RadianceRegion* glare = glare_ ? &cpuGlare_ : nullptr;
    const auto largest = [](const RadianceRegion* image, int scale, const PixelRect& pixels) {
        float most = 0.0f;
        if (!image)
            return most;
        const PixelRect texels =
            intersection({pixels.x0 / scale - 1, pixels.y0 / scale - 1, pixels.x1 / scale + 2, pixels.y1 / scale + 2},
                         image->texels());
        for (int y = texels.y0; y < texels.y1; ++y) {
            const float* texel = image->row(y) + size_t(texels.x0 - image->texels().x0) * 3;
            for (int x = texels.x0; x < texels.x1; ++x, texel += 3)
                most = std::max({most, texel[0], texel[1], texel[2]});
        }
        return most;
    };
    TileCover reached(width_, height_, kCullTile);
    for (const PixelRect& candidate : candidates)
        for (int y0 = candidate.y0 / kCullTile * kCullTile; y0 < candidate.y1; y0 += kCullTile)
            for (int x0 = candidate.x0 / kCullTile * kCullTile; x0 < candidate.x1; x0 += kCullTile) {
                const PixelRect tile = intersection({x0, y0, x0 + kCullTile, y0 + kCullTile}, candidate);
                if (tile.empty())
                    continue;
                // RGB16F rounds the uploaded values by up to 2^-11 of themselves: 1 % to spare.
                // The finest level's texels read the next level's one texel further out.
                const PixelRect around{tile.x0 - 2, tile.y0 - 2, tile.x1 + 2, tile.y1 + 2};
                const float bloom =
                    brightWeight * largest(bright, 2, tile) + (1.0f - brightWeight) * largest(coarser, 4, around);
                const float added =
                    options_.bloomIntensity * bloom + options_.glareIntensity * largest(glare, kGlareScale, tile);
                if (added * 1.01f < kCompositeNothing)
                    continue;
                const std::array<glm::dvec2, 4> square{
                    glm::dvec2(tile.x0 + 0.5, tile.y0 + 0.5), glm::dvec2(tile.x1 - 0.5, tile.y0 + 0.5),
                    glm::dvec2(tile.x1 - 0.5, tile.y1 - 0.5), glm::dvec2(tile.x0 + 0.5, tile.y1 - 0.5)};
                reached.addConvex(square, 0.0);
            }
    std::vector<PixelRect> rects;
    for (const PixelRect& rect : reached.rects())
        for (const PixelRect& candidate : candidates) {
            const PixelRect inside = intersection(rect, candidate);
            if (!inside.empty())
                rects.push_back(inside);
        }
    return rects;
}

void LensEffects::composite(const RenderTarget& target, std::span<const PixelRect> tiles, const PixelRect& bounds,
                            GLuint bloom, GLuint glare)
{
    if (!fetch_)
        copyFrame(target, bounds);
    target.bindForDrawing();
    // Only where the effects can add light: the rest of the frame stays as it is, unread.
    glEnable(GL_SCISSOR_TEST);
    glUseProgram(composite_.name());
    bindTexture(0, fetch_ ? 0 : frameCopy_.texture.name());
    bindTexture(1, bloom);
    bindTexture(2, glare);
    for (const PixelRect& tile : tiles) {
        glScissor(tile.x0, tile.y0, tile.x1 - tile.x0, tile.y1 - tile.y0);
        drawFullscreenTriangle();
    }
    glDisable(GL_SCISSOR_TEST);
}

ImageF LensEffects::read(const Level& level) const
{
    RadianceRegion region;
    std::vector<uint8_t> bytes;
    readLevel(level, {0, 0, level.width, level.height}, region, bytes);
    return region.image();
}

ImageF LensEffects::readBright() const
{
    if (culled_)
        return cpuLevels_.empty() ? ImageF() : cpuLevels_[0].image();
    return down_.empty() ? ImageF() : read(down_[0]);
}

ImageF LensEffects::readBloom() const
{
    if (!options_.bloom || levelSizes_.empty())
        return ImageF();
    if (culled_) {
        const RadianceRegion& bloom = cpuBloom();
        return bloom.width() > 0 ? bloom.image() : ImageF(levelSizes_[0].x, levelSizes_[0].y, 3);
    }
    return read(bloomLevels_ > 1 ? up_[0] : down_[0]);
}

ImageF LensEffects::readGlare() const
{
    if (!glare_)
        return ImageF(0, 0, 3);
    if (culled_)
        return cpuGlare_.width() > 0 ? cpuGlare_.image()
                                     : ImageF(levelSizes_[kGlareLevel].x, levelSizes_[kGlareLevel].y, 3);
    return read(glareLevel_);
}

} // namespace lumar
