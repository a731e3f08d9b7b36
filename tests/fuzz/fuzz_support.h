// Shared by the fuzz targets: a private scratch directory per process, where an input is
// written as the file the loader under test opens (lumar's loaders take paths, as lumar calls
// them), and the one rule every target checks: bad input ends in InputError, nothing else.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "core/error.h"
#include "core/log.h"

namespace lumar::fuzz {

inline const std::filesystem::path& scratchDir()
{
    static const std::filesystem::path dir = [] {
        const std::filesystem::path d =
            std::filesystem::temp_directory_path() / ("lumar-fuzz-" + std::to_string(::getpid()));
        std::filesystem::create_directories(d);
        std::atexit([] {
            std::error_code ignored;
            std::filesystem::remove_all(
                std::filesystem::temp_directory_path() / ("lumar-fuzz-" + std::to_string(::getpid())), ignored);
        });
        log::configure("*:off"); // warnings about odd inputs are expected here
        return d;
    }();
    return dir;
}

inline std::filesystem::path writeInput(const std::string& name, const uint8_t* data, size_t size)
{
    const std::filesystem::path file = scratchDir() / name;
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return file;
}

// Runs `load`; an InputError is the expected answer to a bad input, anything else escapes
// (and libFuzzer or the replay driver reports it).
template <typename Fn> int expectInputErrorOnly(Fn&& load)
{
    try {
        load();
    } catch (const InputError&) {
    }
    return 0;
}

} // namespace lumar::fuzz
