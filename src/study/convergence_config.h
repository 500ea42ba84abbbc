// The study-specific part of a `convergence` config (docs/config.md, "convergence"): the
// methods, tracking modes and tolerances to run, the reference run and the
// scene variants. Defaults live in the member initialisers; one `visit` per
// struct reads and writes them, so unknown keys are rejected and `camdyn
// validate` prints every field.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "io/config.h"
#include "io/json_archive.h"
#include "study/study.h"

namespace camdyn {

/// A variant of the study's scene: `set` holds "dotted.path=VALUE" assignments.
struct ConvergenceScene {
  std::string name = "base";
  std::vector<std::string> set;
  std::optional<std::vector<double>> tolerances;     ///< overrides the study's for this scene
  std::optional<double> reference_rtol;              ///< overrides reference.rtol for this scene
  std::optional<std::vector<double>> rk4_steps_deg;  ///< overrides the study's for this scene
};

/// `reference`: the tight run every other run is measured against.
struct ConvergenceReference {
  IntegrationMethod method = IntegrationMethod::cvode_bdf;
  double rtol = 1e-12;
};

struct ConvergenceConfig {
  std::vector<IntegrationMethod> methods = {IntegrationMethod::cvode_bdf, IntegrationMethod::cvode_adams,
                                            IntegrationMethod::arkode_erk, IntegrationMethod::arkode_dirk,
                                            IntegrationMethod::rk4};
  std::vector<double> tolerances = {1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10};
  ConvergenceReference reference;
  std::vector<Tracking> tracking = {Tracking::differential, Tracking::newton};
  double atol_factor = 1e-4;  ///< atol = rtol × atol_factor (state scale [m])
  /// rk4 has no tolerance: its fixed steps, in degrees of cam angle.
  std::vector<double> rk4_steps_deg = {0.5, 0.25, 0.125, 0.0625, 0.03125, 0.015625};
  std::vector<ConvergenceScene> scenes = {ConvergenceScene{}};
};

/// The largest fixed RK4 step [deg of cam angle]: a revolution (a larger
/// step is a slip, and its step in seconds overflows the run).
inline constexpr double kMaxRk4StepDeg = 360.0;

template <class A>
void visit(A& a, ConvergenceScene& v) {
  a.field("name", v.name, non_empty());
  a.field("set", v.set);
  a.field("tolerances", v.tolerances, non_empty(), open_closed(0, 0.1));
  a.field("reference_rtol", v.reference_rtol, open_closed(0, 0.1));
  a.field("rk4_steps_deg", v.rk4_steps_deg, non_empty(), open_closed(0, kMaxRk4StepDeg));
}

template <class A>
void visit(A& a, ConvergenceReference& r) {
  a.field("method", r.method);
  a.field("rtol", r.rtol, open_closed(0, 0.1));
}

template <class A>
void visit(A& a, ConvergenceConfig& c) {
  a.field("methods", c.methods, non_empty());
  a.field("tolerances", c.tolerances, non_empty(), open_closed(0, 0.1));
  a.field("reference", c.reference);
  a.field("tracking", c.tracking, non_empty());
  a.field("atol_factor", c.atol_factor, open_closed(0, 1));  // a state scale above 1 m is a slip
  a.field("rk4_steps_deg", c.rk4_steps_deg, non_empty(), open_closed(0, kMaxRk4StepDeg));
  a.field("scenes", c.scenes, non_empty());
}

/// A read convergence study: the base scene, the study fields, the scene of
/// each variant and the resolved config (what config.json and `validate` print).
struct ConvergenceStudy {
  SceneConfig base;
  ConvergenceConfig config;
  std::vector<SceneConfig> scenes;  ///< one per config.scenes, its assignments applied
  Json resolved;
};

/// Reads a convergence study document; each scene variant is validated like a
/// scene of its own. Throws InputError naming ctx.config_file.
ConvergenceStudy read_convergence_study(const Json& doc, const StudyContext& ctx);

}  // namespace camdyn
