// The geometry of one design, built once and shared: the motion law, the cam
// synthesised from it for the follower (or fitted from a contour), the
// follower's geometry, the profiles the contact is tracked on and the cam's
// manufacturability figures (docs/model.md §1 and §2). Nothing here depends
// on the cam speed or on the mechanism's masses, springs and contact law, so
// a speed sweep (jump map, speed limit, compare over rpm, an optimiser's
// operating speeds) builds it once and assembles a Model per speed from it
// (dynamics/model.h), or sets the speed in place (set_cam_speed). The heavy
// parts are immutable and held by shared_ptr: copying a CamGeometry (and so
// a Model) copies pointers, never a curve.
#pragma once

#include <cstddef>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "contact/profile_pair_tracking.h"
#include "geometry/cam_roller.h"
#include "geometry/cam_synthesis.h"
#include "geometry/contour_cam.h"
#include "geometry/follower_geometry.h"
#include "geometry/motion_law.h"
#include "geometry/planar_curve.h"
#include "scene/scene.h"

namespace camdyn {

enum class ContactReduction { circle, line };
/// The pair form a model uses (PairFormChoice::automatic resolves to `reduced`).
enum class PairForm { reduced, general };

struct CamGeometry {
  std::shared_ptr<const MotionLaw> law;
  FollowerGeometry follower;
  /// The cam synthesised from the law for this follower (centre curve or contour, checks, rigid kinematics).
  std::shared_ptr<const SynthesisedCam> cam;
  /// The cam-frame profile the contact is tracked against: `cam` for a cam
  /// synthesised from the law; any PeriodicCurve (e.g. a fitted contour, with
  /// profile_offset = the circle's radius) plugs in here unchanged.
  std::shared_ptr<const PeriodicCurve> profile_curve;
  const PeriodicCurve& profile() const { return *profile_curve; }
  ContactReduction reduction = ContactReduction::circle;
  double profile_offset = 0.0;  ///< ρ of the circle reduction: 0 against a centre curve [m]
  /// A cam given as a contour (`motion_law.contour`): the fitted curve, the
  /// rigid follower's lift on it (from which `law` is interpolated) and how
  /// closely the law reproduces that lift. Null for a cam synthesised from a law.
  std::shared_ptr<const ContourCam> contour;
  std::shared_ptr<const RigidFollowerLift> contour_lift;
  double law_interpolation_error = 0.0;  ///< max |s_law − s_lift| between the interpolation knots [m]

  /// General pair form: the cam contour and the follower's face as pair
  /// profiles (cam frame; follower body frame, see follower_motion()).
  PairForm pair_form = PairForm::reduced;
  std::shared_ptr<const PairProfile> pair_cam_base;  ///< the profile pair_cam may be an offset of
  std::shared_ptr<const PairProfile> pair_cam;
  std::shared_ptr<const PairProfile> pair_follower;
  CamGeometryReport geometry;  ///< pressure angle and curvature, checked when the geometry is built
  int direction = +1;          ///< σ: the cam frame is at angle σθ in the world

  /// The cam-profile parameter at which the follower touches the cam at cam
  /// angle θ on the rigid law: θ itself for a synthesised cam (u is the contact's
  /// cam angle), the contour parameter from the rigid lift for a contour cam.
  double pair_guess(double theta) const { return contour_lift ? contour_lift->at(theta).u : theta; }
};

/// Builds the geometry of a scene's design: its motion law, cam, follower
/// geometry, tracked profiles, and the checks of `mechanism.cam.limits` that
/// do not depend on the speed (pressure angle, curvature, jerk). Throws
/// InputError (naming `file` and the field) for a cam that cannot be made.
/// Every call is counted (cam_geometry_builds()).
std::shared_ptr<const CamGeometry> build_cam_geometry(const SceneConfig& scene, const std::string& file);

/// How many geometries build_cam_geometry() has built in this process, for
/// tests that a speed sweep or an optimiser evaluation builds its geometry once.
long cam_geometry_builds();

/// The fields of a scene its geometry is built from: scenes with equal keys
/// have the same geometry (the cam speed, masses, springs, contact law and
/// run settings are not in it).
struct CamGeometryKey {
  MotionLawConfig motion_law;
  double base_radius = 0.0;
  RotationDirection direction = RotationDirection::ccw;
  CamLimitsConfig limits;
  FollowerMotion motion = FollowerMotion::translating;
  double offset = 0.0;
  std::vector<double> pivot;
  double arm_length = 0.0;
  ShapeConfig shape;  ///< its inertia left out (0): the roller's spin is the model's
  PairFormChoice pair_form = PairFormChoice::automatic;

  explicit CamGeometryKey(const SceneConfig& scene);
  bool operator==(const CamGeometryKey&) const = default;
};

/// The geometries of the last few designs a study ran, by key, so that runs
/// that differ only in speed or in the mechanism's numbers (a compare grid)
/// build each geometry once. Safe to share between threads.
class CamGeometryCache {
 public:
  /// The geometry of `scene`, built (outside the lock) when no scene with the same key was seen.
  std::shared_ptr<const CamGeometry> get(const SceneConfig& scene, const std::string& file);

 private:
  static constexpr std::size_t kCapacity = 16;  ///< designs kept, the oldest dropped first
  std::mutex mutex_;
  std::vector<std::pair<CamGeometryKey, std::shared_ptr<const CamGeometry>>> entries_;
};

}  // namespace camdyn
