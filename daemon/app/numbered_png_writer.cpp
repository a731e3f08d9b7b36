#include "numbered_png_writer.h"

#include <cctype>
#include <cstdio>
#include <vector>

#include "core/error.h"

namespace lumar {

NumberedPngWriter::NumberedPngWriter(std::string pattern) : pattern_(std::move(pattern))
{
    // Accept exactly one conversion of the form %[0][width]d, so the pattern can be given to
    // snprintf safely.
    const size_t percent = pattern_.find('%');
    size_t i = percent + 1;
    if (i < pattern_.size() && pattern_[i] == '0')
        ++i;
    while (i < pattern_.size() && std::isdigit(static_cast<unsigned char>(pattern_[i])))
        ++i;
    const bool valid = i < pattern_.size() && pattern_[i] == 'd' && pattern_.find('%', i) == std::string::npos &&
                       std::filesystem::path(pattern_).extension() == ".png";
    if (!valid)
        throw InputError(pattern_ + ": an image sequence needs one %d (e.g. frame_%04d.png) and the .png extension");
}

void NumberedPngWriter::write(const Image8& rgb)
{
    std::vector<char> name(pattern_.size() + 32);
    std::snprintf(name.data(), name.size(), pattern_.c_str(), static_cast<int>(next_++));
    writePng(name.data(), rgb);
}

} // namespace lumar
