#include "capture/y4m_source.h"

#include <filesystem>
#include <system_error>

#include "core/error.h"
#include "core/log.h"

namespace lumar {
namespace {

// Longer header lines than this are not a Y4M file; the cap keeps a binary file from
// being read whole in search of a newline.
constexpr size_t kMaxHeaderLine = 4096;
constexpr std::string_view kFrameMagic = "FRAME";

// Reads up to '\n' (consumed, not stored). Returns false when the cap is reached or the file
// ends before a newline; `line` then holds what was read.
bool readLine(std::ifstream& in, std::string& line)
{
    line.clear();
    char c = 0;
    while (line.size() < kMaxHeaderLine && in.get(c)) {
        if (c == '\n') {
            return true;
        }
        line.push_back(c);
    }
    return false;
}

Y4mHeader readHeader(std::ifstream& in, const std::string& fileName)
{
    std::string line;
    if (!readLine(in, line)) {
        if (line.rfind("YUV4MPEG2", 0) != 0) {
            throw InputError(fileName + ": not a YUV4MPEG2 file (the header must start with \"YUV4MPEG2 \")");
        }
        throw InputError(fileName + ": the header line is unterminated or longer than 4096 bytes");
    }
    return parseY4mHeader(line, fileName);
}

int64_t timestampNs(uint64_t sequence, double fps)
{
    return int64_t(double(sequence) * 1e9 / fps + 0.5);
}

} // namespace

Y4mSource::Y4mSource(const CameraConfig& config)
    : fileName_(config.path.string()), file_(config.path, std::ios::binary), header_(), loop_(config.loop),
      converter_(0, 0, 0, 0)
{
    if (!file_) {
        throw InputError(fileName_ + ": cannot open the Y4M file");
    }
    header_ = readHeader(file_, fileName_);
    firstFrame_ = file_.tellg();

    if (header_.fpsNumerator > 0) {
        fps_ = double(header_.fpsNumerator) / double(header_.fpsDenominator);
    } else {
        if (!(config.fps > 0.0)) {
            throw InputError(fileName_ + ": the header has no frame rate (F field) and camera.fps is not positive");
        }
        fps_ = config.fps;
        LUMAR_LOG(Capture, Warn) << fileName_ << ": no frame rate in the header, using camera.fps " << fps_;
    }

    // A header can claim any size up to 16384²; check that the file holds one whole frame
    // before allocating a buffer for it.
    std::error_code ec;
    const uintmax_t fileSize = std::filesystem::file_size(config.path, ec);
    if (ec) {
        throw InputError(fileName_ + ": cannot read the file size: " + ec.message());
    }
    const uintmax_t remaining = fileSize - uintmax_t(firstFrame_);
    if (remaining == 0) {
        throw InputError(fileName_ + ": the file has a header but no frames");
    }
    if (remaining < kFrameMagic.size() + 1 + header_.frameBytes()) {
        throw InputError(fileName_ + ": frame 0 is truncated (" + std::to_string(remaining) +
                         " bytes after the header, a frame needs " + std::to_string(header_.frameBytes()) +
                         " plus its FRAME line)");
    }

    planes_.resize(header_.frameBytes());
    converter_ = YCbCrToRgb(header_.width, header_.height, header_.chromaWidth(), header_.chromaHeight());
    LUMAR_LOG(Capture, Info) << "y4m " << fileName_ << ": " << header_.width << "x" << header_.height << " at " << fps_
                             << " fps, " << (header_.fullRange ? "full" : "limited") << " range";
}

std::string Y4mSource::where() const
{
    return fileName_ + ": frame " + std::to_string(framesInFile_);
}

bool Y4mSource::readFrameMarker()
{
    std::string line;
    const bool complete = readLine(file_, line);
    if (!complete && line.empty() && file_.eof()) {
        return false; // a clean end: the previous frame was the last
    }
    if (line.rfind(kFrameMagic, 0) != 0 || (line.size() > kFrameMagic.size() && line[kFrameMagic.size()] != ' ')) {
        throw InputError(where() + ": missing FRAME marker");
    }
    if (!complete) {
        throw InputError(where() + ": the FRAME line is unterminated or longer than 4096 bytes");
    }
    return true;
}

bool Y4mSource::next(Frame& frame)
{
    if (!readFrameMarker()) {
        if (!loop_ || framesInFile_ == 0) {
            return false;
        }
        file_.clear();
        file_.seekg(firstFrame_);
        framesInFile_ = 0;
        if (!file_ || !readFrameMarker()) {
            throw InputError(fileName_ + ": cannot seek back to the first frame to loop");
        }
    }
    file_.read(reinterpret_cast<char*>(planes_.data()), std::streamsize(planes_.size()));
    if (size_t(file_.gcount()) != planes_.size()) {
        throw InputError(where() + ": truncated (" + std::to_string(file_.gcount()) + " of " +
                         std::to_string(planes_.size()) + " bytes)");
    }

    const size_t lumaBytes = size_t(header_.width) * size_t(header_.height);
    const size_t chromaBytes = size_t(header_.chromaWidth()) * size_t(header_.chromaHeight());
    PlanarYCbCr picture;
    picture.y = planes_.data();
    if (chromaBytes > 0) {
        picture.cb = planes_.data() + lumaBytes;
        picture.cr = planes_.data() + lumaBytes + chromaBytes;
    }
    picture.fullRange = header_.fullRange;
    converter_.convert(picture, frame.rgb, frame.luma);

    frame.sequence = sequence_;
    frame.timestampNs = timestampNs(sequence_, fps_);
    ++sequence_;
    ++framesInFile_;
    return true;
}

} // namespace lumar
