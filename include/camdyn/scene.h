// A scene: a cam-follower mechanism and how to run it, loaded from a config
// (docs/config.md) and checked completely: the config's fields,
// the motion law, the cam geometry (undercut, pressure angle) and the contact
// law, as `camdyn validate` checks them. Part of the public API.
//
//     const camdyn::Scene scene = camdyn::Scene::load("studies/quickstart.json", {"cam.rpm=1200"});
//     const camdyn::Result result = camdyn::simulate(scene);
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace camdyn {

struct Result;
struct SimulateOptions;

/// The most points one call computes: Scene::profile's points, Scene::law's
/// angles, SimulateOptions::sample_times (the cap of `camdyn export --points`).
inline constexpr int kMaxPointsPerCall = 1'000'000;

/// What the scene's model is made of (summary.json `model`).
struct ModelInfo {
  std::vector<std::string> states;    ///< the state vector's entries, in order ("follower_position", ...)
  std::vector<std::string> elements;  ///< the force elements assembled ("spring", "contact:lankarani_nikravesh", ...)
  std::string cam;                    ///< the drive: "constant_speed", "stationary", "shaft:..._motor"
  std::string follower;               ///< "translating_roller", "oscillating_flat", ...
  std::string contact_pair;           ///< how the contact is tracked, in words
};

/// The cam's outline in the cam frame (the world frame at cam angle 0).
struct CamProfile {
  /// Profile parameter of each point [rad]: the cam angle at which the point
  /// is the contact (a cam made from its law), or the fitted contour's parameter.
  std::vector<double> u;
  std::vector<double> contour_x, contour_y;  ///< the cam contour [m]
  std::vector<double> pitch_x, pitch_y;      ///< the roller's (mushroom's) centre path [m]; empty for a flat face
};

/// The motion law s(θ) and its first three derivatives with respect to the
/// cam angle θ: s [m], ds [m/rad], d2s [m/rad²], d3s [m/rad³] for a
/// translating follower; the arm angle in rad instead of m for an oscillating one.
struct LawValues {
  std::vector<double> s, ds, d2s, d3s;
};

/// A checked scene. Copies share it; several threads may simulate one scene
/// at once. set() changes one scene (not its copies) in place.
class Scene {
 public:
  /// Reads a config file as `camdyn run FILE --set KEY=VALUE ...` does:
  /// `extends` resolved, then each override "dotted.path=VALUE" applied
  /// (VALUE parsed as JSON, else taken as a string; a leading "cam.",
  /// "follower." or "contact." means "mechanism.…"). Relative file names in
  /// it (a profile, a table's CSV) resolve against the file's directory.
  /// Throws InputError naming the file, the dotted path and the reason.
  static Scene load(const std::string& file, const std::vector<std::string>& overrides = {});

  /// A scene from the text of a JSON config (no `extends`). Relative file
  /// names in it resolve against `base_dir` (empty: the current directory).
  /// Throws InputError; its file() is empty, its path() the dotted path.
  static Scene from_json(const std::string& json_text, const std::string& base_dir = {},
                         const std::vector<std::string>& overrides = {});

  /// Sets one field by its dotted path, as `--set PATH=VALUE` does
  /// ("cam.rpm", "mechanism.contact.stiffness", "follower.mass"), checked by
  /// the config loader's own rules (InputError naming the path and the
  /// reason; the scene is then unchanged). The model is changed without
  /// reading the config file again (a lift table's CSV is read again): a change that leaves the
  /// cam's geometry as it is (the speed, masses, springs, contact law, run
  /// settings) keeps the geometry, and the scene then runs to the bit as one
  /// loaded with that override. Copies made before keep the old values.
  void set(const std::string& path, double value);
  /// The same with VALUE as `--set` takes it: JSON text, else a word ("hertz").
  void set(const std::string& path, const std::string& value);

  /// The config's `name`.
  const std::string& name() const;
  /// The cam speed the scene runs at [rpm].
  double rpm() const;
  /// The fully resolved config (every field, defaults filled in) as JSON
  /// text, as `camdyn validate` prints it; Scene::from_json reads it back.
  std::string resolved_json() const;
  /// The rigid-model jump speed [rpm]: the lowest cam speed at which the
  /// follower leaves a rigid cam (docs/model.md §9); +inf if the law never decelerates.
  double jump_speed_rpm() const;
  /// The states and force elements of the model (summary.json `model`).
  ModelInfo model() const;
  /// The cam's contour and pitch curve at `points` (3 … kMaxPointsPerCall)
  /// parameters over one turn, u = 2πk / points; throws InputError (path
  /// "points") for other counts.
  CamProfile profile(int points = 360) const;
  /// The motion law at the given cam angles [deg] (any finite angle: the law
  /// is periodic); throws InputError (path "angles_deg") for an angle that is
  /// not finite or more than kMaxPointsPerCall angles.
  LawValues law(const std::vector<double>& angles_deg) const;

 private:
  struct Impl;
  explicit Scene(std::shared_ptr<const Impl> impl);
  std::shared_ptr<const Impl> impl_;

  friend Result simulate(const Scene& scene, const SimulateOptions& options);
};

}  // namespace camdyn
