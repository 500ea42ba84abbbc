// The cam for manufacturing (docs/export.md): the cam contour, the pitch
// curve (a roller's or mushroom's centre path; a flat face has none) and,
// on request, the centre path of a cutter or grinding wheel, sampled in cam
// angle and written as CSV (profile.csv) and as DXF (profile.dxf, through
// dxflib), each atomically.
//
// Frame: the cam frame at cam angle 0 (docs/model.md §1): the cam's centre at the
// origin, +y along the follower axis away from the cam, +x to the right. The
// point listed at cam angle θ is the one that touches the follower when the
// cam has turned by θ from angle 0, where the start of the motion law is under
// the follower; with `direction` ccw the cam turns counterclockwise in this
// frame. The files are in millimetres (and degrees); in memory everything is
// in metres and radians.
//
// Sampling: either N equal cam-angle steps, or adaptive: 360 equal steps, each
// halved until every curve written deviates from its chords by less than the
// chord tolerance (the sagitta, measured at 1/4, 1/2 and 3/4 of each step
// against 0.9 times the tolerance so that the true maximum stays below it).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "dynamics/model.h"
#include "scene/scene.h"

namespace camdyn {

/// How to sample the profile, in metres.
struct ProfileOptions {
  std::optional<int> points;            ///< N equal cam-angle steps; unset = by chord tolerance
  double chord_tolerance = 1e-6;        ///< largest sagitta between consecutive points [m], > 0
  std::optional<double> cutter_radius;  ///< R_t > 0 [m]: also compute the tool-centre path
};

/// The option names errors point at: the config file and dotted path, or the
/// command-line option ("" file, "--cutter-radius").
struct ProfileOptionNames {
  std::string file;
  std::string cutter_radius = "outputs.profile.cutter_radius_mm";
  std::string points = "outputs.profile.points";
  std::string chord_tolerance = "outputs.profile.chord_tolerance_mm";
};

/// ProfileOptions from a config's `outputs.profile` (millimetres to metres).
ProfileOptions profile_options(const ProfileOutputConfig& config);

/// One sample of the cam, cam frame at angle 0.
struct ProfilePoint {
  double theta = 0.0;                                 ///< cam angle [rad], in [0, 2π)
  double lift = 0.0;                                  ///< follower lift at θ [m] (oscillating: arm angle [rad])
  Eigen::Vector2d contour = Eigen::Vector2d::Zero();  ///< contact point on the cam contour [m]
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();   ///< outward unit normal of the contour there
  Eigen::Vector2d pitch = Eigen::Vector2d::Zero();    ///< circle follower's centre [m] (flat face: = contour)
  Eigen::Vector2d cutter = Eigen::Vector2d::Zero();   ///< tool centre, contour + R_t normal [m] (none: = contour)
  double radius_of_curvature = 0.0;                   ///< of the contour [m]: > 0 convex, < 0 concave, ±inf straight
};

/// The sampled cam and what the files' headers say about it. Not the public
/// API's camdyn::CamProfile (include/camdyn/scene.h): two classes of one name
/// in one program break the one-definition rule, and the linker then gave one
/// class's destructor to the other's objects (docs/architecture.md, "Build time").
struct SampledCamProfile {
  std::vector<ProfilePoint> points;  ///< by increasing cam angle, the first at θ = 0; closed (no repeat)
  bool has_pitch = false;            ///< a circle follower (roller, mushroom)
  bool oscillating = false;          ///< the lift is an arm angle
  int direction = 1;                 ///< σ: +1 ccw, −1 cw
  std::string follower;              ///< "translating roller", ...
  double base_radius = 0.0;          ///< r_b [m]
  double follower_radius = 0.0;      ///< roller / mushroom radius [m] (0 for a flat face)
  double offset = 0.0;               ///< translating: follower axis x = e [m]
  bool contour_cam = false;          ///< the cam was given as contour points (fitted spline)
  std::optional<int> requested_points;
  double chord_tolerance = 0.0;         ///< [m], when sampled by tolerance
  std::optional<double> cutter_radius;  ///< R_t [m]
  double max_chord_error = 0.0;         ///< largest sagitta found between consecutive points, all curves [m]
  double min_concave_radius = 0.0;      ///< smallest |ρ| where the contour is concave [m]; inf if convex
  double min_concave_radius_at = 0.0;   ///< cam angle where [rad]
  double max_radius = 0.0;              ///< largest distance of any written point from the centre [m]
  double lift = 0.0;                    ///< the law's total lift [m] (oscillating: [rad])
};

/// Samples the cam of `model`. Throws InputError(names.file, names.cutter_radius)
/// when the tool radius is not below the smallest concave radius of curvature
/// of the contour (the tool could not reach into the hollow), and
/// InputError(names.file, names.points / names.chord_tolerance) for options
/// out of range.
SampledCamProfile sample_cam_profile(const Model& model, const ProfileOptions& options,
                                     const ProfileOptionNames& names);

/// The header lines both files carry (units, frame, direction, angle origin,
/// follower, sampling), without comment markers.
std::vector<std::string> profile_header_lines(const SampledCamProfile& profile, const std::string& name);

/// profile.csv: the header lines as "# " comments, then the columns
/// cam_angle_deg, lift_mm (oscillating: lift_deg), contour_x_mm, contour_y_mm,
/// [pitch_x_mm, pitch_y_mm], [cutter_x_mm, cutter_y_mm].
void write_profile_csv(const std::filesystem::path& path, const SampledCamProfile& profile, const std::string& name);

/// profile.dxf (AutoCAD 2000, AC1015; $INSUNITS = 4, millimetres): the
/// contour, pitch curve and cutter path as closed LWPOLYLINEs on layers
/// CAM_CONTOUR, PITCH_CURVE and CUTTER_PATH, a point and a cross at the cam's
/// centre (CAM_CENTRE), the base circle (BASE_CIRCLE), the timing mark at cam
/// angle 0 (TIMING_MARK: a line from the centre through the contour point
/// that touches the follower at cam angle 0, and its label), the design data
/// (design_data_lines) as TEXT on layer DESIGN_DATA, and the header lines as
/// 999 comments and as TEXT on layer NOTES below the cam.
void write_profile_dxf(const std::filesystem::path& path, const SampledCamProfile& profile, const std::string& name);

/// The design data block of the drawing: base circle radius, lift, follower, rotation.
std::vector<std::string> design_data_lines(const SampledCamProfile& profile);

/// The lift a different follower would read on the cam as made (a grinder's
/// or a checking fixture's): a roller of radius R on the same axis (offset)
/// as the design's follower, on the cam contour, at equal cam-angle steps.
struct FollowerLiftTable {
  double follower_radius = 0.0;  ///< R [m]
  double offset = 0.0;           ///< e [m], the design's
  double base_radius = 0.0;      ///< r_b [m]: lift 0 is the roller on the base circle
  int direction = 1;             ///< σ: +1 ccw, −1 cw
  std::string design_follower;   ///< "translating roller", ...
  std::vector<double> theta;     ///< cam angle [rad], from 0 in steps of the increment
  std::vector<double> lift;      ///< the roller centre's height above its base-circle height [m]
};

/// The lift table of a roller of radius `radius` [m] > 0 at cam-angle steps of
/// `angle_step` [rad] in (0, 2π]. Throws InputError(names.file, radius_path)
/// for an oscillating follower (not supported), a radius ≤ 0 or a roller whose
/// axis misses the cam, and InputError(names.file, step_path) for a bad step.
FollowerLiftTable follower_lift_table(const Model& model, double radius, double angle_step, const std::string& file,
                                      const std::string& radius_path = "--follower-radius",
                                      const std::string& step_path = "--angle-step-deg");

/// follower_lift.csv: "# " header lines naming the datum (cam angle 0, lift 0,
/// rotation, the follower), then the columns cam_angle_deg, lift_mm.
void write_follower_lift_csv(const std::filesystem::path& path, const FollowerLiftTable& table,
                             const std::string& name);

/// The files `formats` asks for, into `dir`: profile.csv and/or profile.dxf.
/// Returns the paths written.
std::vector<std::filesystem::path> write_profile_files(const std::filesystem::path& dir,
                                                       const SampledCamProfile& profile, const std::string& name,
                                                       const std::vector<ProfileFormat>& formats);

/// What simulate and optimize write when the scene's `outputs.profile` is set
/// (nothing otherwise); `file` is the config, for errors.
std::vector<std::filesystem::path> write_profile_outputs(const std::filesystem::path& dir, const SceneConfig& scene,
                                                         const Model& model, const std::string& file);

}  // namespace camdyn
