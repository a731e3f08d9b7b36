// One KMS output: connector, mode, CRTC and plane chosen on a DRM device, and the commits
// that put framebuffers on it (DESIGN.md §7, after kmscube's atomic path). The first frame
// sets the mode — with a test-only atomic commit first — and later frames are page flips
// paced by the flip events. Drivers without atomic modesetting, or whose test commit fails,
// get the legacy API (SetCrtc + PageFlip).
#pragma once

#include <cstdint>
#include <string>

#include "gles_renderer/display/drm_device.h"

namespace lumar {

struct KmsPreferences {
    std::string connector = "auto"; // a connector name ("HDMI-A-1") or "auto": the first connected
    std::string plane = "primary";  // "primary" | "overlay" (falls back to the primary one)
    std::string mode = "auto";      // "WIDTHxHEIGHT" or "auto": the connector's preferred mode
};

// A property blob (the mode) destroyed with its owner.
class DrmPropertyBlob {
public:
    DrmPropertyBlob() = default;
    DrmPropertyBlob(int fd, const void* data, size_t size);
    DrmPropertyBlob(DrmPropertyBlob&& other) noexcept;
    DrmPropertyBlob& operator=(DrmPropertyBlob&& other) noexcept;
    DrmPropertyBlob(const DrmPropertyBlob&) = delete;
    DrmPropertyBlob& operator=(const DrmPropertyBlob&) = delete;
    ~DrmPropertyBlob();
    [[nodiscard]] uint32_t id() const { return id_; }

private:
    int fd_ = -1;
    uint32_t id_ = 0;
};

class KmsOutput {
public:
    // Chooses the output on `device` (which must outlive it). Throws RuntimeError naming what
    // is missing: no connected connector, the named connector, a CRTC, a plane taking an
    // XRGB8888 or ARGB8888 framebuffer.
    KmsOutput(DrmDevice& device, const KmsPreferences& preferences);
    ~KmsOutput();
    KmsOutput(const KmsOutput&) = delete;
    KmsOutput& operator=(const KmsOutput&) = delete;

    [[nodiscard]] int width() const { return mode_.hdisplay; }
    [[nodiscard]] int height() const { return mode_.vdisplay; }
    [[nodiscard]] double refreshHz() const;
    [[nodiscard]] uint32_t format() const { return format_; } // the plane's framebuffer format
    // "bochs-drm Virtual-1 1024x768@60 CRTC 34 primary plane 31 XR24 atomic", for the log.
    [[nodiscard]] std::string describe() const;

    // Shows `framebuffer` from the next vertical blank. Waits first for a flip still queued
    // (a driver takes one at a time). Throws RuntimeError when the driver refuses.
    void show(uint32_t framebuffer);
    // Waits up to `timeoutMs` for the queued flip; true when none is pending afterwards.
    bool waitForFlip(int timeoutMs);
    [[nodiscard]] bool flipPending() const { return flipPending_; }
    [[nodiscard]] uint64_t flipsCompleted() const { return flipsCompleted_; }
    // When the latest completed flip took effect (CLOCK_MONOTONIC ns, the event's timestamp).
    [[nodiscard]] int64_t lastFlipNs() const { return lastFlipNs_; }

private:
    void chooseConnectorAndMode(const KmsPreferences& preferences);
    void chooseCrtcAndPlane(const KmsPreferences& preferences);
    void lookUpProperties();
    void commitAtomic(uint32_t framebuffer, bool modeset);
    void commitLegacy(uint32_t framebuffer, bool modeset);
    static void onPageFlip(int fd, unsigned sequence, unsigned seconds, unsigned microseconds, void* data);

    DrmDevice& device_;
    uint32_t connectorId_ = 0, crtcId_ = 0, planeId_ = 0;
    int crtcIndex_ = -1;
    std::string connectorName_, planeType_;
    drmModeModeInfo mode_{};
    uint32_t format_ = 0;
    DrmPropertyBlob modeBlob_;
    bool modeSet_ = false;
    bool flipPending_ = false;
    uint64_t flipsCompleted_ = 0;
    int64_t lastFlipNs_ = 0;
    struct {
        uint32_t connectorCrtcId = 0, crtcModeId = 0, crtcActive = 0;
        uint32_t planeFbId = 0, planeCrtcId = 0, planeSrcX = 0, planeSrcY = 0, planeSrcW = 0, planeSrcH = 0;
        uint32_t planeCrtcX = 0, planeCrtcY = 0, planeCrtcW = 0, planeCrtcH = 0;
    } properties_;
};

} // namespace lumar
