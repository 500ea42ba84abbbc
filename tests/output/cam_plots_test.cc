// The cam plots of the reports (output/cam_plots.h): the cam drawn to scale
// (measured on the SVG gnuplot draws), the limit lines, the SVAJ's units.
#include "output/cam_plots.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "cli_run.h"
#include "dynamics/model.h"
#include "gnuplot.h"
#include "io/config.h"
#include "svg_scale.h"

namespace camdyn {
namespace {

// A round shape drawn to scale is as wide as it is high to within the
// rounding of gnuplot's coordinates (2 decimals) and of the line's ends.
constexpr double kPixelTolerance = 1.0;  // [px]

Model roller_cam(const std::string& limits = "{}", const std::string& speed = R"("rpm": 1200)",
                 const std::string& simulation = "{}") {
  const Json doc = Json::parse(R"({"name": "plots", "mechanism": {
      "cam": {"base_radius": 0.04, )" +
                               speed + R"(, "limits": )" + limits + R"(, "motion_law": {"segments": [
        {"type": "rise", "law": "cycloidal", "end_deg": 120, "lift": 0.02}, {"type": "dwell", "end_deg": 180},
        {"type": "return", "law": "cycloidal", "end_deg": 300, "lift": 0.02}, {"type": "dwell", "end_deg": 360}]}},
      "follower": {"shape": {"type": "roller", "radius": 0.01}, "mass": 0.3,
                   "spring": {"stiffness": 5000, "preload": 40}},
      "contact": {"stiffness": 1e10}}, "simulation": )" +
                               simulation + "}");
  return build_model(scene_from_json(doc, ConfigSource{"test.json", "."}), "test.json");
}

// The palette of output/report.cc, in linetype order.
const char* const kPalette[] = {"#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9"};

// The measurement itself: a circle is round on the page only when asked for.
TEST(CamPlots, EqualAxesMakeACircleRoundOnThePage) {
  REQUIRE_GNUPLOT();
  Plot plot;
  Series unit{"unit circle", {}, {}, "lines"};
  for (int i = 0; i <= 360; ++i) {
    unit.x.push_back(std::cos(i * std::numbers::pi / 180.0));
    unit.y.push_back(std::sin(i * std::numbers::pi / 180.0));
  }
  plot.series.push_back(unit);
  const auto free = test::stroke_box(render_svg(plot), test::gnuplot_stroke(kPalette[0]));
  ASSERT_TRUE(free.has_value());
  EXPECT_GT(free->width(), free->height() + 50.0) << "an autoscaled 800×450 plot stretches the circle";
  plot.equal_axes = true;
  const auto round = test::stroke_box(render_svg(plot), test::gnuplot_stroke(kPalette[0]));
  ASSERT_TRUE(round.has_value());
  EXPECT_NEAR(round->width(), round->height(), kPixelTolerance);
}

// The cam layout: equal scales, and the base circle measures the same number
// of pixels per millimetre across as up and down.
TEST(CamPlots, CamLayoutIsDrawnToScale) {
  const Model model = roller_cam();
  const Plot plot = cam_layout_plot({{"cam", &model}}, 0.5);
  EXPECT_TRUE(plot.equal_axes);
  ASSERT_GE(plot.series.size(), 4u);
  EXPECT_EQ(plot.series[0].label, "cam contour");
  EXPECT_EQ(plot.series[1].label, "pitch curve");
  EXPECT_EQ(plot.series[2].label, "base circle");
  EXPECT_EQ(plot.xlabel, "x [mm]");
  EXPECT_EQ(plot.ylabel, "y [mm]");
  REQUIRE_GNUPLOT();
  const std::string svg = render_svg(plot);
  const auto base = test::stroke_box(svg, test::gnuplot_stroke(kPalette[2]));
  ASSERT_TRUE(base.has_value()) << svg.substr(0, 500);
  EXPECT_NEAR(base->width(), base->height(), kPixelTolerance);
  // The contour spans r_b + lift upwards at the angle drawn, more than the base circle.
  const auto contour = test::stroke_box(svg, test::gnuplot_stroke(kPalette[0]));
  ASSERT_TRUE(contour.has_value());
  EXPECT_GT(contour->width(), base->width());
}

TEST(CamPlots, PressureAngleAndCurvatureCarryTheLimits) {
  const Model model = roller_cam(R"({"max_pressure_angle_deg": 35, "min_radius_of_curvature": 0.012})");
  const CamLimitsConfig limits{35.0, 0.012, std::nullopt, std::nullopt};
  const std::vector<Plot> plots = cam_plots(model, limits, 1200.0);
  ASSERT_EQ(plots.size(), 7u);  // layout, φ, ρ, s, v, a, j
  const Plot& phi = plots[1];
  ASSERT_EQ(phi.series.size(), 3u);
  EXPECT_EQ(phi.series[1].y, (std::vector<double>{35.0, 35.0}));
  EXPECT_EQ(phi.series[2].y, (std::vector<double>{-35.0, -35.0}));
  double largest = 0.0;
  for (double y : phi.series[0].y) largest = std::max(largest, std::abs(y));
  EXPECT_NEAR(largest, model.geometry.max_pressure_angle_deg, 0.05);  // 0.5° sampling of a smooth maximum
  const Plot& rho = plots[2];
  EXPECT_EQ(rho.series[1].y, (std::vector<double>{12.0, 12.0}));
  ASSERT_TRUE(rho.yrange.has_value());
  EXPECT_LT(rho.yrange->first, 12.0);
}

TEST(CamPlots, SvajHasUnitsAndScalesWithTheCamSpeed) {
  const Model model = roller_cam();
  const std::vector<Plot> timed = svaj_plots({{"cam", &model}}, 1200.0);
  ASSERT_EQ(timed.size(), 4u);
  EXPECT_EQ(timed[0].ylabel, "lift [mm]");  // a lift of millimetres (output/plot_style.h)
  EXPECT_EQ(timed[1].ylabel, "Velocity [m/s]");
  EXPECT_EQ(timed[2].ylabel, "Acceleration [m/s²]");
  EXPECT_EQ(timed[3].ylabel, "Jerk [m/s³]");
  const double omega = 1200.0 * 2.0 * std::numbers::pi / 60.0;
  const std::size_t i = 100;  // 50°, on the rise
  const double theta = timed[1].series[0].x[i] * std::numbers::pi / 180.0;
  const LawSample l = model.law->eval(theta);
  EXPECT_DOUBLE_EQ(timed[0].series[0].y[i], l.s * 1e3);
  EXPECT_DOUBLE_EQ(timed[1].series[0].y[i], l.ds * omega);
  EXPECT_DOUBLE_EQ(timed[2].series[0].y[i], l.d2s * omega * omega);
  EXPECT_DOUBLE_EQ(timed[3].series[0].y[i], l.d3s * omega * omega * omega);
  const std::vector<Plot> still = svaj_plots({{"cam", &model}}, 0.0);
  EXPECT_EQ(still[2].ylabel, "d²s/dθ² [mm/rad²]");
  EXPECT_DOUBLE_EQ(still[2].series[0].y[i], l.d2s * 1e3);
}

// Two designs (optimise's baseline and optimised): one labelled curve each, in order.
TEST(CamPlots, SvajOverlaysSeveralDesigns) {
  const Model a = roller_cam(), b = roller_cam();
  const std::vector<Plot> plots = svaj_plots({{"baseline", &a}, {"optimised", &b}}, 0.0);
  ASSERT_EQ(plots.size(), 4u);
  for (const Plot& p : plots) {
    ASSERT_EQ(p.series.size(), 2u) << p.title;
    EXPECT_EQ(p.series[0].label, "baseline");
    EXPECT_EQ(p.series[1].label, "optimised");
    EXPECT_EQ(p.series[0].y, p.series[1].y);
  }
}

// A cam held still (a drop test) is drawn as it stands, not where it would push hardest.
TEST(CamPlots, StillCamIsDrawnAtItsInitialAngle) {
  const Model turning = roller_cam();
  EXPECT_NE(cam_plots(turning, CamLimitsConfig{}, 0.0)[0].title.find(
                "at cam angle " + format_number(turning.geometry.max_pressure_angle_at_deg, 4) + "°"),
            std::string::npos);
  const Model still =
      roller_cam("{}", R"("rpm": 0, "initial_angle_deg": 330)", R"({"duration": 1e-3, "output_step": 1e-5})");
  EXPECT_NE(cam_plots(still, CamLimitsConfig{}, 0.0)[0].title.find("at cam angle 330°"), std::string::npos);
}

// A report over several cams says which one it draws, in every title.
TEST(CamPlots, CaptionNamesTheDesignInEveryTitle) {
  const Model model = roller_cam();
  for (const Plot& p : cam_plots(model, CamLimitsConfig{}, 0.0, "base design"))
    EXPECT_TRUE(p.title.ends_with(" — base design")) << p.title;
}

}  // namespace
}  // namespace camdyn
