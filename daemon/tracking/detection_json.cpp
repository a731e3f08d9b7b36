#include "tracking/detection_json.h"

#include <charconv>
#include <cmath>

namespace lumar {
namespace {

// Significant digits: corners and margins are sub-pixel measurements, the pose is kept to
// near float precision so that consumers can re-project without visible loss.
constexpr int kPixelDigits = 6;
constexpr int kPoseDigits = 9;

// std::to_chars is locale-independent, unlike printf's %g.
void appendNumber(std::string& out, double value, int digits)
{
    if (!std::isfinite(value)) {
        out += "null"; // JSON has no NaN or infinity
        return;
    }
    char text[64];
    const auto result = std::to_chars(text, text + sizeof(text), value, std::chars_format::general, digits);
    out.append(text, result.ptr);
}

// Length of the valid UTF-8 sequence starting at text[i], or 0 when it is not valid.
size_t utf8SequenceLength(const std::string& text, size_t i)
{
    const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned char lead = byte(i);
    size_t length = 0;
    unsigned char min2 = 0x80, max2 = 0xBF; // allowed range of the second byte
    if (lead >= 0xC2 && lead <= 0xDF) {
        length = 2;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
        length = 3;
        if (lead == 0xE0)
            min2 = 0xA0; // overlong
        if (lead == 0xED)
            max2 = 0x9F; // surrogates
    } else if (lead >= 0xF0 && lead <= 0xF4) {
        length = 4;
        if (lead == 0xF0)
            min2 = 0x90; // overlong
        if (lead == 0xF4)
            max2 = 0x8F; // beyond U+10FFFF
    } else {
        return 0;
    }
    if (i + length > text.size())
        return 0;
    if (byte(i + 1) < min2 || byte(i + 1) > max2)
        return 0;
    for (size_t k = 2; k < length; ++k)
        if (byte(i + k) < 0x80 || byte(i + k) > 0xBF)
            return 0;
    return length;
}

} // namespace

std::string jsonString(const std::string& text)
{
    static constexpr char kHex[] = "0123456789abcdef";
    std::string out = "\"";
    for (size_t i = 0; i < text.size();) {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c >= 0x80) {
            const size_t length = utf8SequenceLength(text, i);
            if (length == 0) {
                out += "\\ufffd";
                ++i;
            } else {
                out.append(text, i, length);
                i += length;
            }
            continue;
        }
        switch (c) {
        case '"':
            out += "\\\"";
            break;
        case '\\':
            out += "\\\\";
            break;
        case '\b':
            out += "\\b";
            break;
        case '\f':
            out += "\\f";
            break;
        case '\n':
            out += "\\n";
            break;
        case '\r':
            out += "\\r";
            break;
        case '\t':
            out += "\\t";
            break;
        default:
            if (c < 0x20) {
                out += "\\u00";
                out += kHex[c >> 4];
                out += kHex[c & 0xF];
            } else {
                out += char(c);
            }
        }
        ++i;
    }
    out += '"';
    return out;
}

std::string detectionsToJson(const std::string& file, const std::vector<TagDetection>& detections)
{
    std::string out = "{\"file\":" + jsonString(file) + ",\"detections\":[";
    for (size_t i = 0; i < detections.size(); ++i) {
        const TagDetection& d = detections[i];
        if (i > 0)
            out += ',';
        out += "{\"id\":" + std::to_string(d.id) + ",\"hamming\":" + std::to_string(d.hamming) + ",\"margin\":";
        appendNumber(out, d.decisionMargin, kPixelDigits);
        out += ",\"corners\":[";
        for (size_t c = 0; c < d.corners.size(); ++c) {
            out += c > 0 ? ",[" : "[";
            appendNumber(out, d.corners[c].x, kPixelDigits);
            out += ',';
            appendNumber(out, d.corners[c].y, kPixelDigits);
            out += ']';
        }
        out += ']';
        if (d.hasPose) {
            const Pose& p = d.cameraFromMarker;
            out += ",\"R\":[";
            for (int row = 0; row < 3; ++row) {
                out += row > 0 ? ",[" : "[";
                for (int col = 0; col < 3; ++col) {
                    if (col > 0)
                        out += ',';
                    appendNumber(out, p.R[col][row], kPoseDigits); // glm: R[column][row]
                }
                out += ']';
            }
            out += "],\"t\":[";
            for (int k = 0; k < 3; ++k) {
                if (k > 0)
                    out += ',';
                appendNumber(out, p.t[k], kPoseDigits);
            }
            out += ']';
        }
        out += '}';
    }
    out += "]}";
    return out;
}

} // namespace lumar
