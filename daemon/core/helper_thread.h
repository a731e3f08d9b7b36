// One persistent helper thread that runs a job while the caller runs its own: the tracker's
// parallel window search (tracking/tag_tracker.cpp) and the renderer's camera image, reduced
// on the CPU while the frame is uploaded (gles_renderer/scene/camera_image.h). Starting a
// std::thread per frame would cost about as much as a small window's detection; this one
// waits on a condition variable between frames.
#pragma once

#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace lumar {

class HelperThread {
public:
    HelperThread();
    ~HelperThread();
    HelperThread(const HelperThread&) = delete;
    HelperThread& operator=(const HelperThread&) = delete;

    // Runs `theirs` on the helper thread and `ours` on the calling thread, and returns once
    // both are done. An exception from either is rethrown here (ours first).
    void runAlongside(const std::function<void()>& theirs, const std::function<void()>& ours);

private:
    void run();

    std::mutex mutex_;
    std::condition_variable wake_, done_;
    const std::function<void()>* job_ = nullptr; // set while a job is pending or running
    bool finished_ = false;
    bool stopping_ = false;
    std::exception_ptr error_;
    std::thread thread_; // last: started once everything above exists
};

} // namespace lumar
