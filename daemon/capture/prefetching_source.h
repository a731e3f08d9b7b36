// Runs a CaptureSource on its own thread, ahead of the consumer, so capturing the next frame
// (decoding a file, drawing the fake scene, waiting on a device) overlaps tracking and
// rendering of the current one (DESIGN.md §3: capture runs off the render thread). Three ways
// to hand frames over:
//  - in order: every frame and error comes out in the source's order, unchanged, one frame
//    ahead, so an offline render stays deterministic;
//  - latest only (a camera): a frame that is still waiting when a newer one is ready is
//    dropped (and counted), so the consumer always gets the newest frame. A camera runs at
//    its own rate whatever the consumer does; in order, a consumer slower than the camera
//    would be handed frames about three frame intervals old (the one being captured and the
//    one waiting in the slot ageing behind it). Errors are never dropped;
//  - just in time (a source that makes frames when asked, the fake camera live): in order,
//    but each frame is started so that it is done about when the consumer will ask for it
//    (from the consumer's time between requests and the source's time per frame), so it
//    waits little; drawing frames to drop instead would take the CPU from the consumer.
// Three frame buffers cycle between the threads: no allocation per frame.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "capture/capture_source.h"

namespace lumar {

enum class PrefetchMode { InOrder, LatestOnly, JustInTime };

struct PrefetchOptions {
    PrefetchMode mode = PrefetchMode::InOrder;
};

// How `lumar` hands the frames of camera.source over: latest only for cameras, which run at
// their own rate (v4l2, libcamera); just in time for the fake camera when `realTime` (`lumar
// run`); in order for files and for offline use (`lumar render`, bench), where every frame
// counts.
PrefetchOptions prefetchOptionsFor(const std::string& cameraSource, bool realTime);

class PrefetchingSource final : public CaptureSource {
public:
    explicit PrefetchingSource(std::unique_ptr<CaptureSource> inner, PrefetchOptions options = {});
    ~PrefetchingSource() override;
    PrefetchingSource(const PrefetchingSource&) = delete;
    PrefetchingSource& operator=(const PrefetchingSource&) = delete;

    // Rethrows, in order, what the source threw for that frame.
    bool next(Frame& frame) override;
    [[nodiscard]] int width() const override { return width_; }
    [[nodiscard]] int height() const override { return height_; }
    [[nodiscard]] double fps() const override { return fps_; }

    [[nodiscard]] PrefetchMode mode() const { return options_.mode; }
    // Frames replaced by a newer one before the consumer took them (latest only; else 0).
    [[nodiscard]] uint64_t framesDropped() const;

private:
    void produce();
    // Just in time: waits until the slot is empty and the next frame is due to start; false
    // when stopping.
    bool waitToStartFrame();

    std::unique_ptr<CaptureSource> inner_;
    const PrefetchOptions options_;
    const int width_;
    const int height_;
    const double fps_;

    mutable std::mutex mutex_;
    std::condition_variable changed_;
    // The one-slot hand-over: a frame, an error, or the end of the stream.
    Frame slot_;
    bool slotHasFrame_ = false;
    std::exception_ptr slotError_;
    bool ended_ = false;
    bool stopping_ = false;
    uint64_t dropped_ = 0;
    // Just in time, smoothed: the consumer's time from taking a frame to asking for the next,
    // and the source's time per frame; when the consumer last took a frame.
    using Clock = std::chrono::steady_clock;
    double consumerBusyS_ = 0.0;
    double frameTimeS_ = 0.0;
    Clock::time_point takenAt_{};
    std::thread worker_; // last member: starts after everything it uses exists
};

} // namespace lumar
