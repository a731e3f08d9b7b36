// What `lumar probe` reports about the EGL/GLES implementation: versions, renderer, and
// whether each extension lumar uses or will use is present.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace lumar {

struct GlInfo {
    std::string eglVendor, eglVersion, eglClientApis;
    std::string eglPlatform; // the headless display's: "device" (a GPU's EGL device) or "surfaceless"
    std::string glVersion, glRenderer, glslVersion;
    std::string driverName;                                  // the DRI driver (EGL_MESA_query_driver), empty if unknown
    std::string drmDevice;                                   // the DRM node it renders with, empty for none or unknown
    std::string cameraImport;                                // why camera dmabufs cannot be imported; empty: they can
    std::vector<std::pair<std::string, bool>> eglExtensions; // name, present
    std::vector<std::pair<std::string, bool>> glExtensions;
};

// Creates a surfaceless context to ask. Throws RuntimeError where no EGL/GLES 3 exists.
GlInfo probeGl();

} // namespace lumar
