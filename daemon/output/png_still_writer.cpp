#include "output/png_still_writer.h"

#include <utility>

#include "core/log.h"

namespace lumar {

PngStillWriter::PngStillWriter(std::filesystem::path file) : path_(std::move(file)) {}

PngStillWriter::~PngStillWriter()
{
    try {
        finish();
    } catch (const std::exception& e) {
        LUMAR_LOG(Output, Error) << e.what();
    }
}

void PngStillWriter::write(const Image8& rgb)
{
    // Assigning into the same-sized vector reuses its storage: no allocation per frame.
    last_.width = rgb.width;
    last_.height = rgb.height;
    last_.channels = rgb.channels;
    last_.data.assign(rgb.data.begin(), rgb.data.end());
}

void PngStillWriter::finish()
{
    if (finished_) {
        return;
    }
    finished_ = true;
    if (last_.empty()) {
        LUMAR_LOG(Output, Warn) << path_.string() << ": no frame was written, so no PNG either";
        return;
    }
    writePng(path_, last_);
}

} // namespace lumar
