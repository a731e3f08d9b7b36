#include "capture/reconnecting_source.h"

#include <algorithm>
#include <thread>

#include "core/log.h"

namespace lumar {

ReconnectingSource::ReconnectingSource(Opener open, std::string name, ReconnectPolicy policy)
    : open_(std::move(open)), name_(std::move(name)), policy_(policy), source_(open_()), width_(source_->width()),
      height_(source_->height()), fps_(source_->fps())
{
}

void ReconnectingSource::tryToReopen()
{
    std::this_thread::sleep_until(nextAttempt_);
    try {
        auto reopened = open_();
        if (reopened->width() != width_ || reopened->height() != height_)
            throw RuntimeError(name_ + ": came back at " + std::to_string(reopened->width()) + "x" +
                               std::to_string(reopened->height()) + " instead of " + std::to_string(width_) + "x" +
                               std::to_string(height_));
        source_ = std::move(reopened);
        sequenceOffset_ = nextSequence_;
        ++reconnections_;
        delay_ = std::chrono::milliseconds(0);
        LUMAR_LOG(Capture, Info) << name_ << ": camera back (reconnection " << reconnections_ << ")";
    } catch (const RuntimeError& e) {
        delay_ = std::clamp(delay_ * 2, policy_.firstDelay, policy_.maxDelay);
        nextAttempt_ = std::chrono::steady_clock::now() + delay_;
        LUMAR_LOG(Capture, Debug) << "reopen failed, next try in " << delay_.count() << " ms: " << e.what();
        throw CameraUnavailable(name_ + ": camera unavailable, retrying: " + e.what());
    }
}

bool ReconnectingSource::next(Frame& frame)
{
    if (!source_)
        tryToReopen();
    try {
        if (!source_->next(frame))
            return false;
    } catch (const RuntimeError& e) {
        // Drop the failed device now (closing its buffers and fd); the next call reopens.
        source_.reset();
        delay_ = policy_.firstDelay;
        nextAttempt_ = std::chrono::steady_clock::now() + delay_;
        LUMAR_LOG(Capture, Warn) << e.what() << "; reconnecting";
        throw CameraUnavailable(std::string(e.what()) + "; reconnecting");
    }
    frame.sequence += sequenceOffset_;
    nextSequence_ = frame.sequence + 1;
    return true;
}

} // namespace lumar
