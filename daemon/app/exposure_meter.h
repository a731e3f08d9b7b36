// How bright the camera image is relative to its first frames (DESIGN.md §6.5 exposure
// matching): when the lights dim or the camera's auto-exposure moves, the whole image darkens
// or brightens, and the renderer scales the virtual objects (SceneRenderer::setExposure) so
// they follow. No GL: it reads the luma plane every capture source fills.
#pragma once

#include <array>

#include "core/image.h"

namespace lumar {

struct ExposureMeterSettings {
    int gridColumns = 64;    // luma samples across the frame
    int gridRows = 36;       // ... and down
    int referenceFrames = 5; // the reference is the mean of the first frames' levels
    // Exponential smoothing of the ratio, per frame: 0.5 closes 97 % of a step in 5 frames
    // while sensor noise on a still scene moves it well under 1 %.
    double smoothing = 0.5;
    double minRatio = 1.0 / 16.0; // the renderer's camera-built map holds 16 x its reference range
    double maxRatio = 16.0;
};

class ExposureMeter {
public:
    explicit ExposureMeter(const ExposureMeterSettings& settings = {});

    // Measures the frame's luma (1 channel, full-range BT.601 of sRGB-encoded RGB) and returns
    // the smoothed exposure relative to the reference: 1 until the reference frames are in,
    // 0.5 once the image has half the linear light it had then.
    double update(const Image8& luma);

    // Forgets the reference (a new camera, a new configuration): the next frames make one.
    void reset();

    [[nodiscard]] double exposure() const { return exposure_; }
    // The last frame's own ratio to the reference, not smoothed (1 until the reference is in).
    [[nodiscard]] double frameExposure() const { return frameExposure_; }

    // The frame's level: the mean linear luma of the middle half of the samples (ranks a
    // quarter to three quarters). Clipping and crushed blacks keep the samples' order, so as
    // long as under a quarter of the frame is clipped white (or black) the level scales
    // exactly with the light, where a plain mean would be held down by the clipped part.
    [[nodiscard]] double level(const Image8& luma) const;

private:
    ExposureMeterSettings settings_;
    std::array<double, 256> linear_{}; // code value -> linear light
    double reference_ = 0.0;
    int referenceCount_ = 0;
    double exposure_ = 1.0;
    double frameExposure_ = 1.0;
};

} // namespace lumar
