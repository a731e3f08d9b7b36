// Format negotiation with a V4L2 capture device: which of the device's pixel formats and
// frame sizes lumar asks for, and what colorimetry the accepted format carries.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <linux/videodev2.h>

#include "capture/v4l2/ycbcr_to_rgb.h"

namespace lumar {

// The pixel formats lumar converts, best first: NV12 and YUYV carry colour uncompressed, MJPEG
// costs a JPEG decode per frame (but is what UVC cameras send at high rates), GREY is luma only.
const std::vector<uint32_t>& supportedPixelFormats();

// The preferred format among the device's, or 0 when the device offers none lumar converts.
// A non-zero `required` format is chosen when offered (0 otherwise): the config named it.
uint32_t choosePixelFormat(const std::vector<uint32_t>& deviceFormats, uint32_t required = 0);

// The fourcc a config's camera.format names ("nv12", "yuyv", "mjpeg", "grey"), 0 for "auto".
// Throws InputError for any other name.
uint32_t pixelFormatFromName(const std::string& name);

struct FrameSize {
    uint32_t width = 0;
    uint32_t height = 0;
};

// The device size closest to the request (exact when offered; else least area difference,
// ties to the larger). `sizes` must not be empty.
FrameSize chooseFrameSize(const std::vector<FrameSize>& sizes, FrameSize requested);

// The matrix and range a negotiated format carries, with V4L2's defaults for the
// "DEFAULT" values (derived from the colorspace). BT.2020 and SMPTE-240M fall back to
// BT.709, the closest of the two matrices lumar converts.
YCbCrColorimetry colorimetryOf(const v4l2_pix_format& format);

// The most formats and frame sizes an enumeration takes from a driver: a UVC camera lists a
// few formats and tens of sizes, the kernel's vivid over 64 formats (the virtual board's
// camera: a limit of 64 refused it); a driver that never ends its list (found by the fuzz
// target tests/fuzz/fuzz_v4l2_driver.cpp) would otherwise keep lumar enumerating forever.
// Far above any real list, far below what a fuzzed or broken driver costs to walk.
inline constexpr size_t kMaxV4l2Formats = 1024;
inline constexpr size_t kMaxV4l2FrameSizes = 4096;

// Enumerations through the device's ioctls; they throw RuntimeError on a device failure, on a
// list longer than the limits above, and on a size range whose minimum exceeds its maximum.
std::vector<uint32_t> enumeratePixelFormats(const std::string& device, int fd);
std::vector<FrameSize> enumerateFrameSizes(const std::string& device, int fd, uint32_t pixelFormat,
                                           FrameSize requested);

} // namespace lumar
