#pragma once
// One name table per enum, the single place its words are spelled. Beside
// each enum that is read or written as text stand
//   std::string_view name(Enum);                          // the word
//   template <> Enum parse_enum_name<Enum>(std::string_view);  // and back
// both built on a table with the helpers below. parse_enum_name throws
// InputError "'<text>' is not <what>; expected one of: <names>"; callers put
// the option or file:line in front.
#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>

#include "stridemap/core/error.hpp"

namespace stridemap {

/// The enum value named `text`; specialised beside each enum.
template <typename Enum>
Enum parse_enum_name(std::string_view text);

template <typename Enum, std::size_t N>
using EnumNameTable = std::array<std::pair<Enum, std::string_view>, N>;

/// The table's word for `value` ("unknown" for a value not in it, which a
/// cast from a corrupted byte could produce).
template <typename Enum, std::size_t N>
constexpr std::string_view enum_name_in(const EnumNameTable<Enum, N>& table, Enum value) {
  for (const auto& [v, word] : table) {
    if (v == value) return word;
  }
  return "unknown";
}

/// "a, b, c": the words, in the table's order.
template <typename Enum, std::size_t N>
std::string enum_names_list(const EnumNameTable<Enum, N>& table) {
  std::string list;
  for (const auto& entry : table) {
    if (!list.empty()) list += ", ";
    list += entry.second;
  }
  return list;
}

/// The value whose word is `text`; `what` names the kind with its article
/// ("an elevation rule") for the error.
template <typename Enum, std::size_t N>
Enum enum_value_in(const EnumNameTable<Enum, N>& table, std::string_view text, std::string_view what) {
  for (const auto& [v, word] : table) {
    if (word == text) return v;
  }
  throw InputError("'" + std::string(text) + "' is not " + std::string(what) +
                   "; expected one of: " + enum_names_list(table));
}

}  // namespace stridemap
