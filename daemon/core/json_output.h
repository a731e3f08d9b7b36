// JSON output (status file, trace, `lumar detect`, `lumar bench --json`) through nlohmann::json:
// numbers rounded to the precision they carry, and one way to write a value as text.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace lumar {

// Objects keep their keys in insertion order, as the documented output formats list them.
using Json = nlohmann::ordered_json;

// nlohmann writes a double in its shortest round-trip form: 17 significant digits for a
// computed value (1234.5678901234568) and "2.0" for two. A measurement is worth fewer digits,
// so the writers round first; the rounded double then prints as the short decimal (nlohmann's
// Grisu2 is not always shortest: 2 of the ~1,060 numbers of `lumar detect` over
// tests/data/apriltag come out with 17 digits, 0.049973316499999997 for 0.0499733165, which
// parse back to the same double).

// `value` as it is, or null for NaN and infinities (a rate without frames, an error without
// found tags), which JSON cannot represent.
Json jsonNumber(double value);

// `value` rounded to `digits` significant digits (as printf's %.*g); an integral result is an
// integer ("2", not "2.0"). null for NaN and infinities, which JSON cannot represent.
Json jsonSignificant(double value, int digits);

// `value` rounded to `decimals` decimals (as printf's %.*f), written without trailing zeros
// ("2.0" where %.3f wrote "2.000").
// null for NaN and infinities.
Json jsonDecimals(double value, int decimals);

// One line of compact JSON (no newline). Text that is not valid UTF-8 (a file name, a camera
// error) cannot go into JSON as is: each ill-formed sequence (a stray byte, or the start of a
// multi-byte character cut short) becomes one U+FFFD, written in UTF-8 (EF BF BD).
std::string jsonLine(const Json& value);

} // namespace lumar
