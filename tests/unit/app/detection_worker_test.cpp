// The detection worker: results arrive for submitted frames, the newest frame wins when the
// worker is busy, errors come back to the caller, and it shuts down with work pending.
#include <chrono>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "capture/fake_camera.h"
#include "detection_worker.h"

namespace lumar {
namespace {

using namespace std::chrono_literals;

struct Scene {
    CameraConfig config;
    FakeCamera camera{config};
    TrackingConfig tracking;
    TagTracker tracker{tracking, camera.intrinsics(), TagSizes{{{0, 0.16}}, 0.0}};
};

bool waitForResult(DetectionWorker& worker, DetectionWorker::Result& out)
{
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (std::chrono::steady_clock::now() < deadline) {
        if (worker.take(out))
            return true;
        std::this_thread::sleep_for(1ms);
    }
    return false;
}

TEST(DetectionWorker, DetectsTheSubmittedFrame)
{
    Scene scene;
    Frame frame;
    ASSERT_TRUE(scene.camera.next(frame));
    DetectionWorker worker(scene.tracker);
    worker.submit(frame.luma, frame.sequence, frame.timestampNs);
    DetectionWorker::Result result;
    ASSERT_TRUE(waitForResult(worker, result));
    EXPECT_EQ(result.sequence, frame.sequence);
    EXPECT_EQ(result.timestampNs, frame.timestampNs);
    ASSERT_EQ(result.detections.size(), 1u);
    EXPECT_EQ(result.detections[0].id, 0);
    EXPECT_TRUE(result.detections[0].hasPose);
    EXPECT_GT(result.detectMs, 0.0);
    EXPECT_FALSE(worker.take(result)) << "a result is handed out once";
}

// Frames submitted faster than detection runs: the worker skips to the newest, so the last
// result is the last frame's and results never go back in time.
TEST(DetectionWorker, TheNewestFrameWins)
{
    Scene scene;
    std::vector<Frame> frames(12);
    for (Frame& frame : frames) // rendered first: the camera is slower than detection
        ASSERT_TRUE(scene.camera.next(frame));
    DetectionWorker worker(scene.tracker);
    for (const Frame& frame : frames)
        worker.submit(frame.luma, frame.sequence, frame.timestampNs);
    const uint64_t lastSequence = frames.back().sequence;
    DetectionWorker::Result result;
    uint64_t previous = 0;
    bool sawLast = false;
    const auto deadline = std::chrono::steady_clock::now() + 20s;
    while (!sawLast && std::chrono::steady_clock::now() < deadline) {
        if (worker.take(result)) {
            EXPECT_GE(result.sequence, previous);
            previous = result.sequence;
            sawLast = result.sequence == lastSequence;
        } else {
            std::this_thread::sleep_for(1ms);
        }
    }
    EXPECT_TRUE(sawLast);
    EXPECT_GT(worker.skipped(), 0u) << "12 frames in microseconds, each detection takes milliseconds";
}

TEST(DetectionWorker, ReportsADetectionErrorAndStopsWithWorkPending)
{
    Scene scene;
    DetectionWorker::Result result;
    {
        DetectionWorker worker(scene.tracker);
        worker.submit(Image8(), 1, 0); // empty image: the tracker rejects it
        const auto deadline = std::chrono::steady_clock::now() + 10s;
        bool threw = false;
        while (!threw && std::chrono::steady_clock::now() < deadline) {
            try {
                worker.take(result);
                std::this_thread::sleep_for(1ms);
            } catch (const std::exception&) {
                threw = true;
            }
        }
        EXPECT_TRUE(threw);
        Frame frame;
        ASSERT_TRUE(scene.camera.next(frame));
        for (int i = 0; i < 3; ++i)
            worker.submit(frame.luma, frame.sequence, frame.timestampNs);
    } // destroyed with a frame pending: joins without hanging
    SUCCEED();
}

} // namespace
} // namespace lumar
