// Pass 1 of a frame: the camera image copied into the whole framebuffer, bit-exact. A
// single-sampled target gets it uploaded straight into its colour texture (no draw at all);
// a multisampled one gets it drawn by a fullscreen triangle from a persistent texture.
// A YCbCr frame (NV12, YUYV) is uploaded as its planes and converted to RGB by a fullscreen
// triangle (background_ycbcr.frag), matching the CPU converter within one code value. A
// zero-copy frame (a lent camera buffer) is imported as dmabuf textures instead where the
// display can (dmabuf_image.h), else uploaded straight from the buffer's mapping.
#pragma once

#include <memory>
#include <vector>

#include "core/image.h"
#include "core/ycbcr_image.h"
#include "gles_renderer/gl/dmabuf_image.h"
#include "gles_renderer/gl/gl_object.h"
#include "gles_renderer/gl/render_target.h"

namespace lumar {

// Rows of the camera image expanded to RGBA and uploaded at a time.
inline constexpr int kUploadRowsPerStrip = 64;

class EglDisplay;

class BackgroundPass {
public:
    // The texture unit the camera image is bound to while drawing.
    static constexpr GLuint kTextureUnit = 5;

    // `target` must outlive the pass.
    explicit BackgroundPass(const RenderTarget& target);

    // Puts `rgb` (3 channels, the target's size, row 0 at the top) into every pixel of the
    // target, which must be bound for drawing. Throws InputError when the shape differs.
    void draw(const Image8& rgb)
    {
        upload(rgb);
        drawUploaded();
    }
    // draw()'s two steps, so the renderer can reduce the maps' camera image from the same
    // frame on another thread while upload() runs. upload() needs no target bound; where it
    // writes the target's texture itself, drawUploaded() does nothing.
    void upload(const Image8& rgb);
    void drawUploaded();
    // The same from YCbCr planes (not const: the textures are created on first use and
    // recreated when the layout changes). Throws InputError for an empty image, a size other
    // than the target's, or planes smaller than their size and stride need.
    void draw(const YCbCrImage& ycbcr);

    // The second texture unit of the YCbCr path (chroma or packed YUYV).
    static constexpr GLuint kChromaTextureUnit = 6;

    // Lets zero-copy frames be imported from their dmabufs on `display` (which must outlive
    // the pass), where it and the current context can take buffers of `origin`; without this
    // call, or where they cannot, they are uploaded. The context must be current.
    void enableDmabufImport(const EglDisplay& display, DmabufOrigin origin = DmabufOrigin::OtherDevice);
    // The importer, for tests and logs; null until enableDmabufImport.
    [[nodiscard]] const DmabufImporter* dmabufImporter() const { return importer_.get(); }
    // Frames drawn from imported dmabufs so far.
    [[nodiscard]] uint64_t importedFrames() const { return importedFrames_; }

private:
    void uploadInto(GLuint texture, const Image8& rgb);
    void prepareYcbcr(YCbCrLayout layout);
    // Lets go of the camera buffer the last imported frame was drawn from, once the GPU is done.
    void releaseHeldBuffer();

    int width_;
    int height_;
    GLuint targetTexture_; // the target's colour texture; 0 when multisampled
    // Only for multisampled targets:
    GlProgram program_;
    GlTexture texture_;
    // RGBA staging for uploads, kUploadRowsPerStrip rows of it (not a whole frame: resident
    // memory is a target too).
    std::vector<uint8_t> strip_;
    // The YCbCr path, created on its first frame:
    GlProgram ycbcrProgram_;
    GlTexture lumaTexture_;   // NV12 Y plane, R8
    GlTexture chromaTexture_; // NV12 Cb Cr, RG8 of half size; YUYV rows, RGBA8 of half width
    YCbCrLayout texturesLayout_ = YCbCrLayout::None;
    GLint layoutLocation_ = -1;
    GLint bt709Location_ = -1;
    GLint fullRangeLocation_ = -1;
    // Zero-copy: the importer, and the camera buffer the GPU may still be sampling (an
    // imported one is read when the GPU runs, not when draw() returns), held until the fence
    // after its draw has passed so the driver cannot refill it under the GPU.
    std::unique_ptr<DmabufImporter> importer_;
    std::shared_ptr<const CameraBuffer> heldBuffer_;
    GlFence heldFence_;
    uint64_t importedFrames_ = 0;
};

} // namespace lumar
