#include "kms_sink.h"

#include "core/log.h"

namespace lumar {

KmsDisplayOptions kmsDisplayOptions(const Config& config)
{
    KmsDisplayOptions options;
    if (config.board) {
        const BoardDisplayProfile& display = config.board->display;
        options.drivers = display.drmDrivers;
        options.output.connector = display.connector;
        options.output.plane = display.plane;
        options.modifiers = display.modifiers;
        options.finishBeforeFlip = config.board->hasQuirk("no-native-fence");
    }
    const OutputConfig& output = config.output;
    options.device = output.drmDevice;
    if (!output.connector.empty())
        options.output.connector = output.connector;
    if (output.plane != "auto")
        options.output.plane = output.plane;
    options.output.mode = output.mode;
    options.legacyApi = output.kmsApi == "legacy";
    return options;
}

std::unique_ptr<KmsDisplay> openKmsDisplay(const Config& config)
{
    std::string why;
    auto display = KmsDisplay::open(kmsDisplayOptions(config), why);
    if (!display) {
        const std::string fallback =
            config.output.path.empty() ? "no output" : "the headless sink (" + config.output.path.string() + ")";
        LUMAR_LOG(Output, Warn) << "no DRM display to present on (" << why << "); falling back to " << fallback;
    }
    return display;
}

} // namespace lumar
