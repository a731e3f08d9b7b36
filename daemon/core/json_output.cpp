#include "core/json_output.h"

#include <charconv>
#include <cmath>
#include <cstdint>

namespace lumar {
namespace {

// Rounds as printf would (correctly, from the exact binary value) by writing the decimal with
// std::to_chars (locale-independent) and reading it back: the double nearest to the short
// decimal, which nlohmann then writes as that decimal.
double roundThroughText(double value, std::chars_format format, int precision)
{
    char text[64];
    const auto written = std::to_chars(text, text + sizeof text, value, format, precision);
    if (written.ec != std::errc())
        return value; // a huge value in fixed format: it has no decimals left to round
    double rounded = value;
    if (std::from_chars(text, written.ptr, rounded).ec != std::errc())
        return value;
    return rounded;
}

} // namespace

Json jsonNumber(double value)
{
    return std::isfinite(value) ? Json(value) : Json(nullptr);
}

Json jsonSignificant(double value, int digits)
{
    if (!std::isfinite(value))
        return nullptr;
    const double rounded = roundThroughText(value, std::chars_format::general, digits);
    constexpr double kExactIntegers = 9007199254740992.0; // 2^53
    if (std::trunc(rounded) == rounded && std::abs(rounded) < kExactIntegers)
        return static_cast<std::int64_t>(rounded);
    return rounded;
}

Json jsonDecimals(double value, int decimals)
{
    if (!std::isfinite(value))
        return nullptr;
    return roundThroughText(value, std::chars_format::fixed, decimals);
}

std::string jsonLine(const Json& value)
{
    return value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

} // namespace lumar
