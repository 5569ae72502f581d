// One name table per enum: each value with the name files and options
// spell it with, read and written through the same table.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>

namespace pl {

template <class Enum>
struct EnumName {
    Enum value;
    const char* name;
};

template <class Enum, size_t N>
std::optional<Enum> parseEnum(const std::array<EnumName<Enum>, N>& names, const std::string& text) {
    for (const EnumName<Enum>& n : names)
        if (text == n.name) return n.value;
    return std::nullopt;
}

template <class Enum, size_t N>
const char* enumName(const std::array<EnumName<Enum>, N>& names, Enum value) {
    for (const EnumName<Enum>& n : names)
        if (n.value == value) return n.name;
    return "?";
}

// "a, b or c": the names, for messages.
template <class Enum, size_t N>
std::string enumNames(const std::array<EnumName<Enum>, N>& names) {
    std::string text;
    for (size_t i = 0; i < N; ++i) text += (i == 0 ? "" : i + 1 == N ? " or " : ", ") + std::string(names[i].name);
    return text;
}

}  // namespace pl
