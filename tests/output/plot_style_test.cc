// The role table (one look per meaning across every figure) and the length
// units that follow the data (docs/outputs-and-resume.md, "Figures").
#include "output/plot_style.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "cli_run.h"
#include "gnuplot.h"
#include "output/report.h"

namespace camdyn {
namespace {

// The attribute `name` of the first tag in `text` that starts at or after `from`.
std::string attribute_after(const std::string& text, std::size_t from, const std::string& name) {
  const std::size_t at = text.find(name + "='", from);
  if (at == std::string::npos) return {};
  const std::size_t start = at + name.size() + 2;
  return text.substr(start, text.find('\'', start) - start);
}

TEST(LengthUnit, MicrometresBelowAMillimetreMillimetresBelowAMetreElseMetres) {
  EXPECT_EQ(length_unit(0.4e-3).symbol, "µm");
  EXPECT_DOUBLE_EQ(length_unit(0.4e-3).per_metre, 1e6);
  EXPECT_EQ(length_unit(-0.9999e-3).symbol, "µm");  // a penetration counts by its size
  EXPECT_EQ(length_unit(1e-3).symbol, "mm");
  EXPECT_EQ(length_unit(25e-3).symbol, "mm");  // the attack's 25 mm gap, once drawn in µm
  EXPECT_DOUBLE_EQ(length_unit(25e-3).per_metre, 1e3);
  EXPECT_EQ(length_unit(0.999).symbol, "mm");
  EXPECT_EQ(length_unit(1.0).symbol, "m");
  EXPECT_EQ(length_unit(40.0).symbol, "m");
  EXPECT_EQ(length_unit(0.0).symbol, "mm");  // nothing to size: the unit of a cam
}

TEST(LengthUnit, ColumnsGoByTheirLargestFiniteValueAndScaleTheirValues) {
  const std::vector<double> gap = {-2e-6, 0.0, 25e-3, std::nan("")};
  const std::vector<double> law = {0.0, 8e-3};
  const LengthUnit unit = length_unit({&gap, &law});
  EXPECT_EQ(unit.axis("gap"), "gap [mm]");
  const std::vector<double> mm = unit.of(gap);
  EXPECT_DOUBLE_EQ(mm[0], -2e-3);
  EXPECT_DOUBLE_EQ(mm[2], 25.0);
  EXPECT_TRUE(std::isnan(mm[3]));
  const std::vector<double> tiny = {3e-7, -5e-7};
  EXPECT_EQ(length_unit({&tiny}).axis("gap"), "gap [µm]");
}

// Each role has a name of its own; line roles differ from each other in
// colour or dash, marker roles in their marker.
TEST(PlotRoles, EveryRoleHasItsOwnNameAndLook) {
  std::set<std::string> names;
  std::set<std::pair<std::string, int>> lines;
  std::set<int> markers;
  for (const PlotRole role : all_plot_roles()) {
    const RoleStyle& s = role_style(role);
    EXPECT_FALSE(s.name.empty());
    EXPECT_TRUE(names.insert(std::string(s.name)).second) << s.name;
    ASSERT_EQ(s.colour.size(), 7u) << s.name;
    EXPECT_EQ(s.colour[0], '#') << s.name;
    if (s.point_type > 0) {
      EXPECT_TRUE(markers.insert(s.point_type).second) << s.name << ": marker shared";
      EXPECT_GT(s.point_size, 0.0) << s.name;
    } else if (role != PlotRole::measured) {
      EXPECT_TRUE(lines.insert({std::string(s.colour), s.dashtype}).second) << s.name << ": look shared";
    }
  }
  for (const char* event : {"lift-off", "impact", "seat", "section", "minimum"})
    EXPECT_TRUE(names.count(event)) << event << " has no marker";
  EXPECT_TRUE(role_style(PlotRole::automatic).name.empty());
  EXPECT_EQ(gnuplot_with(PlotRole::automatic), "");
  EXPECT_EQ(gnuplot_with(PlotRole::rigid), "lines lc rgb '#000000' lw 1.5 dashtype 2");
  EXPECT_EQ(gnuplot_with(PlotRole::impact), "points lc rgb '#cc79a7' pt 9 ps 0.9");
}

// The SVG gnuplot draws carries each role as data-role on the series'
// group, in the role's colour (and dash), whatever the series' own style and
// its place in the plot; a series without a role carries none.
TEST(PlotRoles, SvgSeriesAreTaggedAndDrawnInTheirRolesColour) {
  REQUIRE_GNUPLOT();
  Plot plot;
  plot.xlabel = "cam angle [deg]";
  plot.ylabel = "force [N]";
  plot.series = {{"plain", {0, 1, 2}, {0, 1, 0}},
                 {"optimised", {0, 1, 2}, {1, 2, 1}, "dashes", PlotRole::optimised},
                 {"baseline", {0, 1, 2}, {2, 3, 2}, "lines", PlotRole::baseline},
                 {"lift-off", {1}, {0}, "lines", PlotRole::lift_off}};
  const std::string svg = render_svg(plot);
  ASSERT_NE(svg.find("gnuplot_plot_4"), std::string::npos) << svg.substr(0, 300);
  EXPECT_EQ(svg.find("<g id=\"gnuplot_plot_1\" data-role"), std::string::npos);
  const std::size_t optimised = svg.find("<g id=\"gnuplot_plot_2\" data-role=\"optimised\"");
  const std::size_t baseline = svg.find("<g id=\"gnuplot_plot_3\" data-role=\"baseline\"");
  const std::size_t lift_off = svg.find("<g id=\"gnuplot_plot_4\" data-role=\"lift-off\"");
  ASSERT_NE(optimised, std::string::npos);
  ASSERT_NE(baseline, std::string::npos);
  ASSERT_NE(lift_off, std::string::npos);
  // gnuplot writes rgb(213,  94,   0) for #d55e00; the role's line is solid.
  const std::string optimised_group = svg.substr(optimised, baseline - optimised);
  EXPECT_NE(optimised_group.find("stroke='rgb(213,  94,   0)'"), std::string::npos) << optimised_group;
  EXPECT_EQ(optimised_group.find("stroke-dasharray"), std::string::npos) << "the role's solid line, not 'dashes'";
  const std::string baseline_group = svg.substr(baseline, lift_off - baseline);
  EXPECT_NE(baseline_group.find("stroke='rgb(127, 127, 127)'"), std::string::npos) << baseline_group;
  EXPECT_NE(baseline_group.find("stroke-dasharray"), std::string::npos);
  // The lift-off is a marker (a filled downward triangle, gnuplot pt 11 = gpPt10) in its colour.
  EXPECT_EQ(attribute_after(svg, lift_off, "xlink:href"), "#gpPt10");
  EXPECT_EQ(attribute_after(svg, svg.find("<use", lift_off), "color"), "rgb(230, 159,   0)");
}

}  // namespace
}  // namespace camdyn
