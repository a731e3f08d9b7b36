// Misuse of the command line (an unknown option, a missing or out-of-range value). main turns
// it into exit code 2 and one line on stderr naming the command and pointing at its --help.
#pragma once

#include <stdexcept>

namespace lumar {

class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

} // namespace lumar
