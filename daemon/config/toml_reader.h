// Typed, validating access to one TOML table. Every value read is checked for type and range,
// every key read is remembered, and finish() rejects the keys nobody read — so a typo in a
// config file is an error with its line, not a silently ignored setting.
#pragma once

#include <filesystem>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <toml++/toml.h>

namespace lumar::config_detail {

class TableReader {
public:
    // `keyPath` is the dotted path of this table in messages ("" for the root, "objects[1]").
    TableReader(const toml::table& table, std::string keyPath, std::string fileName);

    // Each getter leaves `out` unchanged when the key is absent (the default stays) and throws
    // InputError "FILE:LINE: key: what is wrong" for a wrong type or a value out of range.
    void integer(std::string_view key, int& out, long long min, long long max);
    void unsignedInteger(std::string_view key, uint64_t& out);
    void number(std::string_view key, double& out, double min, double max, bool minExclusive = false);
    void boolean(std::string_view key, bool& out);
    void string(std::string_view key, std::string& out);
    void oneOf(std::string_view key, std::string& out, std::initializer_list<std::string_view> allowed);
    void vec2(std::string_view key, glm::dvec2& out, double limit);
    // Three finite numbers; with `limit`, each within [-limit, limit].
    void vec3(std::string_view key, glm::dvec3& out, double limit = std::numeric_limits<double>::infinity());
    // An array of strings, each with its node (for a message on the element's own line);
    // empty when the key is absent.
    std::vector<std::pair<std::string, const toml::node*>> stringArray(std::string_view key);
    // A path, resolved against baseDir; `mustExist` checks the file (or directory) exists.
    enum class Expect { File, Directory, Parent };
    void path(std::string_view key, std::filesystem::path& out, const std::filesystem::path& baseDir, Expect expect);

    [[nodiscard]] bool has(std::string_view key) const { return table_.contains(key); }
    [[nodiscard]] const toml::node* node(std::string_view key) const { return table_.get(key); }
    // A sub-table or array of tables, marked as read; nullptr when absent.
    const toml::table* table(std::string_view key);
    const toml::array* arrayOfTables(std::string_view key);

    // Fails naming `key` unless `value` (read from it) is even: 4:2:0 video needs even sizes.
    void checkEven(std::string_view key, int value) const;

    // Throws for the first key that was never read.
    void finish() const;

    [[noreturn]] void fail(const toml::node* node, std::string_view key, const std::string& what) const;
    [[noreturn]] void failMissing(std::string_view key) const;
    [[nodiscard]] std::string keyName(std::string_view key) const;
    [[nodiscard]] const std::string& fileName() const { return fileName_; }
    [[nodiscard]] const std::string& keyPath() const { return keyPath_; }

private:
    const toml::node* find(std::string_view key);
    // The value of `key` as TOML type T (and its node), or nullptr when the key is absent; a
    // value of another type fails with "expected <expected>, found <its type>".
    template <typename T>
    const toml::value<T>* typed(std::string_view key, const char* expected, const toml::node*& node);
    // Reads an array of exactly `count` (<= 4) finite numbers within [-limit, limit].
    void numbers(std::string_view key, double* out, int count, double limit);

    const toml::table& table_;
    std::string keyPath_;
    std::string fileName_;
    std::set<std::string, std::less<>> read_;
};

} // namespace lumar::config_detail
