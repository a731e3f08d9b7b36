// Marker detection on its own thread (DESIGN.md §3: the render thread never waits for
// detection). The render loop submits every captured frame's luma; the worker always takes
// the newest one, dropping frames it had no time for, and the loop picks up whatever result
// is newest when it renders.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "core/image.h"
#include "tracking/tag_map.h"
#include "tracking/tag_tracker.h"

namespace lumar {

class DetectionWorker {
public:
    struct Result {
        std::vector<TagDetection> detections;
        std::vector<MapDetection> maps;
        std::vector<SearchWindow> windows; // TagTracker::searchedWindows() for that frame
        uint64_t sequence = 0;             // of the frame detected in
        int64_t timestampNs = 0;           // its capture time
        double detectMs = 0.0;             // how long the detection took
    };

    // The tracker is used by the worker thread alone from now until destruction.
    explicit DetectionWorker(TagTracker& tracker);
    ~DetectionWorker();
    DetectionWorker(const DetectionWorker&) = delete;
    DetectionWorker& operator=(const DetectionWorker&) = delete;

    // Hands over a frame (copied), replacing one the worker has not started on.
    void submit(const Image8& luma, uint64_t sequence, int64_t timestampNs);
    // Moves the newest result not taken yet into `out`; false when there is none. Rethrows
    // an exception the detection raised.
    bool take(Result& out);
    // Frames replaced before the worker got to them.
    [[nodiscard]] uint64_t skipped() const;

private:
    void run();

    TagTracker& tracker_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;
    Image8 pending_;
    uint64_t pendingSequence_ = 0;
    int64_t pendingTimestampNs_ = 0;
    bool hasPending_ = false;
    Result result_;
    bool hasResult_ = false;
    uint64_t skipped_ = 0;
    std::exception_ptr error_;
    bool stopping_ = false;
    std::thread thread_; // last: started once everything above exists
};

} // namespace lumar
