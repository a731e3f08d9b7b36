// A FILE* that closes itself, for writers that must still check fclose's result (a full
// disk often shows only there): close() reports, the destructor is the silent fallback.
#pragma once

#include <cstdio>
#include <filesystem>
#include <memory>

namespace lumar {

struct FileCloser {
    void operator()(std::FILE* file) const { std::fclose(file); }
};
using CFile = std::unique_ptr<std::FILE, FileCloser>;

// Opens `file` for binary writing. Throws RuntimeError naming the file and the OS's reason.
CFile openForWriting(const std::filesystem::path& file);

// Writes all `bytes` or throws RuntimeError naming the file.
void writeAll(std::FILE* out, const void* data, size_t bytes, const std::filesystem::path& file);

// Closes and throws RuntimeError naming the file if buffered data could not be written.
void closeChecked(CFile& out, const std::filesystem::path& file);

} // namespace lumar
