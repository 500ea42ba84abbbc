// An optimize study written inline in a test: its scene and its study part,
// read as `camdyn run` reads a config file (relative paths against the
// source tree).
#pragma once

#include <string>

#include "io/config.h"
#include "optim/optimize/optimize_config.h"
#include "study/study.h"

namespace camdyn::optim {

struct Study {
  SceneConfig scene;
  OptimizeStudyConfig config;
};

inline const ConfigSource& inline_study_source() {
  static const ConfigSource source{"test.json", CAMDYN_SOURCE_DIR};
  return source;
}

inline Study study_from(const std::string& text) {
  Json part;
  SceneConfig scene = scene_from_study_json(Json::parse(text), inline_study_source(), optimize_study_keys(), part);
  return {scene, optimize_config_from_json(part, inline_study_source())};
}

}  // namespace camdyn::optim
