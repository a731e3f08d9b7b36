// What `lumar probe` says about DRM/KMS devices: per card node its driver, connectors with
// their state and modes, CRTCs and planes with their types and formats.
#pragma once

#include <string>
#include <vector>

namespace lumar {

// One line each, indented for the probe's listing; a single line saying so when there is no
// DRM device.
std::vector<std::string> describeDrmDevices();

} // namespace lumar
