#include "study/periodic_report.h"

#include <cmath>
#include <numbers>
#include <string>
#include <string_view>

#include "dynamics/coordinate_units.h"
#include "output/cam_plots.h"

namespace camdyn {

namespace {

// The orbit (or the last revolution) in the phase plane, and its section points.
Plot phase_plane(const PeriodicResult& r, const PoincareMap& map) {
  const TimeSeries& s = r.orbit_run.series;
  const CoordinateUnits u = coordinate_units(map.model());
  // A translating follower's position in µm, mm or m as its size needs; an arm's angle in rad.
  const bool length = std::string_view(u.position) == "m";
  const LengthUnit unit = length ? length_unit({&s.follower_position}) : LengthUnit{1.0, u.position};
  Plot p{"Phase plane: follower position against velocity",
         CoordinateUnits::axis(u.velocity_name, u.velocity),
         CoordinateUnits::axis(u.position_name, unit.symbol),
         {}};
  p.series.push_back({r.analysis.orbit ? "orbit" : "last revolution", s.follower_velocity, unit.of(s.follower_position),
                      "lines", PlotRole::dynamic});
  Series section{"Poincaré points (once per revolution)", {}, {}, "points", PlotRole::section};
  if (r.analysis.orbit) {
    const double period = map.period();
    for (std::size_t i = 0; i < s.time.size(); ++i) {
      const double revolutions = s.time[i] / period;
      if (std::abs(revolutions - std::round(revolutions)) < 1e-9) {
        section.x.push_back(s.follower_velocity[i]);
        section.y.push_back(s.follower_position[i] * unit.per_metre);
      }
    }
  } else if (r.analysis.lyapunov) {
    for (const std::vector<double>& x : r.analysis.lyapunov->section_points) {
      section.x.push_back(x[1]);
      section.y.push_back(x[0] * unit.per_metre);
    }
  }
  p.series.push_back(std::move(section));
  return p;
}

Plot contact_force(const PeriodicResult& r) {
  const TimeSeries& s = r.orbit_run.series;
  std::vector<double> angle(s.cam_angle_deg);
  for (double& a : angle) a -= s.cam_angle_deg.front();
  return Plot{"Contact force over one period",
              "cam angle from the section [deg]",
              "contact force [N]",
              {{"contact force", angle, s.contact_force, "lines", PlotRole::dynamic}}};
}

Plot multipliers(const Orbit& o) {
  Series circle{"unit circle", {}, {}, "lines", PlotRole::limit};
  constexpr int kPoints = 180;
  for (int i = 0; i <= kPoints; ++i) {
    const double phi = 2.0 * std::numbers::pi * i / kPoints;
    circle.x.push_back(std::cos(phi));
    circle.y.push_back(std::sin(phi));
  }
  Series mu{"Floquet multipliers", {}, {}, "points"};
  for (const std::complex<double>& m : o.multipliers) {
    mu.x.push_back(m.real());
    mu.y.push_back(m.imag());
  }
  return Plot{"Floquet multipliers (stable inside the unit circle)", "Re μ [-]", "Im μ [-]", {circle, mu}};
}

Plot newton_residuals(const PeriodicAnalysis& a) {
  Plot p{"Shooting: Newton residual per iteration", "iteration [-]", "max |P^k(x) − x| / scale [-]", {}};
  p.logy = true;
  for (const NewtonStep& s : a.newton) {
    if (p.series.empty() || p.series.back().label != "period " + std::to_string(s.period))
      p.series.push_back({"period " + std::to_string(s.period), {}, {}, "linespoints"});
    p.series.back().x.push_back(s.iteration);
    p.series.back().y.push_back(s.residual);
  }
  return p;
}

Table orbit_table(const PeriodicResult& r, const CoordinateUnits& u) {
  Table t{"Impacts and take-offs on the orbit",
          {"event", "cam angle [deg]", "normal speed [m/s]", CoordinateUnits::axis(u.velocity_name, u.velocity)},
          {}};
  for (const OrbitEvent& e : r.impacts)
    t.rows.push_back(
        {"impact", format_number(e.cam_angle_deg), format_number(e.speed), format_number(e.follower_velocity)});
  for (const OrbitEvent& e : r.take_offs)
    t.rows.push_back(
        {"take-off", format_number(e.cam_angle_deg), format_number(e.speed), format_number(e.follower_velocity)});
  return t;
}

}  // namespace

Report periodic_report(const PeriodicStudy& study, const PeriodicResult& r, const PoincareMap& map) {
  const PeriodicAnalysis& a = r.analysis;
  Report rep;
  rep.title = "camdyn periodic: " + study.scene.name;
  rep.subtitle =
      "periodic study: the steady motion at " + format_number(r.rpm) + " rpm by shooting on the Poincaré map";
  rep.verdict =
      Verdict{a.orbit ? (r.impacts.empty() ? Verdict::Tone::good : Verdict::Tone::warning) : Verdict::Tone::bad,
              periodic_verdict(r),
              {}};
  rep.facts = {{"cam speed", format_number(r.rpm) + " rpm"},
               {r.jump_speed_name, format_number(r.jump_speed_rpm, 5) + " rpm"},
               {"motion", to_string(a.motion)}};
  if (a.orbit) {
    std::string mu;
    for (const std::complex<double>& m : a.orbit->multipliers)
      mu += (mu.empty() ? "" : ", ") + format_number(m.real(), 4) + (m.imag() >= 0 ? " + " : " − ") +
            format_number(std::abs(m.imag()), 4) + "i";
    rep.facts.push_back({"period", std::to_string(a.orbit->period) + " revolution(s)"});
    rep.facts.push_back({"Floquet multipliers", mu});
  }
  for (const Orbit& o : a.unstable_orbits)
    rep.facts.push_back({"unstable orbit", "period " + std::to_string(o.period) + ", largest |μ| " +
                                               format_number(o.spectral_radius(), 4)});
  for (const Orbit& o : a.unreached_orbits)
    rep.facts.push_back({"coexisting stable orbit", "period " + std::to_string(o.period) + ", largest |μ| " +
                                                        format_number(o.spectral_radius(), 4) +
                                                        ", not reached from this start"});
  if (a.lyapunov)
    rep.facts.push_back({"largest Lyapunov exponent", format_number(a.lyapunov->per_revolution, 4) +
                                                          " per revolution over " +
                                                          std::to_string(a.lyapunov->revolutions) + " revolutions"});
  rep.facts.push_back({"revolutions integrated",
                       std::to_string(a.revolutions) + " (" + std::to_string(a.map_evaluations) + " map evaluations)"});
  rep.facts.push_back({"run time", format_number(r.run_time_s, 3) + " s"});
  rep.plots.push_back(phase_plane(r, map));
  rep.plots.push_back(contact_force(r));
  for (Plot& p : cam_plots(map.model(), study.scene.mechanism.cam.limits, r.rpm)) rep.plots.push_back(std::move(p));
  if (a.orbit) rep.plots.push_back(multipliers(*a.orbit));
  if (!a.newton.empty()) rep.plots.push_back(newton_residuals(a));
  rep.appendix.push_back(orbit_table(r, coordinate_units(map.model())));
  rep.notes.push_back(
      "The orbit is found by shooting on the once-per-revolution Poincaré map; the metrics in periodic.json and "
      "orbit/summary.json are over one period of it (over the last revolution when no stable orbit converged). "
      "orbit/ holds that period as a simulate run's outputs.");
  return rep;
}

}  // namespace camdyn
