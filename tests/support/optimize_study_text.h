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

/// The quickstart mechanism (cycloidal rise/return, 20 mm) with the loop's
/// two revolutions, its splines designed against the peak contact force at
/// 700 and 900 rpm: the study's fields up to the optimizer's, each line
/// ending in a comma (the caller closes the object).
inline std::string quickstart_force_design_fields() {
  return R"(
    "mechanism": {
      "cam": { "base_radius": 0.04, "rpm": 900, "motion_law": "profiles/cycloidal_rise_return.json" },
      "follower": { "shape": { "type": "roller", "radius": 0.01 }, "mass": 0.3,
                    "spring": { "stiffness": 5000, "preload": 40 }, "damping": 5 },
      "contact": { "stiffness": 1e10 } },
    "simulation": { "cycles": 2, "discard_cycles": 1, "output_step_deg": 1 },
    "integrator": { "rtol": 1e-7 },
    "design": { "segments": ["rise", "return"], "control_points": 5, "degree": 5 },
    "operating_rpm": [700, 900],
    "objective": { "separation": 0, "peak_contact_force": 1 },
    "constraints": { "min_contact_force": 2 },
)";
}

}  // namespace camdyn::optim
