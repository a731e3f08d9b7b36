// Frames captured once, before timing, and then served from memory: what `lumar bench
// --replay` measures, so that the fake camera's own drawing (about 20 ms of CPU per 720p
// frame, a cost no device with a real camera pays) is left out of the pipeline's figures
// (DESIGN.md §9). The loop runs forwards and back (0 1 … N-1 N-2 … 1 0 1 …) so the camera's
// motion reverses instead of jumping; frames keep counting sequence and timestampNs
// (sequence / fps) on, so the tracking filters see a steady stream. Each served frame is
// stamped with CLOCK_MONOTONIC when served: capture-to-present latency then measures the
// pipeline alone, as with a camera whose frame arrives just as the pipeline is ready for it.
//
// Memory: the frames are kept as the source made them (the fake camera: RGB plus luma,
// 3.7 MB per 1280×720 frame), and the source itself is closed once they are captured (the
// fake camera's table and environment cube go with it).
//
// Frames are lent, not copied: next() swaps the held frame's images into the caller's frame
// and takes them back (swapping again) at the next call, so the caller must pass the same
// frame, its images unchanged, as the pipeline does. A copy cost ~0.5 ms of the pipeline's
// thread per 720p frame and 3.7 MB resident, neither of which a camera's frames cost.
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "capture/capture_source.h"
#include "capture/fake_camera.h"

namespace lumar {

class ReplaySource final : public CaptureSource {
public:
    // Captures up to `frames` frames from `source` (fewer when a file ends first), then closes
    // it. Frames from a FakeCamera keep their ground truth. Throws InputError when the source
    // gives no frame at all, or lends camera buffers (zero-copy frames cannot be held).
    ReplaySource(std::unique_ptr<CaptureSource> source, int frames);

    // Never ends. Throws RuntimeError when `frame` does not hold the images lent by the
    // previous call (another frame passed, or its images replaced): the held frame is lost.
    bool next(Frame& frame) override;
    [[nodiscard]] int width() const override { return width_; }
    [[nodiscard]] int height() const override { return height_; }
    [[nodiscard]] double fps() const override { return fps_; }

    [[nodiscard]] int framesHeld() const { return int(frames_.size()); }
    // Bytes of image data held (the frames' pixels, not counting the vectors' headers).
    [[nodiscard]] size_t bytesHeld() const;
    // The held frame served as `sequence` (forwards and back through the loop).
    [[nodiscard]] int heldIndex(uint64_t sequence) const;
    // The fake camera's ground truth for the frame served as `sequence`; empty for other sources.
    [[nodiscard]] const std::vector<TagGroundTruth>& groundTruth(uint64_t sequence) const;

private:
    std::vector<Frame> frames_;
    // The held frame whose images the caller has, and where they are: -1 for none.
    int lent_ = -1;
    std::array<const void*, 3> lentImages_{};
    size_t bytesHeld_ = 0;
    std::vector<std::vector<TagGroundTruth>> groundTruth_; // per held frame; empty: not a fake camera
    int width_ = 0, height_ = 0;
    double fps_ = 0.0;
    uint64_t nextSequence_ = 0;
};

} // namespace lumar
