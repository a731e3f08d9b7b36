#include "capture/prefetching_source.h"

#include <utility>

#include "core/monotonic_clock.h"

namespace lumar {

PrefetchOptions prefetchOptionsFor(const std::string& cameraSource, bool realTime)
{
    PrefetchOptions options;
    if (cameraSource == "v4l2" || cameraSource == "libcamera")
        options.mode = PrefetchMode::LatestOnly;
    else if (cameraSource == "fake" && realTime)
        options.mode = PrefetchMode::JustInTime;
    return options;
}

PrefetchingSource::PrefetchingSource(std::unique_ptr<CaptureSource> inner, PrefetchOptions options)
    : inner_(std::move(inner)), options_(options), width_(inner_->width()), height_(inner_->height()),
      fps_(inner_->fps()), worker_(&PrefetchingSource::produce, this)
{
}

PrefetchingSource::~PrefetchingSource()
{
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    changed_.notify_all();
    worker_.join();
}

uint64_t PrefetchingSource::framesDropped() const
{
    std::lock_guard lock(mutex_);
    return dropped_;
}

bool PrefetchingSource::waitToStartFrame()
{
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return stopping_ || (!slotHasFrame_ && !slotError_); });
    if (stopping_)
        return false;
    // Done a quarter of a frame's making before the consumer is expected: a little early
    // costs that much latency, a little late costs the consumer that much waiting.
    const double leadS = consumerBusyS_ - 1.25 * frameTimeS_;
    if (leadS > 0.0 && takenAt_ != Clock::time_point{}) {
        const auto start = takenAt_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(leadS));
        if (changed_.wait_until(lock, start, [&] { return stopping_; }))
            return false;
    }
    return true;
}

void PrefetchingSource::produce()
{
    const bool latestOnly = options_.mode == PrefetchMode::LatestOnly;
    const bool justInTime = options_.mode == PrefetchMode::JustInTime;
    Frame work;
    for (;;) {
        if (justInTime && !waitToStartFrame())
            return; // stopping: no frame to make
        const auto started = Clock::now();
        bool gotFrame = false;
        std::exception_ptr error;
        try {
            work.capturedNs = 0;
            gotFrame = inner_->next(work);
            // A source without a camera clock (fake, files) captured the frame just now.
            if (gotFrame && work.capturedNs == 0)
                work.capturedNs = monotonicClockNs();
        } catch (...) {
            error = std::current_exception();
        }
        std::unique_lock lock(mutex_);
        if (justInTime) {
            const double seconds = std::chrono::duration<double>(Clock::now() - started).count();
            frameTimeS_ = frameTimeS_ > 0.0 ? 0.8 * frameTimeS_ + 0.2 * seconds : seconds;
        }
        // Latest only, a frame may take the place of a waiting frame; nothing else is dropped.
        const bool replacesFrame = latestOnly && gotFrame && !error;
        changed_.wait(lock, [&] { return stopping_ || (!slotError_ && (replacesFrame || !slotHasFrame_)); });
        if (stopping_)
            return;
        if (error) {
            slotError_ = error;
        } else if (gotFrame) {
            if (slotHasFrame_)
                ++dropped_;
            std::swap(slot_, work); // a dropped frame's buffers come back to be refilled
            slotHasFrame_ = true;
        } else {
            ended_ = true;
        }
        changed_.notify_all();
        if (ended_)
            return;
    }
}

bool PrefetchingSource::next(Frame& frame)
{
    std::unique_lock lock(mutex_);
    if (takenAt_ != Clock::time_point{}) {
        const double busy = std::chrono::duration<double>(Clock::now() - takenAt_).count();
        consumerBusyS_ = consumerBusyS_ > 0.0 ? 0.8 * consumerBusyS_ + 0.2 * busy : busy;
    }
    changed_.wait(lock, [&] { return slotHasFrame_ || slotError_ || ended_; });
    if (slotError_) {
        const std::exception_ptr error = std::exchange(slotError_, nullptr);
        lock.unlock();
        changed_.notify_all();
        std::rethrow_exception(error);
    }
    if (!slotHasFrame_)
        return false;
    std::swap(frame, slot_);
    slotHasFrame_ = false;
    takenAt_ = Clock::now();
    lock.unlock();
    changed_.notify_all();
    return true;
}

} // namespace lumar
