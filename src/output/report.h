// The HTML report shared by every study type (simulate, optimize, identify,
// convergence, compare), so that all reports look alike: a header with facts,
// sortable tables, gnuplot-rendered SVG plots and notes, in one self-contained
// HTML5 file that works offline (inline CSS/SVG/script, no external resources).
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "output/plot_style.h"

namespace camdyn {

/// One curve of a plot; `x` and `y` have the same length. Non-finite points
/// (and non-positive ones on a log axis) are left out and break the line.
struct Series {
  std::string label;
  std::vector<double> x, y;
  std::string style = "lines";  ///< "lines", "points", "linespoints" or "dashes" (a dashed line)
  /// What the series shows; any role but `automatic` draws it in the role's
  /// colour and dash or marker (output/plot_style.h) instead of `style` and
  /// tags its SVG group with `data-role`.
  PlotRole role = PlotRole::automatic;
};

struct Plot {
  std::string title, xlabel, ylabel;
  std::vector<Series> series;
  bool logx = false, logy = false;
  std::optional<std::pair<double, double>> xrange = std::nullopt;  ///< [min, max]; autoscaled if unset
  std::optional<std::pair<double, double>> yrange = std::nullopt;  ///< [min, max]; autoscaled if unset
  /// Drawn to scale: one unit of x and one of y take the same length on the
  /// page (gnuplot `set size ratio -1`), for shapes such as a cam.
  bool equal_axes = false;
  /// Every point drawn, up to kMaxPlotPoints per series (e.g. the last
  /// revolution), instead of each series reduced to its lowest and highest
  /// point per pixel column (output/curve_decimation.h).
  bool full_resolution = false;
};

/// Cells are preformatted text (see format_number).
struct Table {
  std::string title;
  std::vector<std::string> columns;
  std::vector<std::vector<std::string>> rows;  ///< each as long as `columns`
  bool sortable = true;                        ///< click a header to sort (numeric-aware)
  /// Cells (row, column) to highlight, e.g. the best value of a metric: drawn
  /// bold on green with a ★ (added by CSS, so sorting still reads the number).
  std::vector<std::pair<std::size_t, std::size_t>> marked = {};
  bool wrap = false;  ///< long text cells (failure reasons) wrap instead of running off to the right
};

/// The answer of a run in one sentence, shown first on the page in a banner
/// (`<div class="verdict">`, the first element of `<main>`), coloured by tone.
struct Verdict {
  enum class Tone { good, warning, bad, neutral };
  Tone tone = Tone::neutral;
  std::string headline;              ///< the answer, e.g. "stays in contact, minimum contact force 12 N at 95°"
  std::vector<std::string> details;  ///< a few supporting lines under it
};

/// Page order: title and subtitle, the verdict banner, the facts, `tables`,
/// the plots, `appendix` (big tables, solver counters), the notes.
struct Report {
  std::string title;
  std::string subtitle;
  std::vector<std::pair<std::string, std::string>> facts;  ///< key-value list at the top
  std::vector<Table> tables;
  std::vector<Plot> plots;
  std::vector<std::string> notes;
  std::optional<Verdict> verdict = std::nullopt;  ///< every study's report sets it
  std::vector<Table> appendix = {};               ///< tables after the plots
};

/// Most points a series of a full-resolution plot keeps (beyond that it is
/// reduced per column as well, with kMaxPlotPoints / 2 columns); more only
/// bloat the SVG. Other plots keep at most about 2 · kPlotColumns.
inline constexpr std::size_t kMaxPlotPoints = 20000;

/// Renders `plot` with gnuplot to an SVG element (`<svg ...>...</svg>`). If
/// gnuplot is missing or fails, returns a placeholder SVG saying "plot
/// unavailable: <reason>" and warns once per process on stderr; never throws
/// for that. The gnuplot executable is `$CAMDYN_GNUPLOT` if set, else `gnuplot`.
/// Throws std::logic_error if a series has x and y of different lengths.
std::string render_svg(const Plot& plot);

/// The whole report as one self-contained HTML5 page; all text is escaped.
/// The plots are drawn as render_svg draws them, without their titles (the
/// captions carry them), several plots to a gnuplot process (one process
/// per hardware thread, side by side), since starting gnuplot costs more
/// than drawing a plot.
std::string render_html(const Report& report);

/// render_html written atomically to `path`.
void write_report(const std::filesystem::path& path, const Report& report);

/// The series of `plot` as gnuplot gets them: non-finite points (and
/// non-positive ones on a log axis) turned into breaks, then each line
/// reduced to its lowest and highest point per pixel column
/// (decimate_per_column with kPlotColumns columns over the x range the
/// plot's series span, or its xrange); markers ("points", "linespoints")
/// and the series of a full-resolution plot only to at most about
/// kMaxPlotPoints. Series with nothing to draw are left out.
std::vector<Series> plotted_series(const Plot& plot);

/// `value` with `significant` digits for a table cell ("%.6g"); "n/a" if not finite.
std::string format_number(double value, int significant = 6);

/// `text` with & < > " ' replaced by entities.
std::string escape_html(std::string_view text);

}  // namespace camdyn
