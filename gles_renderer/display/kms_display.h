// The DRM/KMS display sink (DESIGN.md §7): a DRM device chosen by the board profile, a GBM
// scan-out surface with an EGL window surface on EGL's GBM platform, and a KMS output that
// flips the surface's front buffers onto a plane. The renderer draws on this display's EGL
// display and copies each finished frame into the window (SceneRenderer::present), so the
// frame never leaves the GPU.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gles_renderer/display/drm_device.h"
#include "gles_renderer/display/gbm_surface.h"
#include "gles_renderer/display/kms_output.h"
#include "gles_renderer/gl/egl_context.h"
#include "gles_renderer/gl/window_target.h"

namespace lumar {

struct KmsDisplayOptions {
    std::string device = "auto";      // a /dev/dri/card* path, or "auto": by `drivers`
    std::vector<std::string> drivers; // drmGetVersion names in preference order; empty: any
    KmsPreferences output;
    bool modifiers = true;  // false: framebuffers without format modifiers (linear)
    bool legacyApi = false; // true: SetCrtc + PageFlip even where the driver has atomic
    // The commits carry no in-fence: the kernel waits for rendering through the buffer's
    // implicit fences. true (board quirk no-native-fence): glFinish before each flip instead,
    // for stacks without implicit sync.
    bool finishBeforeFlip = false;
};

class KmsDisplay final : public WindowTarget {
public:
    // nullptr when there is no usable DRM device, with `why` saying what was found (for the
    // "falling back to headless" log line). Throws RuntimeError when a device exists but
    // cannot be driven (no plane, GBM or EGL failure).
    static std::unique_ptr<KmsDisplay> open(const KmsDisplayOptions& options, std::string& why);
    ~KmsDisplay() override;
    KmsDisplay(const KmsDisplay&) = delete;
    KmsDisplay& operator=(const KmsDisplay&) = delete;

    // The display every renderer presenting here must create its context on.
    [[nodiscard]] const std::shared_ptr<EglDisplay>& eglDisplay() const override { return eglDisplay_; }
    [[nodiscard]] EGLSurface surface() const override { return eglSurface_->handle(); }
    [[nodiscard]] int width() const override { return output_->width(); }
    [[nodiscard]] int height() const override { return output_->height(); }
    [[nodiscard]] bool finishBeforeSwap() const override { return finishBeforeFlip_; }
    void showSwapped() override;
    [[nodiscard]] std::optional<Presentation> presentedDuringLastSwap() const override { return presented_; }

    [[nodiscard]] std::string describe() const { return output_->describe(); }
    [[nodiscard]] uint64_t framesShown() const { return framesShown_; }
    [[nodiscard]] uint64_t flipsCompleted() const { return output_->flipsCompleted(); }

private:
    KmsDisplay(DrmDevice device, const KmsDisplayOptions& options);

    // Destroyed in reverse: buffers back to the surface, the EGL surface and display, the
    // GBM surface and device, the output's mode blob, and last the DRM node.
    DrmDevice drm_;
    std::unique_ptr<KmsOutput> output_;
    GbmDevice gbm_;
    GbmSurface gbmSurface_;
    std::shared_ptr<EglDisplay> eglDisplay_;
    std::optional<EglWindowSurface> eglSurface_;
    LockedBuffer shown_;  // on screen
    LockedBuffer queued_; // committed, on screen from the next flip
    bool modifiers_ = true;
    bool finishBeforeFlip_ = false;
    uint64_t framesShown_ = 0;
    std::optional<Presentation> presented_;
};

} // namespace lumar
