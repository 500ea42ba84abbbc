#include "cli/run_study.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>

#include "common/errors.h"
#include "common/study_budget.h"
#include "dynamics/coordinate_units.h"
#include "dynamics/model.h"
#include "dynamics/plausibility.h"
#include "dynamics/simulation.h"
#include "io/atomic_file.h"
#include "io/config.h"
#include "io/json_writer.h"
#include "optim/identify_study.h"
#include "optim/optimize_study.h"
#include "output/output_folder.h"
#include "output/profile_export.h"
#include "study/compare_study.h"
#include "study/convergence_study.h"
#include "study/jump_map.h"
#include "study/mpi_runner.h"
#include "study/periodic_study.h"
#include "study/simulation_output.h"
#include "study/speed_limit.h"
#include "study/steady_state.h"
#include "study/study.h"

namespace camdyn {

namespace {

constexpr int kExitOk = 0, kExitNumerical = 3;

// A progress line on stderr, redrawn in place, only on a terminal.
class Progress {
 public:
  explicit Progress(bool enabled) : enabled_(enabled && isatty(STDERR_FILENO)) {}
  void operator()(double fraction) const {
    if (!enabled_) return;
    std::fprintf(stderr, "\r  simulating %5.1f %%", 100.0 * fraction);
    if (fraction >= 1.0) std::fprintf(stderr, "\n");
    std::fflush(stderr);
  }
  bool enabled() const { return enabled_; }

 private:
  bool enabled_;
};

// `camdyn validate`'s design check on stderr: the rigid-model jump speed,
// the largest pressure angle and the smallest radius of curvature.
void print_design_check(const Model& model) {
  const CamGeometryReport& g = model.geometry;
  const double jump = jump_speed_rpm(model);  // [rpm]; +inf: the law never decelerates
  char speed[48] = "none (the law never decelerates)";
  if (std::isfinite(jump)) std::snprintf(speed, sizeof speed, "%.4g rpm", jump);
  std::fprintf(stderr,
               "  design check: rigid-model jump speed %s, max pressure angle %.3g deg at %.4g deg, "
               "min radius of curvature %.3g m at %.4g deg\n",
               speed, g.max_pressure_angle_deg, g.max_pressure_angle_at_deg, g.min_radius_of_curvature,
               g.min_radius_of_curvature_at_deg);
}

int run_simulate(const Json& doc, const StudyContext& ctx) {
  const SceneConfig scene = scene_from_json(doc, ctx.source);
  // Building the model checks what the config layer cannot: the motion law,
  // the cam geometry (undercut, pressure angle) and the contact law.
  const Model model = build_model(scene, ctx.config_file);
  // outputs.profile is sampled (and its tool radius checked) before the run, so validate sees its errors too.
  std::optional<CamProfile> profile;
  if (scene.outputs.profile)
    profile = sample_cam_profile(model, profile_options(*scene.outputs.profile), ProfileOptionNames{ctx.config_file});
  if (ctx.validate_only) {
    std::cout << dump_json(to_json(scene));
    std::cerr << "camdyn: " << ctx.config_file << " is valid (" << model.layout.size << " states: ";
    for (size_t i = 0; i < model.layout.names.size(); ++i) std::cerr << (i ? ", " : "") << model.layout.names[i];
    std::cerr << ")\n";
    print_design_check(model);
    for (const PlausibilityWarning& w : input_warnings(scene, model)) std::cerr << warning_line(w) << "\n";
    return kExitOk;
  }
  Workspace ws;
  const Progress progress(ctx.progress);
  SimulationOptions options;
  if (progress.enabled()) options.progress = [&](double f) { progress(f); };
  SimulationResult result = simulate(scene, model, ws, options);
  estimate_error(scene, model, result);
  throw_if_failed(result);
  apply_steady_state(scene, model, result, SteadyStateSearch::full, ctx.threads());
  const std::filesystem::path& out = ctx.out_dir;
  write_simulation_outputs(out, scene, model, result);
  if (profile) write_profile_files(out, *profile, scene.name, scene.outputs.profile->formats);

  const Metrics& m = result.metrics;
  std::printf("%s: %s, %.6g rpm (rigid-model jump speed %.6g rpm)\n", scene.name.c_str(),
              m.separation_fraction > 0.0 ? "follower SEPARATES" : "follower stays in contact", scene.mechanism.cam.rpm,
              m.jump_speed_rpm);
  if (!result.metrics_note.empty()) std::printf("  steady state: %s\n", result.metrics_note.c_str());
  std::printf("  separation_fraction %.4g, impacts %ld, peak_contact_force %.6g N, min_contact_force %.6g N\n",
              m.separation_fraction, m.impact_count, m.peak_contact_force, m.min_contact_force);
  std::printf("  energy_residual %.3g, %ld steps, %ld RHS evaluations, %.3g s\n", m.energy_residual,
              result.solver.counters.steps, result.solver.counters.rhs_evaluations, result.solver.run_time_s);
  if (result.error.richardson)
    std::printf("  error estimate (run at 100x tighter tolerance): position %.3g %s, peak force %.3g\n",
                result.error.position, coordinate_units(model).position, result.error.peak_contact_force);
  std::printf("  report: %s\n", std::filesystem::absolute(out / "report.html").lexically_normal().c_str());
  const std::vector<PlausibilityWarning> warnings = run_warnings(scene, model, result);
  for (const PlausibilityWarning& w : warnings) std::printf("%s\n", warning_line(w).c_str());
  if (ctx.strict && !warnings.empty()) {
    std::fflush(stdout);
    std::cerr << "camdyn: --strict: " << ctx.config_file << ": " << warnings.size()
              << " warning(s), the results should not be trusted (outputs written)\n";
    return kExitNumerical;
  }
  return kExitOk;
}

// The study's runner; every one writes its outputs to ctx.out_dir.
int dispatch(const std::string& study, const Json& doc, const StudyContext& ctx) {
  if (study == "convergence") return run_convergence_study(doc, ctx);
  if (study == "compare") return run_compare_study(doc, ctx);
  if (study == "jump_map") return run_jump_map_study(doc, ctx);
  const bool root = mpi::rank() == 0;
  if (mpi::size() > 1 && !ctx.validate_only) {
    // Only compare studies are spread over ranks; the others run on rank 0.
    if (!root) return kExitOk;
    std::cerr << "camdyn: note: only compare studies use the MPI ranks; this " << study
              << " study runs on rank 0 alone\n";
  }
  if (study == "optimize") return optim::run_optimize_study(doc, ctx);
  if (study == "identify") return optim::run_identify_study(doc, ctx);
  if (study == "speed_limit") return run_speed_limit_study(doc, ctx);
  if (study == "periodic") return run_periodic_study(doc, ctx);
  return run_simulate(doc, ctx);  // simulate; any other study name is reported by the config layer
}

Json request_json(const StudyRequest& request, ConfigSource& source) {
  if (!request.config_file.empty()) {
    source = config_source(request.config_file);
    return load_config_json(request.config_file, request.overrides);
  }
  Json doc = parse_json_text(request.json_text, "");
  for (const std::string& assignment : request.overrides) apply_assignment(doc, assignment);
  source = ConfigSource{
      "", std::filesystem::absolute(request.base_dir.empty() ? "." : request.base_dir).lexically_normal().string()};
  return doc;
}

}  // namespace

std::string main_output_name(const std::string& study) {
  if (study == "optimize") return "result.json";
  if (study == "identify") return "identified.json";
  if (study == "compare") return "comparison.json";
  if (study == "convergence") return "work_precision.csv";
  if (study == "speed_limit") return "speed_limit.json";
  if (study == "periodic") return "periodic.json";
  if (study == "jump_map") return "jump_map.json";
  return "summary.json";
}

StudyOutcome run_study(const StudyRequest& request) {
  StudyContext ctx;
  const Json doc = request_json(request, ctx.source);
  ctx.config_file = request.config_file;
  const std::string name = doc.contains("name") && doc["name"].is_string() ? doc["name"].get<std::string>() : "camdyn";
  ctx.out_dir = request.out_dir.empty() ? std::filesystem::path("out") / name : std::filesystem::path(request.out_dir);
  ctx.jobs = request.jobs;
  ctx.progress = request.progress;
  ctx.validate_only = request.validate_only;
  ctx.strict = request.strict;
  StudyOutcome outcome;
  outcome.study = doc.contains("study") && doc["study"].is_string() ? doc["study"].get<std::string>() : "simulate";
  outcome.out_dir = ctx.out_dir;
  outcome.main_output = ctx.out_dir / main_output_name(outcome.study);
  // One run at a time per output folder (rank 0 writes for all ranks); the
  // completion marker goes first and comes back only once every output is written.
  std::optional<OutputLock> lock;
  if (!ctx.validate_only && mpi::rank() == 0) {
    lock.emplace(ctx.out_dir);
    remove_stale_temporary_files(ctx.out_dir);
    remove_completion_marker(ctx.out_dir);
  }
  try {
    const StudyBudgetScope budget(request.max_study_time_s, request.max_memory_mb);
    outcome.exit_code = dispatch(outcome.study, doc, ctx);
  } catch (const InputError& e) {
    // Errors raised below the config layer may not know the file: name it here.
    if (!e.file().empty() || request.config_file.empty()) throw;
    throw InputError(request.config_file, e.path(), e.reason());
  }
  if (lock && outcome.exit_code == kExitOk)
    write_completion_marker(ctx.out_dir, outcome.study, main_output_name(outcome.study));
  return outcome;
}

}  // namespace camdyn
