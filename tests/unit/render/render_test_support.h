// Helpers shared by the CPU render tests: scratch files and the one-line InputError check.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"

namespace lumar::test {

// A fresh directory under the system temp dir, removed with everything in it on scope exit.
class ScratchDir {
public:
    ScratchDir()
    {
        std::random_device seed;
        const auto unique =
            std::to_string(seed()) + "-" + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count());
        path_ = std::filesystem::temp_directory_path() / ("lumar-render-test-" + unique);
        std::filesystem::create_directories(path_);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    ~ScratchDir()
    {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    [[nodiscard]] std::filesystem::path file(const std::string& name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

inline std::vector<uint8_t> readBytes(const std::filesystem::path& file)
{
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void writeBytes(const std::filesystem::path& file, const std::vector<uint8_t>& bytes)
{
    std::ofstream out(file, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

inline void writeText(const std::filesystem::path& file, const std::string& text)
{
    std::ofstream out(file, std::ios::binary);
    out << text;
}

// `load` must throw InputError with a one-line message that starts with "FILE: ".
// Returns the message (empty when the expectation failed).
inline std::string expectInputErrorNamingFile(const std::function<void()>& load, const std::filesystem::path& file)
{
    try {
        load();
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_EQ(message.find('\r'), std::string::npos) << message;
        return message;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected InputError, got another exception: " << e.what();
        return {};
    }
    ADD_FAILURE() << "expected InputError for " << file;
    return {};
}

inline std::filesystem::path sourcePath(const std::string& relative)
{
    return std::filesystem::path(LUMAR_SOURCE_DIR) / relative;
}

inline std::filesystem::path testDataPath(const std::string& relative)
{
    return std::filesystem::path(LUMAR_TEST_DATA_DIR) / relative;
}

// ../shared/data exists on the development machines only; tests that need it skip elsewhere.
inline std::filesystem::path sharedDataPath(const std::string& relative)
{
    return std::filesystem::path(LUMAR_SHARED_DATA_DIR) / relative;
}

} // namespace lumar::test
