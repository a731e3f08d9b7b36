#include "capture/replay_source.h"

#include <array>
#include <string>
#include <utility>

#include "core/error.h"
#include "core/monotonic_clock.h"

namespace lumar {

ReplaySource::ReplaySource(std::unique_ptr<CaptureSource> source, int frames)
    : width_(source->width()), height_(source->height()), fps_(source->fps())
{
    if (frames < 1)
        throw InputError("replay: at least one frame must be captured (asked for " + std::to_string(frames) + ")");
    const auto* fake = dynamic_cast<const FakeCamera*>(source.get());
    frames_.reserve(size_t(frames));
    for (int i = 0; i < frames; ++i) {
        Frame frame;
        if (!source->next(frame))
            break;
        if (frame.ycbcr.buffer)
            throw InputError("replay: the camera lends its buffers (zero-copy); set [camera] zero_copy = \"off\"");
        if (fake)
            groundTruth_.push_back(fake->groundTruth(frame.sequence));
        frames_.push_back(std::move(frame));
    }
    if (frames_.empty())
        throw InputError("replay: the camera source ended before its first frame");
    for (const Frame& f : frames_)
        bytesHeld_ += f.rgb.data.size() + f.luma.data.size() + f.ycbcr.plane0.size() + f.ycbcr.plane1.size();
    source.reset(); // its own buffers (the fake camera's table and cube) are not needed any more
}

int ReplaySource::heldIndex(uint64_t sequence) const
{
    const uint64_t held = frames_.size();
    if (held == 1)
        return 0;
    const uint64_t period = 2 * held - 2; // forwards then back, the ends shown once
    const uint64_t phase = sequence % period;
    return int(phase < held ? phase : period - phase);
}

namespace {

void swapImages(Frame& a, Frame& b)
{
    std::swap(a.rgb, b.rgb);
    std::swap(a.luma, b.luma);
    std::swap(a.ycbcr, b.ycbcr);
}

// Where a frame's images are: vectors keep their storage when swapped, so lent images are
// found where they were lent.
std::array<const void*, 3> imagesOf(const Frame& frame)
{
    return {frame.rgb.data.data(), frame.luma.data.data(), frame.ycbcr.plane0.data()};
}

} // namespace

bool ReplaySource::next(Frame& frame)
{
    if (lent_ >= 0) {
        if (imagesOf(frame) != lentImages_)
            throw RuntimeError("replay: held frame " + std::to_string(lent_) +
                               " did not come back with the next call (the frames are lent, not copied)");
        swapImages(frame, frames_[size_t(lent_)]);
    }
    lent_ = heldIndex(nextSequence_);
    swapImages(frame, frames_[size_t(lent_)]);
    lentImages_ = imagesOf(frame);
    frame.sequence = nextSequence_;
    frame.timestampNs = int64_t(double(nextSequence_) * 1e9 / fps_ + 0.5);
    frame.capturedNs = monotonicClockNs();
    ++nextSequence_;
    return true;
}

size_t ReplaySource::bytesHeld() const
{
    return bytesHeld_;
}

const std::vector<TagGroundTruth>& ReplaySource::groundTruth(uint64_t sequence) const
{
    static const std::vector<TagGroundTruth> none;
    return groundTruth_.empty() ? none : groundTruth_[size_t(heldIndex(sequence))];
}

} // namespace lumar
