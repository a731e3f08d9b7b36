#include "output/c_file.h"

#include <cerrno>
#include <cstring>
#include <string>

#include "core/error.h"

namespace lumar {
namespace {

std::string reason(int error)
{
    return std::strerror(error);
}

} // namespace

CFile openForWriting(const std::filesystem::path& file)
{
    CFile out(std::fopen(file.c_str(), "wb"));
    if (!out) {
        throw RuntimeError(file.string() + ": cannot open for writing: " + reason(errno));
    }
    return out;
}

void writeAll(std::FILE* out, const void* data, size_t bytes, const std::filesystem::path& file)
{
    if (bytes > 0 && std::fwrite(data, 1, bytes, out) != bytes) {
        throw RuntimeError(file.string() + ": write failed: " + reason(errno));
    }
}

void closeChecked(CFile& out, const std::filesystem::path& file)
{
    if (!out) {
        return;
    }
    // release() first: whatever fclose returns, the stream is gone and must not be closed again.
    const int result = std::fclose(out.release());
    if (result != 0) {
        throw RuntimeError(file.string() + ": write failed while closing: " + reason(errno));
    }
}

} // namespace lumar
