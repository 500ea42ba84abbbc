// Names of the enumerations a scene is made of: each enum of scene.h has one
// table that pairs its values with the words a config uses for them, found by
// argument-dependent lookup as `enum_names(E)`. The config loader reads a word
// into an enum once, at load (io/json_archive.h); everything below works on the
// enum, and outputs print the same word back with enum_name().
#pragma once

#include <optional>
#include <ostream>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace camdyn {

/// One value of an enum and its config word. An empty word marks a value a
/// config cannot name (e.g. "no law" on a dwell segment).
template <class E>
struct EnumName {
  E value;
  std::string_view name;
};

/// An enum with a name table: `enum_names(E{})` returns std::span<const EnumName<E>>.
template <class E>
concept NamedEnum = std::is_enum_v<E> && requires(E e) {
  { enum_names(e) } -> std::convertible_to<std::span<const EnumName<E>>>;
};

/// The config word of `value` ("" for a value a config cannot name).
template <NamedEnum E>
std::string_view enum_name(E value) {
  for (const EnumName<E>& entry : enum_names(value))
    if (entry.value == value) return entry.name;
  return {};
}

/// The value a config word stands for, if any.
template <NamedEnum E>
std::optional<E> enum_from_name(std::string_view name) {
  for (const EnumName<E>& entry : enum_names(E{}))
    if (!entry.name.empty() && entry.name == name) return entry.value;
  return std::nullopt;
}

/// The value a word stands for, for callers that build scenes in code (tests,
/// library users); throws std::invalid_argument naming the valid words.
template <NamedEnum E>
E parse_enum(std::string_view name) {
  if (const std::optional<E> value = enum_from_name<E>(name)) return *value;
  std::string words;
  for (const EnumName<E>& entry : enum_names(E{}))
    if (!entry.name.empty()) words += (words.empty() ? "'" : ", '") + std::string(entry.name) + "'";
  throw std::invalid_argument("'" + std::string(name) + "' is not one of " + words);
}

/// Every word a config may use for E, in table order.
template <NamedEnum E>
std::vector<std::string> enum_name_list() {
  std::vector<std::string> names;
  for (const EnumName<E>& entry : enum_names(E{}))
    if (!entry.name.empty()) names.emplace_back(entry.name);
  return names;
}

/// enum_name() as a std::string, for building messages.
template <NamedEnum E>
std::string to_string(E value) {
  return std::string(enum_name(value));
}

/// Prints the config word (test failure messages, logs).
template <NamedEnum E>
std::ostream& operator<<(std::ostream& out, E value) {
  return out << enum_name(value);
}

}  // namespace camdyn
