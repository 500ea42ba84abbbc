// The loader's `visit` functions (io/config.cc) walked over a typed scene
// without JSON, so that the checks a config's values get are written once
// and serve scenes built in code too (docs/architecture.md, "The scene, and
// where words become enums"):
//   * TypedChecker checks every value of a typed SceneConfig as the loader
//     checks it when reading JSON: the same dotted paths, the same reasons
//     (an Options::IsValid for the scene). check_scene() runs it;
//     check_scene_fields() checks only some fields;
//   * FieldLocator finds a numeric field of a SceneConfig by its dotted path
//     through the same visit, with the checks the loader gives its value
//     (find_scene_field()). A path the loader does not know is refused with
//     the loader's "unknown key ... (did you mean ...)". Identification
//     binds its fitted paths with it and checks their values with the
//     checks it finds (optim/identify/fit_scene.cc).
// The functions below are defined in io/config.cc, beside the visit functions.
#pragma once

#include <cmath>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/errors.h"
#include "io/json_archive.h"
#include "scene/scene.h"

namespace camdyn {

// ---------------------------------------------------------------- checking

/// Typed struct → checks. Value checks throw at once, as the reader's do;
/// conditions between fields (`require`) are kept until finish(), which
/// throws the first.
class TypedChecker {
 public:
  static constexpr bool kReading = false;

  /// Errors name `file`. With `only` given, only the fields at those dotted
  /// paths and below them are checked, and only the conditions that name them.
  explicit TypedChecker(std::string file, std::span<const std::string_view> only = {})
      : file_(std::move(file)), only_(only) {}

  template <class T, class... C>
  void field(std::string_view key, T& value, const C&... checks) {
    std::string path = path_of(key);
    if (!relevant(path)) return;
    const std::vector<Check> list{checks...};
    check(path, value, list);
  }
  template <class T>
  void field_or_file(std::string_view key, T& value, std::string* /*resolved*/) {
    field(key, value);
  }
  void path_field(std::string_view key, std::string& value, const Check& c) { field(key, value, c); }
  bool given(std::string_view /*key*/, bool state) const { return state; }
  bool given_object(std::string_view /*key*/, bool state) const { return state; }
  void allow(std::string_view /*key*/, Json::value_t /*type*/) {}
  /// A typed scene has no keys to forbid: a field its visit leaves out is not read.
  void forbid(std::initializer_list<std::string_view> /*keys*/, const std::string& /*reason*/) {}
  void require(bool ok, std::string_view key, const std::string& reason);
  /// Throws the first failed condition, as InputError(file, path, reason).
  void finish();

 private:
  template <class T>
  void check(const std::string& path, T& value, std::span<const Check> checks);
  std::string path_of(std::string_view key) const;
  bool wanted(const std::string& path) const;    ///< its value is checked
  bool relevant(const std::string& path) const;  ///< it or something below it is checked
  [[noreturn]] void fail(const std::string& path, const std::string& reason) const;
  void run(const std::string& path, double x, std::span<const Check> checks) const;
  void run(const std::string& path, const std::string& s, std::span<const Check> checks) const;

  std::string file_;
  std::span<const std::string_view> only_;
  std::string path_;  ///< of the object being visited
  std::optional<InputError> deferred_;
};

/// Checks every value of `scene` as load_scene() checks a config's: throws
/// InputError(file, dotted path, the loader's reason) for the first it would
/// refuse. For scenes built in code. (The lift table's CSV file is not read.)
void check_scene(const SceneConfig& scene, const std::string& file);

/// check_scene() restricted to the fields at `paths` (dotted paths of fields
/// or of objects, whose fields are all meant) and the conditions between
/// fields that name one of them. The rest of `scene` need not be valid; its
/// choices (follower motion, shape, drive, contact law, which optional blocks
/// are given) decide which fields exist and which checks apply, as in a config.
void check_scene_fields(const SceneConfig& scene, std::span<const std::string_view> paths, const std::string& file);

// ---------------------------------------------------------------- locating

/// A numeric field of a scene, found by its dotted path.
struct SceneField {
  std::string path;           ///< full dotted path ("mechanism.contact.stiffness")
  double* value = nullptr;    ///< the field, in the scene it was found in
  std::vector<Check> checks;  ///< the loader's checks of its value (not the conditions between fields)

  /// "" when `x` passes the checks (and is finite), else the loader's reason.
  std::string reason(double x) const;
};

/// The numeric field at `path` (a full dotted path, or one starting "cam.",
/// "follower." or "contact.", as --set takes it) of `scene`, found through
/// the loader's visit: only a field a config of this scene's choices may give
/// is found (an oscillating follower has 'inertia', not 'mass'). Throws
/// InputError(file, path, reason): the loader's "unknown key 'x' (did you
/// mean 'y'?)" for a path it does not know, or why the field is no number here
/// (an object, a text, an optional block or value the scene does not give).
SceneField find_scene_field(SceneConfig& scene, const std::string& path, const std::string& file);

/// find_scene_field(), or nullopt where it would throw.
std::optional<SceneField> try_find_scene_field(SceneConfig& scene, const std::string& path);

/// Typed struct → the field at one dotted path (what find_scene_field() runs).
class FieldLocator {
 public:
  static constexpr bool kReading = false;

  explicit FieldLocator(std::string target) : target_(std::move(target)) {}

  template <class T, class... C>
  void field(std::string_view key, T& value, const C&... checks) {
    note(key);
    std::string path = path_of(key);
    if (path == target_) {
      found(path, value, std::vector<Check>{checks...});
    } else if (below(path)) {
      descend(path, value, std::vector<Check>{checks...});
    }
  }
  template <class T>
  void field_or_file(std::string_view key, T& value, std::string* /*resolved*/) {
    field(key, value);
  }
  void path_field(std::string_view key, std::string& value, const Check& c) { field(key, value, c); }
  bool given(std::string_view key, bool state) {
    note(key);
    return state;
  }
  bool given_object(std::string_view key, bool state) { return given(key, state); }
  void allow(std::string_view key, Json::value_t /*type*/) { note(key); }
  /// A key the loader refuses in this object: if it is the target's, the reason is why it is not found.
  void forbid(std::initializer_list<std::string_view> keys, const std::string& reason);
  void require(bool /*ok*/, std::string_view /*key*/, const std::string& /*reason*/) {}
  void finish() {}

  /// The field, or nullopt with error_path() and error() saying why not.
  std::optional<SceneField> result() const;
  std::string error_path() const;
  std::string error() const;

 private:
  template <class T>
  void found(const std::string& path, T& value, std::vector<Check> checks);
  /// Into the field at `path`, towards the target (`checks`: the field's, which an array's elements share).
  template <class T>
  void descend(const std::string& path, T& value, std::vector<Check> checks);
  std::string path_of(std::string_view key) const;
  bool below(const std::string& path) const;  ///< the target is inside the field at `path`
  void note(std::string_view key);            ///< a key known where the search has reached
  std::string next_key() const;               ///< the target's key in the object reached

  std::string target_;
  std::string path_;                ///< of the object being visited
  std::string reached_;             ///< the deepest object on the way to the target
  std::vector<std::string> known_;  ///< its keys
  double* value_ = nullptr;
  std::vector<Check> checks_;
  std::string why_not_;       ///< why the target is no number here (empty: not found)
  std::string why_not_path_;  ///< where
};

// ---------------------------------------------------------------- internals

namespace archive_detail {
template <class T>
concept Visited =
    !is_optional<T>::value && !is_vector<T>::value && !is_scalar_v<T> && !NamedEnum<T> && !std::is_same_v<T, bool>;
}  // namespace archive_detail

template <class T>
void TypedChecker::check(const std::string& path, T& value, std::span<const Check> checks) {
  using archive_detail::is_optional;
  using archive_detail::is_vector;
  const bool checked = wanted(path);
  if constexpr (is_optional<T>::value) {
    if (value) check(path, *value, checks);
  } else if constexpr (is_vector<T>::value) {
    for (const Check& c : checks)
      if (checked && c.size)
        if (const std::string reason = c.size(value.size()); !reason.empty()) fail(path, reason);
    for (std::size_t i = 0; i < value.size(); ++i) check(path + "[" + std::to_string(i) + "]", value[i], checks);
  } else if constexpr (std::is_same_v<T, std::string>) {
    if (checked) run(path, value, checks);
  } else if constexpr (NamedEnum<T>) {
    // The field's own checks first, then the enum's words (an unset value has none).
    if (!checked) return;
    const std::string word(enum_name(value));
    run(path, word, checks);
    const Check words = one_of_enum<T>();
    run(path, word, std::span<const Check>(&words, 1));
  } else if constexpr (std::is_same_v<T, bool>) {
    return;
  } else if constexpr (std::is_arithmetic_v<T>) {
    if (checked) run(path, static_cast<double>(value), checks);
  } else {
    const std::string outer = std::exchange(path_, path);
    visit(*this, value);
    path_ = outer;
  }
}

template <class T>
void FieldLocator::found(const std::string& path, T& value, std::vector<Check> checks) {
  using archive_detail::is_optional;
  if constexpr (std::is_same_v<T, double>) {
    value_ = &value;
    checks_ = std::move(checks);
  } else if constexpr (is_optional<T>::value) {
    if (value) {
      found(path, *value, std::move(checks));
    } else {
      why_not_ = "is not given in this scene (null)";
      why_not_path_ = path;
    }
  } else if constexpr (archive_detail::Visited<T>) {
    why_not_ = "is an object, not a number";
    why_not_path_ = path;
  } else {
    why_not_ = "is not a real number";
    why_not_path_ = path;
  }
}

template <class T>
void FieldLocator::descend(const std::string& path, T& value, std::vector<Check> checks) {
  using archive_detail::is_optional;
  using archive_detail::is_vector;
  reached_ = path;
  why_not_path_ = target_;
  if constexpr (is_optional<T>::value) {
    if (value) {
      descend(path, *value, std::move(checks));
    } else {
      why_not_ = "'" + path + "' is not given in this scene (null)";
    }
  } else if constexpr (is_vector<T>::value) {
    // "[i]" follows: the element, if there is one.
    const std::size_t close = target_.find(']', path.size());
    if (target_[path.size()] != '[' || close == std::string::npos) {
      why_not_ = "'" + path + "' is an array";
      return;
    }
    const std::string index = target_.substr(path.size() + 1, close - path.size() - 1);
    const bool digits =
        !index.empty() && index.size() < 10 && index.find_first_not_of("0123456789") == std::string::npos;
    if (!digits || std::stoul(index) >= value.size()) {
      why_not_ = "'" + path + "' has " + std::to_string(value.size()) + " elements, no [" + index + "]";
      return;
    }
    const std::string element = path + "[" + index + "]";
    if (element == target_) {
      found(element, value[std::stoul(index)], std::move(checks));
    } else {
      descend(element, value[std::stoul(index)], std::move(checks));
    }
  } else if constexpr (archive_detail::Visited<T>) {
    const std::string outer = std::exchange(path_, path);
    known_.clear();
    visit(*this, value);
    path_ = outer;
  } else {
    why_not_ = "'" + path + "' is not an object";
  }
}

}  // namespace camdyn
