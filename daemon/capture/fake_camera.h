// The default capture source: a deterministic, seeded synthetic scene — a textured table-top
// with tag36h11 markers lying on it, seen by a camera moving along a known trajectory —
// rendered on the CPU. Every frame's ground truth (each tag's camera_from_marker pose) is
// available, so tests can check tracking and rendering against exact answers.
//
// World frame: the table-top is the plane z = 0 with z up; each tag's marker frame is the
// world frame translated to the tag's centre (FakeTagConfig::position).
//
// With an environment map (CameraConfig::fakeEnvironment, from [environment]) the camera shows
// the world the renderer lights virtual objects with: the map at infinity around the table,
// the table and its tags lit by the map's irradiance, and real objects standing on it
// (CameraConfig::fakeObjects) that are shaded by it and shadow the table. Linear radiance L
// becomes code values as 255 · sRGB(clamp(exposure · L, 0, 1)). Without a map: a plain room
// (its code values read as sRGB for the exposure), where objects are lit from above by its
// lamp and cast no shadow.
#pragma once

#include <memory>
#include <vector>

#include "capture/capture_source.h"
#include "core/camera_model.h"
#include "core/pose.h"

namespace lumar {

struct TagGroundTruth {
    int id = 0;
    double size = 0.0;
    Pose cameraFromMarker;
};

class FakeCamera final : public CaptureSource {
public:
    // Throws InputError for an invalid scene (no tag, an id without a tag36h11 code, ...).
    explicit FakeCamera(const CameraConfig& config);
    ~FakeCamera() override;
    // The constructor's checks alone, without building the scene (which bakes the table's
    // texture: seconds under a sanitizer; the fuzz target tests/fuzz/fuzz_fake_camera.cpp).
    static void validateScene(const CameraConfig& config);

    bool next(Frame& frame) override; // never ends
    [[nodiscard]] int width() const override;
    [[nodiscard]] int height() const override;
    [[nodiscard]] double fps() const override;

    // Renders frame `sequence` into `frame` (same result as the sequence-th call to next()).
    void render(uint64_t sequence, Frame& frame) const;

    [[nodiscard]] Pose cameraFromWorld(uint64_t sequence) const;
    [[nodiscard]] std::vector<TagGroundTruth> groundTruth(uint64_t sequence) const;
    [[nodiscard]] const CameraIntrinsics& intrinsics() const;

    // The exposure of every frame rendered from now on (camera.exposure at start); the scene is
    // re-lit at the next frame. Safe to call from any thread. Throws InputError unless it is
    // positive and finite.
    void setExposure(double exposure);
    [[nodiscard]] double exposure() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace lumar
