#include "io/json_merge.h"

#include <algorithm>

namespace camdyn {

namespace {

void merge_at(Json& base, const Json& patch, const std::vector<std::string>& replaced_whole, const std::string& path) {
  for (const auto& item : patch.items()) {
    const std::string key_path = path.empty() ? item.key() : path + "." + item.key();
    const bool whole = std::find(replaced_whole.begin(), replaced_whole.end(), key_path) != replaced_whole.end();
    auto it = base.find(item.key());
    if (!whole && it != base.end() && it->is_object() && item.value().is_object()) {
      merge_at(*it, item.value(), replaced_whole, key_path);
    } else {
      base[item.key()] = item.value();
    }
  }
}

}  // namespace

void deep_merge(Json& base, const Json& patch, const std::vector<std::string>& replaced_whole) {
  merge_at(base, patch, replaced_whole, "");
}

void merge_config(Json& base, const Json& patch) {
  static const std::vector<std::string> kReplacedWhole = {"mechanism.cam.motion_law"};
  deep_merge(base, patch, kReplacedWhole);
}

}  // namespace camdyn
