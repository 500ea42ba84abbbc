#include "optim/identify/fit_scene.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "common/errors.h"
#include "dynamics/model_parameters.h"
#include "geometry/follower_shape.h"
#include "io/json_archive.h"

namespace camdyn::optim {

namespace {

using Field = double& (*)(SceneConfig&);

struct NamedField {
  const char* path;
  Field field;
};

// The parameter block's fields (dynamics/model_parameters.h), by config path.
// Optional blocks (guide and pivot friction) are bound only when the scene has them.
const NamedField kParameterFields[] = {
    {"mechanism.follower.mass", [](SceneConfig& s) -> double& { return s.mechanism.follower.mass; }},
    {"mechanism.follower.inertia", [](SceneConfig& s) -> double& { return s.mechanism.follower.inertia; }},
    {"mechanism.follower.spring.stiffness",
     [](SceneConfig& s) -> double& { return s.mechanism.follower.spring.stiffness; }},
    {"mechanism.follower.spring.preload",
     [](SceneConfig& s) -> double& { return s.mechanism.follower.spring.preload; }},
    {"mechanism.follower.damping", [](SceneConfig& s) -> double& { return s.mechanism.follower.damping; }},
    {"gravity", [](SceneConfig& s) -> double& { return s.gravity; }},
    {"mechanism.contact.restitution", [](SceneConfig& s) -> double& { return s.mechanism.contact.restitution; }},
    {"mechanism.contact.reference_velocity",
     [](SceneConfig& s) -> double& { return s.mechanism.contact.reference_velocity; }},
    {"mechanism.contact.friction.mu", [](SceneConfig& s) -> double& { return s.mechanism.contact.friction.mu; }},
    {"mechanism.contact.friction.regularization_velocity",
     [](SceneConfig& s) -> double& { return s.mechanism.contact.friction.regularization_velocity; }},
    {"mechanism.follower.shape.inertia", [](SceneConfig& s) -> double& { return s.mechanism.follower.shape.inertia; }},
    {"mechanism.cam.drive.inertia", [](SceneConfig& s) -> double& { return s.mechanism.cam.drive.inertia; }},
    {"mechanism.cam.drive.torsional_stiffness",
     [](SceneConfig& s) -> double& { return s.mechanism.cam.drive.torsional_stiffness; }},
    {"mechanism.cam.drive.torsional_damping",
     [](SceneConfig& s) -> double& { return s.mechanism.cam.drive.torsional_damping; }},
    {"mechanism.cam.drive.motor.stall_torque",
     [](SceneConfig& s) -> double& { return s.mechanism.cam.drive.motor.stall_torque; }},
    {"mechanism.cam.drive.motor.no_load_rpm",
     [](SceneConfig& s) -> double& { return s.mechanism.cam.drive.motor.no_load_rpm; }},
    {"mechanism.cam.drive.motor.inertia",
     [](SceneConfig& s) -> double& { return s.mechanism.cam.drive.motor.inertia; }},
};

const NamedField kGuideFields[] = {
    {"mechanism.follower.guide_friction.mu",
     [](SceneConfig& s) -> double& { return s.mechanism.follower.guide_friction->mu; }},
    {"mechanism.follower.guide_friction.regularization_velocity",
     [](SceneConfig& s) -> double& { return s.mechanism.follower.guide_friction->regularization_velocity; }},
};

const NamedField kPivotFields[] = {
    {"mechanism.follower.pivot_friction.mu",
     [](SceneConfig& s) -> double& { return s.mechanism.follower.pivot_friction->mu; }},
    {"mechanism.follower.pivot_friction.pin_radius",
     [](SceneConfig& s) -> double& { return s.mechanism.follower.pivot_friction->pin_radius; }},
    {"mechanism.follower.pivot_friction.regularization_velocity",
     [](SceneConfig& s) -> double& { return s.mechanism.follower.pivot_friction->regularization_velocity; }},
};

template <std::size_t N>
Field find(const NamedField (&table)[N], const std::string& path) {
  for (const NamedField& f : table)
    if (path == f.path) return f.field;
  return nullptr;
}

std::string values_text(const std::vector<FitParameter>& parameters, const std::vector<double>& values) {
  std::string at;
  for (std::size_t i = 0; i < values.size(); ++i)
    at += (i ? ", " : "") + parameters[i].name + " = " + format_shortest(values[i]);
  return at;
}

}  // namespace

std::optional<FieldBinding> bind_field(const std::string& path, const SceneConfig& scene) {
  const ContactConfig& contact = scene.mechanism.contact;
  const FollowerConfig& follower = scene.mechanism.follower;
  FieldBinding b;
  if ((b.field = find(kParameterFields, path))) return b;
  if (follower.guide_friction && (b.field = find(kGuideFields, path))) return b;
  if (follower.pivot_friction && (b.field = find(kPivotFields, path))) return b;
  if (path == "mechanism.contact.stiffness" && contact.stiffness) {
    b.field = [](SceneConfig& s) -> double& { return *s.mechanism.contact.stiffness; };
    return b;
  }
  if (path == "mechanism.contact.damping" && contact.damping) {
    b.field = [](SceneConfig& s) -> double& { return *s.mechanism.contact.damping; };
    return b;
  }
  if (path == "mechanism.contact.exponent") {
    // Stiffness from materials fixes the exponent: build_model checks it.
    b.kind = contact.from_materials ? FieldKind::geometry : FieldKind::parameter;
    b.field = [](SceneConfig& s) -> double& { return s.mechanism.contact.exponent; };
    return b;
  }
  b.kind = FieldKind::scene;
  if (path == "mechanism.follower.initial.velocity") {
    b.field = [](SceneConfig& s) -> double& { return s.mechanism.follower.initial.velocity; };
    return b;
  }
  b.kind = FieldKind::geometry;
  b.positive = true;
  if (path == "mechanism.cam.base_radius" && !scene.mechanism.cam.motion_law.contour) {
    b.field = [](SceneConfig& s) -> double& { return s.mechanism.cam.base_radius; };
    return b;
  }
  if (path == "mechanism.follower.shape.radius" && follower_shape_traits(follower.shape.type).takes_radius()) {
    b.field = [](SceneConfig& s) -> double& { return s.mechanism.follower.shape.radius; };
    return b;
  }
  return std::nullopt;
}

FitScene::FitScene(const FitExperiment& experiment, const std::vector<FitParameter>& parameters,
                   const ConfigSource& source, bool from_json)
    : experiment_(experiment),
      parameters_(parameters),
      source_(source),
      json_fallback_(from_json),
      scene_(experiment.scene) {
  for (const FitParameter& p : parameters) {
    bindings_.push_back(bind_field(p.path, scene_));
    json_fallback_ = json_fallback_ || !bindings_.back();
  }
  model_ = build_model(scene_, source_.file);
  ws_ = make_workspace(model_);
  options_.record_series = false;
  options_.sample_times = experiment.record.time;
  // The residuals read only the samples; the energy residual is the one
  // sampled column that needs the balance followed over every step, and the
  // only one that needs the quadratures.
  const std::vector<std::string>& signals = experiment.record.signals;
  options_.step_metrics = std::find(signals.begin(), signals.end(), "energy_residual") != signals.end();
  options_.quadratures = options_.step_metrics;
  const std::vector<std::string> names = TimeSeries::column_names();
  for (const std::string& signal : experiment.record.signals) {
    const auto it = std::find(names.begin(), names.end(), signal);
    if (it == names.end()) throw std::logic_error("no timeseries column " + signal);
    columns_.push_back(static_cast<std::size_t>(it - names.begin()));
  }
}

void FitScene::rebuild() {
  model_current_ = false;
  model_ = build_model(scene_, source_.file);
  ++model_builds_;
  model_current_ = true;
}

void FitScene::set(const std::vector<double>& values) {
  if (json_fallback_) {
    // The old route, for paths without a typed field: the whole scene read again.
    scene_ = scene_with(experiment_.scene_json, parameters_, values, source_);
    ++json_reads_;
    rebuild();
    return;
  }
  bool geometry_changed = !model_current_;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const FieldBinding& b = *bindings_[i];
    double& field = b.field(scene_);
    if (b.kind != FieldKind::geometry) {
      field = values[i];
      continue;
    }
    if (b.positive && !(values[i] > 0.0))
      throw InputError(source_.file, parameters_[i].path, positive().number(values[i]));
    geometry_changed = geometry_changed || field != values[i];
    field = values[i];
  }
  if (!geometry_changed) {
    const ModelParameters p = model_parameters(scene_, model_);
    if (same_structure(model_, p)) {
      set_parameters(model_, p, source_.file);
      return;
    }
  }
  rebuild();
}

SimulationResult FitScene::simulate() { return camdyn::simulate(scene_, model_, ws_, options_); }

FitRun FitScene::run(const std::vector<double>& values) {
  FitRun run;
  const auto name = [&] { return "experiment '" + experiment_.name + "': "; };
  try {
    set(values);
    const SimulationResult result = simulate();
    throw_if_failed(result);
    if (result.samples.time.size() != experiment_.record.time.size()) {
      run.error =
          name() + "the simulation ended at " + format_shortest(result.end_time) + " s, before the last measured time";
    } else {
      const std::vector<const std::vector<double>*> columns = result.samples.columns();
      for (const std::size_t k : columns_) run.signals.push_back(*columns[k]);
      run.ok = true;
    }
  } catch (const InputError& e) {
    run.error = name() + e.what();
    run.input_error = std::current_exception();
  } catch (const std::exception& e) {
    run.error = name() + e.what();
  }
  if (!run.ok) run.error += " (at " + values_text(parameters_, values) + ")";
  return run;
}

}  // namespace camdyn::optim
