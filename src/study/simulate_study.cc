#include "study/simulate_study.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <vector>

#include "common/errors.h"
#include "dynamics/coordinate_units.h"
#include "dynamics/model.h"
#include "dynamics/plausibility.h"
#include "dynamics/rigid_jump_speed.h"
#include "dynamics/simulation.h"
#include "dynamics/spring_sizing.h"
#include "dynamics/train_jump_speed.h"
#include "io/config.h"
#include "io/json_writer.h"
#include "output/profile_export.h"
#include "study/simulation_output.h"
#include "study/steady_state.h"

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
  const std::string speed = jump_speed_text(model_jump_speed_rpm(model), 4);
  std::fprintf(stderr,
               "  design check: %s %s, max pressure angle %.3g deg at %.4g deg, "
               "min radius of curvature %.3g m at %.4g deg\n",
               jump_speed_name(model), speed.c_str(), g.max_pressure_angle_deg, g.max_pressure_angle_at_deg,
               g.min_radius_of_curvature, g.min_radius_of_curvature_at_deg);
}

}  // namespace

int run_simulate_study(const Json& doc, const StudyContext& ctx) {
  const SceneConfig scene = scene_from_json(doc, ctx.source);
  // Building the model checks what the config layer cannot: the motion law,
  // the cam geometry (undercut, pressure angle) and the contact law.
  const Model model = build_model(scene, ctx.config_file);
  // outputs.profile is sampled (and its tool radius checked) before the run, so validate sees its errors too.
  std::optional<SampledCamProfile> profile;
  if (scene.outputs.profile)
    profile = sample_cam_profile(model, profile_options(*scene.outputs.profile), ProfileOptionNames{ctx.config_file});
  if (ctx.validate_only) {
    std::cout << dump_json(to_json(scene));
    std::cerr << "camdyn: " << ctx.config_file << " is valid (" << model.layout.size << " states: ";
    for (size_t i = 0; i < model.layout.names.size(); ++i) std::cerr << (i ? ", " : "") << model.layout.names[i];
    std::cerr << ")\n";
    print_design_check(model);
    if (scene.mechanism.contact.from_materials)  // summary.json: resolved.contact_stiffness
      std::fprintf(stderr, "  resolved: contact stiffness %.6g N/m^%g from materials\n", model.contact.stiffness,
                   model.contact.exponent);
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
  // Float decides, not the lash's take-up and seat bounces (docs/valvetrain.md).
  const std::string place = separation_place(m);
  const char* verdict = model.take_up.held_open_body >= 0 ? "VALVE HELD OPEN"
                        : place == "float"                ? "follower SEPARATES"
                        : place == "link"                 ? "train SEPARATES at a link"
                                                          : "follower stays in contact";
  std::printf("%s: %s, %.6g rpm (%s %s)\n", scene.name.c_str(), verdict, scene.mechanism.cam.rpm,
              jump_speed_name(model), jump_speed_text(m.jump_speed_rpm, 6).c_str());
  if (!result.metrics_note.empty()) std::printf("  steady state: %s\n", result.metrics_note.c_str());
  std::printf("  separation_fraction %.4g, impacts %ld, peak_contact_force %.6g N, min_contact_force %.6g N\n",
              m.separation_fraction, m.impact_count, m.peak_contact_force, m.min_contact_force);
  if (m.train && m.train->lash)
    std::printf("  float_fraction %.4g, take_up_bounces %ld, seat_bounces %ld (highest %.4g mm)\n",
                m.float_fraction.value_or(0.0), m.train->take_up_bounces, m.train->seat_bounces,
                m.train->max_seat_bounce_height * 1e3);
  if (rigid_spring_sizing_applies(model)) {
    if (const std::optional<RigidSpringLoad> load = rigid_spring_load(model, 0.0)) {
      const SpringSizing sizing = size_spring(*model.law, *load, model.omega);
      std::printf("  required spring preload %.6g %s at the rate given (rigid model, contact up to this speed)\n",
                  sizing.required_preload, coordinate_units(model).force);
    } else {
      std::printf("  required spring preload: not available (%s)\n", kNoLinearPart);
    }
  } else {  // the held train's (docs/model.md §12)
    const HeldSpringSizing sizing = size_held_spring(model, 0.0, model.omega);
    if (sizing.available)
      std::printf(
          "  required spring preload %.6g %s of %s at the rate given (held train: every contact and link "
          "loaded up to this speed)\n",
          sizing.required_preload, sizing.unit.c_str(), sizing.spring.c_str());
    else
      std::printf("  required spring preload: not available (%s)\n", sizing.reason.c_str());
  }
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

}  // namespace camdyn
