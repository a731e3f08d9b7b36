// Words for TOML values in one-line error messages, shared by the configuration reader and
// the material sidecar reader (both parse with toml++).
#pragma once

#include <cstdio>
#include <string>

#include <toml++/toml.h>

namespace lumar::toml_text {

// "a string", "an integer", ... : what a node holds, for "expected X, found Y".
inline const char* typeName(const toml::node& node)
{
    switch (node.type()) {
    case toml::node_type::string:
        return "a string";
    case toml::node_type::integer:
        return "an integer";
    case toml::node_type::floating_point:
        return "a number";
    case toml::node_type::boolean:
        return "a boolean";
    case toml::node_type::array:
        return "an array";
    case toml::node_type::table:
        return "a table";
    default:
        return "a date/time";
    }
}

// A number as a person writes it (%g): 0.5, 1e+06.
inline std::string formatNumber(double v)
{
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

} // namespace lumar::toml_text
