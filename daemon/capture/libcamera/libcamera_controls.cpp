#include "capture/libcamera/libcamera_controls.h"

#include <algorithm>
#include <cmath>

#include <libcamera/control_ids.h>

#include "core/log.h"

namespace lumar {
namespace {

// libcamera v0.2's AeFlickerMode values (control_ids.yaml): FlickerOff, FlickerManual.
constexpr int32_t kFlickerOff = 0;
constexpr int32_t kFlickerManual = 1;

const libcamera::ControlInfo* advertised(const libcamera::ControlInfoMap& info, const libcamera::ControlId& id)
{
    const auto found = info.find(&id);
    return found == info.end() ? nullptr : &found->second;
}

// A control this libcamera version may not declare, found by its name among those the camera
// advertises (a newer libcamera, or a pipeline handler with it).
const std::pair<const libcamera::ControlId* const, libcamera::ControlInfo>*
advertisedByName(const libcamera::ControlInfoMap& info, const std::string& name)
{
    for (const auto& entry : info) {
        if (entry.first->name() == name) {
            return &entry;
        }
    }
    return nullptr;
}

// `value` clamped into the advertised range where the range is of T (a camera may advertise
// an empty ControlInfo: no range to clamp to). Warns when it had to clamp.
template <typename T>
T clampToRange(const libcamera::ControlInfo& range, T value, const std::string& camera, const std::string& name)
{
    constexpr libcamera::ControlType type = libcamera::details::control_type<T>::value;
    T clamped = value;
    if (range.min().type() == type && !range.min().isArray()) {
        clamped = std::max(clamped, range.min().get<T>());
    }
    if (range.max().type() == type && !range.max().isArray()) {
        clamped = std::min(clamped, range.max().get<T>());
    }
    if (clamped != value) {
        LUMAR_LOG(Capture, Warn) << "libcamera: " << camera << ": " << name << " " << value
                                 << " is outside the camera's range " << range.toString() << "; clamped to " << clamped;
    }
    return clamped;
}

// Collects the settings in order and says what it did; one instance per call.
class ControlWriter {
public:
    ControlWriter(const libcamera::ControlInfoMap& info, libcamera::ControlList& controls, const std::string& camera)
        : info_(info), controls_(controls), camera_(camera)
    {
    }

    // The control's description, or nullptr with a warning that `what` is not set.
    const libcamera::ControlInfo* find(const libcamera::ControlId& id, const std::string& what) const
    {
        const libcamera::ControlInfo* range = advertised(info_, id);
        if (range == nullptr) {
            warnMissing(id.name(), what);
        }
        return range;
    }

    void warnMissing(const std::string& control, const std::string& what) const
    {
        LUMAR_LOG(Capture, Warn) << "libcamera: " << camera_ << ": the camera has no " << control << " control for "
                                 << what << "; not set";
    }

    void setBool(const libcamera::Control<bool>& control, bool value, const std::string& key)
    {
        const libcamera::ControlInfo* range = find(control, key);
        if (range == nullptr) {
            return;
        }
        const std::vector<libcamera::ControlValue>& values = range->values();
        if (!values.empty() && std::none_of(values.begin(), values.end(), [&](const libcamera::ControlValue& v) {
                return v.type() == libcamera::ControlTypeBool && v.get<bool>() == value;
            })) {
            LUMAR_LOG(Capture, Warn) << "libcamera: " << camera_ << ": " << control.name() << " cannot be "
                                     << (value ? "true" : "false") << " on this camera; " << key << " not set";
            return;
        }
        record(control.id(), libcamera::ControlValue(value), key + " (" + control.name() + ")");
    }

    template <typename T> void setNumber(const libcamera::ControlId& id, T value, const std::string& key)
    {
        const libcamera::ControlInfo* range = find(id, key);
        if (range != nullptr) {
            setNumber(id, *range, value, key);
        }
    }

    template <typename T>
    void setNumber(const libcamera::ControlId& id, const libcamera::ControlInfo& range, T value, const std::string& key)
    {
        const std::string name = key + " (" + id.name() + ")";
        record(id.id(), libcamera::ControlValue(clampToRange(range, value, camera_, name)), name);
    }

    void record(unsigned int id, const libcamera::ControlValue& value, const std::string& name)
    {
        controls_.set(id, value);
        applied_.push_back({name, value.toString()});
        LUMAR_LOG(Capture, Info) << "libcamera: " << camera_ << ": " << name << " = " << value.toString();
    }

    [[nodiscard]] const libcamera::ControlInfoMap& info() const { return info_; }
    [[nodiscard]] const std::string& camera() const { return camera_; }
    std::vector<AppliedLibcameraControl> applied() { return std::move(applied_); }

private:
    const libcamera::ControlInfoMap& info_;
    libcamera::ControlList& controls_;
    const std::string& camera_;
    std::vector<AppliedLibcameraControl> applied_;
};

void addExposure(int exposureUs, ControlWriter& writer)
{
    namespace controls = libcamera::controls;
    if (exposureUs == CameraControlsConfig::kAuto) {
        writer.setBool(controls::AeEnable, true, "exposure_us");
        return;
    }
    // Without AeEnable the pipeline may still take a manual exposure time (it then is manual).
    writer.setBool(controls::AeEnable, false, "exposure_us");
    writer.setNumber(controls::ExposureTime, int32_t(exposureUs), "exposure_us");
}

void addWhiteBalance(int kelvin, ControlWriter& writer)
{
    namespace controls = libcamera::controls;
    if (kelvin == CameraControlsConfig::kAuto) {
        writer.setBool(controls::AwbEnable, true, "white_balance_k");
        return;
    }
    writer.setBool(controls::AwbEnable, false, "white_balance_k");
    if (const libcamera::ControlInfo* range = advertised(writer.info(), controls::ColourTemperature)) {
        writer.setNumber(controls::ColourTemperature, *range, int32_t(kelvin), "white_balance_k");
        return;
    }
    const libcamera::ControlInfo* gainsRange = advertised(writer.info(), controls::ColourGains);
    if (gainsRange == nullptr) {
        writer.warnMissing("ColourTemperature or ColourGains", "white_balance_k");
        return;
    }
    const std::string name = "white_balance_k (ColourGains of a " + std::to_string(kelvin) + " K black body)";
    std::array<float, 2> gains = colourGainsForTemperature(kelvin);
    for (float& gain : gains) {
        gain = clampToRange(*gainsRange, gain, writer.camera(), name);
    }
    writer.record(controls::ColourGains.id(), libcamera::ControlValue(libcamera::Span<const float, 2>(gains)), name);
}

void addFlicker(int powerLineHz, ControlWriter& writer)
{
    const auto* mode = advertisedByName(writer.info(), "AeFlickerMode");
    if (mode == nullptr) {
        writer.warnMissing("AeFlickerMode", "power_line_hz (libcamera has it from v0.2)");
        return;
    }
    const libcamera::ControlId& modeId = *mode->first;
    if (powerLineHz == 0) {
        writer.setNumber(modeId, mode->second, kFlickerOff, "power_line_hz");
        return;
    }
    const auto* period = advertisedByName(writer.info(), "AeFlickerPeriod");
    if (period == nullptr) {
        writer.warnMissing("AeFlickerPeriod", "power_line_hz");
        return;
    }
    writer.setNumber(modeId, mode->second, kFlickerManual, "power_line_hz");
    // Lamps flicker at twice the mains frequency: 50 Hz mains, a 10 ms period.
    const auto periodUs = int32_t(std::lround(1e6 / (2.0 * powerLineHz)));
    writer.setNumber(*period->first, period->second, periodUs, "power_line_hz");
}

} // namespace

std::vector<AppliedLibcameraControl> addLibcameraControls(const CameraControlsConfig& config,
                                                          const libcamera::ControlInfoMap& info,
                                                          libcamera::ControlList& controls, const std::string& camera)
{
    ControlWriter writer(info, controls, camera);
    if (config.exposureUs) {
        addExposure(*config.exposureUs, writer);
    }
    if (config.gain) {
        writer.setNumber(libcamera::controls::AnalogueGain, float(*config.gain) / 100.0f, "gain");
    }
    if (config.whiteBalanceK) {
        addWhiteBalance(*config.whiteBalanceK, writer);
    }
    if (config.powerLineHz) {
        addFlicker(*config.powerLineHz, writer);
    }
    return writer.applied();
}

std::optional<std::array<int64_t, 2>> frameDurationFor(double fps, const libcamera::ControlInfoMap& info)
{
    const libcamera::ControlInfo* range = advertised(info, libcamera::controls::FrameDurationLimits);
    if (range == nullptr || !(fps > 0.0)) {
        return std::nullopt;
    }
    int64_t frameUs = std::llround(1e6 / fps);
    if (range->min().type() == libcamera::ControlTypeInteger64 && !range->min().isArray()) {
        frameUs = std::max(frameUs, range->min().get<int64_t>());
    }
    if (range->max().type() == libcamera::ControlTypeInteger64 && !range->max().isArray() &&
        range->max().get<int64_t>() > 0) {
        frameUs = std::min(frameUs, range->max().get<int64_t>());
    }
    return std::array<int64_t, 2>{frameUs, frameUs};
}

std::array<float, 2> colourGainsForTemperature(int kelvin)
{
    // The Planckian locus in CIE 1931 xy (Kim et al., "Design of advanced color temperature
    // control system for HDTV applications", 2002), valid from 1667 K to 25000 K.
    const double t = std::clamp(double(kelvin), 1667.0, 25000.0);
    const double t2 = t * t;
    const double t3 = t2 * t;
    const double x = t <= 4000.0 ? -0.2661239e9 / t3 - 0.2343589e6 / t2 + 0.8776956e3 / t + 0.179910
                                 : -3.0258469e9 / t3 + 2.1070379e6 / t2 + 0.2226347e3 / t + 0.240390;
    const double x2 = x * x;
    const double x3 = x2 * x;
    const double y = t <= 2222.0   ? -1.1063814 * x3 - 1.34811020 * x2 + 2.18555832 * x - 0.20219683
                     : t <= 4000.0 ? -0.9549476 * x3 - 1.37418593 * x2 + 2.09137015 * x - 0.16748867
                                   : 3.0817580 * x3 - 5.87338670 * x2 + 3.75112997 * x - 0.37001483;
    // XYZ with Y = 1, then linear sRGB (IEC 61966-2-1).
    const double X = x / y;
    const double Z = (1.0 - x - y) / y;
    const double r = 3.2406 * X - 1.5372 - 0.4986 * Z;
    const double g = -0.9689 * X + 1.8758 + 0.0415 * Z;
    const double b = 0.0557 * X - 0.2040 + 1.0570 * Z;
    // Below about 1900 K the locus leaves the sRGB gamut (no blue at all): keep the gains finite.
    constexpr double kFloor = 1e-3;
    return {float(g / std::max(r, kFloor)), float(g / std::max(b, kFloor))};
}

} // namespace lumar
