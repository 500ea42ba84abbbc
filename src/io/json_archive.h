// Two-way mapping between config structs and JSON (Drake
// SimulatorConfig::Serialize style). Each struct has one function
//
//   template <class Archive> void visit(Archive& a, CamConfig& c) {
//     a.field("base_radius", c.base_radius, positive());  ...
//   }
//
// that lists every field with its checks. JsonReader runs it to fill a struct
// from JSON (type and range checks, unknown keys rejected with a suggestion,
// every error an InputError with file and dotted path); JsonWriter runs it to
// print a struct with every field, defaults included. Defaults stay in the
// struct initialisers. `visit` is found by argument-dependent lookup, so it
// must live in the namespace of the struct.
//
// Error order: a present but wrong value throws at once; anything caused by
// absence (a missing required field, a failed `require`) is deferred until the
// unknown keys of the whole document have been checked, so a misspelt key is
// reported as such rather than as the missing field it was meant to be.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <limits>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "common/errors.h"
#include "io/config.h"
#include "scene/enum_names.h"

namespace camdyn {

// ---------------------------------------------------------------- checks

/// A check attached to a field. Each test returns "" when the value is fine,
/// else the reason ("must be > 0, got -0.3"). Number tests apply to numbers
/// (and to the elements of number arrays), text tests to strings (and string
/// elements), size tests to arrays and strings.
struct Check {
  std::string expected;  ///< what a valid value is, for a missing field: "a number > 0"
  std::function<std::string(double)> number;
  std::function<std::string(const std::string&)> text;
  std::function<std::string(std::size_t)> size;
};

Check positive();                            ///< > 0
Check non_negative();                        ///< >= 0
Check at_least(double low);                  ///< >= low
Check open_closed(double low, double high);  ///< in (low, high]
Check closed_open(double low, double high);  ///< in [low, high)
Check non_empty();                           ///< a non-empty string or array
/// The string is one of `allowed`. Values in `later` are known but not
/// implemented yet: they fail with `later_reason`, where "{}" stands for the
/// value (default: "'{}' is not supported yet (see the open issues)").
Check one_of(std::vector<std::string> allowed, std::vector<std::string> later = {}, std::string later_reason = {});

/// Shortest round-trip text of a number ("0.3", "1e-08", "4").
std::string format_shortest(double x);
/// A JSON value as a message fragment: `string "abc"`, `boolean true`, `null`, `-0.3`, `an object`.
std::string describe_json(const Json& value);

// ---------------------------------------------------------------- files

/// How deep a config may nest objects and arrays (the studies need under ten).
inline constexpr std::size_t kMaxJsonDepth = 64;

/// Reads and parses a JSON file. Throws InputError(file, "", "cannot open ...")
/// or InputError(file, "line L, column C", reason) for a syntax error, and
/// rejects duplicate keys and nesting deeper than kMaxJsonDepth
/// (InputError(file, dotted path, ...)).
Json read_json_file(const std::string& file);
/// Parses JSON text that came from `file` (only used in messages).
Json parse_json_text(const std::string& text, const std::string& file);

/// Finds a data file named in a config: absolute as it is; otherwise relative
/// to `dir`, then to the current directory, then to CAMDYN_SOURCE_DIR (the
/// repository root). Returns the absolute, normalised path of the first that
/// exists; `tried` receives every candidate (for the error message).
std::optional<std::filesystem::path> find_data_file(const std::string& name, const std::string& dir,
                                                    std::vector<std::string>* tried = nullptr);

/// `name` made absolute against `dir` (unchanged if already absolute), normalised.
std::string absolute_path(const std::string& name, const std::string& dir);

// ---------------------------------------------------------------- archives

namespace archive_detail {
template <class T>
struct is_optional : std::false_type {};
template <class T>
struct is_optional<std::optional<T>> : std::true_type {};
template <class T>
struct is_vector : std::false_type {};
template <class T>
struct is_vector<std::vector<T>> : std::true_type {};
template <class T>
constexpr bool is_scalar_v = std::is_arithmetic_v<T> || std::is_same_v<T, std::string>;
}  // namespace archive_detail

/// The check every enum field gets: its value is one of the enum's config words.
template <NamedEnum E>
Check one_of_enum() {
  return one_of(enum_name_list<E>());
}

/// JSON → struct. Construct on an object, run `visit`, then call finish().
class JsonReader {
 public:
  static constexpr bool kReading = true;

  /// `object` is found at dotted `path` (empty for the document root) of `source.file`.
  /// A reader with a parent hands its deferred errors up instead of throwing them.
  JsonReader(const Json& object, std::string path, ConfigSource source, JsonReader* parent = nullptr);

  /// Reads `key` into `value` if present; if absent, keeps the default, and a
  /// default that fails a check makes it a required field.
  template <class T, class... C>
  void field(std::string_view key, T& value, const C&... checks) {
    const std::vector<Check> list{checks...};
    const std::string k = take(key);
    const auto it = object_.find(k);
    if (it == object_.end()) {
      missing(k, value, list);
    } else {
      read(*it, path_of(k), value, list);
    }
  }

  /// Like field(), but the JSON may instead hold a path to a JSON file whose
  /// top-level object is the value (with an optional "description" string);
  /// the path is found by find_data_file and stored in `*resolved` (may be null).
  template <class T>
  void field_or_file(std::string_view key, T& value, std::string* resolved) {
    const std::string k(key);
    const auto it = object_.find(k);
    if (it == object_.end() || !it->is_string()) {
      field(key, value);
      return;
    }
    take(key);
    const std::filesystem::path file = locate(k, it->template get<std::string>());
    const Json document = read_json_file(file.string());
    const ConfigSource source{file.string(), file.parent_path().string()};
    if (!document.is_object()) {
      throw InputError(source.file, "", "expected a JSON object at the top level, got " + describe_json(document));
    }
    JsonReader child(document, path_of(k), source, this);
    child.allow("description", Json::value_t::string);
    visit(child, value);
    child.finish();
    if (resolved != nullptr) *resolved = file.string();
  }

  /// A file name, made absolute relative to the directory of the file that names it.
  void path_field(std::string_view key, std::string& value, const Check& check) {
    field(key, value, check);
    if (!value.empty()) value = absolute_path(value, source_.dir);
  }

  /// Whether `key` is present and not null (a null counts as absent and is consumed).
  bool given(std::string_view key, bool /*writer_state*/ = false);
  /// Whether `key` holds an object.
  bool given_object(std::string_view key, bool /*writer_state*/ = false);
  /// Accepts and ignores `key` if it has the given type.
  void allow(std::string_view key, Json::value_t type);
  /// Fails with `reason` if any of `keys` is present (not null).
  void forbid(std::initializer_list<std::string_view> keys, const std::string& reason);
  /// A condition between fields; `key` ("" = this object, or a dotted sub-path)
  /// names the field to blame. Deferred until the unknown keys are checked.
  void require(bool ok, std::string_view key, const std::string& reason);
  /// Rejects unknown keys (suggesting the closest known one), then throws the
  /// first deferred error (root reader) or hands it to the parent.
  void finish();

  [[noreturn]] void fail(std::string_view key, const std::string& reason) const;
  std::string path_of(std::string_view key) const;
  const ConfigSource& source() const { return source_; }

 private:
  template <class T>
  void read(const Json& j, const std::string& path, T& value, std::span<const Check> checks);
  template <class T>
  void missing(const std::string& key, T& value, std::span<const Check> checks);

  std::string take(std::string_view key);  ///< marks known and consumed; returns it as a string
  std::filesystem::path locate(const std::string& key, const std::string& name) const;
  void defer(const InputError& error);
  [[noreturn]] void fail_at(const std::string& path, const std::string& reason) const;
  void run_checks(const std::string& path, double x, std::span<const Check> checks) const;
  void run_checks(const std::string& path, const std::string& s, std::span<const Check> checks) const;
  void run_size_checks(const std::string& path, std::size_t n, std::span<const Check> checks) const;

  const Json& object_;
  std::string path_;
  ConfigSource source_;
  JsonReader* parent_;
  std::vector<std::string> known_;
  std::set<std::string> consumed_;
  std::optional<InputError> deferred_;
};

/// Struct → JSON: every field, defaults included; optionals as null.
class JsonWriter {
 public:
  static constexpr bool kReading = false;

  template <class T, class... C>
  void field(std::string_view key, const T& value, const C&... /*checks*/) {
    out_[std::string(key)] = write(value);
  }
  template <class T>
  void field_or_file(std::string_view key, const T& value, const std::string* /*resolved*/) {
    field(key, value);
  }
  void path_field(std::string_view key, const std::string& value, const Check& /*check*/) { field(key, value); }
  bool given(std::string_view /*key*/, bool writer_state) const { return writer_state; }
  bool given_object(std::string_view /*key*/, bool writer_state) const { return writer_state; }
  void allow(std::string_view /*key*/, Json::value_t /*type*/) {}
  void forbid(std::initializer_list<std::string_view> /*keys*/, const std::string& /*reason*/) {}
  void require(bool /*ok*/, std::string_view /*key*/, const std::string& /*reason*/) {}
  void finish() {}

  const Json& json() const { return out_; }

  template <class T>
  static Json write(const T& value) {
    using archive_detail::is_optional;
    using archive_detail::is_vector;
    if constexpr (is_optional<T>::value) {
      return value ? write(*value) : Json(nullptr);
    } else if constexpr (is_vector<T>::value) {
      Json array = Json::array();
      for (const auto& element : value) array.push_back(write(element));
      return array;
    } else if constexpr (archive_detail::is_scalar_v<T>) {
      return Json(value);
    } else if constexpr (NamedEnum<T>) {
      return Json(std::string(enum_name(value)));
    } else {
      T copy = value;  // visit takes a mutable reference (it is shared with the reader)
      JsonWriter writer;
      visit(writer, copy);
      return writer.out_;
    }
  }

 private:
  Json out_ = Json::object();
};

// ---------------------------------------------------------------- reader internals

template <class T>
void JsonReader::read(const Json& j, const std::string& path, T& value, std::span<const Check> checks) {
  using archive_detail::is_optional;
  using archive_detail::is_vector;
  if constexpr (is_optional<T>::value) {
    if (j.is_null()) {
      value.reset();
      return;
    }
    typename T::value_type inner{};
    read(j, path, inner, checks);
    value = std::move(inner);
  } else if constexpr (is_vector<T>::value) {
    if (!j.is_array()) fail_at(path, "expected an array, got " + describe_json(j));
    run_size_checks(path, j.size(), checks);
    T result(j.size());
    for (std::size_t i = 0; i < j.size(); ++i) {
      read(j[i], path + "[" + std::to_string(i) + "]", result[i], checks);
    }
    value = std::move(result);
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (!j.is_string()) fail_at(path, "expected a string, got " + describe_json(j));
    value = j.template get<std::string>();
    run_checks(path, value, checks);
  } else if constexpr (NamedEnum<T>) {
    // Read as a word, checked (the field's own checks first, which may allow
    // fewer words, then the enum's words) and mapped.
    if (!j.is_string()) fail_at(path, "expected a string, got " + describe_json(j));
    const std::string word = j.template get<std::string>();
    run_checks(path, word, checks);
    const Check words = one_of_enum<T>();
    run_checks(path, word, std::span<const Check>(&words, 1));
    value = *enum_from_name<T>(word);
  } else if constexpr (std::is_same_v<T, bool>) {
    if (!j.is_boolean()) fail_at(path, "expected true or false, got " + describe_json(j));
    value = j.template get<bool>();
  } else if constexpr (std::is_floating_point_v<T>) {
    if (!j.is_number()) fail_at(path, "expected a number, got " + describe_json(j));
    const double x = j.template get<double>();
    if (!std::isfinite(x)) fail_at(path, "expected a finite number, got " + describe_json(j));
    run_checks(path, x, checks);
    value = static_cast<T>(x);
  } else if constexpr (std::is_integral_v<T>) {
    // Integers may be written as 4 or 4.0, but not 4.5.
    const bool integral = j.is_number_integer() || (j.is_number_float() && std::isfinite(j.template get<double>()) &&
                                                    std::trunc(j.template get<double>()) == j.template get<double>());
    if (!integral) fail_at(path, "expected an integer, got " + describe_json(j));
    const double x = j.template get<double>();
    // The upper bound is max + 1 (2^31, 2^63: exact as doubles); comparing
    // with max itself would let 2^63 through, as max rounds up to it.
    if (x < static_cast<double>(std::numeric_limits<T>::min()) ||
        x >= static_cast<double>(std::numeric_limits<T>::max()) + 1.0) {
      fail_at(path, "integer out of range, got " + describe_json(j));
    }
    run_checks(path, x, checks);
    value = j.is_number_float() ? static_cast<T>(x) : j.template get<T>();
  } else {
    if (!j.is_object()) fail_at(path, "expected an object, got " + describe_json(j));
    JsonReader child(j, path, source_, this);
    visit(child, value);
    child.finish();
  }
}

template <class T>
void JsonReader::missing(const std::string& key, T& value, std::span<const Check> checks) {
  using archive_detail::is_optional;
  using archive_detail::is_vector;
  if constexpr (is_optional<T>::value) {
    return;  // absent = nullopt
  } else if constexpr (NamedEnum<T>) {
    // A default no config can name (e.g. SegmentLaw::none) makes the field required.
    if (enum_name(value).empty()) {
      defer(InputError(source_.file, path_of(key), "missing (expected " + one_of_enum<T>().expected + ")"));
    }
  } else if constexpr (is_vector<T>::value || std::is_same_v<T, std::string> || std::is_arithmetic_v<T>) {
    // A default that fails its own check means the field is required.
    for (const Check& check : checks) {
      std::string reason;
      if constexpr (is_vector<T>::value) {
        if (check.size) reason = check.size(value.size());
      } else if constexpr (std::is_same_v<T, std::string>) {
        if (check.text) reason = check.text(value);
        if (reason.empty() && check.size) reason = check.size(value.size());
      } else if constexpr (std::is_arithmetic_v<T>) {
        if (check.number) reason = check.number(static_cast<double>(value));
      }
      if (!reason.empty()) {
        defer(InputError(source_.file, path_of(key), "missing (expected " + check.expected + ")"));
        return;
      }
    }
  } else {
    // An absent object is read as {} so that its own required fields are reported.
    read(Json::object(), path_of(key), value, checks);
  }
}

}  // namespace camdyn
