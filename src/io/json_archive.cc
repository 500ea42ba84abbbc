#include "io/json_archive.h"

#include <algorithm>
#include <charconv>
#include <functional>
#include <iterator>
#include <system_error>
#include <utility>

#include "io/input_file.h"
#include "io/suggest.h"

namespace camdyn {

namespace fs = std::filesystem;

// ---------------------------------------------------------------- checks

std::string format_shortest(double x) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

std::string describe_json(const Json& value) {
  switch (value.type()) {
    case Json::value_t::null:
      return "null";
    case Json::value_t::boolean:
      return "boolean " + value.dump();
    case Json::value_t::string: {
      // Bytes that are not UTF-8 are shown as U+FFFD rather than thrown on.
      std::string text = value.dump(-1, ' ', false, Json::error_handler_t::replace);
      if (text.size() > 60) text = text.substr(0, 56) + "...\"";
      return "string " + text;
    }
    case Json::value_t::object:
      return "an object";
    case Json::value_t::array:
      return "an array";
    default:
      return value.dump();
  }
}

namespace {

template <class Predicate>
Check number_check(std::string expected, std::string requirement, Predicate ok) {
  Check check;
  check.expected = std::move(expected);
  check.number = [requirement = std::move(requirement), ok](double x) {
    return ok(x) ? std::string() : requirement + ", got " + format_shortest(x);
  };
  return check;
}

std::string quoted_list(const std::vector<std::string>& values) {
  std::string out;
  for (const std::string& v : values) out += (out.empty() ? "'" : ", '") + v + "'";
  return out;
}

}  // namespace

Check positive() {
  return number_check("a number > 0", "must be > 0", [](double x) { return x > 0; });
}

Check non_negative() {
  return number_check("a number >= 0", "must be >= 0", [](double x) { return x >= 0; });
}

Check at_least(double low) {
  const std::string bound = ">= " + format_shortest(low);
  return number_check("a number " + bound, "must be " + bound, [low](double x) { return x >= low; });
}

Check open_closed(double low, double high) {
  const std::string range = "in (" + format_shortest(low) + ", " + format_shortest(high) + "]";
  return number_check("a number " + range, "must be " + range, [low, high](double x) { return x > low && x <= high; });
}

Check closed_open(double low, double high) {
  const std::string range = "in [" + format_shortest(low) + ", " + format_shortest(high) + ")";
  return number_check("a number " + range, "must be " + range, [low, high](double x) { return x >= low && x < high; });
}

Check non_empty() {
  Check check;
  check.expected = "a non-empty value";
  check.size = [](std::size_t n) { return n > 0 ? std::string() : std::string("must not be empty"); };
  return check;
}

Check one_of(std::vector<std::string> allowed, std::vector<std::string> later, std::string later_reason) {
  if (later_reason.empty()) later_reason = "'{}' is not supported yet (see the open issues)";
  Check check;
  check.expected = "one of " + quoted_list(allowed);
  check.text = [allowed = std::move(allowed), later = std::move(later),
                later_reason = std::move(later_reason)](const std::string& s) -> std::string {
    if (std::find(allowed.begin(), allowed.end(), s) != allowed.end()) return "";
    if (std::find(later.begin(), later.end(), s) != later.end()) {
      std::string reason = later_reason;
      if (const auto at = reason.find("{}"); at != std::string::npos) reason.replace(at, 2, s);
      return reason;
    }
    std::vector<std::string> known = allowed;
    known.insert(known.end(), later.begin(), later.end());
    return "must be one of " + quoted_list(allowed) + ", got " + describe_json(Json(s)) + did_you_mean(s, known);
  };
  return check;
}

// ---------------------------------------------------------------- files

namespace {

/// nlohmann messages start with "[json.exception.parse_error.101] parse error at line 3,
/// column 7: "; keep what follows.
std::string strip_nlohmann_prefix(std::string message) {
  if (message.starts_with("[")) {
    if (const auto end = message.find("] "); end != std::string::npos) message.erase(0, end + 2);
  }
  if (message.starts_with("parse error")) {
    if (const auto colon = message.find(": "); colon != std::string::npos) message.erase(0, colon + 2);
  }
  return message;
}

/// Rejects duplicate keys while parsing (nlohmann keeps the last one silently),
/// reporting the dotted path of the second occurrence, and nesting deeper
/// than kMaxJsonDepth (everything that walks a document recurses). Knows the
/// dotted path being parsed, for errors the parser itself throws.
class DuplicateKeyCheck {
 public:
  explicit DuplicateKeyCheck(std::string file) : file_(std::move(file)) {}

  bool operator()(int /*depth*/, Json::parse_event_t event, Json& parsed) {
    switch (event) {
      case Json::parse_event_t::object_start:
      case Json::parse_event_t::array_start:
        if (frames_.size() >= kMaxJsonDepth)
          throw InputError(file_, path(), "nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
        frames_.push_back({event == Json::parse_event_t::object_start, {}, {}, 0});
        break;
      case Json::parse_event_t::key: {
        Frame& frame = frames_.back();
        frame.key = parsed.get<std::string>();
        if (!frame.keys.insert(frame.key).second) {
          throw InputError(file_, path(), "duplicate key '" + frame.key + "'");
        }
        break;
      }
      case Json::parse_event_t::object_end:
      case Json::parse_event_t::array_end:
        frames_.pop_back();
        element_done();
        break;
      case Json::parse_event_t::value:
        element_done();
        break;
    }
    return true;
  }

 private:
  struct Frame {
    bool object;
    std::set<std::string> keys;
    std::string key;    // object: the key being parsed
    std::size_t index;  // array: the element being parsed
  };

  void element_done() {
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
  }

 public:
  std::string path() const {
    std::string out;
    for (const Frame& frame : frames_) {
      if (frame.object) {
        out += (out.empty() ? "" : ".") + frame.key;
      } else {
        out += "[" + std::to_string(frame.index) + "]";
      }
    }
    return out;
  }

  std::string file_;
  std::vector<Frame> frames_;
};

}  // namespace

/// "line L, column C" of the 1-based byte offset `end` in `text`.
std::string line_and_column(const std::string& text, std::size_t end) {
  end = std::min(end, text.size());
  std::size_t line = 1, column = 0;
  for (std::size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 0;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

Json parse_json_text(const std::string& text, const std::string& file) {
  DuplicateKeyCheck check(file);
  try {
    return Json::parse(text, std::ref(check));
  } catch (const Json::parse_error& e) {
    // e.byte is the 1-based offset of the last character read.
    throw InputError(file, line_and_column(text, e.byte),
                     "JSON " + strip_nlohmann_prefix(e.what()));  // "JSON syntax error while ..."
  } catch (const Json::out_of_range& e) {                         // a number too large for a double
    // nlohmann names the number ("number overflow parsing '1e999'") but not
    // where it is: the path being parsed, and the number's first occurrence.
    std::string where = check.path();
    const std::string what = e.what();
    const auto open = what.find('\''), close = what.rfind('\'');
    if (open != std::string::npos && close > open) {
      const auto at = text.find(what.substr(open + 1, close - open - 1));
      if (at != std::string::npos) where = (where.empty() ? "" : where + " at ") + line_and_column(text, at + 1);
    }
    throw InputError(file, where, "invalid JSON: " + strip_nlohmann_prefix(what));
  } catch (const Json::exception& e) {
    throw InputError(file, check.path(), "invalid JSON: " + strip_nlohmann_prefix(e.what()));
  }
}

Json read_json_file(const std::string& file) {
  std::error_code ec;
  if (fs::is_directory(file, ec)) throw InputError(file, "", "cannot open: it is a directory");
  // A regular file within the memory budget, or refused before it is read (io/input_file.h).
  return parse_json_text(read_input_file(file), file);
}

std::optional<fs::path> find_data_file(const std::string& name, const std::string& dir,
                                       std::vector<std::string>* tried) {
  const fs::path given(name);
  std::vector<fs::path> candidates;
  if (given.is_absolute()) {
    candidates.push_back(given);
  } else {
    candidates.push_back(fs::path(dir) / given);
    candidates.push_back(fs::current_path() / given);
    candidates.push_back(fs::path(CAMDYN_SOURCE_DIR) / given);
  }
  for (const fs::path& candidate : candidates) {
    const fs::path full = fs::absolute(candidate).lexically_normal();
    if (tried != nullptr && std::find(tried->begin(), tried->end(), full.string()) == tried->end()) {
      tried->push_back(full.string());
    }
    std::error_code ec;
    if (fs::is_regular_file(full, ec)) return full;
  }
  return std::nullopt;
}

std::string absolute_path(const std::string& name, const std::string& dir) {
  const fs::path given(name);
  if (given.is_absolute()) return given.lexically_normal().string();
  return fs::absolute(fs::path(dir) / given).lexically_normal().string();
}

// ---------------------------------------------------------------- reader

JsonReader::JsonReader(const Json& object, std::string path, ConfigSource source, JsonReader* parent)
    : object_(object), path_(std::move(path)), source_(std::move(source)), parent_(parent) {}

std::string JsonReader::take(std::string_view key) {
  std::string k(key);
  if (std::find(known_.begin(), known_.end(), k) == known_.end()) known_.push_back(k);
  consumed_.insert(k);
  return k;
}

bool JsonReader::given(std::string_view key, bool /*writer_state*/) {
  const std::string k(key);
  if (std::find(known_.begin(), known_.end(), k) == known_.end()) known_.push_back(k);
  const auto it = object_.find(k);
  if (it == object_.end()) return false;
  if (it->is_null()) {
    consumed_.insert(k);
    return false;
  }
  return true;
}

bool JsonReader::given_object(std::string_view key, bool /*writer_state*/) {
  const std::string k(key);
  if (std::find(known_.begin(), known_.end(), k) == known_.end()) known_.push_back(k);
  const auto it = object_.find(k);
  return it != object_.end() && it->is_object();
}

void JsonReader::allow(std::string_view key, Json::value_t type) {
  const std::string k = take(key);
  const auto it = object_.find(k);
  if (it != object_.end() && it->type() != type) {
    fail(k, "expected " + std::string(Json(type).type_name()) + ", got " + describe_json(*it));
  }
}

void JsonReader::forbid(std::initializer_list<std::string_view> keys, const std::string& reason) {
  for (const std::string_view key : keys) {
    const std::string k(key);
    const auto it = object_.find(k);
    if (it == object_.end()) continue;
    if (!it->is_null()) fail(k, reason);
    consumed_.insert(k);
  }
}

void JsonReader::require(bool ok, std::string_view key, const std::string& reason) {
  if (!ok) defer(InputError(source_.file, path_of(key), reason));
}

void JsonReader::defer(const InputError& error) {
  if (!deferred_) deferred_ = error;
}

void JsonReader::finish() {
  for (const auto& item : object_.items()) {
    if (consumed_.count(item.key()) != 0) continue;
    std::string reason = "unknown key '" + item.key() + "'";
    const std::string hint = did_you_mean(item.key(), known_);
    if (!hint.empty()) {
      reason += hint;
    } else {
      std::string list;
      for (const std::string& k : known_) list += (list.empty() ? "" : ", ") + k;
      reason += " (valid keys here: " + list + ")";
    }
    fail(item.key(), reason);
  }
  if (deferred_) {
    if (parent_ == nullptr) throw *deferred_;
    parent_->defer(*deferred_);
  }
}

std::string JsonReader::path_of(std::string_view key) const {
  if (key.empty()) return path_;
  if (path_.empty()) return std::string(key);
  return path_ + "." + std::string(key);
}

void JsonReader::fail(std::string_view key, const std::string& reason) const { fail_at(path_of(key), reason); }

void JsonReader::fail_at(const std::string& path, const std::string& reason) const {
  throw InputError(source_.file, path, reason);
}

fs::path JsonReader::locate(const std::string& key, const std::string& name) const {
  std::vector<std::string> tried;
  if (name.empty()) fail(key, "expected an object or a file name, got an empty string");
  const auto found = find_data_file(name, source_.dir, &tried);
  if (!found) {
    std::string list;
    for (const std::string& t : tried) list += (list.empty() ? "" : ", ") + t;
    fail(key, "file '" + name + "' not found (looked for " + list + ")");
  }
  return *found;
}

void JsonReader::run_checks(const std::string& path, double x, std::span<const Check> checks) const {
  for (const Check& check : checks) {
    if (!check.number) continue;
    if (const std::string reason = check.number(x); !reason.empty()) fail_at(path, reason);
  }
}

void JsonReader::run_checks(const std::string& path, const std::string& s, std::span<const Check> checks) const {
  for (const Check& check : checks) {
    std::string reason;
    if (check.text) reason = check.text(s);
    if (reason.empty() && check.size) reason = check.size(s.size());
    if (!reason.empty()) fail_at(path, reason);
  }
}

void JsonReader::run_size_checks(const std::string& path, std::size_t n, std::span<const Check> checks) const {
  for (const Check& check : checks) {
    if (!check.size) continue;
    if (const std::string reason = check.size(n); !reason.empty()) fail_at(path, reason);
  }
}

}  // namespace camdyn
