// The configuration tests' fixture: a scratch directory per test (with a small glTF model,
// box.glb, that configs may name) and helpers that parse a text as if it were a file in it.
#pragma once

#include <filesystem>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "config/config.h"
#include "core/error.h"

namespace lumar::test {

class ConfigFixture : public ::testing::Test {
protected:
    // `fileName`: the name error messages give the parsed text.
    explicit ConfigFixture(std::string fileName = "test.toml") : fileName_(std::move(fileName)) {}

    void SetUp() override
    {
        const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = std::filesystem::temp_directory_path() /
               ("lumar-" + std::string(info->test_suite_name()) + "-" + std::string(info->name()));
        std::filesystem::remove_all(dir_);
        std::filesystem::create_directories(dir_);
        std::filesystem::copy_file(std::filesystem::path(LUMAR_TEST_DATA_DIR) / "models/BoxTextured.glb",
                                   dir_ / "box.glb");
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }

    Config parse(const std::string& text) { return parseConfig(text, fileName_, dir_); }

    // Parses `text`, expects an InputError starting with `prefix` on one line, returns it.
    std::string expectError(const std::string& text, const std::string& prefix)
    {
        try {
            (void)parse(text);
        } catch (const InputError& e) {
            const std::string message = e.what();
            EXPECT_EQ(message.rfind(prefix, 0), 0u) << "message: " << message;
            EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
            return message;
        }
        ADD_FAILURE() << "no error for:\n" << text;
        return {};
    }

    std::filesystem::path dir_;
    std::string fileName_;
};

} // namespace lumar::test
