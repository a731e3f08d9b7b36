// Reading a whole input file into memory with the checks every loader needs: a regular file,
// a size bound against hostile inputs. Messages name no file: the caller prefixes it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include "core/error.h"

namespace lumar {

// Throws InputError ("no such file", "not a regular file", "the file is larger than N MiB",
// "cannot read the file").
inline std::vector<uint8_t> readFileBytes(const std::filesystem::path& file, uintmax_t limit)
{
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
        throw InputError(std::filesystem::exists(file, ec) ? "not a regular file" : "no such file");
    const uintmax_t size = std::filesystem::file_size(file, ec);
    if (ec)
        throw InputError("cannot read the file size: " + ec.message());
    if (size > limit)
        throw InputError("the file is larger than " + std::to_string(limit >> 20) + " MiB");
    std::vector<uint8_t> bytes(static_cast<size_t>(size));
    std::ifstream in(file, std::ios::binary);
    if (!in || !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size())))
        throw InputError("cannot read the file");
    return bytes;
}

} // namespace lumar
