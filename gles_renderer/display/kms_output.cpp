#include "gles_renderer/display/kms_output.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <utility>

#include <drm_fourcc.h>
#include <poll.h>

#include "core/error.h"
#include "core/log.h"

namespace lumar {
namespace {

bool parseSize(const std::string& text, int& width, int& height)
{
    return std::sscanf(text.c_str(), "%dx%d", &width, &height) == 2 && width > 0 && height > 0;
}

void addProperty(drmModeAtomicReq* request, uint32_t object, uint32_t property, uint64_t value)
{
    if (property == 0)
        throw RuntimeError("KMS: a property the atomic commit needs is missing");
    if (drmModeAtomicAddProperty(request, object, property, value) < 0)
        throw RuntimeError("KMS: cannot build the atomic request");
}

} // namespace

DrmPropertyBlob::DrmPropertyBlob(int fd, const void* data, size_t size) : fd_(fd)
{
    if (drmModeCreatePropertyBlob(fd, data, size, &id_) != 0)
        throw RuntimeError(std::string("KMS: cannot create the mode blob: ") + std::strerror(errno));
}

DrmPropertyBlob::DrmPropertyBlob(DrmPropertyBlob&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), id_(std::exchange(other.id_, 0))
{
}

DrmPropertyBlob& DrmPropertyBlob::operator=(DrmPropertyBlob&& other) noexcept
{
    if (this != &other) {
        if (id_)
            drmModeDestroyPropertyBlob(fd_, id_);
        fd_ = std::exchange(other.fd_, -1);
        id_ = std::exchange(other.id_, 0);
    }
    return *this;
}

DrmPropertyBlob::~DrmPropertyBlob()
{
    if (id_)
        drmModeDestroyPropertyBlob(fd_, id_);
}

KmsOutput::KmsOutput(DrmDevice& device, const KmsPreferences& preferences) : device_(device)
{
    chooseConnectorAndMode(preferences);
    chooseCrtcAndPlane(preferences);
    if (device_.atomic())
        lookUpProperties();
}

KmsOutput::~KmsOutput()
{
    // A flip still queued would complete on a framebuffer its owner is about to remove.
    waitForFlip(100);
}

double KmsOutput::refreshHz() const
{
    if (mode_.htotal == 0 || mode_.vtotal == 0)
        return mode_.vrefresh;
    return mode_.clock * 1000.0 / (double(mode_.htotal) * double(mode_.vtotal));
}

std::string KmsOutput::describe() const
{
    char text[256];
    std::snprintf(text, sizeof text, "%s %s %dx%d@%.0f CRTC %u %s plane %u %s %s", device_.driver().c_str(),
                  connectorName_.c_str(), width(), height(), refreshHz(), crtcId_, planeType_.c_str(), planeId_,
                  drmFormatName(format_).c_str(), device_.atomic() ? "atomic" : "legacy");
    return text;
}

void KmsOutput::chooseConnectorAndMode(const KmsPreferences& preferences)
{
    const DrmResources resources = device_.resources();
    DrmConnector chosen;
    std::string seen;
    for (int i = 0; i < resources->count_connectors; ++i) {
        DrmConnector connector = device_.connector(resources->connectors[i]);
        if (!connector)
            continue;
        const std::string name = connectorName(*connector);
        const bool connected = connector->connection == DRM_MODE_CONNECTED && connector->count_modes > 0;
        seen += name + (connected ? " (connected) " : " (disconnected) ");
        if (!connected)
            continue;
        if (preferences.connector == "auto" || preferences.connector == name) {
            chosen = std::move(connector);
            break;
        }
    }
    if (!chosen) {
        throw RuntimeError(device_.path().string() + ": no connected connector" +
                           (preferences.connector == "auto" ? "" : " named " + preferences.connector) +
                           "; found: " + (seen.empty() ? "none" : seen));
    }
    connectorId_ = chosen->connector_id;
    connectorName_ = connectorName(*chosen);

    int wantedWidth = 0, wantedHeight = 0;
    const bool wantSize = preferences.mode != "auto" && parseSize(preferences.mode, wantedWidth, wantedHeight);
    const drmModeModeInfo* mode = nullptr;
    for (int i = 0; i < chosen->count_modes && !mode; ++i) {
        const drmModeModeInfo& candidate = chosen->modes[i];
        if (wantSize ? candidate.hdisplay == wantedWidth && candidate.vdisplay == wantedHeight
                     : (candidate.type & DRM_MODE_TYPE_PREFERRED) != 0)
            mode = &candidate;
    }
    if (!mode && wantSize)
        LUMAR_LOG(Output, Warn) << connectorName_ << " has no mode " << preferences.mode << "; using its preferred one";
    if (!mode) {
        for (int i = 0; i < chosen->count_modes && !mode; ++i)
            if (chosen->modes[i].type & DRM_MODE_TYPE_PREFERRED)
                mode = &chosen->modes[i];
    }
    mode_ = mode ? *mode : chosen->modes[0];
}

void KmsOutput::chooseCrtcAndPlane(const KmsPreferences& preferences)
{
    const DrmResources resources = device_.resources();
    const DrmConnector connector = device_.connector(connectorId_);
    // The CRTC the connector drives now, else the first one any of its encoders can use.
    uint32_t possibleCrtcs = 0;
    uint32_t currentCrtc = 0;
    for (int i = 0; i < connector->count_encoders; ++i) {
        const DrmEncoder encoder(drmModeGetEncoder(device_.fd(), connector->encoders[i]));
        if (!encoder)
            continue;
        possibleCrtcs |= encoder->possible_crtcs;
        if (encoder->encoder_id == connector->encoder_id)
            currentCrtc = encoder->crtc_id;
    }
    for (int i = 0; i < resources->count_crtcs; ++i) {
        const bool usable = (possibleCrtcs & (1u << i)) != 0;
        if (resources->crtcs[i] == currentCrtc || (usable && crtcIndex_ < 0)) {
            crtcIndex_ = i;
            crtcId_ = resources->crtcs[i];
            if (resources->crtcs[i] == currentCrtc)
                break;
        }
    }
    if (crtcIndex_ < 0)
        throw RuntimeError(device_.path().string() + ": no CRTC can drive " + connectorName_);

    // The plane: the preferred type first, then the primary one, taking XRGB8888 (opaque:
    // the camera image fills the frame) or else ARGB8888.
    const std::vector<DrmPlaneInfo> planes = device_.planes();
    auto pick = [&](const std::string& type) -> const DrmPlaneInfo* {
        for (const uint32_t format : {DRM_FORMAT_XRGB8888, DRM_FORMAT_ARGB8888})
            for (const DrmPlaneInfo& plane : planes)
                if (plane.type == type && (plane.possibleCrtcs & (1u << crtcIndex_)) &&
                    std::find(plane.formats.begin(), plane.formats.end(), format) != plane.formats.end()) {
                    format_ = format;
                    return &plane;
                }
        return nullptr;
    };
    const DrmPlaneInfo* plane = pick(preferences.plane);
    if (!plane && preferences.plane != "primary") {
        LUMAR_LOG(Output, Warn) << device_.path().string() << ": no " << preferences.plane
                                << " plane for XRGB8888 on this CRTC; using the primary plane";
        plane = pick("primary");
    }
    if (!plane)
        throw RuntimeError(device_.path().string() + ": no plane takes XRGB8888 or ARGB8888 on the CRTC of " +
                           connectorName_);
    planeId_ = plane->id;
    planeType_ = plane->type;
}

void KmsOutput::lookUpProperties()
{
    auto connector = [&](const char* name) {
        return device_.propertyId(connectorId_, DRM_MODE_OBJECT_CONNECTOR, name);
    };
    auto crtc = [&](const char* name) { return device_.propertyId(crtcId_, DRM_MODE_OBJECT_CRTC, name); };
    auto plane = [&](const char* name) { return device_.propertyId(planeId_, DRM_MODE_OBJECT_PLANE, name); };
    properties_.connectorCrtcId = connector("CRTC_ID");
    properties_.crtcModeId = crtc("MODE_ID");
    properties_.crtcActive = crtc("ACTIVE");
    properties_.planeFbId = plane("FB_ID");
    properties_.planeCrtcId = plane("CRTC_ID");
    properties_.planeSrcX = plane("SRC_X");
    properties_.planeSrcY = plane("SRC_Y");
    properties_.planeSrcW = plane("SRC_W");
    properties_.planeSrcH = plane("SRC_H");
    properties_.planeCrtcX = plane("CRTC_X");
    properties_.planeCrtcY = plane("CRTC_Y");
    properties_.planeCrtcW = plane("CRTC_W");
    properties_.planeCrtcH = plane("CRTC_H");
}

void KmsOutput::show(uint32_t framebuffer)
{
    if (flipPending_ && !waitForFlip(1000))
        throw RuntimeError("KMS: the previous page flip did not complete within 1 s");
    const bool modeset = !modeSet_;
    if (device_.atomic()) {
        try {
            commitAtomic(framebuffer, modeset);
        } catch (const RuntimeError& e) {
            if (!modeset)
                throw;
            // The test commit (or the first real one) failed: the legacy API may still work.
            LUMAR_LOG(Output, Warn) << "atomic mode-set refused (" << e.what() << "); using the legacy KMS API";
            device_.useLegacyApi();
            commitLegacy(framebuffer, modeset);
        }
    } else {
        commitLegacy(framebuffer, modeset);
    }
    modeSet_ = true;
}

void KmsOutput::commitAtomic(uint32_t framebuffer, bool modeset)
{
    DrmAtomicRequest request(drmModeAtomicAlloc());
    if (!request)
        throw RuntimeError("KMS: out of memory for an atomic request");
    if (modeset) {
        modeBlob_ = DrmPropertyBlob(device_.fd(), &mode_, sizeof mode_);
        addProperty(request.get(), connectorId_, properties_.connectorCrtcId, crtcId_);
        addProperty(request.get(), crtcId_, properties_.crtcModeId, modeBlob_.id());
        addProperty(request.get(), crtcId_, properties_.crtcActive, 1);
    }
    addProperty(request.get(), planeId_, properties_.planeFbId, framebuffer);
    addProperty(request.get(), planeId_, properties_.planeCrtcId, crtcId_);
    addProperty(request.get(), planeId_, properties_.planeSrcX, 0);
    addProperty(request.get(), planeId_, properties_.planeSrcY, 0);
    addProperty(request.get(), planeId_, properties_.planeSrcW, uint64_t(width()) << 16);
    addProperty(request.get(), planeId_, properties_.planeSrcH, uint64_t(height()) << 16);
    addProperty(request.get(), planeId_, properties_.planeCrtcX, 0);
    addProperty(request.get(), planeId_, properties_.planeCrtcY, 0);
    addProperty(request.get(), planeId_, properties_.planeCrtcW, uint64_t(width()));
    addProperty(request.get(), planeId_, properties_.planeCrtcH, uint64_t(height()));

    uint32_t flags = DRM_MODE_PAGE_FLIP_EVENT;
    if (modeset) {
        // Ask the driver first whether it takes the whole configuration.
        const int tested = drmModeAtomicCommit(device_.fd(), request.get(),
                                               DRM_MODE_ATOMIC_TEST_ONLY | DRM_MODE_ATOMIC_ALLOW_MODESET, nullptr);
        if (tested != 0)
            throw RuntimeError(std::string("test-only commit: ") + std::strerror(errno));
        flags |= DRM_MODE_ATOMIC_ALLOW_MODESET;
    } else {
        flags |= DRM_MODE_ATOMIC_NONBLOCK;
    }
    if (drmModeAtomicCommit(device_.fd(), request.get(), flags, this) != 0)
        throw RuntimeError(std::string("atomic commit: ") + std::strerror(errno));
    flipPending_ = true;
}

void KmsOutput::commitLegacy(uint32_t framebuffer, bool modeset)
{
    if (modeset) {
        uint32_t connector = connectorId_;
        if (drmModeSetCrtc(device_.fd(), crtcId_, framebuffer, 0, 0, &connector, 1, &mode_) != 0)
            throw RuntimeError(std::string("KMS: drmModeSetCrtc: ") + std::strerror(errno));
        return; // the mode-set shows the framebuffer at once: no flip to wait for
    }
    if (drmModePageFlip(device_.fd(), crtcId_, framebuffer, DRM_MODE_PAGE_FLIP_EVENT, this) != 0)
        throw RuntimeError(std::string("KMS: drmModePageFlip: ") + std::strerror(errno));
    flipPending_ = true;
}

void KmsOutput::onPageFlip(int /*fd*/, unsigned /*sequence*/, unsigned seconds, unsigned microseconds, void* data)
{
    auto* output = static_cast<KmsOutput*>(data);
    output->flipPending_ = false;
    ++output->flipsCompleted_;
    // DRM stamps events on CLOCK_MONOTONIC (DRM_CAP_TIMESTAMP_MONOTONIC, the only clock left).
    output->lastFlipNs_ = int64_t(seconds) * 1'000'000'000 + int64_t(microseconds) * 1000;
}

bool KmsOutput::waitForFlip(int timeoutMs)
{
    drmEventContext events{};
    events.version = 2;
    events.page_flip_handler = onPageFlip;
    while (flipPending_) {
        pollfd fd{device_.fd(), POLLIN, 0};
        const int ready = ::poll(&fd, 1, timeoutMs);
        if (ready < 0 && errno == EINTR)
            continue;
        if (ready <= 0)
            return false;
        if (drmHandleEvent(device_.fd(), &events) != 0)
            return false;
    }
    return true;
}

} // namespace lumar
