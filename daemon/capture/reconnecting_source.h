// Keeps a camera alive across unplugs and hangs (DESIGN.md §4): when the device fails
// (RuntimeError: unplugged, no frame within the timeout, a driver error) it is closed and
// reopened with exponential backoff, in the same process. While it is down, next() throws
// CameraUnavailable after waiting at most one backoff step, so the caller's loop keeps running
// (showing its last frame, reporting the state) instead of blocking or exiting.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "capture/capture_source.h"
#include "core/error.h"

namespace lumar {

// The camera is gone for now; lumar is trying to get it back.
class CameraUnavailable : public RuntimeError {
public:
    using RuntimeError::RuntimeError;
};

struct ReconnectPolicy {
    std::chrono::milliseconds firstDelay{100};
    std::chrono::milliseconds maxDelay{2000};
};

class ReconnectingSource final : public CaptureSource {
public:
    using Opener = std::function<std::unique_ptr<CaptureSource>()>;

    // Opens once at once: a camera that cannot be opened at start is an error for the caller
    // (the exception propagates), not something to wait for silently.
    ReconnectingSource(Opener open, std::string name, ReconnectPolicy policy = {});

    // Sequence numbers continue across reconnections, so "frames since" arithmetic holds.
    bool next(Frame& frame) override;
    [[nodiscard]] int width() const override { return width_; }
    [[nodiscard]] int height() const override { return height_; }
    [[nodiscard]] double fps() const override { return fps_; }

    [[nodiscard]] int reconnections() const { return reconnections_; }

private:
    void tryToReopen();

    Opener open_;
    std::string name_;
    ReconnectPolicy policy_;
    std::unique_ptr<CaptureSource> source_;
    int width_ = 0, height_ = 0;
    double fps_ = 0;
    uint64_t sequenceOffset_ = 0; // added to the current device's own sequence numbers
    uint64_t nextSequence_ = 0;   // one past the last sequence handed out
    std::chrono::milliseconds delay_{0};
    std::chrono::steady_clock::time_point nextAttempt_{};
    int reconnections_ = 0;
};

} // namespace lumar
