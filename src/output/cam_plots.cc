#include "output/cam_plots.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include "common/constants.h"
#include "geometry/vec2.h"
#include "output/profile_export.h"

namespace camdyn {

namespace {

constexpr const char* kCamAngle = "cam angle [deg]";

void add_point(Series& s, const Eigen::Vector2d& p_m) {
  s.x.push_back(p_m.x() * kMm);
  s.y.push_back(p_m.y() * kMm);
}

/// A closed curve of the profile turned into the world at cam angle `mark` (σ·mark), in mm.
Series closed_curve(const SampledCamProfile& profile, Eigen::Vector2d ProfilePoint::*member, double turn,
                    std::string label, std::string style = "lines") {
  Series s{std::move(label), {}, {}, std::move(style)};
  for (const ProfilePoint& p : profile.points) add_point(s, rotate(p.*member, turn));
  if (!profile.points.empty()) add_point(s, rotate(profile.points.front().*member, turn));
  return s;
}

Series circle(const Eigen::Vector2d& centre, double radius, std::string label, std::string style = "lines") {
  Series s{std::move(label), {}, {}, std::move(style)};
  constexpr int kSegments = 180;
  for (int i = 0; i <= kSegments; ++i) {
    const double a = kTwoPi * i / kSegments;
    add_point(s, centre + radius * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return s;
}

/// The follower on the law at cam angle θ, world frame: its circle or face, and its stem or arm.
Series follower_series(const Model& model, double theta) {
  const FollowerGeometry& f = model.follower;
  const double q = model.law->eval(std::fmod(theta, kTwoPi)).s;
  const std::string label = "follower (" + std::string(f.traits().label) + ")";
  if (f.circle()) {
    Vec2<double> c, c_q;
    f.centre(q, c, c_q);
    const Eigen::Vector2d centre = to_eigen(c);
    Series s = circle(centre, f.radius, label);
    s.x.push_back(kBreak);
    s.y.push_back(kBreak);
    // The stem up the follower axis, or the arm back to the pivot.
    add_point(s, centre);
    add_point(s, f.oscillating() ? f.pivot : Eigen::Vector2d(centre + Eigen::Vector2d(0.0, 0.6 * f.base_radius)));
    return s;
  }
  Vec2<double> origin, dir;
  f.face_frame(q, origin, dir);
  const Eigen::Vector2d along = to_eigen(dir);
  Series s{label, {}, {}, "lines"};
  if (f.oscillating()) {
    // The face lies on the arm's line: from the pivot to the far end of the face.
    add_point(s, f.pivot);
    add_point(s, to_eigen(origin) + 0.5 * f.face_width * along);
    return s;
  }
  const Eigen::Vector2d centre(f.offset, f.base_radius + q);
  add_point(s, centre - 0.5 * f.face_width * along);
  add_point(s, centre + 0.5 * f.face_width * along);
  s.x.push_back(kBreak);
  s.y.push_back(kBreak);
  add_point(s, centre);
  add_point(s, centre + Eigen::Vector2d(0.0, 0.6 * f.base_radius));
  return s;
}

std::string angle_text(double theta) { return format_number(std::fmod(theta, kTwoPi) * kRadToDeg, 4) + "°"; }

/// Samples a function of cam angle over a revolution, [0°, 360°].
template <class F>
Series against_angle(std::string label, F f) {
  Series s{std::move(label), {}, {}, "lines"};
  for (int i = 0; i <= kCamPlotSamples; ++i) {
    const double theta = kTwoPi * i / kCamPlotSamples;
    s.x.push_back(theta * kRadToDeg);
    const double v = f(std::min(theta, kTwoPi * (1.0 - 1e-12)));
    s.y.push_back(std::isfinite(v) ? v : kBreak);
  }
  return s;
}

Series horizontal(double y, std::string label) {
  return Series{std::move(label), {0.0, 360.0}, {y, y}, "dashes", PlotRole::limit};
}

Plot against_angle_plot(std::string title, std::string ylabel, std::vector<Series> series) {
  Plot plot;
  plot.title = std::move(title);
  plot.xlabel = kCamAngle;
  plot.ylabel = std::move(ylabel);
  plot.series = std::move(series);
  plot.xrange = std::pair{0.0, 360.0};
  return plot;
}

}  // namespace

Plot cam_layout_plot(const std::vector<CamDesign>& designs, double mark) {
  Plot plot;
  plot.xlabel = "x [mm]";
  plot.ylabel = "y [mm]";
  plot.equal_axes = true;
  if (designs.empty()) return plot;
  const Model& model = *designs.front().model;
  const double turn = model.direction * mark;
  ProfileOptions options;
  options.points = kCamPlotSamples;
  const std::string suffix = designs.size() > 1 ? " (" + designs.front().label + ")" : "";
  const SampledCamProfile profile = sample_cam_profile(model, options, ProfileOptionNames{});
  plot.series.push_back(closed_curve(profile, &ProfilePoint::contour, turn, "cam contour" + suffix));
  plot.series.back().role = designs.front().role;
  if (profile.has_pitch)
    plot.series.push_back(closed_curve(profile, &ProfilePoint::pitch, turn, "pitch curve" + suffix, "dashes"));
  plot.series.push_back(circle(Eigen::Vector2d::Zero(), model.follower.base_radius, "base circle", "dashes"));
  plot.series.push_back(follower_series(model, mark));
  const SynthesisedCam::Kinematics k = model.cam->kinematics(std::fmod(mark, kTwoPi));
  Series contact{"contact point", {}, {}, "points"};
  add_point(contact, k.contact);
  Series centre{"cam centre", {0.0}, {0.0}, "points"};
  plot.series.push_back(std::move(contact));
  plot.series.push_back(std::move(centre));
  for (std::size_t i = 1; i < designs.size(); ++i) {
    const SampledCamProfile other = sample_cam_profile(*designs[i].model, options, ProfileOptionNames{});
    plot.series.push_back(closed_curve(other, &ProfilePoint::contour, designs[i].model->direction * mark,
                                       "cam contour (" + designs[i].label + ")"));
    plot.series.back().role = designs[i].role;
  }
  plot.title = "Cam and follower to scale at cam angle " + angle_text(mark) + " (the cam turns " +
               (model.direction > 0 ? "counterclockwise" : "clockwise") + "; world frame, mm)";
  return plot;
}

Plot pressure_angle_plot(const std::vector<CamDesign>& designs, std::optional<double> limit_deg) {
  std::vector<Series> series;
  for (const CamDesign& d : designs) {
    series.push_back(
        against_angle("pressure angle" + (designs.size() > 1 ? " (" + d.label + ")" : std::string()),
                      [&](double theta) { return d.model->cam->kinematics(theta).pressure_angle * kRadToDeg; }));
    series.back().role = d.role;
  }
  if (limit_deg) {
    series.push_back(horizontal(*limit_deg, "limit +" + format_number(*limit_deg, 4) + "°"));
    series.push_back(horizontal(-*limit_deg, "limit −" + format_number(*limit_deg, 4) + "°"));
  }
  return against_angle_plot("Pressure angle against cam angle", "pressure angle [deg]", std::move(series));
}

Plot curvature_plot(const std::vector<CamDesign>& designs, std::optional<double> limit) {
  std::vector<Series> series;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo, clip = 0.0;
  for (const CamDesign& d : designs) {
    // ρ beyond a few cam radii says "nearly straight" and nothing more.
    clip = std::max(clip, 3.0 * (d.model->follower.base_radius + d.model->geometry.max_face_offset) * kMm);
    series.push_back(
        against_angle("radius of curvature" + (designs.size() > 1 ? " (" + d.label + ")" : std::string()),
                      [&](double theta) { return d.model->cam->kinematics(theta).radius_of_curvature * kMm; }));
    series.back().role = d.role;
    for (double y : series.back().y) {
      if (!std::isfinite(y)) continue;
      lo = std::min(lo, y);
      hi = std::max(hi, y);
    }
  }
  bool concave = lo < 0.0;
  if (limit) {
    series.push_back(horizontal(*limit * kMm, "limit |ρ| ≥ " + format_number(*limit * kMm, 4) + " mm"));
    if (concave) series.push_back(horizontal(-*limit * kMm, "limit (concave)"));
    hi = std::max(hi, *limit * kMm);
    if (concave) lo = std::min(lo, -*limit * kMm);
  }
  Plot plot = against_angle_plot("Radius of curvature of the cam contour against cam angle (> 0 convex)",
                                 "radius of curvature [mm]", std::move(series));
  if (std::isfinite(lo) && std::isfinite(hi)) {
    lo = std::max(std::min(lo, 0.0), -clip);
    hi = std::min(hi, clip);
    if (lo < hi) plot.yrange = std::pair{lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo)};
  }
  return plot;
}

std::vector<Plot> svaj_plots(const std::vector<CamDesign>& designs, double rpm) {
  std::vector<Plot> plots;
  if (designs.empty()) return plots;
  const bool arm = designs.front().model->follower.oscillating();
  const double omega = rpm * kTwoPi / 60.0;
  const bool timed = omega > 0.0;
  // The n-th derivative: with the cam turning, times ωⁿ [m/sⁿ, arm rad/sⁿ];
  // with the cam still, per radian of cam angle [mm/radⁿ, arm deg/radⁿ].
  double largest_lift = 0.0;  // [m]
  for (const CamDesign& d : designs)
    for (int i = 0; i < kCamPlotSamples; ++i)
      largest_lift = std::max(largest_lift, std::abs(d.model->law->eval(kTwoPi * i / kCamPlotSamples).s));
  const LengthUnit lift_unit = length_unit(largest_lift);
  const double length = arm ? kRadToDeg : kMm;
  const char* power[] = {"", "", "²", "³"};
  const char* names[] = {"Lift", "Velocity", "Acceleration", "Jerk"};
  const std::string at = timed ? " at " + format_number(rpm, 6) + " rpm" : " per radian of cam angle";
  for (int n = 0; n <= 3; ++n) {
    std::string ylabel;
    if (n == 0) {
      ylabel = arm ? "arm angle [deg]" : lift_unit.axis("lift");
    } else if (timed) {
      ylabel = std::string(names[n]) + " [" + (arm ? "rad" : "m") + "/s" + power[n] + "]";
    } else {
      ylabel = std::string("d") + power[n] + "s/dθ" + power[n] + " [" + (arm ? "deg" : "mm") + "/rad" + power[n] + "]";
    }
    const double scale = n == 0 ? (arm ? kRadToDeg : lift_unit.per_metre) : timed ? std::pow(omega, n) : length;
    std::vector<Series> curves;
    for (const CamDesign& d : designs) {
      const Model& model = *d.model;
      curves.push_back(against_angle(designs.size() > 1 ? d.label : names[n], [&model, scale, n](double t) {
        const LawSample l = model.law->eval(t);
        const double derivative[] = {l.s, l.ds, l.d2s, l.d3s};
        return derivative[n] * scale;
      }));
      curves.back().role = d.role;
    }
    plots.push_back(against_angle_plot(std::string(names[n]) + " of the follower (motion law)" + (n > 0 ? at : ""),
                                       ylabel, std::move(curves)));
  }
  return plots;
}

std::vector<Plot> cam_plots(const Model& model, const CamLimitsConfig& limits, double rpm, const std::string& caption) {
  const std::vector<CamDesign> designs = {{"cam", &model}};
  // A cam held still (a drop test) is drawn as it stands; a turning one where it pushes hardest sideways.
  double mark = model.geometry.max_pressure_angle_at_deg / kRadToDeg;
  if (model.omega == 0.0) {
    mark = std::fmod(model.theta0, kTwoPi);
    if (mark < 0.0) mark += kTwoPi;
  }
  std::vector<Plot> plots = {cam_layout_plot(designs, mark),
                             pressure_angle_plot(designs, limits.max_pressure_angle_deg),
                             curvature_plot(designs, limits.min_radius_of_curvature)};
  for (Plot& p : svaj_plots(designs, rpm)) plots.push_back(std::move(p));
  if (!caption.empty())
    for (Plot& p : plots) p.title += " — " + caption;
  return plots;
}

std::vector<Plot> scene_cam_plots(const SceneConfig& scene, const std::string& file, double rpm,
                                  const std::string& caption) {
  return cam_plots(build_model(scene, file), scene.mechanism.cam.limits, rpm, caption);
}

}  // namespace camdyn
