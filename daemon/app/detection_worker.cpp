#include "detection_worker.h"

#include <chrono>
#include <utility>

namespace lumar {

DetectionWorker::DetectionWorker(TagTracker& tracker) : tracker_(tracker), thread_([this] { run(); }) {}

DetectionWorker::~DetectionWorker()
{
    {
        const std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    wake_.notify_one();
    thread_.join();
}

void DetectionWorker::submit(const Image8& luma, uint64_t sequence, int64_t timestampNs)
{
    {
        const std::lock_guard lock(mutex_);
        if (hasPending_)
            ++skipped_;
        pending_.reshape(luma.width, luma.height, luma.channels);
        std::copy(luma.data.begin(), luma.data.end(), pending_.data.begin());
        pendingSequence_ = sequence;
        pendingTimestampNs_ = timestampNs;
        hasPending_ = true;
    }
    wake_.notify_one();
}

bool DetectionWorker::take(Result& out)
{
    const std::lock_guard lock(mutex_);
    if (error_)
        std::rethrow_exception(std::exchange(error_, nullptr));
    if (!hasResult_)
        return false;
    out = std::move(result_);
    hasResult_ = false;
    return true;
}

uint64_t DetectionWorker::skipped() const
{
    const std::lock_guard lock(mutex_);
    return skipped_;
}

void DetectionWorker::run()
{
    Image8 working;
    for (;;) {
        uint64_t sequence = 0;
        int64_t timestampNs = 0;
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [this] { return stopping_ || hasPending_; });
            if (stopping_)
                return;
            std::swap(working, pending_);
            sequence = pendingSequence_;
            timestampNs = pendingTimestampNs_;
            hasPending_ = false;
        }
        Result result;
        result.sequence = sequence;
        result.timestampNs = timestampNs;
        try {
            const auto start = std::chrono::steady_clock::now();
            result.detections = tracker_.detect(working);
            result.maps = tracker_.detectMaps(result.detections);
            result.windows = tracker_.searchedWindows();
            result.detectMs =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        } catch (...) {
            const std::lock_guard lock(mutex_);
            error_ = std::current_exception();
            continue;
        }
        const std::lock_guard lock(mutex_);
        result_ = std::move(result);
        hasResult_ = true;
    }
}

} // namespace lumar
