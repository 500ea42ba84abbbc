// One look per meaning across every figure of every report (docs/outputs-and-resume.md,
// "Figures"): a series that plays a role (the baseline design, the optimised
// one, the rigid model, the simulated dynamics, a limit, measured data, a fit)
// gets that role's colour and dash wherever it is drawn, an event (lift-off,
// impact, seating, a once-per-revolution sample, the verdict's minimum) that event's marker; and a
// length axis takes the unit its data needs (µm, mm or m). Series with no
// role take the report's palette by position.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace camdyn {

/// What a series shows. Line roles first, then the event markers.
enum class PlotRole {
  automatic,  ///< no role: the palette by position, the series' own style
  dynamic,    ///< the simulated (elastic, dynamic) answer
  rigid,      ///< the rigid / kinematic model: the motion law, the rigid-model force
  baseline,   ///< the design before optimisation
  optimised,  ///< the design after optimisation
  limit,      ///< a limit, bound or threshold (a stress limit, a jump speed, a checking height)
  measured,   ///< measured data (markers)
  fitted,     ///< the model fitted to measured data
  lift_off,   ///< event: the follower leaves the cam
  impact,     ///< event: it comes back (impact, re-contact)
  seat,       ///< event: a valve seats
  section,    ///< event: a once-per-revolution sample (Poincaré section)
  minimum,    ///< event: where the verdict's least value falls (the minimum contact force)
};

/// How a role is drawn: colour `#rrggbb`, a gnuplot dash type (1 solid,
/// 2 dashed, 3 dotted, 4 dash-dot) for a line, or a gnuplot point type
/// (> 0) for a marker.
struct RoleStyle {
  std::string_view name;    ///< the SVG series' data-role ("baseline", "lift-off", ...)
  std::string_view colour;  ///< "#rrggbb"
  int dashtype = 1;         ///< line roles: gnuplot dashtype
  int point_type = 0;       ///< marker roles: gnuplot pointtype, 0 for a line
  double point_size = 0.0;  ///< marker roles: gnuplot pointsize
};

/// The style table: the one place a role's look is decided.
const RoleStyle& role_style(PlotRole role);

/// Every role but `automatic`, in the order of the enum.
const std::vector<PlotRole>& all_plot_roles();

/// The colours (`#rrggbb`) of series without a role, by their place in the plot, repeating.
const std::vector<std::string_view>& series_palette();

/// The gnuplot `with` clause of a series in `role`, e.g.
/// "lines lc rgb '#000000' dashtype 2"; empty for `automatic`.
std::string gnuplot_with(PlotRole role);

/// A length unit for an axis: values in metres times `per_metre` read in `symbol`.
struct LengthUnit {
  double per_metre = 1.0;
  std::string symbol = "m";
  /// `name [symbol]`, e.g. "gap [mm]".
  std::string axis(std::string_view name) const;
  /// `metres` in this unit (non-finite values kept as they are).
  std::vector<double> of(const std::vector<double>& metres) const;
};

/// The unit for lengths whose largest magnitude is `largest_m` [m]: µm below
/// 1 mm, mm below 1 m, m from 1 m (mm when nothing finite or all zero).
LengthUnit length_unit(double largest_m);

/// length_unit of the largest finite magnitude among `columns` [m].
LengthUnit length_unit(const std::vector<const std::vector<double>*>& columns);

}  // namespace camdyn
