// One experiment of an identification, ready to be simulated at any values of
// the fitted parameters: its typed scene, the model built from it once and a
// workspace, owned by one worker at a time. Each fitted dotted path is bound
// once, at construction, to a typed field of the scene:
//   parameter  any field the model is assembled from but its geometry (the
//              mass, springs, contact law, friction, drive, cam speed, a
//              follower train's numbers): set in place with
//              set_scene_parameters (dynamics/model.h), the model is not
//              rebuilt (unless the value changes the model's structure:
//              then it is built on the same geometry);
//   scene      read by simulate() from the scene only (the initial velocity);
//   geometry   a field the cam's geometry is built from (its CamGeometryKey:
//              base radius, roller radius, offset, ...): set in the typed
//              scene, the geometry and the model are built again.
// Every value is checked first with the loader's checks of its field. No
// JSON is read for these. A path with no typed field (an element of an
// array, a motion-law constant, a field of a block the scene does not give,
// ...) falls back to the old route, counted in json_reads(): the resolved
// scene's JSON with the values set, read again.
#pragma once

#include <cstddef>
#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "io/typed_archive.h"
#include "optim/identify/identify.h"

namespace camdyn::optim {

enum class FieldKind { parameter, scene, geometry };

/// A fitted dotted path bound to the typed scene field it names.
struct FieldBinding {
  FieldKind kind = FieldKind::parameter;
  double* field = nullptr;  ///< in the scene it was bound in
  SceneField checked;       ///< the loader's checks of its value (io/typed_archive.h)
};

/// The typed field `path` (full dotted path) names in `scene`, found through
/// the config loader's visit (io/typed_archive.h), or nothing when it has
/// none (an array element, a field of an absent optional block, one the
/// scene's choices leave out).
std::optional<FieldBinding> bind_field(const std::string& path, SceneConfig& scene);

/// The simulated signals of one experiment at one parameter vector.
struct FitRun {
  bool ok = false;
  std::string error;                         ///< why the simulation failed
  std::exception_ptr input_error;            ///< an InputError (a parameter value the scene rejects)
  std::vector<std::vector<double>> signals;  ///< [s][i]: record signal s at record time i
};

class FitScene {
 public:
  /// `experiment.scene` at the initial values; `parameters` name the fitted
  /// paths. `from_json`: take the old route for every path (the reference
  /// the in-place route is tested and measured against).
  FitScene(const FitExperiment& experiment, const std::vector<FitParameter>& parameters, const ConfigSource& source,
           bool from_json = false);

  /// Sets the parameter values (one per parameter). Throws InputError for a
  /// value the scene rejects; the scene stays usable for the next values.
  void set(const std::vector<double>& values);

  /// Simulates at the values last set, sampled at the record's times.
  SimulationResult simulate();

  /// set() and simulate(), failures caught and described (with the values).
  FitRun run(const std::vector<double>& values);

  const SceneConfig& scene() const { return *scene_; }
  const Model& model() const { return model_; }
  long model_builds() const { return model_builds_; }  ///< models built after construction
  long json_reads() const { return json_reads_; }      ///< scenes read from JSON after construction

 private:
  void rebuild(bool geometry_changed);

  const FitExperiment& experiment_;
  const std::vector<FitParameter>& parameters_;
  ConfigSource source_;
  std::vector<std::optional<FieldBinding>> bindings_;  ///< per parameter
  bool json_fallback_ = false;                   ///< the old route: some parameter has no typed field (or from_json)
  std::unique_ptr<SceneConfig> scene_;           ///< on the heap: the bindings point into it, and a FitScene may move
  std::shared_ptr<const CamGeometry> geometry_;  ///< of scene_'s cam, shared by every model built for it
  Model model_;
  bool model_current_ = true;  ///< model_ is built from scene_ (false after a failed rebuild)
  Workspace ws_;
  SimulationOptions options_;
  std::vector<std::size_t> columns_;  ///< timeseries column of each record signal
  long model_builds_ = 0, json_reads_ = 0;
};

}  // namespace camdyn::optim
