// Helpers for the hostile-input tests (issue 16): each builds a hostile file in the test and
// expects exactly one outcome, an InputError whose message is one line "FILE...: what".
#pragma once

#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"

namespace lumar::test {

// `load` must throw InputError with one line starting with `prefix` and containing `detail`.
inline std::string expectRejected(const std::function<void()>& load, const std::string& prefix,
                                  const std::string& detail)
{
    try {
        load();
    } catch (const InputError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(prefix, 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_NE(message.find(detail), std::string::npos) << "expected '" << detail << "' in: " << message;
        return message;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "expected InputError, got: " << e.what();
        return {};
    }
    ADD_FAILURE() << "expected InputError (" << detail << ")";
    return {};
}

inline std::string repeat(const std::string& s, int n)
{
    std::string out;
    out.reserve(s.size() * size_t(n));
    for (int i = 0; i < n; ++i)
        out += s;
    return out;
}

} // namespace lumar::test
