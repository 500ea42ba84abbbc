#include "io/dotted_path.h"

#include "common/errors.h"
#include "io/json_archive.h"
#include "io/suggest.h"

namespace camdyn {

namespace {

bool is_short_head(const std::string& key) { return key == "cam" || key == "follower" || key == "contact"; }

/// The steps walked so far as text, for messages: "mechanism.cam.motion_law.segments[0]".
void append_step(std::string& walked, const PathStep& step) {
  if (step.is_index()) {
    walked += "[" + std::to_string(step.index) + "]";
  } else {
    walked += (walked.empty() ? "" : ".") + step.key;
  }
}

}  // namespace

std::vector<PathStep> parse_dotted_path(const std::string& path) {
  const auto bad = [&](const std::string& why) -> InputError {
    return InputError("--set", path,
                      why +
                          " (expected a dotted path like mechanism.cam.rpm "
                          "or mechanism.cam.motion_law.segments[0].lift)");
  };
  std::vector<PathStep> steps;
  std::size_t i = 0;
  while (true) {
    std::string key;
    while (i < path.size() && path[i] != '.' && path[i] != '[') {
      const char c = path[i++];
      const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
      if (!ok) throw bad(std::string("unexpected character '") + c + "'");
      key += c;
    }
    if (key.empty()) throw bad("empty key");
    steps.push_back({key, 0});
    while (i < path.size() && path[i] == '[') {
      const std::size_t close = path.find(']', i);
      const std::string digits = close == std::string::npos ? "" : path.substr(i + 1, close - i - 1);
      if (digits.empty() || digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) {
        throw bad("bad array index");
      }
      steps.push_back({"", static_cast<std::size_t>(std::stoul(digits))});
      i = close + 1;
    }
    if (i == path.size()) break;
    if (path[i] != '.') throw bad("unexpected character after ']'");
    ++i;
  }
  if (is_short_head(steps.front().key)) steps.insert(steps.begin(), PathStep{"mechanism", 0});
  return steps;
}

std::string full_dotted_path(const std::string& path) {
  for (const char* head : {"cam", "follower", "contact"}) {
    const std::string h(head);
    if (path == h || path.starts_with(h + ".") || path.starts_with(h + "[")) return "mechanism." + path;
  }
  return path;
}

const Json* find_dotted_field(const Json& document, const std::string& path, std::string& why) {
  std::vector<PathStep> steps;
  try {
    steps = parse_dotted_path(path);
  } catch (const InputError& e) {
    why = e.reason();
    return nullptr;
  }
  const Json* node = &document;
  std::string walked;
  for (const PathStep& step : steps) {
    if (step.is_index()) {
      if (!node->is_array() || step.index >= node->size()) {
        why = "'" + walked + "' has no element " + std::to_string(step.index);
        return nullptr;
      }
      node = &(*node)[step.index];
    } else {
      if (!node->is_object() || !node->contains(step.key)) {
        std::vector<std::string> keys;
        if (node->is_object())
          for (const auto& item : node->items()) keys.push_back(item.key());
        why = "'" + step.key + "' is not a field of " +
              (walked.empty() ? std::string("the scene") : "'" + walked + "'") + did_you_mean(step.key, keys);
        return nullptr;
      }
      node = &(*node)[step.key];
    }
    append_step(walked, step);
  }
  return node;
}

void set_dotted_field(Json& document, const std::string& path, const Json& value) {
  const std::vector<PathStep> steps = parse_dotted_path(path);
  Json* node = &document;
  std::string walked;
  for (const PathStep& step : steps) {
    if (!step.is_index()) {
      if (node->is_null()) *node = Json::object();
      if (!node->is_object()) {
        throw InputError("--set", path, "'" + walked + "' is " + describe_json(*node) + ", not an object");
      }
      node = &(*node)[step.key];
    } else {
      if (!node->is_array()) {
        throw InputError("--set", path, "'" + walked + "' is " + describe_json(*node) + ", not an array");
      }
      if (step.index >= node->size()) {
        throw InputError("--set", path,
                         "index " + std::to_string(step.index) + " is out of range: '" + walked + "' has " +
                             std::to_string(node->size()) + " elements");
      }
      node = &(*node)[step.index];
    }
    append_step(walked, step);
  }
  *node = value;
}

}  // namespace camdyn
