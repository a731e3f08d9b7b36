
#include "gles_renderer/ibl_gpu/ibl_pipeline.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <string>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "core/error.h"
#include "core/log.h"
#include "gles_renderer/gl/fullscreen_triangle.h"
#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/gl/shader_program.h"
#include "gles_renderer/ibl/cube_face_camera.h"
#include "gles_renderer/ibl/cube_map.h"
#include "gles_renderer/ibl/sh_projection.h"
#include "gles_renderer/ibl/sphere_samples.h"

namespace lumar {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;
// Texture unit every pass of the pipeline reads its source from, and the sample table's.
constexpr GLint kSourceUnit = 0;
constexpr GLint kSamplesUnit = 1;
// The prefilter's LobeSamples block: its binding point (0 and 1 are the mesh pass's, see
// uniform_blocks.h) and its size in samples (phong_prefilter.frag).
constexpr GLuint kLobeSamplesBinding = 2;
constexpr int kMaxLobeSamples = 512;
// A glossy lobe is integrated where cos^n exceeds this fraction of its peak.
constexpr float kLobeCutoff = 0.01f;
// glossy-2's samples have density ∝ cos^(this x n) (makeLobePrefilter): between the lobe's
// own (1, fewest samples in the tails) and equal solid angles (0). Measured with
// ibl_lookup_test at 104 samples, next to venice's sun: 0.5 gives 0.081 worst, 0.0124 rms;
// 0.375 0.105, 0.0151; 0.625 0.113, 0.0126; 0.75 0.127, 0.0136 (at 112: 0.5 0.073, 0.0110;
// 0.75 0.114, 0.0136).
constexpr double kSampleDensityPower = 0.5;
// The SH sums' fragments each add up kShGroups coefficients (sh_project.glsl's outputs).
constexpr int kShGroups = 3;
// shaders_es/rgbm.glsl's range.
constexpr float kRgbmRange = 16.0f;

void checkSettings(const IblSettings& s)
{
    const auto powerOfTwo = [](int v) { return v >= 4 && v <= 1024 && (v & (v - 1)) == 0; };
    if (!powerOfTwo(s.mirrorSize) || !powerOfTwo(s.diffuseSize) || !powerOfTwo(s.glossy1Size) ||
        !powerOfTwo(s.glossy2Size))
        throw InputError("environment map sizes must be powers of two from 4 to 1024");
    if (s.shSamples < 16 || s.shSamples > 65536 || s.shRows < 1 || s.shRows > 1024 || s.shSamples % s.shRows != 0)
        throw InputError("SH projection needs 16..65536 samples split evenly into 1..1024 partial-sum rows");
    if (s.prefilterSamples < 4 || s.prefilterSamples > kMaxLobeSamples || s.cascadeSamples < 4 ||
        s.cascadeSamples > kMaxLobeSamples || !(s.glossy1Exponent >= 1.0f) || !(s.glossy2Exponent > s.glossy1Exponent))
        throw InputError("glossy prefilter needs 4..512 samples and exponents 1 <= n1 < n2");
}

// A cube map of `size`-px faces as a 2D atlas (shaders_es/cube_atlas.glsl's layout): with
// power-of-two faces every 2 x 2 box of a mip level lies inside one cell, so
// glGenerateMipmap keeps the faces apart down to 1 px.
// `slots` atlases stacked (a bank, ibl_maps.h).
GlTexture makeCubeAtlas(int size, int levels, bool rgbm, int slots = 1)
{
    GlTexture texture = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, texture.name());
    const glm::ivec2 extent = cubeAtlasSize(size) * glm::ivec2(1, slots);
    glTexStorage2D(GL_TEXTURE_2D, levels, rgbm ? GL_RGBA8 : GL_RGBA16F, extent.x, extent.y);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return texture;
}

// A float texture (RGBA32F or RGBA16F) read with texelFetch only.
GlTexture makeFloatTexture(int width, int height, const float* texels, GLenum format = GL_RGBA32F)
{
    GlTexture texture = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D, texture.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, format, width, height);
    if (texels)
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, GL_RGBA, GL_FLOAT, texels);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return texture;
}

// The mip level of a size-px cube whose texels cover about `solidAngle` steradians each.
float lodForSolidAngle(int size, float solidAngle)
{
    const float texelsPerSide = std::sqrt(4.0f * kPi / (6.0f * solidAngle));
    return std::max(0.0f, std::log2(float(size) / texelsPerSide));
}

// The exponent x such that lobe n2 followed by lobe x has the angular variance of lobe n1,
// with a normalised Phong lobe's mean squared angle ~ 2 / (n + 2).
float cascadedExponent(float n1, float n2)
{
    return 1.0f / (1.0f / (n1 + 2.0f) - 1.0f / (n2 + 2.0f)) - 2.0f;
}

glm::mat3 environmentFromFace(int face)
{
    return glm::mat3(glm::transpose(faceCameraFromCube(face)));
}

void bindTextureUnit(GLint unit, GLenum target, GLuint texture)
{
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    glBindTexture(target, texture);
}

} // namespace

IblPipeline::IblPipeline(const IblSettings& settings)
    : settings_(settings), skybox_(linkProgram(kSkyboxProgram)), atlasCopy_(linkProgram(kAtlasCopyProgram)),
      shProject_(linkProgram(kShProjectProgram)), shProjectEquirect_(linkProgram(kShProjectEquirectProgram)),
      shReduce_(linkProgram(kShReduceProgram)), diffuseFromSH_(linkProgram(kDiffuseFromShProgram)),
      phongPrefilter_(linkProgram(kPhongPrefilterProgram)),
      phongPrefilterLevels_(linkProgram(kPhongPrefilterProgram, "#define SAMPLE_LEVELS 1\n"))
{
    checkSettings(settings_);
    // Core GLES 3.0 renders to no float format. EXT_color_buffer_float adds RGBA16F and
    // RGBA32F (the SH sums then keep full precision); EXT_color_buffer_half_float RGBA16F
    // alone, enough for radiance and for sums of 64 samples (11-bit mantissa: ~0.05 %).
    const bool fullFloat = hasGlExtension("GL_EXT_color_buffer_float");
    if (fullFloat && !settings_.halfFloatOnly) {
        sumFormat_ = GL_RGBA32F;
    } else if (fullFloat || hasGlExtension("GL_EXT_color_buffer_half_float")) {
        sumFormat_ = GL_RGBA16F;
    } else {
        rgbm_ = true;
        LUMAR_LOG(Render, Warn)
            << "the GLES implementation renders to no float format (neither "
               "GL_EXT_color_buffer_float nor GL_EXT_color_buffer_half_float): environment maps are "
               "RGBA8 RGBM, their SH sums run on the CPU";
    }
    rgbm_ = rgbm_ || settings_.forceRgbm;

    skyboxEnvironmentFromFace_ = uniformLocation(skybox_, "uEnvironmentFromFace");
    skyboxLod_ = uniformLocation(skybox_, "uLod");
    skyboxIntensity_ = uniformLocation(skybox_, "uIntensity");
    glUseProgram(skybox_.name());
    glUniform1i(uniformLocation(skybox_, "uEquirect"), kSourceUnit);
    glUniform1i(uniformLocation(skybox_, "uRgbm"), rgbm_);

    const int samples = settings_.shSamples;
    glUseProgram(shProject_.name());
    glUniform1i(uniformLocation(shProject_, "uEnvironment"), kSourceUnit);
    glUniform1i(uniformLocation(shProject_, "uSamples"), kSamplesUnit);
    glUniform1f(uniformLocation(shProject_, "uWeight"), 4.0f * kPi / float(samples));
    // Half a level coarser than one texel per sample, read from a single level: every texel
    // then meets a few samples, so a small bright source is counted at its true weight
    // (venice_sunset_1k.hdr: 0.54 % error against 0.95 % at the matched level; a smooth sky
    // loses a little band-2 detail, 0.42 % against 0.11 %).
    shLod_ = lodForSolidAngle(settings_.mirrorSize, 4.0f * kPi / float(samples)) + 0.5f;
    glUseProgram(shProjectEquirect_.name());
    glUniform1i(uniformLocation(shProjectEquirect_, "uEnvironment"), kSourceUnit);
    glUniform1i(uniformLocation(shProjectEquirect_, "uSamples"), kSamplesUnit);
    glUniform1f(uniformLocation(shProjectEquirect_, "uWeight"), 4.0f * kPi / float(samples));
    equirectLod_ = uniformLocation(shProjectEquirect_, "uLod");

    glUseProgram(shReduce_.name());
    glUniform1i(uniformLocation(shReduce_, "uPartialSums"), kSourceUnit);
    glUniform1i(uniformLocation(shReduce_, "uRows"), settings_.shRows);
    glUseProgram(diffuseFromSH_.name());
    glUniform1i(uniformLocation(diffuseFromSH_, "uCoefficients"), kSourceUnit);
    diffuseSlot_ = uniformLocation(diffuseFromSH_, "uSlot");
    diffuseEnvironmentFromFace_ = uniformLocation(diffuseFromSH_, "uEnvironmentFromFace");
    glUniform1i(uniformLocation(diffuseFromSH_, "uRgbm"), rgbm_);
    for (const GlProgram* program : {&phongPrefilter_, &phongPrefilterLevels_}) {
        glUseProgram(program->name());
        glUniform1i(uniformLocation(*program, "uEnvironment"), kSourceUnit);
        bindUniformBlock(*program, "LobeSamples", kLobeSamplesBinding);
        glUniform1i(uniformLocation(*program, "uRgbm"), rgbm_);
    }
    glUseProgram(atlasCopy_.name());
    glUniform1i(uniformLocation(atlasCopy_, "uSource"), kSourceUnit);
    atlasCopyOffset_ = uniformLocation(atlasCopy_, "uOffset");

    // The SH sample set, rows x (N / rows) directions: row i is fragment i's share.
    // The spherical Fibonacci set: equal weights and, unlike a jittered grid, no clumps or
    // gaps, so a small bright source (the sun) read from the matching mip level is counted
    // once: measured 0.6 % SH error on venice_sunset_1k.hdr against 11 % for jittered.
    const std::vector<glm::vec3> directions = fibonacciSphereSamples(samples);
    shDirections_ = directions;
    std::vector<float> texels;
    texels.reserve(directions.size() * 4);
    for (const glm::vec3& d : directions)
        texels.insert(texels.end(), {d.x, d.y, d.z, 0.0f});
    shSamples_ = makeFloatTexture(samples / settings_.shRows, settings_.shRows, texels.data());
    // glossy-2 from the mirror map; glossy-1 from glossy-2 (cascaded: a Phong lobe of
    // exponent n1 is close to n2's followed by the one whose angular variance makes up the
    // difference, and the blurred source needs far fewer samples).
    const int fullChain = int(std::log2(settings_.mirrorSize)) + 1;
    glossy2_ = makeLobePrefilter(settings_.glossy2Exponent, settings_.prefilterSamples, fullChain);
    glossy1_ = makeCapPrefilter(cascadedExponent(settings_.glossy1Exponent, settings_.glossy2Exponent),
                                settings_.cascadeSamples, settings_.glossy2Size);
    // glossy-2's program reads a level per sample; glossy-1's reads its source's single
    // level with a constant lod, llvmpipe's cheaper lookup.
    glossy2_.program = phongPrefilterLevels_.name();
    glossy1_.program = phongPrefilter_.name();
    for (Prefilter* p : {&glossy1_, &glossy2_}) {
        const GLuint program = p->program;
        p->environmentFromFace = glGetUniformLocation(program, "uEnvironmentFromFace");
        p->atlasSize = glGetUniformLocation(program, "uAtlasSize");
        p->slot = glGetUniformLocation(program, "uSlot");
        p->sampleCount = glGetUniformLocation(program, "uSampleCount");
    }
    // The mirror map keeps only the mip levels something reads (the SH and glossy-2 passes
    // read one level each, the mesh shader level 0): llvmpipe builds every level of every
    // face with a blit, 36 of them for a full 64-px chain.
    mirrorLevels_ = std::clamp(std::max(int(std::ceil(shLod_)) + 1, glossy2_.levels), 1, fullChain);
    glUseProgram(shProject_.name());
    shProjectAtlasSize_ = uniformLocation(shProject_, "uAtlasSize");
    shProjectSlot_ = uniformLocation(shProject_, "uSlot");
    shProjectCellOrigin_ = uniformLocation(shProject_, "uCellOrigin");

    // Sources of the sums are read from one mip level (bilinear): the LOD is chosen so a
    // texel is about a sample's solid angle, and blending two levels doubled the cost. The
    // cube's base level is moved to that level for the pass and read without mipmapping
    // (readMirrorLevel): the same texels and weights as LINEAR_MIPMAP_NEAREST at that LOD,
    // but llvmpipe then skips the per-fragment level selection of every fetch.
    singleLevel_ = GlSampler::create();
    glSamplerParameteri(singleLevel_.name(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glSamplerParameteri(singleLevel_.name(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(singleLevel_.name(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(singleLevel_.name(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    nearestLevel_ = GlSampler::create(); // the glossy-2 prefilter: a level per sample
    glSamplerParameteri(nearestLevel_.name(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_NEAREST);
    glSamplerParameteri(nearestLevel_.name(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(nearestLevel_.name(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glSamplerParameteri(nearestLevel_.name(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    nearestLevelWrapped_ = GlSampler::create(); // the same for lat-long maps: longitude wraps
    glSamplerParameteri(nearestLevelWrapped_.name(), GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_NEAREST);
    glSamplerParameteri(nearestLevelWrapped_.name(), GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glSamplerParameteri(nearestLevelWrapped_.name(), GL_TEXTURE_WRAP_S, GL_REPEAT);
    glSamplerParameteri(nearestLevelWrapped_.name(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);

    plainFramebuffer_ = GlFramebuffer::create();
    partialSumsFramebuffer_ = GlFramebuffer::create();
    readFramebuffer_ = GlFramebuffer::create();

    // Every map is its own atlas (cube_atlas.glsl), drawn through these two framebuffers:
    // the mirror maps with a shared depth buffer, the derived maps colour only.
    mirrorAtlasFramebuffer_ = GlFramebuffer::create();
    derivedAtlasFramebuffer_ = GlFramebuffer::create();
    reserveSlots(1);
    checkGlError("creating the environment-map pipeline");
}

void IblPipeline::reserveSlots(int slots) const
{
    if (slots <= reservedSlots_)
        return;
    reservedSlots_ = slots;
    // kShGroups layers of (rows x slots) x kShGroups texels: layer c of row g holds
    // coefficient g x kShGroups + c, each layer a colour attachment of the sums' framebuffer.
    partialSums_ = GlTexture::create();
    glBindTexture(GL_TEXTURE_2D_ARRAY, partialSums_.name());
    glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, sumFormat_, settings_.shRows * slots, kShGroups, kShGroups);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, partialSumsFramebuffer_.name());
    GLenum drawBuffers[kShGroups];
    for (int c = 0; c < kShGroups; ++c) {
        drawBuffers[c] = GLenum(GL_COLOR_ATTACHMENT0 + c);
        glFramebufferTextureLayer(GL_FRAMEBUFFER, drawBuffers[c], partialSums_.name(), 0, c);
    }
    glDrawBuffers(kShGroups, drawBuffers);
    // One depth buffer the size of the largest bank, shared by every mirror pass (a smaller
    // colour attachment limits the area drawn).
    mirrorAtlasDepth_ = GlRenderbuffer::create();
    glBindRenderbuffer(GL_RENDERBUFFER, mirrorAtlasDepth_.name());
    const glm::ivec2 mirrorExtent = cubeAtlasSize(settings_.mirrorSize) * glm::ivec2(1, slots);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, mirrorExtent.x, mirrorExtent.y);
    glBindFramebuffer(GL_FRAMEBUFFER, mirrorAtlasFramebuffer_.name());
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, mirrorAtlasDepth_.name());
    checkGlError("growing the environment-map pipeline's buffers");
}

IblPipeline::Prefilter IblPipeline::uploadPrefilter(const std::vector<glm::vec4>& samples,
                                                    const std::vector<glm::vec2>& levels)
{
    if (samples.size() > size_t(kMaxLobeSamples))
        throw InputError("glossy prefilter needs at most " + std::to_string(kMaxLobeSamples) + " samples");
    // The whole block (std140: a vec4 per entry): uSamples, then uLevels, zeros past the samples.
    std::vector<float> block(size_t(kMaxLobeSamples) * 8, 0.0f);
    for (size_t k = 0; k < samples.size(); ++k) {
        std::memcpy(&block[k * 4], &samples[k].x, 4 * sizeof(float));
        block[(size_t(kMaxLobeSamples) + k) * 4] = levels[k].x;
        block[(size_t(kMaxLobeSamples) + k) * 4 + 1] = levels[k].y;
    }
    Prefilter p;
    p.samples = GlBuffer::create();
    glBindBuffer(GL_UNIFORM_BUFFER, p.samples.name());
    glBufferData(GL_UNIFORM_BUFFER, GLsizeiptr(block.size() * sizeof(float)), block.data(), GL_STATIC_DRAW);
    p.count = int(samples.size());
    for (const glm::vec2& l : levels)
        p.levels = std::max(p.levels, int(l.x) + 1);
    return p;
}

IblPipeline::Prefilter IblPipeline::makeLobePrefilter(float exponent, int count, int sourceLevels) const
{
    // Importance sampling with mip levels (after Krivanek & Colbert's filtered importance
    // sampling, GPU Gems 3 ch. 20): the directions are spread over the lobe's cap with
    // density ∝ cos^m, m = kSampleDensityPower x n, weighted by cos^n / density and
    // normalised (a constant map stays constant), and each is read from the mip level whose
    // texels cover about its own solid angle 1 / (N density): dense, fine samples where the
    // lobe is high, sparse ones from coarse, pre-averaged levels in the tails, so no radiance
    // falls between samples. The level depends on the sample alone, the same for every
    // fragment. m = n (equal weights, the paper's) blurred the lobed sky's peak and aliased
    // venice's sun (ibl_lookup_test: 0.007-0.009 rms at 64-112 samples); m = 0 is the equal
    // solid-angle scheme that needed 144 samples.
    const int size = settings_.mirrorSize;
    const double texelSolidAngle = 4.0 * double(kPi) / (6.0 * double(size) * double(size));
    const double m = kSampleDensityPower * double(exponent);
    // Rounded to float as powerCapSamples takes it, so the density is the directions' own.
    const double cosMax = double(std::pow(kLobeCutoff, 1.0f / exponent));
    const std::vector<glm::vec3> directions = powerCapSamples(count, float(m), float(cosMax));
    std::vector<glm::vec4> samples;
    std::vector<glm::vec2> levels;
    double total = 0.0;
    for (const glm::vec3& d : directions) {
        const double density = powerCapPdf(double(d.z), m, cosMax);
        const double lod = 0.5 * std::log2(1.0 / (double(count) * density) / texelSolidAngle);
        const int level = std::clamp(int(std::lround(lod)), 0, sourceLevels - 1);
        const double weight = std::pow(double(d.z), double(exponent)) / density;
        total += weight;
        samples.emplace_back(d, float(weight));
        // The clamp half a texel of that level inside the face (cube_atlas.glsl's stMin).
        levels.emplace_back(float(level), 0.5f / float(std::max(size >> level, 1)));
    }
    for (glm::vec4& sample : samples)
        sample.w = float(double(sample.w) / total);
    return uploadPrefilter(samples, levels);
}

IblPipeline::Prefilter IblPipeline::makeCapPrefilter(float exponent, int count, int sourceSize) const
{
    // Equal-solid-angle samples of the cap where cos^n >= kLobeCutoff, weighted by cos^n and
    // normalised: the discrete lobe integrates to exactly one, so a constant map stays
    // constant. Read from the source's single level (glossy-2, smooth already).
    const float cosMax = std::pow(kLobeCutoff, 1.0f / exponent);
    const std::vector<glm::vec3> cap = fibonacciCapSamples(count, cosMax);
    double total = 0.0;
    for (const glm::vec3& d : cap)
        total += std::pow(double(std::max(d.z, 0.0f)), double(exponent));
    std::vector<glm::vec4> samples;
    for (const glm::vec3& d : cap)
        samples.emplace_back(d, float(std::pow(double(std::max(d.z, 0.0f)), double(exponent)) / total));
    return uploadPrefilter(samples, std::vector<glm::vec2>(cap.size(), glm::vec2(0.0f, 0.5f / float(sourceSize))));
}

int IblPipeline::maxBankSlots(int wanted) const
{
    constexpr int kLeastMaximumTextureSize = 2048;
    return std::clamp(kLeastMaximumTextureSize / cubeAtlasSize(settings_.mirrorSize).y, 1, std::max(1, wanted));
}

GlTexture IblPipeline::createMirror(int slots) const
{
    return makeCubeAtlas(settings_.mirrorSize, mirrorLevels_, rgbm_, slots);
}

IblMaps IblPipeline::createMaps(int slots) const
{
    if (slots < 1 || slots > maxBankSlots(slots))
        throw InputError("an environment-map bank holds 1 to " + std::to_string(maxBankSlots(1 << 20)) + " sets");
    reserveSlots(slots);
    IblMaps maps;
    maps.slots = slots;
    maps.mirrorLevels = mirrorLevels_;
    maps.mirror = createMirror(slots);
    // RGBM: the CPU writes the coefficients, sampling a float texture needs no extension.
    maps.coefficients =
        makeFloatTexture(slots, 9, nullptr, rgbm_ ? (settings_.halfFloatOnly ? GL_RGBA16F : GL_RGBA32F) : sumFormat_);
    maps.diffuse = makeCubeAtlas(settings_.diffuseSize, 1, rgbm_, slots);
    maps.glossy1 = makeCubeAtlas(settings_.glossy1Size, 1, rgbm_, slots);
    maps.glossy2 = makeCubeAtlas(settings_.glossy2Size, 1, rgbm_, slots);
    checkGlError("allocating environment maps");
    return maps;
}

glm::vec2 IblPipeline::mirrorLevelSize(int level, int slots) const
{
    return glm::vec2(glm::max((cubeAtlasSize(settings_.mirrorSize) * glm::ivec2(1, slots)) >> level, glm::ivec2(1)));
}

int IblPipeline::mirrorLevel(float lod) const
{
    // GLES 3.0 §3.8.10.4: LINEAR_MIPMAP_NEAREST reads the base level up to LOD 1/2, level
    // ceil(lod + 1/2) - 1 above, clamped to the last level.
    return lod <= 0.5f ? 0 : std::min(int(std::ceil(lod + 0.5f)) - 1, mirrorLevels_ - 1);
}

void IblPipeline::renderMirror(IblMaps& maps, const IblMaps* backdrop,
                               const std::function<void(int face)>& drawFace) const
{
    const MirrorSlot slot{0, backdrop ? backdrop->mirror.name() : 0, false, drawFace};
    renderMirrorSlots(maps, std::span(&slot, 1));
}

void IblPipeline::renderMirrorSlots(IblMaps& bank, std::span<const MirrorSlot> slots) const
{
    const int size = settings_.mirrorSize;
    const glm::ivec2 extent = cubeAtlasSize(size);
    glBindFramebuffer(GL_FRAMEBUFFER, mirrorAtlasFramebuffer_.name());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, bank.mirror.name(), 0);
    glDisable(GL_SCISSOR_TEST);
    glDepthMask(GL_TRUE);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    glClear(GL_DEPTH_BUFFER_BIT);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    // The scissor keeps every face in its cell whatever the rasteriser's guard band lets
    // through, and every backdrop in its slot.
    glEnable(GL_SCISSOR_TEST);
    for (const MirrorSlot& s : slots) {
        const glm::ivec2 origin(0, s.slot * extent.y);
        glViewport(origin.x, origin.y, extent.x, extent.y);
        glScissor(origin.x, origin.y, extent.x, extent.y);
        if (s.backdrop == 0) {
            glClear(GL_COLOR_BUFFER_BIT);
            continue;
        }
        // The backdrop's atlas has the same layout: one draw over the whole atlas copies
        // every face, binned into the same scene as the faces drawn over it.
        glUseProgram(atlasCopy_.name());
        const glm::ivec2 offset = s.backdropIsBank ? glm::ivec2(0) : origin;
        glUniform2i(atlasCopyOffset_, offset.x, offset.y);
        bindTextureUnit(kSourceUnit, GL_TEXTURE_2D, s.backdrop);
        glDepthMask(GL_FALSE);
        drawFullscreenTriangle();
        glDepthMask(GL_TRUE);
    }
    for (const MirrorSlot& s : slots) {
        if (!s.drawFace)
            continue;
        for (int face = 0; face < kCubeFaces; ++face) {
            const glm::ivec2 origin = cubeAtlasCellOrigin(face, size) + glm::ivec2(0, s.slot * extent.y);
            glViewport(origin.x, origin.y, size, size);
            glScissor(origin.x, origin.y, size, size);
            s.drawFace(face);
        }
    }
    glDisable(GL_SCISSOR_TEST);
    // Nothing reads the depth buffer after the faces are drawn.
    const GLenum depth = GL_DEPTH_ATTACHMENT;
    glInvalidateFramebuffer(GL_FRAMEBUFFER, 1, &depth);
    // One 2 x 2 box blit per level for all faces of all slots (the cells stay apart,
    // makeCubeAtlas).
    bindTextureUnit(kSourceUnit, GL_TEXTURE_2D, bank.mirror.name());
    glGenerateMipmap(GL_TEXTURE_2D);
}

void IblPipeline::drawSkybox(int face, GLuint equirect, int equirectWidth, float intensity) const
{
    glUseProgram(skybox_.name());
    const glm::mat3 m = environmentFromFace(face);
    glUniformMatrix3fv(skyboxEnvironmentFromFace_, 1, GL_FALSE, glm::value_ptr(m));
    // The equirect's equator has equirectWidth texels round 360 degrees, a face 4 x size.
    glUniform1f(skyboxLod_, std::max(0.0f, std::log2(float(equirectWidth) / float(4 * settings_.mirrorSize))));
    glUniform1f(skyboxIntensity_, intensity);
    bindTextureUnit(kSourceUnit, GL_TEXTURE_2D, equirect);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDepthMask(GL_FALSE);
    drawFullscreenTriangle();
    glDepthMask(GL_TRUE);
}

void IblPipeline::renderFaces(GLuint atlas, int size, std::span<const int> slots, GLuint program,
                              const std::function<void(int slot, int face)>& perFace) const
{
    glBindFramebuffer(GL_FRAMEBUFFER, derivedAtlasFramebuffer_.name());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, atlas, 0);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glUseProgram(program);
    glEnable(GL_SCISSOR_TEST);
    for (const int slot : slots)
        for (int face = 0; face < kCubeFaces; ++face) {
            const glm::ivec2 origin = cubeAtlasCellOrigin(face, size) + glm::ivec2(0, slot * cubeAtlasSize(size).y);
            glViewport(origin.x, origin.y, size, size);
            glScissor(origin.x, origin.y, size, size);
            perFace(slot, face);
            drawFullscreenTriangle();
        }
    glDisable(GL_SCISSOR_TEST);
}

void IblPipeline::sumSamples(GLuint program, GLuint sampler, GLuint coefficients, std::span<const int> slots,
                             const std::function<void(int slot)>& perSlot) const
{
    glBindFramebuffer(GL_FRAMEBUFFER, partialSumsFramebuffer_.name());
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);

    // Pass 1: partial sums, one fragment per (row of samples, group of kShGroups coefficients)
    // writing one coefficient to each attachment, slot k's rows from column k x rows: a
    // sample's radiance is fetched once per group, not once per coefficient (the fetch, not
    // the basis polynomial, is what costs llvmpipe).
    glUseProgram(program);
    bindTextureUnit(kSamplesUnit, GL_TEXTURE_2D, shSamples_.name());
    glBindSampler(GLuint(kSourceUnit), sampler);
    glEnable(GL_SCISSOR_TEST);
    for (const int slot : slots) {
        glViewport(slot * settings_.shRows, 0, settings_.shRows, kShGroups);
        glScissor(slot * settings_.shRows, 0, settings_.shRows, kShGroups);
        perSlot(slot);
        drawFullscreenTriangle();
    }
    glBindSampler(GLuint(kSourceUnit), 0);

    // Pass 2: the sums of each slot's rows, fragment (k, j) into column k of the coefficients.
    glBindFramebuffer(GL_FRAMEBUFFER, plainFramebuffer_.name());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, coefficients, 0);
    glUseProgram(shReduce_.name());
    bindTextureUnit(kSourceUnit, GL_TEXTURE_2D_ARRAY, partialSums_.name());
    for (const int slot : slots) {
        glViewport(slot, 0, 1, 9);
        glScissor(slot, 0, 1, 9);
        drawFullscreenTriangle();
    }
    glDisable(GL_SCISSOR_TEST);
}

void IblPipeline::projectShOnCpu(IblMaps& maps, int slot) const
{
    // Level 0, decoded here: the GPU's mip levels of RGBM texels average the encodings.
    const int size = settings_.mirrorSize;
    const int slotOrigin = slot * cubeAtlasSize(size).y;
    CubeMapF cube;
    cube.size = size;
    std::vector<uint8_t> texels(size_t(size) * size_t(size) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, readFramebuffer_.name());
    glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, maps.mirror.name(), 0);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    for (int face = 0; face < kCubeFaces; ++face) {
        const glm::ivec2 origin = cubeAtlasCellOrigin(face, size);
        glReadPixels(origin.x, origin.y + slotOrigin, size, size, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
        ImageF& image = cube.faces[size_t(face)];
        image = ImageF(size, size, 3);
        for (size_t i = 0; i < size_t(size) * size_t(size); ++i) {
            const float scale = float(texels[i * 4 + 3]) / 255.0f * kRgbmRange / 255.0f;
            for (size_t c = 0; c < 3; ++c)
                image.data[i * 3 + c] = float(texels[i * 4 + c]) * scale;
        }
    }
    const SH9 sh = projectSH9Uniform(shDirections_, [&](glm::vec3 d) { return sampleCubeBilinear(cube, d); });
    float block[9 * 4] = {};
    for (size_t j = 0; j < 9; ++j)
        for (size_t c = 0; c < 3; ++c)
            block[j * 4 + c] = sh[j][int(c)];
    glBindTexture(GL_TEXTURE_2D, maps.coefficients.name());
    glTexSubImage2D(GL_TEXTURE_2D, 0, slot, 0, 1, 9, GL_RGBA, GL_FLOAT, block);
}

void IblPipeline::projectEquirectSH(GLuint equirect, int equirectWidth, IblMaps& maps) const
{
    if (rgbm_)
        throw RuntimeError("the lat-long SH projection needs float render targets");
    // A lat-long map of width W has W^2 / 2 texels, W^2 / 2^(2L+1) at level L: about one per
    // sample where that equals N (texels near the poles cover less, which the samples'
    // equal weights already account for).
    const int samples = settings_.shSamples;
    const float lod = std::max(0.0f, std::log2(float(equirectWidth) / std::sqrt(2.0f * float(samples))));
    glUseProgram(shProjectEquirect_.name());
    glUniform1f(equirectLod_, lod);
    bindTextureUnit(kSourceUnit, GL_TEXTURE_2D, equirect);
    const int slot = 0;
    sumSamples(shProjectEquirect_.name(), nearestLevelWrapped_.name(), maps.coefficients.name(), std::span(&slot, 1),
               [](int) {});
}

void IblPipeline::readMirrorLevel(const IblMaps& maps, float lod, const std::function<void()>& pass) const
{
    bindTextureUnit(kSourceUnit, GL_TEXTURE_2D, maps.mirror.name());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, mirrorLevel(lod));
    glBindSampler(GLuint(kSourceUnit), singleLevel_.name());
    pass();
    glBindSampler(GLuint(kSourceUnit), 0);
    bindTextureUnit(kSourceUnit, GL_TEXTURE_2D, maps.mirror.name());
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_BASE_LEVEL, 0);
}

void IblPipeline::projectSH(IblMaps& maps) const
{
    const int slot = 0;
    projectSHSlots(maps, std::span(&slot, 1));
}

void IblPipeline::projectSHSlots(IblMaps& bank, std::span<const int> slots) const
{
    if (slots.empty())
        return;
    if (rgbm_) {
        for (const int slot : slots)
            projectShOnCpu(bank, slot);
    } else {
        const glm::vec2 source = mirrorLevelSize(mirrorLevel(shLod_), bank.slots);
        readMirrorLevel(bank, shLod_, [&] {
            sumSamples(shProject_.name(), singleLevel_.name(), bank.coefficients.name(), slots, [&](int slot) {
                glUniform2f(shProjectAtlasSize_, source.x, source.y);
                glUniform2f(shProjectSlot_, float(slot), float(bank.slots));
                glUniform2i(shProjectCellOrigin_, slot * settings_.shRows, 0);
            });
        });
    }

    // The diffuse maps from the nine coefficients.
    bindTextureUnit(kSourceUnit, GL_TEXTURE_2D, bank.coefficients.name());
    renderFaces(bank.diffuse.name(), settings_.diffuseSize, slots, diffuseFromSH_.name(), [&](int slot, int face) {
        const glm::mat3 m = environmentFromFace(face);
        glUniformMatrix3fv(diffuseEnvironmentFromFace_, 1, GL_FALSE, glm::value_ptr(m));
        glUniform1i(diffuseSlot_, slot);
    });
}

void IblPipeline::prefilter(IblMaps& maps) const
{
    const int slot = 0;
    prefilterSlots(maps, std::span(&slot, 1));
}

void IblPipeline::prefilterSlots(IblMaps& bank, std::span<const int> slots) const
{
    prefilterSlots(bank, slots, slots);
}

void IblPipeline::prefilterSlots(IblMaps& bank, std::span<const int> glossy2Slots,
                                 std::span<const int> glossy1Slots) const
{
    if (glossy2Slots.empty())
        return;
    // source: the size of the bank's level read.
    const auto run = [&](const Prefilter& p, std::span<const int> slots, GLuint atlas, int size, glm::vec2 source) {
        if (slots.empty())
            return;
        glBindBufferBase(GL_UNIFORM_BUFFER, kLobeSamplesBinding, p.samples.name());
        renderFaces(atlas, size, slots, p.program, [&](int slot, int face) {
            const glm::mat3 m = environmentFromFace(face);
            glUniformMatrix3fv(p.environmentFromFace, 1, GL_FALSE, glm::value_ptr(m));
            glUniform2f(p.atlasSize, source.x, source.y);
            glUniform2f(p.slot, float(slot), float(bank.slots));
            glUniform1i(p.sampleCount, p.count);
        });
    };
    // Every mirror level, the level of each sample's own choosing (LINEAR_MIPMAP_NEAREST).
    bindTextureUnit(kSourceUnit, GL_TEXTURE_2D, bank.mirror.name());
    glBindSampler(GLuint(kSourceUnit), nearestLevel_.name());
    run(glossy2_, glossy2Slots, bank.glossy2.name(), settings_.glossy2Size, mirrorLevelSize(0, bank.slots));
    glBindSampler(GLuint(kSourceUnit), 0);
    // glossy-2 has a single level: read as it is.
    bindTextureUnit(kSourceUnit, GL_TEXTURE_2D, bank.glossy2.name());
    run(glossy1_, glossy1Slots, bank.glossy1.name(), settings_.glossy1Size,
        glm::vec2(cubeAtlasSize(settings_.glossy2Size) * glm::ivec2(1, bank.slots)));
    bank.ready = true;
}

void IblPipeline::updateDerivedMaps(IblMaps& maps) const
{
    projectSH(maps);
    prefilter(maps);
}

} // namespace lumar
