#include "dynamics/cam_geometry.h"

#include <atomic>
#include <cmath>
#include <numbers>
#include <vector>

#include "common/constants.h"
#include "common/errors.h"
#include "dynamics/unit_slip.h"
#include "geometry/check_text.h"
#include "scene/follower_shape.h"

namespace camdyn {

namespace {

std::atomic<long> geometry_builds{0};

/// Fits the contour, checks that the follower can follow it, and derives the
/// kinematic law: the rigid follower's lift interpolated by a periodic quintic
/// spline through kLawKnots cam angles (its error is measured between them).
void build_contour_cam(const ContourConfig& config, const FollowerConfig& f, int direction, const std::string& file,
                       CamGeometry& model) {
  const std::string path = "mechanism.cam.motion_law.contour";
  std::vector<Eigen::Vector2d> points;
  points.reserve(config.points.size());
  for (const std::vector<double>& p : config.points) points.emplace_back(p[0], p[1]);
  ContourFitOptions options;
  options.degree = config.degree;
  options.control_points = config.control_points;
  options.smoothing = config.smoothing;
  options.parameter_corrections = config.parameter_corrections;
  model.contour = std::make_shared<const ContourCam>(ContourCam::fit(points, options, file, path));
  const FollowerContact kind = follower_shape_traits(f.shape.type).contact;
  check_contour_for_follower(*model.contour, kind, f.shape.radius, file, path);
  model.contour_lift =
      std::make_shared<const RigidFollowerLift>(*model.contour, kind, f.shape.radius, f.offset, direction, 2048, file);

  constexpr int kLawKnots = 720;
  PeriodicSplineConfig spline;
  spline.degree = 5;
  for (int i = 0; i < kLawKnots; ++i) {
    spline.knots_deg.push_back(360.0 * i / kLawKnots);
    spline.lift.push_back(model.contour_lift->displacement(kTwoPi * i / kLawKnots));
  }
  MotionLawConfig law;
  law.spline = std::move(spline);
  model.law = std::make_shared<const MotionLaw>(build_motion_law(law, file, path));
  double error = 0.0;
  for (int i = 0; i < kLawKnots; ++i) {
    const double theta = kTwoPi * (i + 0.5) / kLawKnots;
    error = std::max(error, std::abs(model.law->eval(theta).s - model.contour_lift->displacement(theta)));
  }
  model.law_interpolation_error = error;
}

/// The general pair form: the cam's contour (a roller cam's from its pitch
/// curve) and the follower's circle or face segment in its body frame.
void build_general_pair(CamGeometry& model) {
  const FollowerGeometry& fg = model.follower;
  model.pair_form = PairForm::general;
  model.pair_cam_base = std::make_shared<const ClosedCurveProfile>(model.profile());
  model.pair_cam = model.profile_offset == 0.0 && fg.circle()
                       ? std::make_shared<const InwardOffsetProfile>(*model.pair_cam_base, fg.radius)
                       : model.pair_cam_base;
  const Eigen::Vector2d centre = fg.oscillating() ? Eigen::Vector2d(fg.arm_length, 0.0) : Eigen::Vector2d::Zero();
  if (fg.circle()) {
    model.pair_follower = std::make_shared<const CircleProfile>(fg.radius, centre);
  } else {
    // The face line's normal towards the cam, in the body frame (follower_geometry.h face()).
    const Eigen::Vector2d normal = fg.oscillating() ? Eigen::Vector2d(0.0, fg.face_side) : Eigen::Vector2d(0.0, -1.0);
    model.pair_follower = std::make_shared<const SegmentProfile>(centre, normal, 0.5 * fg.face_width);
  }
}

/// Throws InputError naming `mechanism.cam.limits.<key>` when the cam breaks a limit.
void check_cam_limits(const CamLimitsConfig& limits, const CamGeometryReport& g, const MotionLaw& law,
                      const std::string& file) {
  const std::string at = "mechanism.cam.limits.";
  if (limits.max_pressure_angle_deg && g.max_pressure_angle_deg > *limits.max_pressure_angle_deg)
    throw InputError(file, at + "max_pressure_angle_deg",
                     "the cam's pressure angle reaches " + check_text::num(g.max_pressure_angle_deg) +
                         " deg at cam angle " + check_text::num(g.max_pressure_angle_at_deg) +
                         " deg, above the limit " + check_text::num(*limits.max_pressure_angle_deg) + " deg");
  if (limits.min_radius_of_curvature && g.min_radius_of_curvature < *limits.min_radius_of_curvature)
    throw InputError(file, at + "min_radius_of_curvature",
                     "the cam contour's radius of curvature falls to " + check_text::num(g.min_radius_of_curvature) +
                         " m at cam angle " + check_text::num(g.min_radius_of_curvature_at_deg) +
                         " deg, below the limit " + check_text::num(*limits.min_radius_of_curvature) + " m");
  if (limits.max_peak_jerk) {
    const double jerk = law_peaks(law).jerk;
    if (jerk > *limits.max_peak_jerk)
      throw InputError(file, at + "max_peak_jerk",
                       "the law's peak jerk |d³s/dθ³| is " + check_text::num(jerk) + ", above the limit " +
                           check_text::num(*limits.max_peak_jerk));
  }
}

/// The base radius of a contour cam: of the circle the follower touches at
/// its lowest position [m]. Refuses a circle too large for it, as the loader
/// does for a law's cam (io/config.cc), known here once the contour is fitted.
double contour_base_radius(const CamGeometry& g, const FollowerConfig& f, const std::string& file) {
  const double lowest = g.contour_lift->lowest();
  const FollowerShapeTraits shape = follower_shape_traits(f.shape.type);
  const double base_radius = shape.circle() ? std::hypot(lowest, f.offset) - f.shape.radius : lowest;
  if (shape.circle() && f.shape.radius > kMaxCircleToBaseRadius * base_radius)
    throw InputError(file, "mechanism.follower.shape.radius",
                     "a " + std::string(shape.label) + " radius of " + check_text::num(f.shape.radius) +
                         " m on a contour whose base circle is " + check_text::num(base_radius) + " m (more than " +
                         check_text::num(kMaxCircleToBaseRadius) +
                         " times it) is flat to within the contact's penetration, and the contact point is lost "
                         "in rounding so the run never finishes: give the radius in metres, or use a 'flat' face");
  return base_radius;
}

CamGeometry assemble_geometry(const SceneConfig& scene, const std::string& file) {
  const MechanismConfig& mech = scene.mechanism;
  const FollowerConfig& f = mech.follower;
  CamGeometry g;
  g.direction = mech.cam.direction == RotationDirection::cw ? -1 : +1;
  double base_radius = mech.cam.base_radius;
  if (mech.cam.motion_law.contour) {
    build_contour_cam(*mech.cam.motion_law.contour, f, g.direction, file, g);
    base_radius = contour_base_radius(g, f, file);
  } else {
    g.law = std::make_shared<const MotionLaw>(build_motion_law(mech.cam.motion_law, file));
  }
  g.follower = make_follower_geometry(f, base_radius, file);
  const FollowerGeometry& fg = g.follower;
  g.cam = std::make_shared<const SynthesisedCam>(g.law, fg, g.direction);
  g.reduction = fg.circle() ? ContactReduction::circle : ContactReduction::line;
  if (g.contour) {
    // The contact works on the contour itself: a circle's centre at distance ρ from it.
    g.profile_curve = g.contour;
    g.profile_offset = fg.circle() ? fg.radius : 0.0;
  } else {
    g.profile_curve = g.cam;
    g.profile_offset = 0.0;  // the synthesised centre curve already carries the circle's radius
  }
  // For a contour cam this checks the cam the interpolated law synthesises, a
  // copy of the contour within law_interpolation_error: pressure angle, and the
  // contact's travel across a flat face against its width.
  g.geometry = check_cam(*g.cam, file);
  check_cam_limits(mech.cam.limits, g.geometry, *g.law, file);
  if (mech.contact.pair_form == PairFormChoice::general) build_general_pair(g);
  return g;
}

}  // namespace

std::shared_ptr<const CamGeometry> build_cam_geometry(const SceneConfig& scene, const std::string& file) {
  ++geometry_builds;
  try {
    return std::make_shared<const CamGeometry>(assemble_geometry(scene, file));
  } catch (const InputError& e) {
    // A cam that cannot be made from a length in millimetres: name the slip.
    rethrow_naming_unit_slip(scene, file, e);
  }
}

long cam_geometry_builds() { return geometry_builds.load(); }

CamGeometryKey::CamGeometryKey(const SceneConfig& scene)
    : motion_law(scene.mechanism.cam.motion_law),
      base_radius(scene.mechanism.cam.base_radius),
      direction(scene.mechanism.cam.direction),
      limits(scene.mechanism.cam.limits),
      motion(scene.mechanism.follower.motion),
      offset(scene.mechanism.follower.offset),
      pivot(scene.mechanism.follower.pivot),
      arm_length(scene.mechanism.follower.arm_length),
      shape(scene.mechanism.follower.shape),
      pair_form(scene.mechanism.contact.pair_form) {
  motion_law.source.clear();  // which file the law came from does not change it
  shape.inertia = 0.0;        // the roller's inertia is the model's (its spin), not the geometry's
}

std::shared_ptr<const CamGeometry> CamGeometryCache::get(const SceneConfig& scene, const std::string& file) {
  CamGeometryKey key(scene);
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [k, geometry] : entries_)
      if (k == key) return geometry;
  }
  std::shared_ptr<const CamGeometry> built = build_cam_geometry(scene, file);
  const std::lock_guard<std::mutex> lock(mutex_);
  if (entries_.size() == kCapacity) entries_.erase(entries_.begin());
  entries_.emplace_back(std::move(key), built);
  return built;
}

}  // namespace camdyn
