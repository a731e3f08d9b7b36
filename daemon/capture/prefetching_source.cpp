#include "capture/prefetching_source.h"

#include <utility>

#include "core/monotonic_clock.h"

namespace lumar {

PrefetchingSource::PrefetchingSource(std::unique_ptr<CaptureSource> inner)
    : inner_(std::move(inner)), width_(inner_->width()), height_(inner_->height()), fps_(inner_->fps()),
      worker_(&PrefetchingSource::produce, this)
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

void PrefetchingSource::produce()
{
    Frame work;
    for (;;) {
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
        changed_.wait(lock, [&] { return stopping_ || (!slotHasFrame_ && !slotError_); });
        if (stopping_)
            return;
        if (error) {
            slotError_ = error;
        } else if (gotFrame) {
            std::swap(slot_, work);
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
