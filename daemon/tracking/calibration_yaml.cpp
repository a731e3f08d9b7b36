#include "tracking/calibration_yaml.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/error.h"

namespace lumar::calibration_yaml {
namespace {

struct Line {
    size_t number = 0;
    size_t indent = 0;
    std::string_view content; // without indentation, comment and trailing blanks
};

std::string_view trim(std::string_view s)
{
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t'))
        s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t'))
        s.remove_suffix(1);
    return s;
}

// A comment starts with '#' at the start of the content or after a blank, outside quotes.
std::string_view withoutComment(std::string_view s)
{
    char quote = 0;
    for (size_t i = 0; i < s.size(); ++i) {
        const char c = s[i];
        if (quote) {
            if (c == quote)
                quote = 0;
        } else if (c == '"' || c == '\'') {
            quote = c;
        } else if (c == '#' && (i == 0 || s[i - 1] == ' ' || s[i - 1] == '\t')) {
            return s.substr(0, i);
        }
    }
    return s;
}

class Parser {
public:
    Parser(std::string_view text, const std::string& fileName) : fileName_(fileName) { split(text); }

    Document run()
    {
        Document document;
        size_t i = 0;
        skipBlank(i);
        if (i < lines_.size() && lines_[i].content.starts_with('%')) {
            if (!lines_[i].content.starts_with("%YAML"))
                fail(lines_[i], "unsupported directive '" + std::string(lines_[i].content) + "'");
            ++i;
            skipBlank(i);
        }
        if (i < lines_.size() && lines_[i].content == "---")
            ++i;
        while (i < lines_.size()) {
            const Line& line = lines_[i];
            if (line.content.empty()) {
                ++i;
                continue;
            }
            if (line.content == "...")
                break;
            if (line.content == "---")
                fail(line, "holds more than one YAML document");
            if (line.indent != 0)
                fail(line, "unexpected indentation");
            const auto [key, rest] = keyAndRest(line);
            if (document.count(key))
                fail(line, "duplicate key '" + std::string(key) + "'");
            Value value;
            value.line = line.number;
            ++i;
            if (rest == "!!opencv-matrix") {
                value.kind = Value::Kind::Matrix;
                value.matrix = matrix(key, line, i);
            } else if (rest.empty()) {
                value.kind = Value::Kind::Block; // read by no one: its lines are skipped
                while (i < lines_.size() && (lines_[i].content.empty() || lines_[i].indent > 0))
                    ++i;
            } else {
                scalarOrSequence(rest, line, i, value);
            }
            document.emplace(std::string(key), std::move(value));
        }
        return document;
    }

private:
    [[noreturn]] void fail(const Line& line, const std::string& what) const
    {
        throw InputError(fileName_ + ":" + std::to_string(line.number) + ": malformed file: " + what);
    }

    void split(std::string_view text)
    {
        size_t number = 1;
        for (size_t start = 0; start <= text.size(); ++number) {
            size_t end = text.find('\n', start);
            if (end == std::string_view::npos)
                end = text.size();
            std::string_view raw = text.substr(start, end - start);
            if (!raw.empty() && raw.back() == '\r')
                raw.remove_suffix(1);
            Line line;
            line.number = number;
            for (const char c : raw) {
                const auto byte = static_cast<unsigned char>(c);
                if (byte < 0x20 && c != '\t' && c != '\r') {
                    char hex[8];
                    std::snprintf(hex, sizeof hex, "0x%02x", byte);
                    fail(line, std::string("cannot parse a control character (") + hex + ")");
                }
            }
            while (line.indent < raw.size() && raw[line.indent] == ' ')
                ++line.indent;
            line.content = trim(withoutComment(raw.substr(line.indent)));
            lines_.push_back(line);
            start = end + 1;
        }
    }

    void skipBlank(size_t& i) const
    {
        while (i < lines_.size() && lines_[i].content.empty())
            ++i;
    }

    // "key: rest" with a key of letters, digits, '_' and '-' that starts with a letter or '_'.
    std::pair<std::string_view, std::string_view> keyAndRest(const Line& line) const
    {
        const std::string_view s = line.content;
        size_t k = 0;
        while (k < s.size() && (std::isalnum(static_cast<unsigned char>(s[k])) || s[k] == '_' || s[k] == '-'))
            ++k;
        const bool startsWell = k > 0 && !std::isdigit(static_cast<unsigned char>(s[0])) && s[0] != '-';
        if (!startsWell || k >= s.size() || s[k] != ':' || (k + 1 < s.size() && s[k + 1] != ' ' && s[k + 1] != '\t')) {
            if (line.content.starts_with("<?xml") || line.content.starts_with("<opencv_storage") ||
                line.content.starts_with("{"))
                fail(line, "cannot parse: only OpenCV's YAML calibration files are read, not XML or JSON");
            fail(line, "cannot parse '" + std::string(s.substr(0, 40)) + "' (expected 'key: value')");
        }
        return {s.substr(0, k), trim(s.substr(k + 1))};
    }

    // A scalar, or a flow sequence "[ a, b, ... ]" that may continue on indented lines.
    void scalarOrSequence(std::string_view rest, const Line& line, size_t& next, Value& value)
    {
        if (rest.front() == '[') {
            value.kind = Value::Kind::Sequence;
            value.entries = sequence(rest, line, next);
            return;
        }
        if (rest.front() == '"' || rest.front() == '\'') {
            const char quote = rest.front();
            if (rest.size() < 2 || rest.back() != quote)
                fail(line, "unterminated quoted text");
            value.scalar = std::string(rest.substr(1, rest.size() - 2));
            return;
        }
        if (std::string_view("{&*!|>@`").find(rest.front()) != std::string_view::npos)
            fail(line, "cannot parse '" + std::string(rest.substr(0, 40)) + "' (unsupported YAML)");
        value.scalar = std::string(rest);
    }

    std::vector<std::string> sequence(std::string_view rest, const Line& first, size_t& next)
    {
        std::vector<std::string> entries;
        std::string item;
        const Line* line = &first;
        std::string_view s = rest.substr(1);
        for (;;) {
            for (size_t at = 0; at < s.size(); ++at) {
                const char c = s[at];
                if (c == ']' || c == ',') {
                    const std::string_view entry = trim(item);
                    if (entry.empty() && !(c == ']' && entries.empty()))
                        fail(*line, "empty element in a sequence");
                    if (!entry.empty())
                        entries.emplace_back(entry);
                    if (entries.size() > kMaxMatrixElements)
                        fail(*line, "a sequence longer than " + std::to_string(kMaxMatrixElements) + " elements");
                    item.clear();
                    if (c == ']') {
                        if (at + 1 != s.size())
                            fail(*line, "text after the end of a sequence");
                        return entries;
                    }
                } else if (c == '[' || c == '{' || c == '}' || c == ':' || c == '"' || c == '\'') {
                    fail(*line, std::string("unexpected '") + c + "' in a sequence");
                } else {
                    item.push_back(c);
                }
            }
            item.push_back(' ');
            while (next < lines_.size() && lines_[next].content.empty())
                ++next;
            if (next >= lines_.size() || lines_[next].indent == 0)
                fail(*line, "the sequence has no closing ']'");
            line = &lines_[next++];
            s = line->content;
        }
    }

    Matrix matrix(std::string_view key, const Line& header, size_t& next)
    {
        std::optional<int> rows, cols;
        std::optional<char> type;
        std::optional<std::vector<std::string>> data;
        const std::string name(key);
        while (next < lines_.size() && (lines_[next].content.empty() || lines_[next].indent > 0)) {
            const Line& line = lines_[next++];
            if (line.content.empty())
                continue;
            // Not a structured binding: the lambda below captures `field`, which clang before
            // 16 cannot do with a binding (the fuzz targets build with Debian 12's clang 14).
            const std::pair<std::string_view, std::string_view> fieldAndRest = keyAndRest(line);
            const std::string_view field = fieldAndRest.first;
            const std::string_view rest = fieldAndRest.second;
            if (rest.empty())
                fail(line, name + "." + std::string(field) + ": no value");
            Value value;
            scalarOrSequence(rest, line, next, value);
            const auto integer = [&](std::optional<int>& out) {
                int v = 0;
                const auto [end, ec] =
                    std::from_chars(value.scalar.data(), value.scalar.data() + value.scalar.size(), v);
                if (value.kind != Value::Kind::Scalar || ec != std::errc() ||
                    end != value.scalar.data() + value.scalar.size() || v < 1 || size_t(v) > kMaxMatrixElements)
                    throw InputError(fileName_ + ": " + name + ": not a valid !!opencv-matrix (" + std::string(field) +
                                     " must be an integer in 1.." + std::to_string(kMaxMatrixElements) + ")");
                out = v;
            };
            if (field == "rows" && !rows) {
                integer(rows);
            } else if (field == "cols" && !cols) {
                integer(cols);
            } else if (field == "dt" && !type) {
                if (value.kind != Value::Kind::Scalar || value.scalar.size() != 1 ||
                    std::string_view("ucwsifd").find(value.scalar[0]) == std::string_view::npos)
                    throw InputError(fileName_ + ": " + name +
                                     ": not a valid !!opencv-matrix (dt must be one of u c w s i f d: one channel)");
                type = value.scalar[0];
            } else if (field == "data" && !data) {
                if (value.kind != Value::Kind::Sequence)
                    fail(line, name + ".data: expected a sequence [ ... ]");
                data = std::move(value.entries);
            } else {
                fail(line, name + ": unknown or repeated matrix field '" + std::string(field) + "'");
            }
        }
        if (!rows || !cols || !type || !data)
            throw InputError(fileName_ + ": " + name +
                             ": not a valid !!opencv-matrix (rows, cols, dt and data needed)");
        if (size_t(*rows) * size_t(*cols) != data->size())
            throw InputError(fileName_ + ": " + name + ": not a valid !!opencv-matrix (" +
                             std::to_string(data->size()) + " values for " + std::to_string(*rows) + "x" +
                             std::to_string(*cols) + ")");
        Matrix m;
        m.rows = *rows;
        m.cols = *cols;
        m.type = *type;
        m.data.reserve(data->size());
        for (const std::string& text : *data) {
            const std::optional<double> v = toNumber(text);
            if (!v)
                throw InputError(fileName_ + ":" + std::to_string(header.number) + ": " + name +
                                 ": not a valid !!opencv-matrix ('" + text.substr(0, 40) + "' is not a number)");
            m.data.push_back(*v);
        }
        return m;
    }

    const std::string& fileName_;
    std::vector<Line> lines_;
};

} // namespace

std::optional<double> toNumber(std::string_view text)
{
    std::string_view digits = text;
    bool negative = false;
    if (!digits.empty() && (digits.front() == '+' || digits.front() == '-')) {
        negative = digits.front() == '-';
        digits.remove_prefix(1);
    }
    if (digits == ".inf" || digits == ".Inf" || digits == ".INF")
        return negative ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
    if (text == ".nan" || text == ".NaN" || text == ".NAN")
        return std::numeric_limits<double>::quiet_NaN();
    if (digits.empty() || !(std::isdigit(static_cast<unsigned char>(digits.front())) || digits.front() == '.'))
        return std::nullopt; // from_chars would also take "inf" and "nan"
    double value = 0.0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (ec != std::errc() || end != digits.data() + digits.size())
        return std::nullopt;
    return negative ? -value : value;
}

Document parse(std::string_view text, const std::string& fileName)
{
    if (text.size() > kMaxFileBytes)
        throw InputError(fileName + ": the file is larger than " + std::to_string(kMaxFileBytes >> 20) + " MiB");
    return Parser(text, fileName).run();
}

} // namespace lumar::calibration_yaml
