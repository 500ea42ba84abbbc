#include "optim/identify/fit_scene.h"

#include <algorithm>
#include <iterator>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "common/errors.h"
#include "dynamics/cam_geometry.h"
#include "io/json_archive.h"
#include "io/typed_archive.h"

namespace camdyn::optim {

namespace {

std::string values_text(const std::vector<FitParameter>& parameters, const std::vector<double>& values) {
  std::string at;
  for (std::size_t i = 0; i < values.size(); ++i)
    at += (i ? ", " : "") + parameters[i].name + " = " + format_shortest(values[i]);
  return at;
}

}  // namespace

std::optional<FieldBinding> bind_field(const std::string& path, SceneConfig& scene) {
  std::optional<SceneField> field = try_find_scene_field(scene, path);
  if (!field) return std::nullopt;
  FieldBinding b;
  b.field = field->value;
  if (path == "mechanism.follower.initial.velocity") {
    b.kind = FieldKind::scene;
  } else {
    // A field the cam's geometry is built from (its CamGeometryKey changes
    // with it) builds the geometry again; any other is set in place.
    const double kept = *b.field;
    const CamGeometryKey before(scene);
    *b.field = kept == 0.0 ? 1.0 : 2.0 * kept;
    b.kind = CamGeometryKey(scene) == before ? FieldKind::parameter : FieldKind::geometry;
    *b.field = kept;
  }
  b.checked = std::move(*field);
  return b;
}

FitScene::FitScene(const FitExperiment& experiment, const std::vector<FitParameter>& parameters,
                   const ConfigSource& source, bool from_json)
    : experiment_(experiment),
      parameters_(parameters),
      source_(source),
      json_fallback_(from_json),
      scene_(std::make_unique<SceneConfig>(experiment.scene)) {
  for (const FitParameter& p : parameters) {
    bindings_.push_back(bind_field(p.path, *scene_));
    json_fallback_ = json_fallback_ || !bindings_.back();
  }
  geometry_ = build_cam_geometry(*scene_, source_.file);
  model_ = build_model(*geometry_, *scene_, source_.file);
  ws_ = make_workspace(model_);
  options_.record_series = false;
  options_.sample_times = experiment.record.time;
  // The residuals read only the samples; the energy residual is the one
  // sampled column that needs the balance followed over every step, and the
  // only one that needs the quadratures.
  const std::vector<std::string>& signals = experiment.record.signals;
  options_.step_metrics = std::find(signals.begin(), signals.end(), "energy_residual") != signals.end();
  options_.quadratures = options_.step_metrics;
  const std::vector<std::string> names = series_column_names(model_);
  for (const std::string& signal : experiment.record.signals) {
    const auto it = std::find(names.begin(), names.end(), signal);
    if (it == names.end())
      throw InputError(source_.file, "reference.signals." + signal,
                       "'" + signal +
                           "' is not a column of this scene's time series (its train has no such body "
                           "or element)");
    columns_.push_back(static_cast<std::size_t>(it - names.begin()));
  }
}

void FitScene::rebuild(bool geometry_changed) {
  model_current_ = false;
  if (geometry_changed) geometry_ = build_cam_geometry(*scene_, source_.file);
  model_ = build_model(*geometry_, *scene_, source_.file);
  ++model_builds_;
  model_current_ = true;
}

void FitScene::set(const std::vector<double>& values) {
  if (json_fallback_) {
    // The old route, for paths without a typed field: the whole scene read again.
    *scene_ = scene_with(experiment_.scene_json, parameters_, values, source_);
    ++json_reads_;
    rebuild(true);
    return;
  }
  bool geometry_changed = !model_current_;
  // Every value checked first (the loader's reason for one no config may
  // give), so that a refused vector leaves the scene as the model has it.
  for (std::size_t i = 0; i < values.size(); ++i) {
    const FieldBinding& b = *bindings_[i];
    if (std::string reason = b.checked.reason(values[i]); !reason.empty())
      throw InputError(source_.file, parameters_[i].path, std::move(reason));
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    const FieldBinding& b = *bindings_[i];
    double& field = *b.field;
    if (b.kind != FieldKind::geometry) {
      field = values[i];
      continue;
    }
    geometry_changed = geometry_changed || field != values[i];
    field = values[i];
  }
  // In place, a follower train's elements too; built again where the structure changes.
  if (!geometry_changed && set_scene_parameters(model_, *scene_, source_.file)) return;
  rebuild(geometry_changed);
}

SimulationResult FitScene::simulate() { return camdyn::simulate(*scene_, model_, ws_, options_); }

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
      const std::vector<const std::vector<double>*> columns = result.samples.all_columns();
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
