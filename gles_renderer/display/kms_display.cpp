#include "gles_renderer/display/kms_display.h"

#include <utility>

#include "core/error.h"
#include "core/log.h"
#include "core/monotonic_clock.h"

namespace lumar {

std::unique_ptr<KmsDisplay> KmsDisplay::open(const KmsDisplayOptions& options, std::string& why)
{
    std::optional<DrmDevice> device;
    if (options.device != "auto") {
        if (!std::filesystem::exists(options.device)) {
            why = options.device + " does not exist";
            return nullptr;
        }
        device.emplace(options.device);
    } else {
        device = DrmDevice::openPreferred(options.drivers, why);
        if (!device)
            return nullptr;
    }
    if (options.legacyApi)
        device->useLegacyApi();
    return std::unique_ptr<KmsDisplay>(new KmsDisplay(std::move(*device), options));
}

KmsDisplay::KmsDisplay(DrmDevice device, const KmsDisplayOptions& options)
    : drm_(std::move(device)), output_(std::make_unique<KmsOutput>(drm_, options.output)), gbm_(drm_.fd()),
      gbmSurface_(gbm_, output_->width(), output_->height(), output_->format()),
      eglDisplay_(EglDisplay::gbm(gbm_.handle())), modifiers_(options.modifiers),
      finishBeforeFlip_(options.finishBeforeFlip)
{
    eglSurface_.emplace(eglDisplay_, gbmSurface_.handle(), output_->format());
    LUMAR_LOG(Output, Info) << "KMS output: " << drm_.path().string() << " " << output_->describe();
}

KmsDisplay::~KmsDisplay()
{
    // Let the last flip land before its buffers go back to GBM and their framebuffers are
    // removed (KmsOutput's destructor waits too; this one runs first).
    output_->waitForFlip(100);
}

void KmsDisplay::showSwapped()
{
    LockedBuffer next(gbmSurface_);
    const uint32_t framebuffer = next.framebuffer(drm_.fd(), modifiers_);
    // show() first waits for the flip still queued: after it the queued buffer is on screen
    // and the one it replaced goes back to GBM (the move releases it).
    const uint64_t flipsBefore = output_->flipsCompleted();
    output_->show(framebuffer);
    presented_.reset();
    if (queued_.valid()) {
        shown_ = std::move(queued_);
        if (output_->flipsCompleted() != flipsBefore)
            presented_ = Presentation{output_->lastFlipNs(), 1};
    }
    if (output_->flipPending()) {
        queued_ = std::move(next);
    } else {
        shown_ = std::move(next); // a legacy mode-set shows the buffer at once
        presented_ = Presentation{monotonicClockNs(), 0};
    }
    ++framesShown_;
}

} // namespace lumar
