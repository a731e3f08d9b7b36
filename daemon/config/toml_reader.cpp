#include "toml_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <glm/gtc/type_ptr.hpp>

#include "config/toml_text.h"
#include "core/error.h"

namespace lumar::config_detail {
namespace {

using toml_text::formatNumber;
using toml_text::typeName;

} // namespace

TableReader::TableReader(const toml::table& table, std::string keyPath, std::string fileName)
    : table_(table), keyPath_(std::move(keyPath)), fileName_(std::move(fileName))
{
}

std::string TableReader::keyName(std::string_view key) const
{
    return keyPath_.empty() ? std::string(key) : keyPath_ + "." + std::string(key);
}

void TableReader::fail(const toml::node* node, std::string_view key, const std::string& what) const
{
    const toml::source_region& where = node ? node->source() : table_.source();
    const auto line = where.begin.line ? where.begin.line : 1;
    throw InputError(fileName_ + ":" + std::to_string(line) + ": " + keyName(key) + ": " + what);
}

void TableReader::failMissing(std::string_view key) const
{
    fail(nullptr, key, "required key is missing");
}

const toml::node* TableReader::find(std::string_view key)
{
    const toml::node* node = table_.get(key);
    if (node)
        read_.emplace(key);
    return node;
}

template <typename T>
const toml::value<T>* TableReader::typed(std::string_view key, const char* expected, const toml::node*& node)
{
    node = find(key);
    if (!node)
        return nullptr;
    const auto* value = node->as<T>();
    if (!value)
        fail(node, key, std::string("expected ") + expected + ", found " + typeName(*node));
    return value;
}

void TableReader::integer(std::string_view key, int& out, long long min, long long max)
{
    const toml::node* node = nullptr;
    const auto* v = typed<int64_t>(key, "an integer", node);
    if (!v)
        return;
    const long long value = v->get();
    if (value < min || value > max)
        fail(node, key,
             std::to_string(value) + " is outside [" + std::to_string(min) + ", " + std::to_string(max) + "]");
    out = int(value);
}

void TableReader::unsignedInteger(std::string_view key, uint64_t& out)
{
    const toml::node* node = nullptr;
    const auto* v = typed<int64_t>(key, "an integer", node);
    if (!v)
        return;
    if (v->get() < 0)
        fail(node, key, "must not be negative");
    out = uint64_t(v->get());
}

void TableReader::number(std::string_view key, double& out, double min, double max, bool minExclusive)
{
    const toml::node* node = find(key);
    if (!node)
        return;
    double value = 0;
    if (const auto* f = node->as_floating_point())
        value = f->get();
    else if (const auto* i = node->as_integer())
        value = double(i->get());
    else
        fail(node, key, std::string("expected a number, found ") + typeName(*node));
    const bool below = minExclusive ? value <= min : value < min;
    if (!std::isfinite(value) || below || value > max)
        fail(node, key,
             formatNumber(value) + " is outside " + (minExclusive ? "(" : "[") + formatNumber(min) + ", " +
                 formatNumber(max) + "]");
    out = value;
}

void TableReader::boolean(std::string_view key, bool& out)
{
    const toml::node* node = nullptr;
    if (const auto* v = typed<bool>(key, "true or false", node))
        out = v->get();
}

void TableReader::string(std::string_view key, std::string& out)
{
    const toml::node* node = nullptr;
    if (const auto* v = typed<std::string>(key, "a string", node))
        out = v->get();
}

void TableReader::oneOf(std::string_view key, std::string& out, std::initializer_list<std::string_view> allowed)
{
    std::string value = out;
    string(key, value);
    for (std::string_view a : allowed) {
        if (value == a) {
            out = value;
            return;
        }
    }
    std::string list;
    for (std::string_view a : allowed)
        list += (list.empty() ? "" : ", ") + std::string(a);
    fail(table_.get(key), key, "'" + value + "' is not one of " + list);
}

void TableReader::numbers(std::string_view key, double* out, int count, double limit)
{
    const toml::node* node = find(key);
    if (!node)
        return;
    const std::string expected =
        "expected an array of " + std::to_string(count) + " numbers" +
        (std::isfinite(limit) ? " within [-" + formatNumber(limit) + ", " + formatNumber(limit) + "]" : std::string());
    const auto* array = node->as_array();
    if (!array || array->size() != size_t(count))
        fail(node, key, expected);
    double values[4] = {};
    for (int i = 0; i < count; ++i) {
        const auto v = (*array)[size_t(i)].value<double>();
        if (!v || !std::isfinite(*v) || std::abs(*v) > limit)
            fail(node, key, expected);
        values[i] = *v;
    }
    std::copy(values, values + count, out);
}

void TableReader::vec2(std::string_view key, glm::dvec2& out, double limit)
{
    numbers(key, glm::value_ptr(out), 2, limit);
}

void TableReader::vec3(std::string_view key, glm::dvec3& out, double limit)
{
    numbers(key, glm::value_ptr(out), 3, limit);
}

std::vector<std::pair<std::string, const toml::node*>> TableReader::stringArray(std::string_view key)
{
    std::vector<std::pair<std::string, const toml::node*>> values;
    const toml::node* node = find(key);
    if (!node)
        return values;
    const auto* array = node->as_array();
    if (!array)
        fail(node, key, std::string("expected an array of strings, found ") + typeName(*node));
    for (const toml::node& element : *array) {
        const auto* text = element.as_string();
        if (!text)
            fail(&element, key, std::string("expected an array of strings, found ") + typeName(element));
        values.emplace_back(text->get(), &element);
    }
    return values;
}

void TableReader::path(std::string_view key, std::filesystem::path& out, const std::filesystem::path& baseDir,
                       Expect expect)
{
    std::string text;
    string(key, text);
    if (!table_.contains(key))
        return;
    const toml::node* node = table_.get(key);
    if (text.empty())
        fail(node, key, "must not be empty");
    std::filesystem::path p(text);
    if (p.is_relative())
        p = baseDir / p;
    p = p.lexically_normal();
    std::error_code ec;
    switch (expect) {
    case Expect::File:
        if (!std::filesystem::is_regular_file(p, ec))
            fail(node, key, "no such file: " + p.string());
        break;
    case Expect::Directory:
        if (!std::filesystem::is_directory(p, ec))
            fail(node, key, "no such directory: " + p.string());
        break;
    case Expect::Parent:
        if (p.has_parent_path() && !std::filesystem::is_directory(p.parent_path(), ec))
            fail(node, key, "no such directory: " + p.parent_path().string());
        break;
    }
    out = p;
}

const toml::table* TableReader::table(std::string_view key)
{
    const toml::node* node = find(key);
    if (!node)
        return nullptr;
    const auto* t = node->as_table();
    if (!t)
        fail(node, key, std::string("expected a table, found ") + typeName(*node));
    return t;
}

const toml::array* TableReader::arrayOfTables(std::string_view key)
{
    const toml::node* node = find(key);
    if (!node)
        return nullptr;
    const auto* a = node->as_array();
    if (!a || !a->is_array_of_tables())
        fail(node, key,
             std::string("expected an array of tables ([[") + keyName(key) + "]]), found " + typeName(*node));
    return a;
}

void TableReader::checkEven(std::string_view key, int value) const
{
    if (value % 2 != 0)
        fail(node(key), key, std::to_string(value) + " must be even (4:2:0 video needs even sizes)");
}

void TableReader::finish() const
{
    for (const auto& [key, node] : table_) {
        if (!read_.count(key.str()))
            fail(&node, key.str(), "unknown key");
    }
}

} // namespace lumar::config_detail
