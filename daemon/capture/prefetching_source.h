// Runs a CaptureSource on its own thread, one frame ahead of the consumer, so capturing the
// next frame (decoding a file, drawing the fake scene, later waiting on a device) overlaps
// tracking and rendering of the current one (DESIGN.md §3: capture runs off the render
// thread). Frames and errors come out in the source's order, unchanged, so an offline render
// stays deterministic. Three frame buffers cycle between the threads: no allocation per frame.
#pragma once

#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

#include "capture/capture_source.h"

namespace lumar {

class PrefetchingSource final : public CaptureSource {
public:
    explicit PrefetchingSource(std::unique_ptr<CaptureSource> inner);
    ~PrefetchingSource() override;
    PrefetchingSource(const PrefetchingSource&) = delete;
    PrefetchingSource& operator=(const PrefetchingSource&) = delete;

    // Rethrows, in order, what the source threw for that frame.
    bool next(Frame& frame) override;
    [[nodiscard]] int width() const override { return width_; }
    [[nodiscard]] int height() const override { return height_; }
    [[nodiscard]] double fps() const override { return fps_; }

private:
    void produce();

    std::unique_ptr<CaptureSource> inner_;
    const int width_;
    const int height_;
    const double fps_;

    std::mutex mutex_;
    std::condition_variable changed_;
    // The one-slot hand-over: a frame, an error, or the end of the stream.
    Frame slot_;
    bool slotHasFrame_ = false;
    std::exception_ptr slotError_;
    bool ended_ = false;
    bool stopping_ = false;
    std::thread worker_; // last member: starts after everything it uses exists
};

} // namespace lumar
