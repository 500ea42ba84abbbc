#include "study/convergence_config.h"

#include "common/errors.h"
#include "dynamics/simulation.h"

namespace camdyn {

namespace {

const std::vector<std::string> kConvergenceKeys = {"methods",     "tolerances",    "reference", "tracking",
                                                   "atol_factor", "rk4_steps_deg", "scenes"};

}  // namespace

ConvergenceStudy read_convergence_study(const Json& doc, const StudyContext& ctx) {
  ConvergenceStudy study;
  Json study_json;
  study.base = scene_from_study_json(doc, ctx.source, kConvergenceKeys, study_json);
  ConvergenceConfig& config = study.config;
  JsonReader reader(study_json, "", ctx.source);
  visit(reader, config);
  reader.finish();

  // The scene variants, each validated like a scene of its own.
  for (size_t k = 0; k < config.scenes.size(); ++k) {
    Json variant = to_json(study.base);
    for (const std::string& assignment : config.scenes[k].set) apply_assignment(variant, assignment);
    try {
      study.scenes.push_back(scene_from_json(variant, ctx.source));
      build_model(study.scenes.back(), ctx.config_file);
    } catch (const InputError& e) {
      throw InputError(ctx.config_file, "scenes[" + std::to_string(k) + "].set",
                       std::string("scene '") + config.scenes[k].name + "': " + e.what());
    }
  }
  JsonWriter writer;
  visit(writer, config);
  study.resolved = resolved_study_json(study.base, "convergence", writer.json());
  return study;
}

}  // namespace camdyn
