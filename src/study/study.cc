#include "study/study.h"

#include <algorithm>
#include <thread>

namespace camdyn {

int StudyContext::threads() const {
  if (jobs > 0) return jobs;
  return std::max(1u, std::thread::hardware_concurrency());
}

SceneConfig scene_from_study_json(const Json& doc, const ConfigSource& source,
                                  const std::vector<std::string>& study_keys, Json& study_part) {
  Json scene = doc;
  study_part = Json::object();
  for (const std::string& key : study_keys) {
    if (auto it = scene.find(key); it != scene.end()) {
      study_part[key] = *it;
      scene.erase(it);
    }
  }
  scene["study"] = "simulate";
  return scene_from_json(scene, source);
}

Json resolved_study_json(const SceneConfig& scene, const std::string& study, const Json& study_part) {
  Json resolved = to_json(scene);
  resolved["study"] = study;
  for (const auto& [key, value] : study_part.items()) resolved[key] = value;
  return resolved;
}

}  // namespace camdyn
