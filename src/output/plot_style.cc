#include "output/plot_style.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>

namespace camdyn {
namespace {

// Colour-blind-safe (Okabe–Ito where it has room); the line roles differ by
// dash as well as colour, so that they survive a grey print.
const RoleStyle kAutomatic{"", "", 1, 0, 0.0};
const RoleStyle kDynamic{"dynamic", "#0072b2", 1, 0, 0.0};
const RoleStyle kRigid{"rigid", "#000000", 2, 0, 0.0};
const RoleStyle kBaseline{"baseline", "#7f7f7f", 3, 0, 0.0};
const RoleStyle kOptimised{"optimised", "#d55e00", 1, 0, 0.0};
const RoleStyle kLimit{"limit", "#b2182b", 4, 0, 0.0};
const RoleStyle kMeasured{"measured", "#5f5f5f", 1, 7, 0.4};
const RoleStyle kFitted{"fitted", "#009e73", 1, 0, 0.0};
// Markers: filled shapes, one per event kind.
const RoleStyle kLiftOff{"lift-off", "#e69f00", 1, 11, 0.9};  // triangle pointing down
const RoleStyle kImpact{"impact", "#cc79a7", 1, 9, 0.9};      // triangle pointing up
const RoleStyle kSeat{"seat", "#56b4e9", 1, 5, 0.8};          // square
const RoleStyle kSection{"section", "#882255", 1, 13, 0.7};   // diamond
const RoleStyle kMinimum{"minimum", "#009e73", 1, 15, 0.9};   // pentagon

}  // namespace

const RoleStyle& role_style(PlotRole role) {
  switch (role) {
    case PlotRole::automatic:
      return kAutomatic;
    case PlotRole::dynamic:
      return kDynamic;
    case PlotRole::rigid:
      return kRigid;
    case PlotRole::baseline:
      return kBaseline;
    case PlotRole::optimised:
      return kOptimised;
    case PlotRole::limit:
      return kLimit;
    case PlotRole::measured:
      return kMeasured;
    case PlotRole::fitted:
      return kFitted;
    case PlotRole::lift_off:
      return kLiftOff;
    case PlotRole::impact:
      return kImpact;
    case PlotRole::seat:
      return kSeat;
    case PlotRole::section:
      return kSection;
    case PlotRole::minimum:
      return kMinimum;
  }
  return kAutomatic;
}

const std::vector<PlotRole>& all_plot_roles() {
  static const std::vector<PlotRole> roles = {PlotRole::dynamic,   PlotRole::rigid,    PlotRole::baseline,
                                              PlotRole::optimised, PlotRole::limit,    PlotRole::measured,
                                              PlotRole::fitted,    PlotRole::lift_off, PlotRole::impact,
                                              PlotRole::seat,      PlotRole::section,  PlotRole::minimum};
  return roles;
}

const std::vector<std::string_view>& series_palette() {
  // Okabe–Ito: colour-blind safe, reads on screen and in print.
  static const std::vector<std::string_view> palette = {"#0072b2", "#d55e00", "#009e73", "#cc79a7",
                                                        "#e69f00", "#56b4e9", "#000000", "#f0e442"};
  return palette;
}

std::string gnuplot_with(PlotRole role) {
  const RoleStyle& s = role_style(role);
  if (s.name.empty()) return {};
  const std::string colour = "lc rgb '" + std::string(s.colour) + "'";
  if (s.point_type > 0) {
    char size[32];
    std::snprintf(size, sizeof size, "%.2g", s.point_size);
    return "points " + colour + " pt " + std::to_string(s.point_type) + " ps " + size;
  }
  return "lines " + colour + " lw 1.5 dashtype " + std::to_string(s.dashtype);
}

std::string LengthUnit::axis(std::string_view name) const { return std::string(name) + " [" + symbol + "]"; }

std::vector<double> LengthUnit::of(const std::vector<double>& metres) const {
  std::vector<double> out(metres.size());
  for (std::size_t i = 0; i < metres.size(); ++i) out[i] = metres[i] * per_metre;
  return out;
}

LengthUnit length_unit(double largest_m) {
  const double m = std::abs(largest_m);
  if (!std::isfinite(m) || m == 0.0) return {1e3, "mm"};
  if (m < 1e-3) return {1e6, "µm"};
  if (m < 1.0) return {1e3, "mm"};
  return {1.0, "m"};
}

LengthUnit length_unit(const std::vector<const std::vector<double>*>& columns) {
  double largest = 0.0;
  for (const std::vector<double>* column : columns)
    if (column != nullptr)
      for (double v : *column)
        if (std::isfinite(v)) largest = std::max(largest, std::abs(v));
  return length_unit(largest);
}

}  // namespace camdyn
