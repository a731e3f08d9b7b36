#include "config/toml_parse.h"

#include <vector>

#include "core/error.h"

namespace lumar {
namespace {

// The line of byte `offset` (1-based).
size_t lineOf(std::string_view text, size_t offset)
{
    size_t line = 1;
    for (size_t i = 0; i < offset && i < text.size(); ++i)
        line += text[i] == '\n' ? 1 : 0;
    return line;
}

// Offset of the first byte that is not part of valid UTF-8 (RFC 3629: no overlong forms, no
// surrogates, nothing above U+10FFFF), or npos.
size_t firstInvalidUtf8(std::string_view text)
{
    const auto* s = reinterpret_cast<const unsigned char*>(text.data());
    const size_t n = text.size();
    size_t i = 0;
    while (i < n) {
        const unsigned char c = s[i];
        if (c < 0x80) {
            ++i;
            continue;
        }
        size_t length = 0;
        unsigned char lo = 0x80, hi = 0xBF; // the valid range of the second byte
        if (c >= 0xC2 && c <= 0xDF) {
            length = 2;
        } else if (c >= 0xE0 && c <= 0xEF) {
            length = 3;
            lo = c == 0xE0 ? 0xA0 : 0x80;
            hi = c == 0xED ? 0x9F : 0xBF;
        } else if (c >= 0xF0 && c <= 0xF4) {
            length = 4;
            lo = c == 0xF0 ? 0x90 : 0x80;
            hi = c == 0xF4 ? 0x8F : 0xBF;
        } else {
            return i;
        }
        if (i + length > n || s[i + 1] < lo || s[i + 1] > hi)
            return i;
        for (size_t k = 2; k < length; ++k)
            if (s[i + k] < 0x80 || s[i + k] > 0xBF)
                return i;
        i += length;
    }
    return std::string_view::npos;
}

// Finds keys, strings, comments and brackets the way TOML 1.0 delimits them, to measure how
// deep the parser will nest. It does not validate anything else: where the text is not TOML,
// toml++ stops at that point with its own message, before reaching anything after it.
class DepthScanner {
public:
    DepthScanner(std::string_view text, const std::string& fileName) : text_(text), fileName_(fileName) {}

    void run()
    {
        while (pos_ < text_.size()) {
            skipBlanks();
            if (pos_ >= text_.size())
                break;
            const char c = text_[pos_];
            if (c == '\n' || c == '\r') {
                ++pos_;
            } else if (c == '#') {
                skipToLineEnd();
            } else if (c == '[') {
                tableHeader();
            } else {
                keyValue(tableDepth_);
            }
        }
    }

private:
    [[noreturn]] void fail(const std::string& what) const
    {
        throw InputError(fileName_ + ":" + std::to_string(lineOf(text_, pos_)) + ": " + what);
    }

    void checkDepth(int depth) const
    {
        if (depth > kMaxTomlDepth)
            fail("nested deeper than " + std::to_string(kMaxTomlDepth) + " levels");
    }

    [[nodiscard]] bool at(char c) const { return pos_ < text_.size() && text_[pos_] == c; }
    [[nodiscard]] bool startsWith(std::string_view s) const
    {
        return pos_ < text_.size() && text_.substr(pos_).starts_with(s);
    }

    void skipBlanks()
    {
        while (at(' ') || at('\t'))
            ++pos_;
    }

    void skipToLineEnd()
    {
        while (pos_ < text_.size() && text_[pos_] != '\n')
            ++pos_;
    }

    // A quoted string starting at pos_; multi-line forms only where values may use them.
    void string(bool allowMultiLine)
    {
        const char quote = text_[pos_];
        const std::string triple(3, quote);
        if (allowMultiLine && startsWith(triple)) {
            pos_ += 3;
            while (pos_ < text_.size() && !startsWith(triple)) {
                if (quote == '"' && text_[pos_] == '\\')
                    ++pos_;
                ++pos_;
            }
            pos_ += 3;
            while (at(quote)) // up to two quotes may close the content ("""a"""")
                ++pos_;
            return;
        }
        ++pos_;
        while (pos_ < text_.size() && text_[pos_] != quote && text_[pos_] != '\n') {
            if (quote == '"' && text_[pos_] == '\\')
                ++pos_;
            ++pos_;
        }
        if (at(quote))
            ++pos_;
    }

    // A dotted key; returns its number of segments (0 when there is no key here).
    int key()
    {
        int segments = 0;
        for (;;) {
            skipBlanks();
            const size_t start = pos_;
            if (at('"') || at('\'')) {
                string(false);
            } else {
                while (pos_ < text_.size() &&
                       std::string_view(" \t=.[]{},#\r\n\"'").find(text_[pos_]) == std::string_view::npos)
                    ++pos_;
            }
            if (pos_ == start)
                return segments;
            if (pos_ - start > kMaxTomlKeyBytes)
                fail("a key is longer than " + std::to_string(kMaxTomlKeyBytes) + " bytes");
            ++segments;
            skipBlanks();
            if (!at('.'))
                return segments;
            ++pos_;
        }
    }

    void tableHeader()
    {
        ++pos_;
        if (at('['))
            ++pos_;
        tableDepth_ = key();
        checkDepth(tableDepth_);
        skipToLineEnd();
    }

    void keyValue(int depth)
    {
        const int segments = key();
        skipBlanks();
        if (segments == 0 || !at('=')) {
            skipToLineEnd(); // not a key/value line: toml++ reports it
            return;
        }
        ++pos_;
        checkDepth(depth + segments);
        value(depth + segments);
    }

    // One value: scalars, strings, arrays and inline tables, nested without recursion.
    void value(int depth)
    {
        struct Level {
            char close;
            int depth;
        };
        std::vector<Level> open;
        bool expectKey = false; // inside an inline table, after '{' or ','
        int valueDepth = depth;
        while (pos_ < text_.size()) {
            skipBlanks();
            if (pos_ >= text_.size())
                return;
            if (expectKey) {
                expectKey = false;
                if (!at('}')) {
                    const int segments = key();
                    skipBlanks();
                    if (segments == 0 || !at('='))
                        return skipToLineEnd();
                    ++pos_;
                    valueDepth = open.back().depth + segments;
                    checkDepth(valueDepth);
                    continue;
                }
            }
            const char c = text_[pos_];
            if (c == '\n' || c == '\r' || c == '#') {
                if (open.empty() || open.back().close == '}')
                    return; // the statement ends here (or is malformed: toml++ reports it)
                if (c == '#')
                    skipToLineEnd();
                else
                    ++pos_;
                continue;
            }
            if (c == '[' || c == '{') {
                ++pos_;
                open.push_back({c == '[' ? ']' : '}', valueDepth + 1});
                checkDepth(valueDepth + 1);
                valueDepth = valueDepth + 1;
                expectKey = c == '{';
                continue;
            }
            if (c == ']' || c == '}') {
                ++pos_;
                if (open.empty())
                    return skipToLineEnd();
                open.pop_back();
                if (open.empty())
                    return skipToLineEnd();
                valueDepth = open.back().depth;
                continue;
            }
            if (c == ',') {
                ++pos_;
                if (open.empty())
                    return skipToLineEnd();
                valueDepth = open.back().depth;
                expectKey = open.back().close == '}';
                continue;
            }
            if (c == '"' || c == '\'') {
                string(true);
            } else {
                const size_t start = pos_;
                while (pos_ < text_.size() &&
                       std::string_view(" \t,[]{}#\r\n").find(text_[pos_]) == std::string_view::npos)
                    ++pos_;
                if (pos_ == start)
                    ++pos_;
            }
            if (open.empty())
                return skipToLineEnd();
        }
    }

    std::string_view text_;
    const std::string& fileName_;
    size_t pos_ = 0;
    int tableDepth_ = 0;
};

} // namespace

void checkTomlText(std::string_view text, const std::string& fileName)
{
    if (const size_t bad = firstInvalidUtf8(text); bad != std::string_view::npos)
        throw InputError(fileName + ":" + std::to_string(lineOf(text, bad)) + ": invalid UTF-8 (byte " +
                         std::to_string(bad) + ")");
    DepthScanner(text, fileName).run();
}

toml::table parseToml(std::string_view text, const std::string& fileName)
{
    checkTomlText(text, fileName);
    try {
        return toml::parse(text, fileName);
    } catch (const toml::parse_error& e) {
        std::string what(e.description());
        if (const size_t nl = what.find('\n'); nl != std::string::npos)
            what.resize(nl);
        throw InputError(fileName + ":" + std::to_string(e.source().begin.line) + ": " + what);
    }
}

} // namespace lumar
