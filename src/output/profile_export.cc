#include "output/profile_export.h"

#include <camdyn/version.h>
#include <dxflib/dl_dxf.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <memory>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "common/constants.h"
#include "common/errors.h"
#include "contact/profile_pair_tracking.h"
#include "geometry/contour_cam.h"
#include "geometry/vec2.h"
#include "io/atomic_file.h"
#include "io/csv_writer.h"

namespace camdyn {

namespace {

constexpr int kInitialSteps = 360;              // adaptive sampling starts from 1° steps
constexpr int kMaxHalvings = 30;                // 1° / 2^30: far below any tolerance allowed
constexpr int kConcaveScanSteps = 7200;         // cam-angle grid on which concave radii are searched
constexpr double kToleranceMargin = 0.9;        // sagitta sampled at 3 points must stay below 0.9 × tolerance
constexpr double kMaxToolToCamRadius = 1000.0;  // a tool radius at most 1000 × the cam's largest radius

std::string mm(double metres, int digits = 6) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, metres * kMm);
  return buffer;
}

std::string deg(double radians) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.6g", radians * kRadToDeg);
  return buffer;
}

/// The cam at one cam angle, from whichever description the model has: the
/// synthesised centre curve (circle followers), the synthesised contour (flat
/// face), or the fitted contour of a contour cam with its rigid lift.
class ProfileSource {
 public:
  ProfileSource(const Model& model, std::optional<double> cutter) : model_(model), cutter_(cutter) {}

  ProfilePoint at(double theta) const {
    ProfilePoint p;
    p.theta = theta;
    if (model_.contour) {
      from_contour(theta, p);
    } else if (model_.follower.circle()) {
      from_pitch(theta, p);
    } else {
      from_flat(theta, p);
    }
    p.cutter = cutter_ ? Eigen::Vector2d(p.contour + *cutter_ * p.normal) : p.contour;
    return p;
  }

 private:
  double law_lift(double theta) const { return model_.law->eval(std::fmod(theta, kTwoPi)).s; }

  // Circle follower: the pitch curve P is the synthesised curve; the contour
  // is its inner offset by ρ along the outward normal n = σ J P' / |P'|.
  void from_pitch(double theta, ProfilePoint& p) const {
    const CurvePoint c = model_.cam->at(theta);
    const double sigma = model_.direction;
    const double speed = c.dr.norm();
    p.normal = sigma * perp(c.dr) / speed;
    p.pitch = c.r;
    p.contour = c.r - model_.follower.radius * p.normal;
    const double kappa = -sigma * cross(c.dr, c.d2r) / (speed * speed * speed);  // pitch curvature, convex > 0
    p.radius_of_curvature =
        kappa == 0.0 ? std::numeric_limits<double>::infinity() : 1.0 / kappa - model_.follower.radius;
    p.lift = law_lift(theta);
  }

  // Flat face: the synthesised curve is the contour; the contact normal comes
  // from the rigid kinematics, turned from the world into the cam frame.
  void from_flat(double theta, ProfilePoint& p) const {
    const SynthesisedCam::Kinematics k = model_.cam->kinematics(theta);
    p.contour = model_.cam->at(theta).r;
    p.pitch = p.contour;
    p.normal = rotate(k.normal, -model_.direction * theta);
    p.radius_of_curvature = k.radius_of_curvature;
    p.lift = law_lift(theta);
  }

  // Contour cam: the contact parameter u(θ) of the rigid follower on the fitted contour.
  void from_contour(double theta, ProfilePoint& p) const {
    const RigidLift lift = model_.contour_lift->at(theta);
    const ContourCam& cam = *model_.contour;
    p.contour = cam.at(lift.u).r;
    p.normal = cam.outward_normal(lift.u);
    const double kappa = cam.curvature(lift.u);
    p.radius_of_curvature = kappa == 0.0 ? std::numeric_limits<double>::infinity() : 1.0 / kappa;
    p.pitch = model_.follower.circle() ? Eigen::Vector2d(p.contour + model_.follower.radius * p.normal) : p.contour;
    p.lift = lift.y - model_.contour_lift->lowest();
  }

  const Model& model_;
  std::optional<double> cutter_;
};

/// Distance from q to the segment [a, b] [m].
double segment_distance(const Eigen::Vector2d& q, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((q - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (q - (a + t * ab)).norm();
}

/// Largest distance of the curves at `m` from their chords between `a` and `b` [m].
double deviation(const ProfilePoint& a, const ProfilePoint& b, const ProfilePoint& m) {
  return std::max({segment_distance(m.contour, a.contour, b.contour), segment_distance(m.pitch, a.pitch, b.pitch),
                   segment_distance(m.cutter, a.cutter, b.cutter)});
}

/// The sagitta of every curve between `a` and `b`, sampled at 1/4, 1/2 and 3/4
/// of the cam-angle step; `mid` receives the midpoint sample.
double step_error(const ProfileSource& source, const ProfilePoint& a, const ProfilePoint& b, ProfilePoint& mid) {
  const double h = b.theta - a.theta;
  mid = source.at(a.theta + 0.5 * h);
  return std::max({deviation(a, b, source.at(a.theta + 0.25 * h)), deviation(a, b, mid),
                   deviation(a, b, source.at(a.theta + 0.75 * h))});
}

struct Sampler {
  const ProfileSource& source;
  double limit;                     // accepted sagitta [m]
  std::size_t max_points;           // refuse a tolerance that needs more
  const ProfileOptionNames& names;  // for the error
  std::vector<ProfilePoint>& out;
  double max_error = 0.0;

  /// Appends the points strictly between a and b (a is already in `out`).
  void refine(const ProfilePoint& a, const ProfilePoint& b, int depth) {
    ProfilePoint mid;
    const double error = step_error(source, a, b, mid);
    if (error <= limit || depth >= kMaxHalvings) {
      max_error = std::max(max_error, error);
      return;
    }
    if (out.size() >= max_points)
      throw InputError(
          names.file, names.chord_tolerance,
          "the chord tolerance needs more than " + std::to_string(max_points) + " points: give a larger tolerance");
    refine(a, mid, depth + 1);
    out.push_back(mid);
    refine(mid, b, depth + 1);
  }
};

/// Keeps the smallest |ρ| of the contour where it is concave, and where.
void note_concave(const ProfilePoint& p, SampledCamProfile& profile) {
  if (p.radius_of_curvature < 0.0 && -p.radius_of_curvature < profile.min_concave_radius) {
    profile.min_concave_radius = -p.radius_of_curvature;
    profile.min_concave_radius_at = p.theta;
  }
}

/// A tool must be smaller than the tightest hollow it cuts.
void check_tool(const ProfileOptions& options, const SampledCamProfile& profile, const ProfileOptionNames& names) {
  if (!options.cutter_radius || *options.cutter_radius < profile.min_concave_radius) return;
  throw InputError(names.file, names.cutter_radius,
                   "the tool radius " + mm(*options.cutter_radius) +
                       " mm is not smaller than the smallest concave radius of curvature of the cam contour, " +
                       mm(profile.min_concave_radius) + " mm at cam angle " + deg(profile.min_concave_radius_at) +
                       "°: the tool cannot reach into the hollow (use a tool radius below " +
                       mm(profile.min_concave_radius) + " mm)");
}

void check_options(const ProfileOptions& options, const ProfileOptionNames& names) {
  if (options.points &&
      (*options.points < ProfileOutputConfig::kMinPoints || *options.points > ProfileOutputConfig::kMaxPoints))
    throw InputError(names.file, names.points,
                     "the number of points must be in [" + std::to_string(ProfileOutputConfig::kMinPoints) + ", " +
                         std::to_string(ProfileOutputConfig::kMaxPoints) + "], got " + std::to_string(*options.points));
  if (!options.points && !(options.chord_tolerance >= ProfileOutputConfig::kMinChordToleranceMm / kMm))
    throw InputError(names.file, names.chord_tolerance,
                     "the chord tolerance must be at least " + mm(ProfileOutputConfig::kMinChordToleranceMm / kMm) +
                         " mm, got " + mm(options.chord_tolerance) + " mm");
  if (options.cutter_radius && !(std::isfinite(*options.cutter_radius) && *options.cutter_radius > 0.0))
    throw InputError(names.file, names.cutter_radius,
                     "the tool radius must be a finite number > 0, got " + mm(*options.cutter_radius) + " mm");
}

/// A tool far larger than the cam is a slip (metres for millimetres), and its
/// centre path would overflow the files' number formats.
void check_tool_size(const ProfileOptions& options, double cam_radius, const ProfileOptionNames& names) {
  if (!options.cutter_radius || *options.cutter_radius <= kMaxToolToCamRadius * cam_radius) return;
  throw InputError(names.file, names.cutter_radius,
                   "the tool radius " + mm(*options.cutter_radius) + " mm is more than " +
                       std::to_string(static_cast<int>(kMaxToolToCamRadius)) + " times the cam's largest radius, " +
                       mm(cam_radius) + " mm: give it in mm");
}

SampledCamProfile describe(const Model& model, const ProfileOptions& options) {
  const FollowerGeometry& f = model.follower;
  SampledCamProfile profile;
  profile.has_pitch = f.circle();
  profile.oscillating = f.oscillating();
  profile.direction = model.direction;
  profile.follower = std::string(f.oscillating() ? "oscillating " : "translating ") + std::string(f.traits().label);
  profile.base_radius = f.base_radius;
  profile.follower_radius = f.circle() ? f.radius : 0.0;
  profile.offset = f.offset;
  profile.contour_cam = model.contour != nullptr;
  profile.requested_points = options.points;
  profile.chord_tolerance = options.points ? 0.0 : options.chord_tolerance;
  profile.cutter_radius = options.cutter_radius;
  profile.lift = model.law->lift();
  return profile;
}

}  // namespace

ProfileOptions profile_options(const ProfileOutputConfig& config) {
  ProfileOptions options;
  options.points = config.points;
  options.chord_tolerance = config.chord_tolerance_mm.value_or(ProfileOutputConfig::kDefaultChordToleranceMm) / kMm;
  if (config.cutter_radius_mm) options.cutter_radius = *config.cutter_radius_mm / kMm;
  return options;
}

SampledCamProfile sample_cam_profile(const Model& model, const ProfileOptions& options,
                                     const ProfileOptionNames& names) {
  check_options(options, names);
  SampledCamProfile profile = describe(model, options);
  const ProfileSource source(model, options.cutter_radius);
  // The tool's fit first, on a fine grid: a tool too large makes the offset loop, and the sampling would chase it.
  profile.min_concave_radius = std::numeric_limits<double>::infinity();
  double cam_radius = 0.0;  // the contour's largest distance from the cam's centre [m]
  for (int i = 0; i < kConcaveScanSteps; ++i) {
    const ProfilePoint p = source.at(kTwoPi * i / kConcaveScanSteps);
    note_concave(p, profile);
    cam_radius = std::max(cam_radius, p.contour.norm());
  }
  check_tool_size(options, cam_radius, names);
  check_tool(options, profile, names);

  const int steps = options.points.value_or(kInitialSteps);
  std::vector<ProfilePoint> grid;
  for (int i = 0; i <= steps; ++i) grid.push_back(source.at(kTwoPi * i / steps));
  Sampler sampler{source,
                  options.points ? std::numeric_limits<double>::infinity() : kToleranceMargin * options.chord_tolerance,
                  static_cast<std::size_t>(ProfileOutputConfig::kMaxPoints), names, profile.points};
  for (int i = 0; i < steps; ++i) {
    profile.points.push_back(grid[i]);
    sampler.refine(grid[i], grid[i + 1], 0);
  }
  profile.max_chord_error = sampler.max_error;
  // Again with the samples, which are densest where the curvature is.
  for (const ProfilePoint& p : profile.points) note_concave(p, profile);
  check_tool(options, profile, names);
  for (const ProfilePoint& p : profile.points)
    profile.max_radius = std::max({profile.max_radius, p.contour.norm(), p.pitch.norm(), p.cutter.norm()});
  return profile;
}

std::vector<std::string> profile_header_lines(const SampledCamProfile& profile, const std::string& name) {
  std::vector<std::string> lines;
  lines.push_back("camdyn cam profile of '" + name + "' (camdyn " CAMDYN_VERSION ")");
  lines.push_back(std::string("units: millimetres (x, y") +
                  (profile.oscillating ? "), degrees (cam angle, lift = arm angle)" : ", lift), degrees (cam angle)"));
  lines.push_back(
      "frame: the cam frame at cam angle 0; the cam's centre at (0, 0), +y along the follower axis away from the "
      "cam, +x to the right");
  lines.push_back(std::string("rotation: the cam turns ") +
                  (profile.direction > 0 ? "counterclockwise (ccw)" : "clockwise (cw)") +
                  " in this frame, seen from +z (x right, y up)");
  lines.push_back(
      "angle origin: cam angle 0 puts the start of the motion law under the follower; the point listed at cam "
      "angle t touches the follower when the cam has turned by t from there");
  std::string follower = "follower: " + profile.follower;
  if (profile.has_pitch) follower += ", radius " + mm(profile.follower_radius) + " mm";
  if (!profile.oscillating) follower += ", offset " + mm(profile.offset) + " mm";
  lines.push_back(follower + "; base circle radius " + mm(profile.base_radius) + " mm");
  std::string curves = "curves: contour = the cam contour (the surface to make)";
  if (profile.has_pitch) curves += "; pitch = the follower centre's path (pitch curve)";
  if (profile.cutter_radius)
    curves += "; cutter = the centre path of a tool of radius " + mm(*profile.cutter_radius) +
              " mm (the contour offset outwards)";
  lines.push_back(curves);
  const std::string error = mm(profile.max_chord_error, 3);
  if (profile.requested_points)
    lines.push_back("sampling: " + std::to_string(profile.points.size()) + " points at equal cam-angle steps (" +
                    "largest chord deviation " + error + " mm)");
  else
    lines.push_back("sampling: " + std::to_string(profile.points.size()) + " points within a chord tolerance of " +
                    mm(profile.chord_tolerance) + " mm (largest chord deviation " + error + " mm)");
  if (std::isfinite(profile.min_concave_radius))
    lines.push_back("smallest concave radius of curvature of the contour: " + mm(profile.min_concave_radius) +
                    " mm at cam angle " + deg(profile.min_concave_radius_at) + " deg");
  else
    lines.push_back("the contour is convex everywhere");
  if (profile.contour_cam) lines.push_back("the cam was given as contour points: the contour is their fitted spline");
  return lines;
}

std::vector<std::string> design_data_lines(const SampledCamProfile& profile) {
  std::vector<std::string> lines = {"DESIGN DATA", "base circle radius: " + mm(profile.base_radius) + " mm"};
  lines.push_back(profile.oscillating ? "lift: " + deg(profile.lift) + " deg (arm angle)"
                                      : "lift: " + mm(profile.lift) + " mm");
  std::string follower = "follower: " + profile.follower;
  if (profile.has_pitch) follower += ", radius " + mm(profile.follower_radius) + " mm";
  if (!profile.oscillating) follower += ", offset " + mm(profile.offset) + " mm";
  lines.push_back(follower);
  lines.push_back(std::string("rotation: ") + (profile.direction > 0 ? "counterclockwise (ccw)" : "clockwise (cw)") +
                  ", seen from +z");
  lines.push_back("timing mark: cam angle 0, the start of the motion law under the follower");
  return lines;
}

void write_profile_csv(const std::filesystem::path& path, const SampledCamProfile& profile, const std::string& name) {
  std::string text;
  for (const std::string& line : profile_header_lines(profile, name)) text += "# " + line + "\n";
  std::vector<std::string> columns = {"cam_angle_deg", profile.oscillating ? "lift_deg" : "lift_mm", "contour_x_mm",
                                      "contour_y_mm"};
  if (profile.has_pitch) columns.insert(columns.end(), {"pitch_x_mm", "pitch_y_mm"});
  if (profile.cutter_radius) columns.insert(columns.end(), {"cutter_x_mm", "cutter_y_mm"});
  for (std::size_t i = 0; i < columns.size(); ++i) text += (i > 0 ? "," : "") + columns[i];
  text += '\n';
  auto cell = [&](double v) {
    if (!std::isfinite(v)) throw std::logic_error("profile " + path.string() + ": non-finite value");
    text += ',';
    text += format_double(v);
  };
  // The cam angle with 12 digits: 1.5, not the 1.5000000000000002 that degrees from radians give.
  auto angle_cell = [&](double degrees) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%.12g", degrees);
    text += buffer;
  };
  for (const ProfilePoint& p : profile.points) {
    angle_cell(p.theta * kRadToDeg);
    cell(profile.oscillating ? p.lift * kRadToDeg : p.lift * kMm);
    cell(p.contour.x() * kMm);
    cell(p.contour.y() * kMm);
    if (profile.has_pitch) {
      cell(p.pitch.x() * kMm);
      cell(p.pitch.y() * kMm);
    }
    if (profile.cutter_radius) {
      cell(p.cutter.x() * kMm);
      cell(p.cutter.y() * kMm);
    }
    text += '\n';
  }
  write_file_atomic(path, text);
}

namespace {

constexpr const char* kContourLayer = "CAM_CONTOUR";
constexpr const char* kPitchLayer = "PITCH_CURVE";
constexpr const char* kCutterLayer = "CUTTER_PATH";
constexpr const char* kNotesLayer = "NOTES";
constexpr const char* kCentreLayer = "CAM_CENTRE";
constexpr const char* kBaseCircleLayer = "BASE_CIRCLE";
constexpr const char* kTimingLayer = "TIMING_MARK";
constexpr const char* kDesignLayer = "DESIGN_DATA";
constexpr double kTextHeightMm = 2.5;

DL_Attributes on_layer(const std::string& layer) { return DL_Attributes(layer, 256, -1, "BYLAYER", 1.0); }

// The header section's variables beyond $ACADVER: drawing units and angle conventions.
void write_header_variables(DL_WriterA& dw) {
  dw.dxfString(9, "$INSUNITS");
  dw.dxfInt(70, 4);  // millimetres
  dw.dxfString(9, "$MEASUREMENT");
  dw.dxfInt(70, 1);  // metric
  dw.dxfString(9, "$LUNITS");
  dw.dxfInt(70, 2);  // decimal
  dw.dxfString(9, "$ANGBASE");
  dw.dxfReal(50, 0.0);  // CAD angles from +x
  dw.dxfString(9, "$ANGDIR");
  dw.dxfInt(70, 0);  // CAD angles counterclockwise
  dw.sectionEnd();
}

// The tables a DXF R2000 reader expects (viewport, line types, layers, text
// style, view, UCS, application id, dimension style, block records), as the
// dxflib programmer's guide writes them.
void write_tables(DL_Dxf& dxf, DL_WriterA& dw) {
  dw.sectionTables();
  dxf.writeVPort(dw);
  dw.tableLinetypes(3);
  dxf.writeLinetype(dw, DL_LinetypeData("BYBLOCK", "", 0, 0, 0.0));
  dxf.writeLinetype(dw, DL_LinetypeData("BYLAYER", "", 0, 0, 0.0));
  dxf.writeLinetype(dw, DL_LinetypeData("CONTINUOUS", "Solid line", 0, 0, 0.0));
  dw.tableEnd();
  const std::pair<const char*, int> layers[] = {{"0", DL_Codes::black}, {kContourLayer, 7}, {kPitchLayer, 5},
                                                {kCutterLayer, 1},      {kCentreLayer, 3},  {kNotesLayer, 8},
                                                {kBaseCircleLayer, 4},  {kTimingLayer, 1},  {kDesignLayer, 8}};
  dw.tableLayers(static_cast<int>(std::size(layers)));
  for (const auto& [layer, colour] : layers)
    dxf.writeLayer(dw, DL_LayerData(layer, 0), DL_Attributes(std::string(""), colour, 25, "CONTINUOUS", 1.0));
  dw.tableEnd();
  dw.tableStyle(1);
  dxf.writeStyle(dw, DL_StyleData("standard", 0, 0.0, 1.0, 0.0, 0, kTextHeightMm, "txt", ""));
  dw.tableEnd();
  dxf.writeView(dw);
  dxf.writeUcs(dw);
  dw.tableAppid(1);
  dxf.writeAppid(dw, "ACAD");
  dw.tableEnd();
  dxf.writeDimStyle(dw, 2.5, 0.625, 0.625, 0.625, kTextHeightMm);
  dxf.writeBlockRecord(dw);
  dw.tableEnd();
  dw.sectionEnd();
  dw.sectionBlocks();
  for (const char* block : {"*Model_Space", "*Paper_Space", "*Paper_Space0"}) {
    dxf.writeBlock(dw, DL_BlockData(block, 0, 0.0, 0.0, 0.0));
    dxf.writeEndBlock(dw, block);
  }
  dw.sectionEnd();
}

template <class Get>
void write_closed_polyline(DL_Dxf& dxf, DL_WriterA& dw, const SampledCamProfile& profile, const char* layer, Get get) {
  dxf.writePolyline(dw, DL_PolylineData(static_cast<int>(profile.points.size()), 0, 0, 1), on_layer(layer));
  for (const ProfilePoint& p : profile.points) {
    const Eigen::Vector2d v = get(p) * kMm;
    if (!v.allFinite()) throw std::logic_error("profile DXF: non-finite vertex on layer " + std::string(layer));
    dxf.writeVertex(dw, DL_VertexData(v.x(), v.y(), 0.0, 0.0));
  }
  dxf.writePolylineEnd(dw);
}

void write_text(DL_Dxf& dxf, DL_WriterA& dw, double x, double y, const std::string& text, const char* layer) {
  dxf.writeText(dw, DL_TextData(x, y, 0.0, x, y, 0.0, kTextHeightMm, 1.0, 0, 0, 0, text, "standard", 0.0),
                on_layer(layer));
}

// What a drawing for the shop needs besides the curves: the centre as a cross,
// the base circle, the timing mark at cam angle 0 and the design data (mm).
void write_drawing_aids(DL_Dxf& dxf, DL_WriterA& dw, const SampledCamProfile& profile) {
  const double rb = profile.base_radius * kMm, outer = profile.max_radius * kMm;
  const double arm = std::max(0.1 * rb, kTextHeightMm);
  dxf.writeLine(dw, DL_LineData(-arm, 0.0, 0.0, arm, 0.0, 0.0), on_layer(kCentreLayer));
  dxf.writeLine(dw, DL_LineData(0.0, -arm, 0.0, 0.0, arm, 0.0), on_layer(kCentreLayer));
  dxf.writeCircle(dw, DL_CircleData(0.0, 0.0, 0.0, rb), on_layer(kBaseCircleLayer));
  // The mark: from half the base radius out past the cam, through the contour
  // point that touches the follower at cam angle 0.
  const Eigen::Vector2d d = profile.points.front().contour.normalized();
  const Eigen::Vector2d from = 0.5 * rb * d, to = (outer + 2.0 * kTextHeightMm) * d;
  dxf.writeLine(dw, DL_LineData(from.x(), from.y(), 0.0, to.x(), to.y(), 0.0), on_layer(kTimingLayer));
  const Eigen::Vector2d label = to + kTextHeightMm * d;
  write_text(dxf, dw, label.x(), label.y(), "TIMING MARK: cam angle 0", kTimingLayer);
  double y = outer;
  for (const std::string& line : design_data_lines(profile)) {
    write_text(dxf, dw, outer + 4.0 * kTextHeightMm, y, line, kDesignLayer);
    y -= 1.6 * kTextHeightMm;
  }
}

void write_entities(DL_Dxf& dxf, DL_WriterA& dw, const SampledCamProfile& profile,
                    const std::vector<std::string>& notes) {
  dw.sectionEntities();
  write_closed_polyline(dxf, dw, profile, kContourLayer, [](const ProfilePoint& p) { return p.contour; });
  if (profile.has_pitch)
    write_closed_polyline(dxf, dw, profile, kPitchLayer, [](const ProfilePoint& p) { return p.pitch; });
  if (profile.cutter_radius)
    write_closed_polyline(dxf, dw, profile, kCutterLayer, [](const ProfilePoint& p) { return p.cutter; });
  dxf.writePoint(dw, DL_PointData(0.0, 0.0, 0.0), on_layer(kCentreLayer));
  write_drawing_aids(dxf, dw, profile);
  // The notes below the cam, one line each, left-aligned.
  const double left = -profile.max_radius * kMm;
  double y = -profile.max_radius * kMm - 4.0 * kTextHeightMm;
  for (const std::string& line : notes) {
    dxf.writeText(dw, DL_TextData(left, y, 0.0, left, y, 0.0, kTextHeightMm, 1.0, 0, 0, 0, line, "standard", 0.0),
                  on_layer(kNotesLayer));
    y -= 1.6 * kTextHeightMm;
  }
  dw.sectionEnd();
}

/// A scratch file for dxflib (which writes to a file name), in a private
/// folder of its own (mkdtemp, mode 0700) under the system's temporary
/// folder: never in the output folder, where a planted link could redirect
/// it. The file and the folder are removed on scope exit.
class ScratchFile {
 public:
  explicit ScratchFile(const std::string& name) {
    std::string pattern = (std::filesystem::temp_directory_path() / "camdyn-dxf-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr)
      throw std::runtime_error("cannot create a scratch folder in '" + std::filesystem::temp_directory_path().string() +
                               "': " + std::strerror(errno));
    dir_ = pattern;
    path_ = dir_ / name;
  }
  ~ScratchFile() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path dir_, path_;
};

}  // namespace

void write_profile_dxf(const std::filesystem::path& path, const SampledCamProfile& profile, const std::string& name) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  // dxflib writes to a file of its own; its content then goes to `path` atomically.
  ScratchFile scratch(path.filename().string());
  const std::vector<std::string> notes = profile_header_lines(profile, name);
  {
    DL_Dxf dxf;
    const std::unique_ptr<DL_WriterA> dw(dxf.out(scratch.path().c_str(), DL_Codes::AC1015));
    if (!dw) throw std::runtime_error("cannot create '" + scratch.path().string() + "'");
    for (const std::string& line : notes) dxf.writeComment(*dw, line);
    dxf.writeHeader(*dw);
    write_header_variables(*dw);
    write_tables(dxf, *dw);
    write_entities(dxf, *dw, profile, notes);
    dxf.writeObjects(*dw);
    dxf.writeObjectsEnd(*dw);
    dw->dxfEOF();
    dw->close();
  }
  std::ifstream in(scratch.path(), std::ios::binary);
  const std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw std::runtime_error("cannot read back '" + scratch.path().string() + "'");
  write_file_atomic(path, content);
}

// ---------------------------------------------------------------- the lift another follower reads

namespace {

/// A tracked pair profile seen as a plain closed curve (RigidFollowerLift reads r, r', r'').
class ProfileAsCurve final : public PeriodicCurve {
 public:
  explicit ProfileAsCurve(const PairProfile& profile) : profile_(&profile) {}
  CurvePoint at(double u) const override { return profile_->at(u); }

 private:
  const PairProfile* profile_;
};

}  // namespace

FollowerLiftTable follower_lift_table(const Model& model, double radius, double angle_step, const std::string& file,
                                      const std::string& radius_path, const std::string& step_path) {
  const FollowerGeometry& f = model.follower;
  if (f.oscillating())
    throw InputError(file, radius_path,
                     "the lift table of another follower is for translating followers; this cam drives an "
                     "oscillating arm");
  if (!(radius > 0.0) || !std::isfinite(radius))
    throw InputError(file, radius_path, "the follower radius must be > 0, got " + mm(radius) + " mm");
  // As for a cutter (check_tool_size): a roller far larger than the cam is a
  // slip, and at 1e297 m its lift lost every digit (NaN; found by export_fuzzer).
  if (radius > kMaxToolToCamRadius * f.base_radius)
    throw InputError(file, radius_path,
                     "the follower radius " + mm(radius) + " mm is more than " +
                         std::to_string(static_cast<int>(kMaxToolToCamRadius)) + " times the base radius, " +
                         mm(f.base_radius) + " mm: give it in mm");
  if (!(angle_step > 0.0) || !(angle_step <= kTwoPi))
    throw InputError(file, step_path, "the angle step must be in (0, 360] deg, got " + deg(angle_step) + " deg");
  const double rows = std::ceil(kTwoPi / angle_step - 1e-9);
  if (rows > ProfileOutputConfig::kMaxPoints)
    throw InputError(file, step_path,
                     "the angle step gives more than " + std::to_string(ProfileOutputConfig::kMaxPoints) +
                         " rows: give a larger step");
  if (std::abs(f.offset) >= f.base_radius + radius)
    throw InputError(file, radius_path,
                     "a roller of radius " + mm(radius) + " mm on the axis at offset " + mm(f.offset) +
                         " mm does not reach the base circle (radius " + mm(f.base_radius) + " mm)");
  // The cam as made: the fitted contour, or the synthesised profile moved to the contour.
  const ClosedCurveProfile tracked(model.profile());
  const InwardOffsetProfile offset_contour(tracked, f.circle() ? f.radius - model.profile_offset : 0.0);
  const ProfileAsCurve synthesised(offset_contour);
  const PeriodicCurve& contour = model.contour ? static_cast<const PeriodicCurve&>(*model.contour) : synthesised;
  const RigidFollowerLift roller(contour, FollowerContact::circle, radius, f.offset, model.direction, 2048, file,
                                 radius_path);
  FollowerLiftTable table;
  table.follower_radius = radius;
  table.offset = f.offset;
  table.base_radius = f.base_radius;
  table.direction = model.direction;
  table.design_follower = std::string("translating ") + std::string(f.traits().label);
  const double base_height = std::sqrt(std::pow(f.base_radius + radius, 2) - f.offset * f.offset);  // [m]
  for (int k = 0; k < static_cast<int>(rows); ++k) {
    const double theta = k * angle_step;
    table.theta.push_back(theta);
    table.lift.push_back(roller.at(theta).y - base_height);
  }
  return table;
}

void write_follower_lift_csv(const std::filesystem::path& path, const FollowerLiftTable& table,
                             const std::string& name) {
  const double base_height =
      std::sqrt(std::pow(table.base_radius + table.follower_radius, 2) - table.offset * table.offset);
  const std::vector<std::string> header = {
      "camdyn follower lift table of '" + name + "' (camdyn " CAMDYN_VERSION ")",
      "units: millimetres (lift), degrees (cam angle)",
      "follower: a roller of radius " + mm(table.follower_radius) + " mm on the design's follower axis (x = offset " +
          mm(table.offset) + " mm, moving along +y); the cam was designed for a " + table.design_follower,
      "datum: cam angle 0 = the start of the motion law under the follower (the drawing's timing mark); lift 0 = "
      "the roller on the base circle (radius " +
          mm(table.base_radius) + " mm), its centre " + mm(base_height) + " mm from the cam's centre",
      std::string("rotation: the cam turns ") + (table.direction > 0 ? "counterclockwise (ccw)" : "clockwise (cw)") +
          " seen from +z; the lift at cam angle t is read when the cam has turned by t from angle 0",
      "lift: the height of the roller's centre above its base-circle height, the roller touching the cam contour"};
  std::string text;
  for (const std::string& line : header) text += "# " + line + "\n";
  text += "cam_angle_deg,lift_mm\n";
  for (std::size_t i = 0; i < table.theta.size(); ++i) {
    if (!std::isfinite(table.lift[i])) throw std::logic_error("follower lift " + path.string() + ": non-finite lift");
    char angle[32];
    std::snprintf(angle, sizeof angle, "%.12g", table.theta[i] * kRadToDeg);
    text += std::string(angle) + "," + format_double(table.lift[i] * kMm) + "\n";
  }
  write_file_atomic(path, text);
}

std::vector<std::filesystem::path> write_profile_files(const std::filesystem::path& dir,
                                                       const SampledCamProfile& profile, const std::string& name,
                                                       const std::vector<ProfileFormat>& formats) {
  std::vector<std::filesystem::path> written;
  auto wants = [&](ProfileFormat f) { return std::find(formats.begin(), formats.end(), f) != formats.end(); };
  if (wants(ProfileFormat::csv)) {
    written.push_back(dir / "profile.csv");
    write_profile_csv(written.back(), profile, name);
  }
  if (wants(ProfileFormat::dxf)) {
    written.push_back(dir / "profile.dxf");
    write_profile_dxf(written.back(), profile, name);
  }
  return written;
}

std::vector<std::filesystem::path> write_profile_outputs(const std::filesystem::path& dir, const SceneConfig& scene,
                                                         const Model& model, const std::string& file) {
  if (!scene.outputs.profile) return {};
  const ProfileOutputConfig& config = *scene.outputs.profile;
  const SampledCamProfile profile = sample_cam_profile(model, profile_options(config), ProfileOptionNames{file});
  return write_profile_files(dir, profile, scene.name, config.formats);
}

}  // namespace camdyn
