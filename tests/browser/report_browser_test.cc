// Every study type's report.html opened in headless Chromium: the page loads
// with no console message (no script error, no failed resource), the verdict
// banner is the first element of the page's content, every figure holds a
// non-empty gnuplot SVG (not a placeholder) whose x and y axes both carry a
// unit, and the cam is drawn to scale (measured on the page) with its
// pressure angle, radius of curvature and SVAJ; every series that plays a
// role (baseline, optimised, rigid, dynamic, limit, measured, fitted) is drawn
// in that role's one colour and dash, and every event (lift-off, impact,
// seat, once-per-revolution sample) with its one marker, in every report
// type (output/plot_style.h). Skips only when Chromium is not installed
// (scripts/setup.sh installs it).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "output/plot_style.h"
#include "required_tool.h"
#include "study_paths.h"
#include "svg_scale.h"

namespace {

namespace fs = std::filesystem;
using camdyn::test::read_text;

std::string find_chromium() {
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    if (camdyn::test::on_path(name)) return name;
  }
  return {};
}

struct PageCheck {
  std::string dom;
  std::vector<std::string> console;  // the page's console messages
};

// Loads `page` headless (scripts run; virtual time lets them finish) and
// returns the DOM after load and the console messages Chromium logged.
PageCheck load(const std::string& chromium, const fs::path& page, const fs::path& dir) {
  const std::string tag = page.parent_path().filename().string() + "_" + page.stem().string();
  const pid_t pid = camdyn::test::spawn(
      {chromium, "--headless", "--disable-gpu", "--no-sandbox", "--disable-dev-shm-usage", "--enable-logging=stderr",
       "--v=0", "--virtual-time-budget=3000", "--user-data-dir=" + (dir / ("profile_" + tag)).string(), "--dump-dom",
       "file://" + fs::absolute(page).string()},
      dir / (tag + ".dom"), dir / (tag + ".log"));
  EXPECT_GT(pid, 0);
  EXPECT_EQ(camdyn::test::wait_for(pid), 0) << read_text(dir / (tag + ".log"));
  PageCheck check{read_text(dir / (tag + ".dom")), {}};
  std::istringstream log(read_text(dir / (tag + ".log")));
  for (std::string line; std::getline(log, line);)
    if (line.find(":CONSOLE") != std::string::npos) check.console.push_back(line);
  return check;
}

class ReportInBrowser : public ::testing::Test {
 protected:
  void SetUp() override {
    chromium_ = find_chromium();
    REQUIRE_TOOL(!chromium_.empty(), "chromium");
    dir_ = fs::temp_directory_path() / ("camdyn_browser_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!HasFailure() && !dir_.empty()) fs::remove_all(dir_);
  }

  // Runs `camdyn run config args...` into dir_/name and checks its report;
  // each of `roles` (data-role names) must be drawn in at least one figure.
  void check_report(const std::string& name, const std::string& config, std::vector<std::string> args,
                    std::size_t min_figures, const std::vector<std::string>& roles = {}) {
    const fs::path out = dir_ / name;
    std::vector<std::string> argv = {"run", config, "--quiet", "--out", out.string()};
    argv.insert(argv.end(), args.begin(), args.end());
    const camdyn::test::Outcome run = camdyn::test::run_camdyn(argv, dir_, name);
    ASSERT_EQ(run.code, 0) << run.err;
    const PageCheck page = load(chromium_, out / "report.html", dir_);
    for (const std::string& line : page.console) ADD_FAILURE() << name << ": console: " << line;
    EXPECT_NE(page.dom.find("</footer>"), std::string::npos) << name << ": the page did not load completely";
    std::size_t figures = 0;
    for (std::size_t at = page.dom.find("<figure"); at != std::string::npos; at = page.dom.find("<figure", at + 1)) {
      ++figures;
      const std::string figure = page.dom.substr(at, page.dom.find("</figure>", at) - at);
      const std::size_t svg = figure.find("<svg");
      ASSERT_NE(svg, std::string::npos) << name << ": figure " << figures << " has no image";
      EXPECT_NE(figure.find("<path", svg), std::string::npos) << name << ": figure " << figures << " is empty";
      EXPECT_EQ(figure.find("plot unavailable"), std::string::npos) << name << ": figure " << figures;
      EXPECT_EQ(figure.find("no data to plot"), std::string::npos) << name << ": figure " << figures;
      expect_units_on_axes(name + ": figure " + std::to_string(figures), figure);
    }
    EXPECT_GE(figures, min_figures) << name;
    expect_roles_drawn_alike(name, page.dom, roles);
    expect_verdict_first(name, page.dom);
    last_dom_ = page.dom;
    expect_cam_to_scale(name);
    expect_svaj(name);
  }

  // How one series with a data-role is drawn, as the page has it.
  struct RoleLook {
    std::string role;
    std::string stroke;  // a line's colour, "rgb(r,g,b)"; empty for a marker
    bool dashed = false;
    std::string marker;  // a marker's symbol ("gpPt10"); empty for a line
    std::string marker_colour;
  };
  static std::vector<RoleLook> role_looks(const std::string& dom) {
    namespace d = camdyn::test::svg_detail;
    std::vector<RoleLook> looks;
    for (std::size_t at = dom.find(" data-role=\""); at != std::string::npos; at = dom.find(" data-role=\"", at + 1)) {
      const std::size_t tag_start = dom.rfind('<', at);
      RoleLook look;
      look.role = d::attribute(dom.substr(tag_start, dom.find('>', at) - tag_start), "data-role");
      // The series' group runs to the next series or the end of its picture.
      const std::size_t end = std::min(dom.find("gnuplot_plot_", at), dom.find("</svg>", at));
      const std::string group = dom.substr(at, end - at);
      const std::size_t use = group.find("<use");
      if (use != std::string::npos) {
        const std::string tag = group.substr(use, group.find('>', use) - use);
        std::string href = d::attribute(tag, "xlink:href");
        if (href.empty()) href = d::attribute(tag, "href");
        look.marker = href.substr(std::min(href.size(), href.find("gpPt")));
        look.marker_colour = d::without_spaces(d::attribute(tag, "color"));
      } else {
        for (std::size_t path = group.find("<path"); path != std::string::npos; path = group.find("<path", path + 1)) {
          const std::string tag = group.substr(path, group.find('>', path) - path);
          const std::string stroke = d::without_spaces(d::attribute(tag, "stroke"));
          if (stroke.rfind("rgb(", 0) != 0) continue;
          look.stroke = stroke;
          look.dashed = !d::attribute(tag, "stroke-dasharray").empty();
          break;
        }
      }
      looks.push_back(look);
    }
    return looks;
  }

  // Every series with a role is drawn as output/plot_style.h's table says
  // (so each role looks the same in every figure of every report type), and
  // each of `expected` roles appears.
  static void expect_roles_drawn_alike(const std::string& name, const std::string& dom,
                                       const std::vector<std::string>& expected) {
    std::set<std::string> seen;
    for (const RoleLook& look : role_looks(dom)) {
      seen.insert(look.role);
      const camdyn::RoleStyle* style = nullptr;
      for (const camdyn::PlotRole role : camdyn::all_plot_roles())
        if (camdyn::role_style(role).name == look.role) style = &camdyn::role_style(role);
      ASSERT_NE(style, nullptr) << name << ": unknown role " << look.role;
      const std::string colour = camdyn::test::gnuplot_stroke(std::string(style->colour));
      if (style->point_type > 0) {
        EXPECT_EQ(look.marker, "gpPt" + std::to_string(style->point_type - 1)) << name << ": " << look.role;
        EXPECT_EQ(look.marker_colour, colour) << name << ": " << look.role;
      } else {
        EXPECT_EQ(look.stroke, colour) << name << ": " << look.role;
        EXPECT_EQ(look.dashed, style->dashtype != 1) << name << ": " << look.role;
        EXPECT_TRUE(look.marker.empty()) << name << ": " << look.role << " drawn with markers";
      }
    }
    for (const std::string& role : expected) EXPECT_TRUE(seen.count(role)) << name << ": no series in role " << role;
  }

  // One x and one y axis label, each with its unit in brackets.
  static void expect_units_on_axes(const std::string& where, const std::string& figure) {
    const camdyn::test::AxisLabels labels = camdyn::test::axis_labels(figure.substr(0, figure.find("<figcaption")));
    EXPECT_EQ(labels.x.size(), 1u) << where << ": x axis labels";
    EXPECT_EQ(labels.y.size(), 1u) << where << ": y axis labels";
    for (const auto* axis : {&labels.x, &labels.y})
      for (const std::string& label : *axis)
        EXPECT_TRUE(camdyn::test::has_unit(label)) << where << ": no unit on the axis '" << label << "'";
  }

  // The figure of the report just checked whose caption starts with `title`
  // ("Figure N. " left out): its SVG and its caption.
  struct Figure {
    std::string svg, caption;
  };
  std::optional<Figure> figure_titled(const std::string& title) const {
    for (std::size_t at = last_dom_.find("<figcaption>"); at != std::string::npos;
         at = last_dom_.find("<figcaption>", at + 1)) {
      const std::size_t text = last_dom_.find(". ", at) + 2;
      if (last_dom_.compare(text, title.size(), title) != 0) continue;
      const std::size_t figure = last_dom_.rfind("<figure", at);
      return Figure{last_dom_.substr(figure, at - figure),
                    last_dom_.substr(text, last_dom_.find("</figcaption>", at) - text)};
    }
    return std::nullopt;
  }

  // The verdict banner is the first element of <main> (before the facts, the
  // tables and the figures) and says something.
  static void expect_verdict_first(const std::string& name, const std::string& dom) {
    const std::size_t main = dom.find("<main>");
    ASSERT_NE(main, std::string::npos) << name;
    const std::size_t first = dom.find('<', main + 6);
    EXPECT_EQ(dom.compare(first, 19, "<div class=\"verdict"), 0) << name << ": " << dom.substr(first, 80);
    const std::size_t headline = dom.find("<p class=\"headline\">", first);
    ASSERT_NE(headline, std::string::npos) << name;
    EXPECT_NE(dom.compare(headline + 21, 4, "</p>"), 0) << name << ": empty verdict";
  }

  // The report just checked has the cam drawn to scale: in the figure whose
  // caption says so, the base circle is as wide as it is high on the page,
  // as the browser lays it out; its pressure angle and radius of curvature
  // are plotted.
  void expect_cam_to_scale(const std::string& name) const {
    const std::optional<Figure> cam = figure_titled("Cam and follower to scale at cam angle");
    ASSERT_TRUE(cam.has_value()) << name << ": no cam drawn to scale";
    const auto base = camdyn::test::series_box(cam->svg, "base circle");
    ASSERT_TRUE(base.has_value()) << name << ": no base circle in the cam plot";
    EXPECT_GT(base->width(), 20.0) << name << ": the base circle is a dot";
    EXPECT_NEAR(base->width(), base->height(), 1.0) << name << ": the cam is not drawn to scale";
    for (const char* what : {"Pressure angle against cam angle", "Radius of curvature of the cam contour"})
      EXPECT_TRUE(figure_titled(what).has_value()) << name << ": " << what;
  }

  // The law's lift, velocity, acceleration and jerk, each against cam angle
  // in degrees and in a unit of its own kind: a length or an angle, then per
  // second (at a speed) or per radian of cam angle, squared, cubed.
  void expect_svaj(const std::string& name) const {
    const char* titles[] = {"Lift of the follower", "Velocity of the follower", "Acceleration of the follower",
                            "Jerk of the follower"};
    const char* powers[] = {"", "", "²", "³"};
    for (int n = 0; n < 4; ++n) {
      const std::optional<Figure> f = figure_titled(titles[n]);
      ASSERT_TRUE(f.has_value()) << name << ": no " << titles[n];
      const camdyn::test::AxisLabels labels = camdyn::test::axis_labels(f->svg);
      ASSERT_EQ(labels.x.size(), 1u) << name << ": " << titles[n];
      ASSERT_EQ(labels.y.size(), 1u) << name << ": " << titles[n];
      EXPECT_EQ(labels.x[0], "cam angle [deg]") << name << ": " << titles[n];
      const std::string& y = labels.y[0];
      const std::string unit = y.substr(y.rfind(" [") + 2, y.size() - y.rfind(" [") - 3);
      if (n == 0) {
        EXPECT_TRUE(unit == "µm" || unit == "mm" || unit == "m" || unit == "deg") << name << ": lift in " << y;
      } else {
        const bool timed = f->caption.find(" rpm") != std::string::npos;
        const std::string per = std::string(timed ? "/s" : "/rad") + powers[n];
        EXPECT_TRUE(unit.ends_with(per)) << name << ": " << titles[n] << " in " << y << " (" << f->caption << ")";
      }
    }
  }

  std::string last_dom_;

  std::string chromium_;
  fs::path dir_;
};

// The harness itself: a page with a script error must be caught.
TEST_F(ReportInBrowser, HarnessSeesConsoleErrors) {
  std::ofstream(dir_ / "bad.html") << "<!DOCTYPE html><html><body><script>nosuch();</script></body></html>";
  const PageCheck page = load(chromium_, dir_ / "bad.html", dir_);
  ASSERT_EQ(page.console.size(), 1u);
  EXPECT_NE(page.console[0].find("nosuch is not defined"), std::string::npos);
}

TEST_F(ReportInBrowser, Simulate) {
  check_report("simulate", kStudies + "quickstart.json", {"--set", "simulation.cycles=2"}, 3,
               {"dynamic", "rigid", "lift-off", "impact"});
  EXPECT_NE(last_dom_.find("m/s³"), std::string::npos) << "the SVAJ at the scene's speed";
}

TEST_F(ReportInBrowser, SimulateContourCam) {
  // 4 time-series plots, the contour against its points, the fit residual.
  check_report("contour", kStudies + "contour_cam/measured_roller_cam.json", {"--set", "simulation.cycles=2"}, 6,
               {"measured", "fitted", "dynamic", "rigid"});
}

TEST_F(ReportInBrowser, SimulateValvetrainWithSeat) {
  // The train's figures (its seatings marked; its last revolution with the
  // angle where the verdict says it lets go), the valve lift with its checking heights.
  check_report("valvetrain", kStudies + "valvetrain/pushrod_rocker.json",
               {"--set", "simulation.cycles=2", "--set", R"(outputs.valvetrain={"crank_ratio": 2})"}, 6,
               {"dynamic", "rigid", "seat", "limit", "lift-off"});
}

TEST_F(ReportInBrowser, Convergence) {
  std::ofstream(dir_ / "convergence.json") << R"({
    "extends": ")" << kStudies << R"(quickstart.json", "name": "convergence", "study": "convergence",
    "simulation": { "cycles": 2, "discard_cycles": 1 },
    "methods": ["cvode_bdf", "cvode_adams"], "tolerances": [1e-5, 1e-6],
    "reference": { "method": "cvode_bdf", "rtol": 1e-9 } })";
  check_report("convergence", (dir_ / "convergence.json").string(), {}, 1);
}

TEST_F(ReportInBrowser, Compare) {
  std::ofstream(dir_ / "compare.json") << R"({
    "extends": ")" << kStudies << R"(quickstart.json", "name": "compare", "study": "compare",
    "simulation": { "cycles": 2, "discard_cycles": 1 },
    "cases": [ { "name": "cycloidal" }, { "name": "soft", "set": ["mechanism.contact.stiffness=1e4"] },
               { "name": "heavy", "set": ["mechanism.follower.mass=0.45"] } ],
    "grid": { "mechanism.cam.rpm": [1000, 1300], "mechanism.contact.restitution": [0.5, 0.8] },
    "overlays": [ { "mechanism.cam.rpm": 1300 } ] })";
  check_report("compare", (dir_ / "compare.json").string(), {}, 5);
  // The big results table comes after the figures, in a box that scrolls.
  EXPECT_LT(last_dom_.rfind("<figure"), last_dom_.find("<h2>Results")) << "compare";
}

TEST_F(ReportInBrowser, Optimize) {
  check_report("optimize", kStudies + "optimize_jump.json",
               {"--set", "optimizer.max_evaluations=4", "--set", "simulation.cycles=2"}, 1, {"baseline", "optimised"});
}

TEST_F(ReportInBrowser, Periodic) {
  // The phase plane, the contact force over a period, the multipliers, the Newton residuals.
  check_report("periodic", kStudies + "periodic/bouncing_ball.json", {}, 4, {"dynamic", "section", "limit"});
}

TEST_F(ReportInBrowser, JumpMap) {
  // Impact speed, Poincaré section and impact angles against rpm.
  check_report("jump_map", kStudies + "quickstart.json",
               {"--set", "study=jump_map", "--set",
                R"(jump_map={"low_rpm": 1000, "high_rpm": 1300, "speeds": 4, "ranges": 2, "transient_revolutions": 5,
                   "samples": 5})",
                "--set", R"(periodic={"max_period": 1, "lyapunov_revolutions": 10})"},
               3);
}

TEST_F(ReportInBrowser, SpeedLimit) {
  // Separation and the smallest contact force against speed.
  check_report("speed_limit", kStudies + "quickstart.json",
               {"--set", "study=speed_limit", "--set",
                R"(speed_limit={"low_rpm": 1000, "high_rpm": 1300, "scan": 3, "tolerance_rpm": 50})", "--set",
                "simulation.cycles=2"},
               2);
}

TEST_F(ReportInBrowser, Identify) {
  check_report("identify", kStudies + "identify_drop/identify_drop.json", {"--set", "solver.max_iterations=2"}, 1,
               {"measured", "fitted"});
}

}  // namespace
