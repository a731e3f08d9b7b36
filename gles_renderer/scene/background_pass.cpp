#include "gles_renderer/scene/background_pass.h"

#include <algorithm>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/log.h"
#include "core/pixel_pack.h"
#include "gles_renderer/gl/fullscreen_triangle.h"
#include "gles_renderer/gl/gl_check.h"
#include "gles_renderer/gl/shader_program.h"
#include "gles_renderer/scene/frame_shape.h"

namespace lumar {

namespace {

// Allocates `texture` (bound to the active unit) with nearest filtering: the shader reads
// texels with texelFetch only.
void allocateTexture(const GlTexture& texture, GLenum internalFormat, int width, int height)
{
    glBindTexture(GL_TEXTURE_2D, texture.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, internalFormat, width, height);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
}

// Uploads `rows` rows of a plane whose rows are `stride` bytes apart, as `width` texels of
// `texelBytes` each; throws InputError when the plane is too small.
void uploadPlane(const uint8_t* plane, size_t planeSize, size_t stride, int width, int rows, size_t texelBytes,
                 GLenum format, const char* what)
{
    const size_t rowBytes = size_t(width) * texelBytes;
    if (plane == nullptr || stride < rowBytes || planeSize < stride * size_t(rows - 1) + rowBytes)
        throw InputError(std::string("YCbCr background: the ") + what + " plane holds " + std::to_string(planeSize) +
                         " bytes with stride " + std::to_string(stride) + ", " + std::to_string(rows) + " rows of " +
                         std::to_string(rowBytes) + " bytes are needed");
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (stride % texelBytes == 0) {
        // The padding is whole texels: one upload skips it.
        glPixelStorei(GL_UNPACK_ROW_LENGTH, GLint(stride / texelBytes));
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, rows, format, GL_UNSIGNED_BYTE, plane);
        glPixelStorei(GL_UNPACK_ROW_LENGTH, 0);
        return;
    }
    // A stride that splits a texel (YUYV rows padded by 2 bytes) cannot be a row length.
    for (int row = 0; row < rows; ++row)
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, row, width, 1, format, GL_UNSIGNED_BYTE, plane + stride * size_t(row));
}

} // namespace

BackgroundPass::BackgroundPass(const RenderTarget& target)
    : width_(target.width()), height_(target.height()), targetTexture_(target.colourTexture())
{
    if (targetTexture_ != 0)
        return;
    program_ = linkProgram(kBackgroundProgram);
    texture_ = GlTexture::create();
    glUseProgram(program_.name());
    glUniform1i(uniformLocation(program_, "uCamera"), GLint(kTextureUnit));

    glActiveTexture(GL_TEXTURE0 + kTextureUnit);
    glBindTexture(GL_TEXTURE_2D, texture_.name());
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA8, width_, height_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    checkGlError("creating the background pass");
}

void BackgroundPass::uploadInto(GLuint texture, const Image8& rgb)
{
    strip_.resize(size_t(width_) * size_t(std::min(height_, kUploadRowsPerStrip)) * 4);
    glActiveTexture(GL_TEXTURE0 + kTextureUnit);
    glBindTexture(GL_TEXTURE_2D, texture);
    // RGBA rows straight into the RGBA8 texture, a strip at a time: the driver copies rows of
    // its own layout as they are, where RGB rows took a per-pixel conversion inside Mesa that
    // cost more than this loop and the copy together (1280 x 720: ~1 ms of the frame). Image
    // row y goes to texture row y, which the target keeps as image row y (see clipFromCamera).
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    const uint8_t* in = rgb.data.data();
    for (int y = 0; y < height_; y += kUploadRowsPerStrip) {
        const int rows = std::min(kUploadRowsPerStrip, height_ - y);
        const size_t pixels = size_t(width_) * size_t(rows);
        expandRgbToRgba(in, strip_.data(), pixels);
        in += pixels * 3;
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, y, width_, rows, GL_RGBA, GL_UNSIGNED_BYTE, strip_.data());
    }
}

void BackgroundPass::upload(const Image8& rgb)
{
    releaseHeldBuffer();
    checkRgbFrame(rgb, width_, height_, "background image");
    if (targetTexture_ != 0) {
        // Straight into the framebuffer's own texture: the copy is exact by construction and
        // costs no fragment work.
        uploadInto(targetTexture_, rgb);
        glBindTexture(GL_TEXTURE_2D, 0); // never leave the render target bound for sampling
        return;
    }
    uploadInto(texture_.name(), rgb);
}

void BackgroundPass::drawUploaded()
{
    if (targetTexture_ != 0)
        return;
    glActiveTexture(GL_TEXTURE0 + kTextureUnit);
    glBindTexture(GL_TEXTURE_2D, texture_.name());
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glUseProgram(program_.name());
    drawFullscreenTriangle();
}

void BackgroundPass::prepareYcbcr(YCbCrLayout layout)
{
    if (ycbcrProgram_.name() == 0) {
        ycbcrProgram_ = linkProgram(kBackgroundYcbcrProgram);
        glUseProgram(ycbcrProgram_.name());
        glUniform1i(uniformLocation(ycbcrProgram_, "uLuma"), GLint(kTextureUnit));
        glUniform1i(uniformLocation(ycbcrProgram_, "uChroma"), GLint(kChromaTextureUnit));
        layoutLocation_ = uniformLocation(ycbcrProgram_, "uLayout");
        bt709Location_ = uniformLocation(ycbcrProgram_, "uBt709");
        fullRangeLocation_ = uniformLocation(ycbcrProgram_, "uFullRange");
    }
    if (texturesLayout_ == layout)
        return;
    // Immutable storage: a new layout gets new textures.
    lumaTexture_ = GlTexture::create();
    chromaTexture_ = GlTexture::create();
    glActiveTexture(GL_TEXTURE0 + kTextureUnit);
    allocateTexture(lumaTexture_, GL_R8, layout == YCbCrLayout::Nv12 ? width_ : 1,
                    layout == YCbCrLayout::Nv12 ? height_ : 1);
    glActiveTexture(GL_TEXTURE0 + kChromaTextureUnit);
    if (layout == YCbCrLayout::Nv12)
        allocateTexture(chromaTexture_, GL_RG8, width_ / 2, height_ / 2);
    else
        allocateTexture(chromaTexture_, GL_RGBA8, width_ / 2, height_);
    texturesLayout_ = layout;
    checkGlError("creating the YCbCr background textures");
}

void BackgroundPass::draw(const YCbCrImage& ycbcr)
{
    if (ycbcr.empty() || ycbcr.width != width_ || ycbcr.height != height_ || width_ % 2 != 0 ||
        (ycbcr.layout == YCbCrLayout::Nv12 && height_ % 2 != 0))
        throw InputError("YCbCr background is " + std::to_string(ycbcr.width) + "x" + std::to_string(ycbcr.height) +
                         (ycbcr.empty() ? " without a layout" : "") + ", the renderer needs " + std::to_string(width_) +
                         "x" + std::to_string(height_) + " (even width; even height for NV12)");
    releaseHeldBuffer();
    prepareYcbcr(ycbcr.layout);
    const bool nv12 = ycbcr.layout == YCbCrLayout::Nv12;
    const DmabufTextures* imported = importer_ ? importer_->texturesFor(ycbcr) : nullptr;
    if (imported != nullptr) {
        glActiveTexture(GL_TEXTURE0 + kTextureUnit);
        glBindTexture(GL_TEXTURE_2D, imported->luma != 0 ? imported->luma : lumaTexture_.name());
        glActiveTexture(GL_TEXTURE0 + kChromaTextureUnit);
        glBindTexture(GL_TEXTURE_2D, imported->chroma);
    } else {
        glActiveTexture(GL_TEXTURE0 + kTextureUnit);
        glBindTexture(GL_TEXTURE_2D, lumaTexture_.name());
        if (nv12)
            uploadPlane(ycbcr.planeData(0), ycbcr.planeSize(0), ycbcr.stride0, width_, height_, 1, GL_RED, "Y");
        glActiveTexture(GL_TEXTURE0 + kChromaTextureUnit);
        glBindTexture(GL_TEXTURE_2D, chromaTexture_.name());
        if (nv12)
            uploadPlane(ycbcr.planeData(1), ycbcr.planeSize(1), ycbcr.stride1, width_ / 2, height_ / 2, 2, GL_RG,
                        "CbCr");
        else
            uploadPlane(ycbcr.planeData(0), ycbcr.planeSize(0), ycbcr.stride0, width_ / 2, height_, 4, GL_RGBA, "YUYV");
    }

    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glUseProgram(ycbcrProgram_.name());
    glUniform1i(layoutLocation_, nv12 ? 0 : 1);
    glUniform1i(bt709Location_, ycbcr.colorimetry.matrix == YCbCrMatrix::Bt709 ? 1 : 0);
    glUniform1i(fullRangeLocation_, ycbcr.colorimetry.fullRange ? 1 : 0);
    drawFullscreenTriangle();
    if (imported != nullptr) {
        heldBuffer_ = ycbcr.buffer;
        heldFence_ = GlFence::insert();
        ++importedFrames_;
    }
}

void BackgroundPass::enableDmabufImport(const EglDisplay& display, DmabufOrigin origin)
{
    importer_ = std::make_unique<DmabufImporter>(display, origin);
}

void BackgroundPass::releaseHeldBuffer()
{
    if (!heldBuffer_)
        return;
    // A frame's draw is long done by the next frame's; the bound only guards a hung GPU,
    // which the watchdog catches (the buffer is then released anyway).
    constexpr uint64_t kWaitNs = 1'000'000'000;
    if (!heldFence_.wait(kWaitNs))
        LUMAR_LOG(Render, Warn) << "the GPU is still reading a camera buffer after 1 s; releasing it anyway";
    heldFence_.reset();
    heldBuffer_.reset();
}

} // namespace lumar
