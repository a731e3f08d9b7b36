#include "gles_renderer/scene/camera_environment.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/gtc/type_ptr.hpp>

#include "core/error.h"
#include "gles_renderer/gl/fullscreen_triangle.h"
#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/gl/gpu_texture.h"
#include "gles_renderer/gl/shader_program.h"
#include "gles_renderer/ibl/cube_face_camera.h"

namespace lumar {
namespace {

// Texture units of the two passes.
constexpr GLint kRadianceUnit = 0;
constexpr GLint kWeightUnit = 1;
constexpr GLint kCameraUnit = 2;
constexpr GLint kEquirectUnit = 3;
// Past the camera image's last mip level: textureLod clamps to it, the image's mean.
constexpr float kLastLevel = 32.0f;

GlTexture makeMapTexture(GLenum format, int width, int height)
{
    // The skybox reads it bilinearly (longitude wraps); the accumulation with texelFetch.
    return makeRenderTexture(format, width, height, GL_LINEAR, GL_REPEAT);
}

void bindTextureUnit(GLint unit, GLuint texture)
{
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    glBindTexture(GL_TEXTURE_2D, texture);
}

} // namespace

CameraEnvironment::CameraEnvironment(bool rgbm, int width)
    : rgbm_(rgbm), width_(width), height_(width / 2), accumulate_(linkProgram(kCameraEnvironmentAccumulateProgram)),
      skybox_(linkProgram(kCameraEnvironmentSkyboxProgram))
{
    if (width_ < 4 || width_ > 4096)
        throw InputError("the camera environment map needs 4..4096 texels round");
    buffers_[0] = makeBuffer();
    buffers_[1] = makeBuffer();

    glUseProgram(accumulate_.name());
    glUniform1i(uniformLocation(accumulate_, "uPreviousRadiance"), kRadianceUnit);
    glUniform1i(uniformLocation(accumulate_, "uPreviousWeight"), kWeightUnit);
    glUniform1i(uniformLocation(accumulate_, "uCamera"), kCameraUnit);
    glUniform1f(uniformLocation(accumulate_, "uMaxWeight"), kMaxWeight);
    glUniform1i(uniformLocation(accumulate_, "uRgbm"), rgbm_);
    accumulateCameraFromEnvironment_ = uniformLocation(accumulate_, "uCameraFromEnvironment");
    accumulateClipFromCamera_ = uniformLocation(accumulate_, "uClipFromCamera");
    accumulateExposure_ = uniformLocation(accumulate_, "uExposure");

    glUseProgram(skybox_.name());
    glUniform1i(uniformLocation(skybox_, "uRadiance"), kRadianceUnit);
    glUniform1i(uniformLocation(skybox_, "uWeight"), kWeightUnit);
    glUniform1i(uniformLocation(skybox_, "uCamera"), kCameraUnit);
    glUniform1i(uniformLocation(skybox_, "uEquirect"), kEquirectUnit);
    glUniform1f(uniformLocation(skybox_, "uMaxWeight"), kMaxWeight);
    glUniform1i(uniformLocation(skybox_, "uRgbm"), rgbm_);
    skyboxEnvironmentFromFace_ = uniformLocation(skybox_, "uEnvironmentFromFace");
    skyboxFillFromHdr_ = uniformLocation(skybox_, "uFillFromHdr");
    skyboxEquirectLod_ = uniformLocation(skybox_, "uEquirectLod");
    skyboxCameraLod_ = uniformLocation(skybox_, "uCameraLod");
    skyboxExposure_ = uniformLocation(skybox_, "uExposure");
    reset();
    checkGlError("creating the camera environment");
}

CameraEnvironment::Buffer CameraEnvironment::makeBuffer() const
{
    Buffer buffer;
    buffer.radiance = makeMapTexture(rgbm_ ? GL_RGBA8 : GL_RGBA16F, width_, height_);
    buffer.weight = makeMapTexture(GL_R8, width_, height_);
    buffer.framebuffer = GlFramebuffer::create();
    glBindFramebuffer(GL_FRAMEBUFFER, buffer.framebuffer.name());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, buffer.radiance.name(), 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, buffer.weight.name(), 0);
    const GLenum attachments[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    glDrawBuffers(2, attachments);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw RuntimeError("the camera environment's framebuffer is incomplete");
    return buffer;
}

void CameraEnvironment::reset()
{
    // Zero radiance and weight: nothing seen (RGBM zero decodes to black as well).
    const GLfloat zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    for (Buffer& buffer : buffers_) {
        glBindFramebuffer(GL_FRAMEBUFFER, buffer.framebuffer.name());
        glClearBufferfv(GL_COLOR, 0, zero);
        glClearBufferfv(GL_COLOR, 1, zero);
    }
    current_ = 0;
}

void CameraEnvironment::accumulate(const CameraView& camera, const glm::dmat3& environmentFromCamera, float exposure)
{
    if (camera.texture == 0)
        return;
    const Buffer& previous = buffers_[current_];
    const Buffer& next = buffers_[1 - current_];
    glBindFramebuffer(GL_FRAMEBUFFER, next.framebuffer.name());
    glViewport(0, 0, width_, height_);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glDepthMask(GL_FALSE);
    glUseProgram(accumulate_.name());
    const glm::mat3 cameraFromEnvironment(glm::transpose(environmentFromCamera));
    glUniformMatrix3fv(accumulateCameraFromEnvironment_, 1, GL_FALSE, glm::value_ptr(cameraFromEnvironment));
    glUniformMatrix4fv(accumulateClipFromCamera_, 1, GL_FALSE, glm::value_ptr(camera.clipFromCamera));
    glUniform1f(accumulateExposure_, exposure);
    bindTextureUnit(kRadianceUnit, previous.radiance.name());
    bindTextureUnit(kWeightUnit, previous.weight.name());
    bindTextureUnit(kCameraUnit, camera.texture);
    drawFullscreenTriangle();
    glDepthMask(GL_TRUE);
    current_ = 1 - current_;
    checkGlError("projecting the camera image into the environment");
}

void CameraEnvironment::drawSkybox(int face, int faceSize, GLuint equirect, int equirectWidth, const CameraView& camera,
                                   float exposure) const
{
    const Buffer& map = buffers_[current_];
    glUseProgram(skybox_.name());
    const glm::mat3 environmentFromFace(glm::transpose(faceCameraFromCube(face)));
    glUniformMatrix3fv(skyboxEnvironmentFromFace_, 1, GL_FALSE, glm::value_ptr(environmentFromFace));
    glUniform1i(skyboxFillFromHdr_, equirect != 0);
    glUniform1f(skyboxEquirectLod_, std::max(0.0f, std::log2(float(equirectWidth) / float(4 * faceSize))));
    glUniform1f(skyboxCameraLod_, kLastLevel);
    glUniform1f(skyboxExposure_, exposure);
    bindTextureUnit(kRadianceUnit, map.radiance.name());
    bindTextureUnit(kWeightUnit, map.weight.name());
    bindTextureUnit(kCameraUnit, camera.texture);
    bindTextureUnit(kEquirectUnit, equirect);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glDepthMask(GL_FALSE);
    drawFullscreenTriangle();
    glDepthMask(GL_TRUE);
}

double CameraEnvironment::coverage() const
{
    std::vector<uint8_t> texels(size_t(width_) * size_t(height_) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, buffers_[current_].framebuffer.name());
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    checkGlError("reading the camera environment's coverage");
    // Row y spans polar angles y..y+1 of height_ * pi: solid angle in proportion to sin(theta).
    double seen = 0.0, total = 0.0;
    for (int y = 0; y < height_; ++y) {
        const double solidAngle = std::sin((y + 0.5) / height_ * std::numbers::pi);
        for (int x = 0; x < width_; ++x) {
            total += solidAngle;
            if (texels[(size_t(y) * size_t(width_) + size_t(x)) * 4] > 0)
                seen += solidAngle;
        }
    }
    return total > 0.0 ? seen / total : 0.0;
}

} // namespace lumar
