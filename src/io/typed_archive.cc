#include "io/typed_archive.h"

#include <algorithm>

#include "io/suggest.h"

namespace camdyn {

namespace {

/// `path` is `prefix` or inside it ("a.b" and "a.b[0].c" are inside "a.b").
bool inside(std::string_view path, std::string_view prefix) {
  if (prefix.empty()) return true;
  if (!path.starts_with(prefix)) return false;
  return path.size() == prefix.size() || path[prefix.size()] == '.' || path[prefix.size()] == '[';
}

std::string join_path(const std::string& object, std::string_view key) {
  if (key.empty()) return object;
  if (object.empty()) return std::string(key);
  return object + "." + std::string(key);
}

}  // namespace

// ---------------------------------------------------------------- TypedChecker

std::string TypedChecker::path_of(std::string_view key) const { return join_path(path_, key); }

bool TypedChecker::wanted(const std::string& path) const {
  return only_.empty() || std::any_of(only_.begin(), only_.end(), [&](std::string_view p) { return inside(path, p); });
}

bool TypedChecker::relevant(const std::string& path) const {
  return only_.empty() || std::any_of(only_.begin(), only_.end(),
                                      [&](std::string_view p) { return inside(path, p) || inside(p, path); });
}

void TypedChecker::require(bool ok, std::string_view key, const std::string& reason) {
  if (ok || deferred_) return;
  const std::string path = path_of(key);
  if (wanted(path)) deferred_ = InputError(file_, path, reason);
}

void TypedChecker::finish() {
  if (deferred_) throw *deferred_;
}

void TypedChecker::fail(const std::string& path, const std::string& reason) const {
  throw InputError(file_, path, reason);
}

void TypedChecker::run(const std::string& path, double x, std::span<const Check> checks) const {
  // A number read from JSON is finite; one set in code may not be.
  if (!std::isfinite(x)) fail(path, "expected a finite number, got " + format_shortest(x));
  for (const Check& c : checks) {
    if (!c.number) continue;
    if (const std::string reason = c.number(x); !reason.empty()) fail(path, reason);
  }
}

void TypedChecker::run(const std::string& path, const std::string& s, std::span<const Check> checks) const {
  for (const Check& c : checks) {
    std::string reason;
    if (c.text) reason = c.text(s);
    if (reason.empty() && c.size) reason = c.size(s.size());
    if (!reason.empty()) fail(path, reason);
  }
}

// ---------------------------------------------------------------- SceneField

std::string SceneField::reason(double x) const {
  if (!std::isfinite(x)) return "expected a finite number, got " + format_shortest(x);
  for (const Check& check : checks) {
    if (!check.number) continue;
    if (std::string why = check.number(x); !why.empty()) return why;
  }
  return "";
}

// ---------------------------------------------------------------- FieldLocator

std::string FieldLocator::path_of(std::string_view key) const { return join_path(path_, key); }

bool FieldLocator::below(const std::string& path) const {
  return target_.size() > path.size() && inside(target_, path);
}

std::string FieldLocator::next_key() const {
  const std::size_t start = reached_.empty() ? 0 : reached_.size() + 1;
  if (start > target_.size()) return "";
  const std::size_t end = target_.find_first_of(".[", start);
  return target_.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

void FieldLocator::note(std::string_view key) {
  if (path_ != reached_ || key.empty()) return;
  if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.emplace_back(key);
}

void FieldLocator::forbid(std::initializer_list<std::string_view> keys, const std::string& reason) {
  if (path_ != reached_ || value_ != nullptr) return;
  const std::string key = next_key();
  if (std::find(keys.begin(), keys.end(), key) == keys.end()) return;
  why_not_ = reason;
  why_not_path_ = join_path(reached_, key);
}

std::optional<SceneField> FieldLocator::result() const {
  if (value_ == nullptr) return std::nullopt;
  return SceneField{target_, value_, checks_};
}

std::string FieldLocator::error_path() const {
  if (value_ != nullptr) return "";
  if (!why_not_.empty()) return why_not_path_;
  return join_path(reached_, next_key());  // the unknown key, in the object reached
}

std::string FieldLocator::error() const {
  if (value_ != nullptr) return "";
  if (!why_not_.empty()) return why_not_;
  const std::string key = next_key();
  if (std::find(known_.begin(), known_.end(), key) != known_.end()) return "is not given in this scene";
  // As the loader words an unknown key (JsonReader::finish).
  std::string reason = "unknown key '" + key + "'";
  const std::string hint = did_you_mean(key, known_);
  if (!hint.empty()) return reason + hint;
  std::string list;
  for (const std::string& k : known_) list += (list.empty() ? "" : ", ") + k;
  return reason + " (valid keys here: " + list + ")";
}

}  // namespace camdyn
