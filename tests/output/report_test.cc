#include "output/report.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_run.h"
#include "gnuplot.h"
#include "output/curve_decimation.h"

namespace camdyn {
namespace {

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

Plot make_plot(std::string title, std::string xlabel, std::string ylabel) {
  Plot plot;
  plot.title = std::move(title);
  plot.xlabel = std::move(xlabel);
  plot.ylabel = std::move(ylabel);
  return plot;
}

Series make_series(std::string label, std::vector<double> x, std::vector<double> y, std::string style = "lines") {
  Series s;
  s.label = std::move(label);
  s.x = std::move(x);
  s.y = std::move(y);
  s.style = std::move(style);
  return s;
}

Table make_table(std::string title, std::vector<std::string> columns, std::vector<std::vector<std::string>> rows,
                 bool sortable = true) {
  Table t;
  t.title = std::move(title);
  t.columns = std::move(columns);
  t.rows = std::move(rows);
  t.sortable = sortable;
  return t;
}

Plot sine_plot() {
  Plot plot = make_plot("Follower lift", "cam angle [deg]", "lift [m]");
  Series s = make_series("follower_position", {}, {});
  for (int i = 0; i <= 360; ++i) {
    s.x.push_back(i);
    s.y.push_back(0.01 * (1.0 - std::cos(i * 3.14159265358979 / 180.0)));
  }
  plot.series.push_back(s);
  return plot;
}

// Control characters from the inputs are escaped like the markup
// (common/printable_text.h): no raw ESC in the page, nor invalid XML in its SVGs.
TEST(EscapeHtml, ControlCharactersAreWrittenAsVisibleEscapes) {
  EXPECT_EQ(escape_html("a\x1b]0;t\x07<b>&\"'"), "a\\x1b]0;t\\x07&lt;b&gt;&amp;&quot;&#39;");
  EXPECT_EQ(escape_html("θ = 90°\n"), "θ = 90°\n");
}

TEST(Report, GnuplotSvgHasAPath) {
  REQUIRE_GNUPLOT();
  const std::string svg = render_svg(sine_plot());
  EXPECT_EQ(svg.rfind("<svg", 0), 0u) << svg.substr(0, 200);  // no XML prolog: it is inlined
  EXPECT_NE(svg.find("<path"), std::string::npos);
  EXPECT_EQ(svg.find("plot unavailable"), std::string::npos);
  // The label is printed literally: '_' is not an enhanced-text subscript.
  EXPECT_NE(svg.find("follower_position"), std::string::npos);
}

TEST(Report, LogAxesDropNonPositiveValues) {
  REQUIRE_GNUPLOT();
  Plot plot = make_plot("Work precision", "rtol", "error");
  plot.logx = plot.logy = true;
  plot.series.push_back(make_series("bdf", {1e-4, 1e-6, 0.0, 1e-8, -1.0}, {1e-3, 0.0, 1e-5, 1e-7, 1.0}, "linespoints"));
  const std::string svg = render_svg(plot);
  EXPECT_NE(svg.find("<path"), std::string::npos);
  EXPECT_EQ(svg.find("plot unavailable"), std::string::npos) << svg;
}

TEST(Report, EmptyOrUndrawableSeriesGiveAPlaceholder) {
  Plot plot = make_plot("Nothing", "x", "y");
  plot.logy = true;
  plot.series.push_back(make_series("empty", {}, {}));
  plot.series.push_back(make_series("negative", {1.0, 2.0}, {-1.0, 0.0}));
  const std::string svg = render_svg(plot);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("no data"), std::string::npos);
}

TEST(Report, MismatchedSeriesLengthsAreAProgrammingError) {
  Plot plot = make_plot("Bad", "x", "y");
  plot.series.push_back(make_series("s", {1.0, 2.0}, {1.0}));
  EXPECT_THROW(render_svg(plot), std::logic_error);
}

TEST(Report, MissingGnuplotGivesAPlaceholderNotAnException) {
  ::setenv("CAMDYN_GNUPLOT", "/nonexistent/gnuplot", 1);
  std::string svg;
  EXPECT_NO_THROW(svg = render_svg(sine_plot()));
  ::unsetenv("CAMDYN_GNUPLOT");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("plot unavailable"), std::string::npos);
}

TEST(Report, PlottedSeriesAreReducedPerPixelColumnAndKeepThePeak) {
  Plot plot = make_plot("Contact force", "time [s]", "force [N]");
  Series s = make_series("force", {}, {});
  const std::size_t n = 200000;
  for (std::size_t i = 0; i < n; ++i) {
    s.x.push_back(static_cast<double>(i));
    s.y.push_back(std::sin(static_cast<double>(i) * 1e-3));
  }
  const std::size_t peak = 123457;  // a one-sample impact spike
  s.y[peak] = 1000.0;
  plot.series.push_back(s);
  plot.series.push_back(make_series("empty", {}, {}));  // nothing to draw: left out
  const std::vector<Series> drawn = plotted_series(plot);
  ASSERT_EQ(drawn.size(), 1u);
  const Series& d = drawn.front();
  EXPECT_LE(d.x.size(), 2 * kPlotColumns + 2);
  EXPECT_GT(d.x.size(), kPlotColumns);
  ASSERT_EQ(d.x.size(), d.y.size());
  EXPECT_EQ(*std::max_element(d.y.begin(), d.y.end()), 1000.0);
  EXPECT_DOUBLE_EQ(d.x.front(), 0.0);
  EXPECT_DOUBLE_EQ(d.x.back(), static_cast<double>(n - 1));
  EXPECT_TRUE(std::is_sorted(d.x.begin(), d.x.end()));
}

TEST(Report, FullResolutionPlotsKeepEveryPointUpToTheCap) {
  Plot plot = make_plot("Last revolution", "cam angle [deg]", "force [N]");
  plot.full_resolution = true;
  plot.xrange = std::make_pair(0.0, 360.0);
  Series s = make_series("force", {}, {});
  for (int i = 0; i <= 3600; ++i) {  // 0.1° steps
    s.x.push_back(0.1 * i);
    s.y.push_back(std::cos(0.1 * i));
  }
  plot.series.push_back(s);
  EXPECT_EQ(plotted_series(plot).front().x, s.x);
  plot.full_resolution = false;
  EXPECT_LE(plotted_series(plot).front().x.size(), 2 * kPlotColumns + 2);
  // Far beyond the cap even a full-resolution plot is reduced.
  plot.full_resolution = true;
  plot.xrange.reset();
  for (int i = 3601; i <= 100000; ++i) {
    plot.series[0].x.push_back(0.1 * i);
    plot.series[0].y.push_back(std::cos(0.1 * i));
  }
  EXPECT_LE(plotted_series(plot).front().x.size(), kMaxPlotPoints);
}

TEST(Report, DecimatedPlotStillReachesThePeak) {
  REQUIRE_GNUPLOT();
  Plot plot = make_plot("Contact force", "time [s]", "force [N]");
  Series s = make_series("contact_force", {}, {});
  for (std::size_t i = 0; i < 200000; ++i) {
    s.x.push_back(static_cast<double>(i) * 1e-5);
    s.y.push_back(i == 150001 ? 1000.0 : 1.0);
  }
  plot.series.push_back(s);
  const std::string svg = render_svg(plot);
  EXPECT_LT(svg.size(), 2'000'000u);
  // The autoscaled y axis reaches 1000 only if the spike was kept.
  EXPECT_NE(svg.find(" 1000<"), std::string::npos);  // the top tic label
}

Report sample_report() {
  Report r;
  r.title = "roller <script>alert(1)</script>";
  r.subtitle = "simulate & check";
  r.facts = {{"rpm", "1200"}, {"name", "a\"b'c"}};
  r.tables.push_back(make_table("Metrics", {"metric", "value <unit>"},
                                {{"peak_contact_force", "1234.5"}, {"separation_fraction", "0"}}));
  r.tables.push_back(make_table("Solver", {"steps", "rhs_evaluations"}, {{"10", "20"}}, false));
  r.plots.push_back(sine_plot());
  Plot second = sine_plot();
  second.title = "Second <b>plot</b>";
  r.plots.push_back(second);
  r.notes = {"note with <script>evil()</script>"};
  return r;
}

TEST(Report, HtmlHasHeadersEscapedTextAndOneSvgPerPlot) {
  const Report r = sample_report();
  const std::string html = render_html(r);
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  for (const auto& table : r.tables) {
    for (const auto& column : table.columns) {
      // Built by appending: GCC 12 at -O3 flags `"literal" + std::string&&` with a false -Wrestrict.
      std::string cell = ">";
      cell += escape_html(column);
      cell += "</th>";
      EXPECT_NE(html.find(cell), std::string::npos) << column;
    }
  }
  EXPECT_EQ(html.find("<script>alert"), std::string::npos);
  EXPECT_EQ(html.find("<script>evil"), std::string::npos);
  EXPECT_NE(html.find("&lt;script&gt;alert(1)&lt;/script&gt;"), std::string::npos);
  EXPECT_NE(html.find("a&quot;b&#39;c"), std::string::npos);
  EXPECT_EQ(count(html, "<svg"), r.plots.size());
  EXPECT_EQ(count(html, "<figure"), r.plots.size());
  EXPECT_EQ(count(html, "<table class=\"sortable\">"), 1u);
  // Only the page's own sorting script; nothing fetched from elsewhere.
  EXPECT_EQ(count(html, "<script"), 1u);
  EXPECT_EQ(html.find("src="), std::string::npos);
  EXPECT_EQ(html.find("http://www.w3.org/1999/xhtml"), std::string::npos);
}

TEST(Report, HtmlSvgIdsAreUniqueAcrossPlots) {
  REQUIRE_GNUPLOT();
  const std::string html = render_html(sample_report());
  EXPECT_NE(html.find("id='fig1-gpPt0'"), std::string::npos);
  EXPECT_NE(html.find("id='fig2-gpPt0'"), std::string::npos);
  EXPECT_EQ(html.find("id='gpPt0'"), std::string::npos);
  EXPECT_EQ(html.find("href='#gpPt"), std::string::npos);
}

// `svg` without its empty groups (`<g ...>` directly followed by `</g>`):
// gnuplot's SVG terminal opens one before drawing anything whose attributes
// depend on what it drew last, and nothing in it is drawn.
std::string without_empty_groups(std::string svg) {
  for (std::size_t p = svg.find("<g "); p != std::string::npos; p = svg.find("<g ", p)) {
    const std::size_t open_end = svg.find(">\n", p);
    if (open_end != std::string::npos && svg.compare(open_end + 2, 5, "</g>\n") == 0) {
      svg.erase(p, open_end + 7 - p);
    } else {
      ++p;
    }
  }
  return svg;
}

// A report draws several plots in one gnuplot process; each picture must be
// the one the plot gives on its own (nothing a log axis, a range or equal
// axes set carries over to the next plot), and a plot gnuplot cannot draw
// must not take the others of its process with it.
TEST(Report, PlotsDrawnTogetherLookAsEachDrawnAlone) {
  REQUIRE_GNUPLOT();
  Report r;
  Plot log = sine_plot();
  log.title = "log";
  log.logy = true;
  log.yrange = std::make_pair(1e-6, 1.0);
  Plot to_scale = sine_plot();
  to_scale.title = "to scale";
  to_scale.equal_axes = true;
  to_scale.xrange = std::make_pair(-10.0, 400.0);
  Plot plain = sine_plot();
  plain.title = "plain";
  Plot empty = make_plot("empty", "x", "y");
  empty.series.push_back(make_series("nothing", {}, {}));
  for (int k = 0; k < 3; ++k) {
    r.plots.push_back(log);
    r.plots.push_back(plain);
    r.plots.push_back(to_scale);
    r.plots.push_back(empty);
    r.plots.push_back(plain);
  }
  const std::string html = render_html(r);
  for (std::size_t i = 0; i < r.plots.size(); ++i) {
    Plot untitled = r.plots[i];
    untitled.title.clear();
    // The page's copy, with its figure's id prefix taken out again.
    const std::string prefix = "fig" + std::to_string(i + 1) + "-";
    const std::size_t begin = html.find("<svg", html.find("<figure id=\"figure-" + std::to_string(i + 1) + "\">"));
    const std::size_t end = html.find("</svg>", begin);
    ASSERT_NE(end, std::string::npos);
    std::string on_page = html.substr(begin, end - begin);
    for (std::size_t p = on_page.find(prefix); p != std::string::npos; p = on_page.find(prefix, p))
      on_page.erase(p, prefix.size());
    const std::string alone = render_svg(untitled);
    EXPECT_EQ(without_empty_groups(on_page), without_empty_groups(alone.substr(0, alone.find("</svg>"))))
        << "figure " << i + 1 << " (" << r.plots[i].title << ")";
  }
}

TEST(Report, APlotGnuplotRejectsLeavesTheOthersDrawn) {
  REQUIRE_GNUPLOT();
  // A fake gnuplot that fails whenever it is given more than one plot (its
  // script then holds a `reset`): every plot is drawn again on its own.
  const std::string fake =
      (std::filesystem::temp_directory_path() / ("camdyn-fake-gnuplot-" + std::to_string(::getpid()) + ".sh")).string();
  {
    std::ofstream script(fake);
    script << "#!/bin/sh\nif grep -q '^reset' \"$1\"; then echo 'batch refused' >&2; exit 1; fi\nexec gnuplot \"$1\"\n";
  }
  std::filesystem::permissions(fake, std::filesystem::perms::owner_all);
  ::setenv("CAMDYN_GNUPLOT", fake.c_str(), 1);
  Report r;
  // More plots than threads: every process gets several.
  for (unsigned k = 0; k < 2 * std::max(1u, std::thread::hardware_concurrency()) + 1; ++k)
    r.plots.push_back(sine_plot());
  const std::string html = render_html(r);
  const std::size_t labels_per_plot = count(render_svg(sine_plot()), "follower_position");
  ::unsetenv("CAMDYN_GNUPLOT");
  std::filesystem::remove(fake);
  EXPECT_EQ(count(html, "<svg"), r.plots.size());
  EXPECT_EQ(count(html, "plot unavailable"), 0u);
  EXPECT_GT(labels_per_plot, 0u);
  EXPECT_EQ(count(html, "follower_position"), labels_per_plot * r.plots.size());
}

TEST(Report, RaggedTableRowIsAProgrammingError) {
  Report r;
  r.tables.push_back(make_table("T", {"a", "b"}, {{"1"}}));
  EXPECT_THROW(render_html(r), std::logic_error);
}

TEST(Report, FormatNumber) {
  EXPECT_EQ(format_number(1234.56789), "1234.57");
  EXPECT_EQ(format_number(1e-9, 3), "1e-09");
  EXPECT_EQ(format_number(std::nan("")), "n/a");
}

}  // namespace
}  // namespace camdyn
