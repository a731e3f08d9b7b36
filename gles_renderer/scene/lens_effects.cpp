#include "gles_renderer/scene/lens_effects.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.h"
#include "gles_renderer/gl/fullscreen_triangle.h"
#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/gl/gpu_texture.h"
#include "gles_renderer/gl/shader_program.h"

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

void bindTexture(GLint unit, GLuint texture)
{
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    glBindTexture(GL_TEXTURE_2D, texture);
}

} // namespace

LensEffects::LensEffects(const RenderTarget& target, const LensOptions& options, bool rgbm)
    : options_(options), radianceRgbm_(rgbm), rgbm_(rgbm || options.images == LensImageFormat::Rgbm ||
                                                    (options.images == LensImageFormat::Auto && softwareRasteriser())),
      width_(target.width()), height_(target.height()), samples_(target.samples()),
      targetFramebuffer_(target.drawFramebuffer()), downsample_(linkProgram(kLensDownsampleProgram)),
      upsample_(linkProgram(kLensUpsampleProgram)), glareProgram_(linkProgram(kLensGlareProgram)),
      composite_(linkProgram(kLensCompositeProgram))
{
    checkOptions(options_);
    const GLenum format = radianceRgbm_ ? GL_RGBA8 : GL_RGBA16F;
    radiance_ = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, radiance_.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, format, width_, height_);
    glBindFramebuffer(GL_FRAMEBUFFER, targetFramebuffer_);
    if (samples_ > 1) {
        multisampledRadiance_ = GlRenderbuffer::create();
        glBindRenderbuffer(GL_RENDERBUFFER, multisampledRadiance_.name());
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples_, format, width_, height_);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_RENDERBUFFER, multisampledRadiance_.name());
        resolveFramebuffer_ = GlFramebuffer::create();
    } else {
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, radiance_.name(), 0);
    }
    endVirtual(); // attachment 1 stays out of every other pass
    checkFramebufferComplete("the frame with the lens effects' radiance image");
    if (samples_ > 1) {
        glBindFramebuffer(GL_FRAMEBUFFER, resolveFramebuffer_.name());
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, radiance_.name(), 0);
        checkFramebufferComplete("the lens effects' radiance resolve");
    }

    // The pyramid: levels whose texels are 2, 4, ... output pixels, the coarsest no wider
    // than the radius; the glare reads level kGlareLevel and needs it.
    bloomLevels_ = std::clamp(int(std::floor(std::log2(options_.bloomRadius))), 1, kMaxBloomLevels);
    const int levels = std::max(options_.bloom ? bloomLevels_ : 0, options_.glare ? kGlareLevel + 1 : 0);
    int w = width_, h = height_;
    for (int k = 0; k < levels && (w > 1 || h > 1); ++k) {
        w = (w + 1) / 2;
        h = (h + 1) / 2;
        down_.push_back(makeLevel(w, h));
        up_.push_back(options_.bloom && k + 1 < bloomLevels_ ? makeLevel(w, h) : Level{});
    }
    bloomLevels_ = std::min(bloomLevels_, int(down_.size()));
    if (options_.glare && down_.size() > size_t(kGlareLevel))
        glare_ = makeLevel(down_[kGlareLevel].width, down_[kGlareLevel].height);
    frameCopy_.width = width_;
    frameCopy_.height = height_;
    frameCopy_.texture = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, frameCopy_.texture.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width_, height_);
    frameCopy_.framebuffer = GlFramebuffer::create();
    glBindFramebuffer(GL_FRAMEBUFFER, frameCopy_.framebuffer.name());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, frameCopy_.texture.name(), 0);
    checkFramebufferComplete("the lens effects' copy of the frame");

    const GLuint programs[] = {downsample_.name(), upsample_.name(), glareProgram_.name(), composite_.name()};
    for (const GLuint program : programs) {
        glUseProgram(program);
        glUniform1i(glGetUniformLocation(program, "uRgbm"), rgbm_ ? 1 : 0);
    }
    glUseProgram(downsample_.name());
    glUniform1i(uniformLocation(downsample_, "uSource"), 0);
    sourceRgbm_ = uniformLocation(downsample_, "uSourceRgbm");
    glUseProgram(upsample_.name());
    glUniform1i(uniformLocation(upsample_, "uLevel"), 0);
    glUniform1i(uniformLocation(upsample_, "uCoarser"), 1);
    glUseProgram(composite_.name());
    glUniform1i(uniformLocation(composite_, "uFrame"), 0);
    glUniform1i(uniformLocation(composite_, "uBloom"), 1);
    glUniform1i(uniformLocation(composite_, "uGlare"), 2);
    glUniform1f(uniformLocation(composite_, "uGlareScale"), 1.0f / float(kGlareScale));
    glUniform2f(uniformLocation(composite_, "uIntensity"),
                options_.bloom && bloomLevels_ > 0 ? options_.bloomIntensity : 0.0f,
                glare_.width > 0 ? options_.glareIntensity : 0.0f);

    if (glare_.width > 0) {
        // Rays in the glare's texels; the frame's texel rows run down the image, like the
        // angle's +y.
        const float length = options_.glareLength / float(kGlareScale);
        const int samples = std::clamp(int(std::ceil(length / kGlareSampleSpacing)) + 1, 2, kMaxSamples);
        const float step = length / float(samples - 1);
        std::array<GLfloat, 2 * kMaxStreaks> steps{};
        const double first = double(options_.glareAngle) * std::numbers::pi / 180.0;
        for (int s = 0; s < options_.glareStreaks; ++s) {
            const double angle = first + 2.0 * std::numbers::pi * s / options_.glareStreaks;
            // lens_glare.frag gathers from behind (p - step i): a bright texel's light moves
            // along the step.
            steps[size_t(2 * s)] = GLfloat(std::cos(angle) * step);
            steps[size_t(2 * s + 1)] = GLfloat(std::sin(angle) * step);
        }
        std::array<GLfloat, kMaxSamples> weights{};
        double total = 0.0;
        for (int i = 0; i < samples; ++i) {
            weights[size_t(i)] = GLfloat(std::exp(-kGlareFalloff * i / double(samples - 1)));
            total += weights[size_t(i)] * options_.glareStreaks; // the centre is shared: counted as in the shader
        }
        for (GLfloat& weight : weights)
            weight = GLfloat(weight / total);
        glUseProgram(glareProgram_.name());
        glUniform1i(uniformLocation(glareProgram_, "uSource"), 0);
        glUniform2fv(uniformLocation(glareProgram_, "uSteps"), kMaxStreaks, steps.data());
        glUniform1i(uniformLocation(glareProgram_, "uStreaks"), options_.glareStreaks);
        glUniform1i(uniformLocation(glareProgram_, "uSamples"), samples);
        glUniform1fv(uniformLocation(glareProgram_, "uWeights"), kMaxSamples, weights.data());
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

void LensEffects::drawInto(const Level& level) const
{
    glBindFramebuffer(GL_FRAMEBUFFER, level.framebuffer.name());
    glViewport(0, 0, level.width, level.height);
    drawFullscreenTriangle();
}

PixelRect LensEffects::reach(std::span<const GpuModel> models, std::span<const DrawItem> items,
                             const glm::mat4& clipFromCamera) const
{
    // Bloom: the coarsest level's texels (2^levels pixels) spread about two of them; beyond
    // that lies under 1 % of its energy (the tests' bound at twice the radius). Glare: the rays.
    const int bloom = options_.bloom ? 2 << bloomLevels_ : 0;
    const int glare = glare_.width > 0 ? int(std::ceil(options_.glareLength)) + 2 * kGlareScale : 0;
    const int margin = std::max(bloom, glare) + 4;
    PixelRect rect;
    for (const DrawItem& item : items) {
        if (item.phantom)
            continue;
        const GpuModel& model = models[size_t(item.model)];
        const glm::dmat4 clipFromModel = glm::dmat4(clipFromCamera) * item.cameraFromModel;
        for (int corner = 0; corner < 8; ++corner) {
            const glm::dvec3 local((corner & 1) ? model.boundsMax.x : model.boundsMin.x,
                                   (corner & 2) ? model.boundsMax.y : model.boundsMin.y,
                                   (corner & 4) ? model.boundsMax.z : model.boundsMin.z);
            const glm::dvec4 clip = clipFromModel * glm::dvec4(local, 1.0);
            if (!(clip.w > 1e-6))
                return {0, 0, width_, height_}; // reaches behind the camera
            const double x = (clip.x / clip.w * 0.5 + 0.5) * width_, y = (clip.y / clip.w * 0.5 + 0.5) * height_;
            const PixelRect pixel{int(std::floor(std::max(x, -1e6))), int(std::floor(std::max(y, -1e6))),
                                  int(std::ceil(std::min(x, 1e6))), int(std::ceil(std::min(y, 1e6)))};
            rect = rect.empty() ? PixelRect{pixel.x0, pixel.y0, pixel.x0 + 1, pixel.y0 + 1}
                                : PixelRect{std::min(rect.x0, pixel.x0), std::min(rect.y0, pixel.y0),
                                            std::max(rect.x1, pixel.x1), std::max(rect.y1, pixel.y1)};
        }
    }
    if (rect.empty())
        return rect;
    return {std::clamp(rect.x0 - margin, 0, width_), std::clamp(rect.y0 - margin, 0, height_),
            std::clamp(rect.x1 + margin, 0, width_), std::clamp(rect.y1 + margin, 0, height_)};
}

void LensEffects::copyFrame(const RenderTarget& target, const PixelRect& area)
{
    target.resolveColour();
    glBindFramebuffer(GL_READ_FRAMEBUFFER, target.readFramebuffer());
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, frameCopy_.framebuffer.name());
    glBlitFramebuffer(area.x0, area.y0, area.x1, area.y1, area.x0, area.y0, area.x1, area.y1, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
}

void LensEffects::apply(const RenderTarget& target, const PixelRect& area)
{
    if (area.empty())
        return;
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    if (samples_ > 1) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, targetFramebuffer_);
        glReadBuffer(GL_COLOR_ATTACHMENT1);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolveFramebuffer_.name());
        glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        glReadBuffer(GL_COLOR_ATTACHMENT0);
    }

    // Bright pass and the pyramid.
    glUseProgram(downsample_.name());
    const GLint threshold = uniformLocation(downsample_, "uThreshold");
    for (size_t k = 0; k < down_.size(); ++k) {
        glUniform1i(sourceRgbm_, k == 0 ? radianceRgbm_ : rgbm_);
        bindTexture(0, k == 0 ? radiance_.name() : down_[k - 1].texture.name());
        glUniform1f(threshold, k == 0 ? options_.threshold : 0.0f);
        drawInto(down_[k]);
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
            drawInto(up_[size_t(k)]);
        }
    }
    if (glare_.width > 0) {
        glUseProgram(glareProgram_.name());
        bindTexture(0, down_[kGlareLevel].texture.name());
        drawInto(glare_);
    }

    copyFrame(target, area);
    target.bindForDrawing();
    // Only where the effects can add light: the rest of the frame stays as it is, unread.
    glEnable(GL_SCISSOR_TEST);
    glScissor(area.x0, area.y0, area.x1 - area.x0, area.y1 - area.y0);
    glUseProgram(composite_.name());
    bindTexture(0, frameCopy_.texture.name());
    bindTexture(1, !options_.bloom || down_.empty() ? 0
                   : bloomLevels_ > 1               ? up_[0].texture.name()
                                                    : down_[0].texture.name());
    bindTexture(2, glare_.texture.name());
    drawFullscreenTriangle();
    glDisable(GL_SCISSOR_TEST);
    glUseProgram(0);
    glActiveTexture(GL_TEXTURE0);
    checkGlError("drawing the lens effects");
}

ImageF LensEffects::read(const Level& level) const
{
    ImageF image(level.width, level.height, 3);
    if (level.width == 0)
        return image;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, level.framebuffer.name());
    std::vector<float> rgba(size_t(level.width) * size_t(level.height) * 4);
    if (rgbm_) {
        std::vector<uint8_t> bytes(rgba.size());
        glReadPixels(0, 0, level.width, level.height, GL_RGBA, GL_UNSIGNED_BYTE, bytes.data());
        // rgbm.glsl's decoding.
        constexpr float kRgbmRange = 16.0f;
        for (size_t i = 0; i < bytes.size(); i += 4)
            for (size_t c = 0; c < 4; ++c)
                rgba[i + c] = c < 3 ? bytes[i + c] / 255.0f * (bytes[i + 3] / 255.0f * kRgbmRange) : 1.0f;
    } else {
        glReadPixels(0, 0, level.width, level.height, GL_RGBA, GL_FLOAT, rgba.data());
    }
    checkGlError("reading a lens-effect image");
    for (int y = 0; y < level.height; ++y)
        for (int x = 0; x < level.width; ++x)
            for (int c = 0; c < 3; ++c)
                image.at(x, y)[c] = rgba[(size_t(y) * size_t(level.width) + size_t(x)) * 4 + size_t(c)];
    return image;
}

ImageF LensEffects::readBright() const
{
    return down_.empty() ? ImageF() : read(down_[0]);
}

ImageF LensEffects::readBloom() const
{
    if (!options_.bloom || down_.empty())
        return ImageF();
    return read(bloomLevels_ > 1 ? up_[0] : down_[0]);
}

ImageF LensEffects::readGlare() const
{
    return read(glare_);
}

} // namespace lumar
