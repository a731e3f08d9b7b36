#include "capture/prefetching_source.h"

#include <utility>

#include "core/monotonic_clock.h"

namespace lumar {

PrefetchOptions prefetchOptionsFor(const std::string& cameraSource, bool realTime)
{
    PrefetchOptions options;
    const bool camera = cameraSource == "v4l2" || cameraSource == "libcamera";
    const bool fakeLive = cameraSource == "fake" && realTime;
    if (camera || fakeLive)
        options.mode = PrefetchMode::LatestOnly;
    options.paceToFps = fakeLive;
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

void PrefetchingSource::waitForCaptureTime(std::chrono::steady_clock::time_point& due)
{
    using Clock = std::chrono::steady_clock;
    const auto interval = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / fps_));
    const auto now = Clock::now();
    if (due == Clock::time_point{} || now > due + interval)
        due = now; // the first frame, or the source fell behind: no burst to catch up
    {
        std::unique_lock lock(mutex_);
        changed_.wait_until(lock, due, [&] { return stopping_; });
    }
    due += interval;
}

void PrefetchingSource::produce()
{
    const bool latestOnly = options_.mode == PrefetchMode::LatestOnly;
    const bool pace = options_.paceToFps && fps_ > 0.0;
    std::chrono::steady_clock::time_point due{};
    Frame work;
    for (;;) {
        if (pace)
            waitForCaptureTime(due);
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
    lock.unlock();
    changed_.notify_all();
    return true;
}

} // namespace lumar
