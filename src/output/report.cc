#include "output/report.h"

#include <camdyn/version.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <iterator>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <vector>

#include "common/constants.h"
#include "common/parallel.h"
#include "common/printable_text.h"
#include "io/atomic_file.h"
#include "output/curve_decimation.h"

extern char** environ;  // NOLINT: POSIX, passed on to gnuplot

namespace camdyn {
namespace {

bool is_break(double x, double y) { return std::isnan(x) || std::isnan(y); }

// ------------------------------------------------------------------ gnuplot

// A gnuplot single-quoted string: only the quote itself needs escaping (doubled).
// Control characters (a newline would end the command) become spaces.
std::string gp_quote(std::string_view s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') {
      out += "''";
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += ' ';
    } else {
      out += c;
    }
  }
  out += '\'';
  return out;
}

std::string gp_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Non-finite points, and non-positive ones on a log axis, cannot be drawn:
// they become a break in the line, so that no segment bridges a gap in the data.
Series drawable_points(const Series& s, bool logx, bool logy) {
  Series out{s.label, {}, {}, s.style, s.role};
  out.x.reserve(s.x.size());
  out.y.reserve(s.y.size());
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    const double x = s.x[i], y = s.y[i];
    const bool ok = std::isfinite(x) && std::isfinite(y) && !(logx && x <= 0.0) && !(logy && y <= 0.0);
    if (ok) {
      out.x.push_back(x);
      out.y.push_back(y);
    } else if (!out.x.empty() && !is_break(out.x.back(), out.y.back())) {
      out.x.push_back(kBreak);
      out.y.push_back(kBreak);
    }
  }
  if (!out.x.empty() && is_break(out.x.back(), out.y.back())) {
    out.x.pop_back();
    out.y.pop_back();
  }
  return out;
}

// A private directory for one gnuplot run, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "camdyn-plot-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) {
      throw std::runtime_error("cannot create a temporary directory in " +
                               std::filesystem::temp_directory_path().string() + ": " + std::strerror(errno));
    }
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

std::string read_all(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// gnuplot's messages collapsed to one short line, for the placeholder and the warning.
std::string one_line(const std::string& text, std::size_t max_chars = 300) {
  std::string out;
  for (char c : text) {
    const bool space = std::isspace(static_cast<unsigned char>(c)) != 0;
    if (space && (out.empty() || out.back() == ' ')) continue;
    out += space ? ' ' : c;
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  if (out.size() > max_chars) out = out.substr(0, max_chars) + "...";
  return out;
}

// Runs `program script` with stdin from /dev/null and stdout+stderr to `log`.
// Returns an empty string on success, else the reason.
std::string run_gnuplot(const std::string& program, const std::filesystem::path& script,
                        const std::filesystem::path& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_adddup2(&actions, 2, 1);
  std::string script_arg = script.string();
  std::string program_arg = program;
  char* argv[] = {program_arg.data(), script_arg.data(), nullptr};
  pid_t pid = 0;
  const int rc = ::posix_spawnp(&pid, program.c_str(), &actions, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return "cannot run '" + program + "': " + std::strerror(rc);

  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return std::string("waiting for gnuplot failed: ") + std::strerror(errno);
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return {};
  const std::string messages = one_line(read_all(log));
  std::string reason = WIFEXITED(status) ? "gnuplot exited with status " + std::to_string(WEXITSTATUS(status))
                                         : "gnuplot killed by signal " + std::to_string(WTERMSIG(status));
  if (!messages.empty()) reason += ": " + messages;
  return reason;
}

std::string placeholder_svg(const std::string& title, const std::string& message) {
  std::string svg =
      "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 800 450\" role=\"img\">\n"
      "<title>" +
      escape_html(title) +
      "</title>\n"
      "<rect x=\"0.5\" y=\"0.5\" width=\"799\" height=\"449\" fill=\"#fafafa\" stroke=\"#cccccc\"/>\n";
  if (!title.empty()) {
    svg +=
        "<text x=\"400\" y=\"40\" text-anchor=\"middle\" font-family=\"sans-serif\" "
        "font-size=\"14\" fill=\"#333333\">" +
        escape_html(title) + "</text>\n";
  }
  svg +=
      "<text x=\"400\" y=\"225\" text-anchor=\"middle\" font-family=\"sans-serif\" "
      "font-size=\"14\" fill=\"#777777\">" +
      escape_html(message) + "</text>\n</svg>\n";
  return svg;
}

std::string unavailable(std::string_view title, const std::string& reason) {
  // One warning per process: a report with ten plots should not print ten.
  static std::atomic<bool> warned{false};
  if (!warned.exchange(true)) {
    std::cerr << "camdyn: warning: plot unavailable: " << reason << " (reports will show placeholders)\n";
  }
  return placeholder_svg(std::string(title), "plot unavailable: " + reason);
}

// Data for gnuplot: one "x y" line per point, a blank line for a break.
void write_data(const std::filesystem::path& path, const Series& s) {
  std::ofstream out(path);
  char buf[64];
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    if (is_break(s.x[i], s.y[i])) {
      out << '\n';
      continue;
    }
    // 10 digits are far below a pixel; the full 17 would only grow the file.
    std::snprintf(buf, sizeof buf, "%.10g %.10g\n", s.x[i], s.y[i]);
    out << buf;
  }
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// The whole script for one plot, from the terminal to `unset output`. Scripts
// of several plots run one after the other in one gnuplot each start with
// `reset`, so that nothing one plot sets carries over to the next.
std::string gnuplot_script(const Plot& plot, std::string_view title, const std::vector<std::filesystem::path>& data,
                           const std::vector<const Series*>& series, const std::filesystem::path& svg) {
  std::ostringstream gp;
  gp << "set encoding utf8\n"
     << "set terminal svg size 800,450 dynamic enhanced font 'sans,11' background '#ffffff'\n"
     << "set output " << gp_quote(svg.string()) << "\n"
     << "set grid\nset key below\nset border 3\nset tics nomirror\n";
  // Series without a role: the palette by position (output/plot_style.h).
  const std::vector<std::string_view>& colours = series_palette();
  for (std::size_t i = 0; i < colours.size(); ++i) {
    gp << "set linetype " << i + 1 << " lc rgb '" << colours[i] << "' lw 1.5 pt " << i + 1 << " ps 0.6\n";
  }
  gp << "set linetype cycle " << colours.size() << "\n";
  // noenhanced everywhere: a user's "cam_angle" must not turn into a subscript.
  if (!title.empty()) gp << "set title " << gp_quote(title) << " noenhanced\n";
  gp << "set xlabel " << gp_quote(plot.xlabel) << " noenhanced\n";
  gp << "set ylabel " << gp_quote(plot.ylabel) << " noenhanced\n";
  if (plot.logx) gp << "set logscale x\n";
  if (plot.logy) gp << "set logscale y\n";
  if (plot.xrange) {
    const auto [lo, hi] = *plot.xrange;
    const bool usable = std::isfinite(lo) && std::isfinite(hi) && lo < hi && !(plot.logx && lo <= 0);
    if (usable) gp << "set xrange [" << gp_number(lo) << ":" << gp_number(hi) << "]\n";
  }
  if (plot.yrange) {
    const auto [lo, hi] = *plot.yrange;
    const bool usable = std::isfinite(lo) && std::isfinite(hi) && lo < hi && !(plot.logy && lo <= 0);
    if (usable) gp << "set yrange [" << gp_number(lo) << ":" << gp_number(hi) << "]\n";
  }
  // Equal units per pixel on both axes; the key goes to the right so that the
  // square-ish drawing keeps the height of the figure.
  if (plot.equal_axes) gp << "set size ratio -1\nset key outside right top vertical\n";
  gp << "plot ";
  for (std::size_t i = 0; i < series.size(); ++i) {
    const std::string& style = series[i]->style;
    const bool known = style == "lines" || style == "points" || style == "linespoints";
    std::string with = gnuplot_with(series[i]->role);
    if (with.empty()) with = style == "dashes" ? "lines dashtype 2" : known ? style : "lines";
    gp << (i > 0 ? ", \\\n     " : "") << gp_quote(data[i].string()) << " using 1:2 with " << with << " title "
       << gp_quote(series[i]->label) << " noenhanced";
  }
  gp << "\nunset output\n";
  return gp.str();
}

// Several gnuplot SVGs inlined in one page would repeat the same ids
// (gpPt0, gnuplot_canvas, ...); ids must be unique in an HTML document, so
// each plot's ids and the references to them get a prefix. Only tag text is
// rewritten, never the text content of labels.
std::string prefix_svg_ids(const std::string& svg, const std::string& prefix) {
  static const char* const kPatterns[] = {" id=\"", " id='", "href=\"#", "href='#", "url(#"};
  std::string out;
  out.reserve(svg.size() + 1024);
  bool in_tag = false;
  for (std::size_t i = 0; i < svg.size(); ++i) {
    const char c = svg[i];
    if (c == '<') in_tag = true;
    if (c == '>') in_tag = false;
    out += c;
    // Every pattern starts with ' ', 'h' or 'u': the others need no compare
    // (five per character of tag text had been a tenth of a quickstart run).
    if (!in_tag || (c != ' ' && c != 'h' && c != 'u')) continue;
    for (const char* pattern : kPatterns) {
      const std::size_t n = std::strlen(pattern);
      if (svg.compare(i, n, pattern) == 0) {
        out.append(pattern + 1, n - 1);
        out += prefix;
        i += n - 1;
        break;
      }
    }
  }
  return out;
}

// gnuplot draws series i (from 1) in `<g id="gnuplot_plot_i" >`: each
// series with a role gets `data-role="name"` there, so that a reader (or a
// test) can tell what a curve shows without going by its colour.
std::string tag_series_roles(std::string svg, const std::vector<Series>& series) {
  for (std::size_t i = 0; i < series.size(); ++i) {
    const std::string_view name = role_style(series[i].role).name;
    if (name.empty()) continue;
    const std::string group = "<g id=\"gnuplot_plot_" + std::to_string(i + 1) + "\"";
    const std::size_t at = svg.find(group);
    if (at == std::string::npos) continue;
    svg.insert(at + group.size(), " data-role=\"" + std::string(name) + "\"");
  }
  return svg;
}

bool looks_numeric(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  while (end != nullptr && *end == ' ') ++end;
  return end != nullptr && *end == '\0' && !std::isspace(static_cast<unsigned char>(s[0]));
}

constexpr const char* kStyle = R"css(
:root { --fg: #1d2330; --muted: #5b6475; --line: #d8dde6; --panel: #ffffff; }
* { box-sizing: border-box; }
body { margin: 0; color: var(--fg); background: #f4f6f9;
  font: 15px/1.5 system-ui, -apple-system, "Segoe UI", Roboto, "Helvetica Neue", Arial, sans-serif; }
header, main, footer { max-width: 1100px; margin: 0 auto; padding: 0 24px; }
header { padding-top: 28px; }
h1 { font-size: 1.7em; margin: 0 0 4px; }
h2 { font-size: 1.2em; margin: 0 0 10px; }
.subtitle { color: var(--muted); margin: 0 0 16px; }
dl.facts { display: grid; grid-template-columns: repeat(auto-fill, minmax(220px, 1fr)); gap: 8px 20px;
  margin: 0; padding: 14px 16px; background: var(--panel); border: 1px solid var(--line); border-radius: 8px; }
dl.facts dt { font-size: .78em; text-transform: uppercase; letter-spacing: .04em; color: var(--muted); }
dl.facts dd { margin: 0; font-variant-numeric: tabular-nums; overflow-wrap: anywhere; }
section { margin: 28px 0; }
.verdict { margin: 0 0 16px; padding: 14px 18px; border-radius: 8px; border: 1px solid var(--line);
  border-left: 6px solid #6b7280; background: var(--panel); }
.verdict.good { border-left-color: #1a7f37; background: #eef8f1; }
.verdict.warning { border-left-color: #b7791f; background: #fdf6e7; }
.verdict.bad { border-left-color: #c2410c; background: #fdf0ea; }
.verdict .headline { font-size: 1.2em; font-weight: 650; margin: 0; }
.verdict ul { margin: 6px 0 0; padding-left: 20px; color: var(--muted); }
.table-wrap { overflow: auto; max-height: 70vh; background: var(--panel); border: 1px solid var(--line); border-radius: 8px; }
table { border-collapse: collapse; width: 100%; font-size: .92em; }
th, td { padding: 6px 12px; border-bottom: 1px solid var(--line); text-align: left; white-space: nowrap; }
td.num { text-align: right; font-variant-numeric: tabular-nums; }
td.best { font-weight: 700; background: #e3f4e8; }
td.best::after { content: " \2605"; color: #1a7f37; }
table.wrap td { white-space: normal; overflow-wrap: anywhere; }
thead th { background: #eef1f6; position: sticky; top: 0; }
table.sortable th { cursor: pointer; user-select: none; }
table.sortable th::after { content: " \2195"; color: #a8afbd; }
table.sortable th[aria-sort="ascending"]::after { content: " \2191"; color: var(--fg); }
table.sortable th[aria-sort="descending"]::after { content: " \2193"; color: var(--fg); }
tbody tr:nth-child(even) { background: #fafbfd; }
tbody tr:hover { background: #eef5fc; }
.empty { color: var(--muted); padding: 8px 12px; margin: 0; }
figure { margin: 0 0 24px; padding: 12px; background: var(--panel); border: 1px solid var(--line); border-radius: 8px; }
figure svg { display: block; width: 100%; height: auto; }
figcaption { color: var(--muted); font-size: .92em; padding-top: 6px; }
.notes li { margin: 4px 0; }
footer { color: var(--muted); font-size: .85em; padding-bottom: 28px; }
@media print { body { background: #fff; } figure, .table-wrap { break-inside: avoid; } }
)css";

// Click (or Enter on) a header of a sortable table to sort by that column:
// numbers numerically and before text, text in natural order; again to reverse.
constexpr const char* kSortScript = R"js(
(function () {
  'use strict';
  function sortKey(cell) {
    var text = cell ? cell.textContent.trim() : '';
    var num = text === '' ? NaN : Number(text);
    return { text: text, num: isFinite(num) ? num : null };
  }
  function compare(a, b) {
    if (a.num !== null && b.num !== null) return a.num - b.num;
    if (a.num !== null) return -1;
    if (b.num !== null) return 1;
    return a.text.localeCompare(b.text, undefined, { numeric: true, sensitivity: 'base' });
  }
  var tables = document.querySelectorAll('table.sortable');
  Array.prototype.forEach.call(tables, function (table) {
    if (!table.tHead || !table.tBodies.length) return;
    var headers = table.tHead.rows[0].cells;
    Array.prototype.forEach.call(headers, function (th, column) {
      th.tabIndex = 0;
      function sort() {
        var ascending = th.getAttribute('aria-sort') !== 'ascending';
        Array.prototype.forEach.call(headers, function (h) { h.removeAttribute('aria-sort'); });
        th.setAttribute('aria-sort', ascending ? 'ascending' : 'descending');
        var body = table.tBodies[0];
        var rows = Array.prototype.map.call(body.rows, function (row, index) {
          return { row: row, index: index, key: sortKey(row.cells[column]) };
        });
        rows.sort(function (a, b) {
          var c = compare(a.key, b.key);
          return (ascending ? c : -c) || a.index - b.index;
        });
        rows.forEach(function (r) { body.appendChild(r.row); });
      }
      th.addEventListener('click', sort);
      th.addEventListener('keydown', function (event) {
        if (event.key === 'Enter' || event.key === ' ') { event.preventDefault(); sort(); }
      });
    });
  });
})();
)js";

void render_table(std::ostringstream& html, const Table& table) {
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    if (table.rows[r].size() != table.columns.size()) {
      throw std::logic_error("report table '" + table.title + "' row " + std::to_string(r + 1) + " has " +
                             std::to_string(table.rows[r].size()) + " cells for " +
                             std::to_string(table.columns.size()) + " columns");
    }
  }
  html << "<section class=\"table\">\n";
  if (!table.title.empty()) html << "<h2>" << escape_html(table.title) << "</h2>\n";
  html << "<div class=\"table-wrap\">\n<table";
  if (table.sortable || table.wrap)
    html << " class=\"" << (table.sortable ? "sortable" : "") << (table.sortable && table.wrap ? " " : "")
         << (table.wrap ? "wrap" : "") << "\"";
  html << ">\n<thead><tr>";
  for (const auto& column : table.columns) html << "<th scope=\"col\">" << escape_html(column) << "</th>";
  html << "</tr></thead>\n<tbody>\n";
  const std::set<std::pair<std::size_t, std::size_t>> marked(table.marked.begin(), table.marked.end());
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    html << "<tr>";
    for (std::size_t c = 0; c < table.rows[r].size(); ++c) {
      const std::string& cell = table.rows[r][c];
      const bool best = marked.count({r, c}) > 0;
      const char* open = looks_numeric(cell) ? (best ? "<td class=\"num best\">" : "<td class=\"num\">")
                                             : (best ? "<td class=\"best\">" : "<td>");
      html << open << escape_html(cell) << "</td>";
    }
    html << "</tr>\n";
  }
  html << "</tbody>\n</table>\n";
  if (table.rows.empty()) html << "<p class=\"empty\">No rows.</p>\n";
  html << "</div>\n</section>\n";
}

void render_verdict(std::ostringstream& html, const Verdict& verdict) {
  static constexpr const char* kTone[] = {"good", "warning", "bad", "neutral"};
  html << "<div class=\"verdict " << kTone[static_cast<int>(verdict.tone)]
       << "\" id=\"verdict\">\n<p class=\"headline\">" << escape_html(verdict.headline) << "</p>\n";
  if (!verdict.details.empty()) {
    html << "<ul>\n";
    for (const std::string& line : verdict.details) html << "<li>" << escape_html(line) << "</li>\n";
    html << "</ul>\n";
  }
  html << "</div>\n";
}

}  // namespace

std::string escape_html(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  // Control characters are not text either (nor valid XML in the SVGs): escaped first (common/printable_text.h).
  for (char c : printable_text(text)) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string format_number(double value, int significant) {
  if (!std::isfinite(value)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", std::clamp(significant, 1, 17), value);
  return buf;
}

std::vector<Series> plotted_series(const Plot& plot) {
  std::vector<Series> drawable;
  drawable.reserve(plot.series.size());
  for (const auto& s : plot.series) {
    if (s.x.size() != s.y.size()) {
      throw std::logic_error("plot '" + plot.title + "' series '" + s.label + "': " + std::to_string(s.x.size()) +
                             " x values for " + std::to_string(s.y.size()) + " y values");
    }
    Series d = drawable_points(s, plot.logx, plot.logy);
    if (!d.x.empty()) drawable.push_back(std::move(d));
  }
  // One set of columns for the whole plot, over the x range all its series span.
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Series& s : drawable) {
    for (const double x : s.x) {
      if (std::isnan(x)) continue;  // drawable points: NaN marks a break, all else is finite
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  }
  const double span[] = {lo, hi};
  const PlotColumns pixels = PlotColumns::spanning(span, kPlotColumns, plot.logx, plot.xrange);
  const PlotColumns cap = PlotColumns::spanning(span, kMaxPlotPoints / 2 - 1, plot.logx, plot.xrange);
  for (Series& s : drawable) {
    // A line hides what lies between the lowest and highest point of its
    // pixel column; a marker does not, so markers are only capped.
    const bool markers = s.style == "points" || s.style == "linespoints" || role_style(s.role).point_type > 0;
    Curve c = decimate_per_column(s.x, s.y, plot.full_resolution || markers ? cap : pixels);
    s.x = std::move(c.x);
    s.y = std::move(c.y);
  }
  return drawable;
}

namespace {

// A plot ready for gnuplot: its settings, the title drawn on it (none in a
// report, whose caption carries it) and its series as plotted_series gives them.
struct PreparedPlot {
  const Plot* plot = nullptr;
  std::string_view title;
  std::vector<Series> series;
};

// Renders `batch` with one gnuplot process (starting gnuplot costs more than
// drawing a plot): the SVG element of each plot, in order. Returns an empty
// vector and sets `error` if gnuplot failed; throws std::runtime_error if a
// temporary file cannot be written.
std::vector<std::string> run_batch(const std::vector<const PreparedPlot*>& batch, std::string& error) {
  const char* env = std::getenv("CAMDYN_GNUPLOT");
  const std::string program = env != nullptr && *env != '\0' ? env : "gnuplot";
  TempDir dir;
  std::string script;
  std::vector<std::filesystem::path> svg_paths;
  for (std::size_t k = 0; k < batch.size(); ++k) {
    const PreparedPlot& p = *batch[k];
    const std::string stem = "plot" + std::to_string(k);
    std::vector<std::filesystem::path> data;
    std::vector<const Series*> series;
    for (std::size_t i = 0; i < p.series.size(); ++i) {
      data.push_back(dir.path() / (stem + "-series" + std::to_string(i) + ".dat"));
      write_data(data.back(), p.series[i]);
      series.push_back(&p.series[i]);
    }
    svg_paths.push_back(dir.path() / (stem + ".svg"));
    if (k > 0) script += "reset\n";
    script += gnuplot_script(*p.plot, p.title, data, series, svg_paths.back());
  }
  const auto script_path = dir.path() / "plots.gp";
  {
    std::ofstream out(script_path);
    out << script;
    if (!out) throw std::runtime_error("cannot write " + script_path.string());
  }
  error = run_gnuplot(program, script_path, dir.path() / "gnuplot.log");
  if (!error.empty()) return {};
  std::vector<std::string> svgs;
  for (std::size_t k = 0; k < batch.size(); ++k) {
    const std::string svg = read_all(svg_paths[k]);
    const std::size_t start = svg.find("<svg");
    if (start == std::string::npos) {
      error = "gnuplot wrote no SVG";
      return {};
    }
    // Drop the XML prolog (not allowed inside HTML) and name the figure after the plot.
    std::string element = svg.substr(start);
    const std::string default_title = "<title>Gnuplot</title>";
    if (const auto t = element.find(default_title); t != std::string::npos) {
      element.replace(t, default_title.size(), "<title>" + escape_html(batch[k]->title) + "</title>");
    }
    svgs.push_back(tag_series_roles(element, batch[k]->series));
  }
  return svgs;
}

// One plot in a gnuplot of its own; a placeholder (and the warning) if gnuplot fails.
std::string render_prepared(const PreparedPlot& p) {
  // Nothing to draw is a property of the data, not a failure of gnuplot: no warning.
  if (p.series.empty()) return placeholder_svg(std::string(p.title), "no data to plot");
  try {
    std::string error;
    std::vector<std::string> svgs = run_batch({&p}, error);
    if (!error.empty()) return unavailable(p.title, error);
    return std::move(svgs.front());
  } catch (const std::exception& e) {  // temp files: a report must not die for a plot
    return unavailable(p.title, e.what());
  }
}

// The plots of a report, without their titles (the captions carry them):
// the drawable ones dealt round-robin into one batch per thread, each batch
// one gnuplot process, the batches side by side. A batch that fails is drawn
// again plot by plot, so that one plot gnuplot cannot draw does not take the
// others with it.
std::vector<std::string> render_report_plots(const std::vector<Plot>& plots, int threads) {
  std::vector<PreparedPlot> prepared;
  prepared.reserve(plots.size());
  for (const Plot& plot : plots) prepared.push_back({&plot, {}, plotted_series(plot)});
  std::vector<std::string> svgs(plots.size());
  std::vector<std::vector<const PreparedPlot*>> batches;
  std::size_t drawable = 0;
  for (const PreparedPlot& p : prepared) drawable += p.series.empty() ? 0 : 1;
  batches.resize(std::min<std::size_t>(drawable, static_cast<std::size_t>(std::max(threads, 1))));
  std::size_t next = 0;
  for (std::size_t i = 0; i < prepared.size(); ++i) {
    if (prepared[i].series.empty()) {
      svgs[i] = render_prepared(prepared[i]);
    } else {
      batches[next++ % batches.size()].push_back(&prepared[i]);
    }
  }
  const auto index = [&](const PreparedPlot* p) { return static_cast<std::size_t>(p - prepared.data()); };
  parallel_for(batches.size(), threads, [&](std::size_t b) {
    const std::vector<const PreparedPlot*>& batch = batches[b];
    std::string error;
    std::vector<std::string> out;
    try {
      out = run_batch(batch, error);
    } catch (const std::exception& e) {
      error = e.what();
    }
    if (error.empty()) {
      for (std::size_t k = 0; k < batch.size(); ++k) svgs[index(batch[k])] = std::move(out[k]);
    } else if (batch.size() == 1) {
      svgs[index(batch.front())] = unavailable(batch.front()->title, error);
    } else {
      for (const PreparedPlot* p : batch) svgs[index(p)] = render_prepared(*p);
    }
  });
  return svgs;
}

}  // namespace

std::string render_svg(const Plot& plot) { return render_prepared({&plot, plot.title, plotted_series(plot)}); }

std::string render_html(const Report& report) {
  std::ostringstream html;
  const std::string title = report.title.empty() ? "camdyn report" : report.title;
  html << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
       << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
       << "<title>" << escape_html(title) << "</title>\n<style>" << kStyle << "</style>\n"
       << "</head>\n<body>\n<header>\n<h1>" << escape_html(title) << "</h1>\n";
  if (!report.subtitle.empty()) {
    html << "<p class=\"subtitle\">" << escape_html(report.subtitle) << "</p>\n";
  }
  html << "</header>\n<main>\n";
  if (report.verdict) render_verdict(html, *report.verdict);
  if (!report.facts.empty()) {
    html << "<dl class=\"facts\">\n";
    for (const auto& [key, value] : report.facts) {
      html << "<div><dt>" << escape_html(key) << "</dt><dd>" << escape_html(value) << "</dd></div>\n";
    }
    html << "</dl>\n";
  }
  for (const auto& table : report.tables) render_table(html, table);
  if (!report.plots.empty()) html << "<section class=\"plots\">\n";
  // The plots in one gnuplot process per thread, side by side (a compare
  // report has a dozen), then the page assembled in order.
  const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const std::vector<std::string> svgs = render_report_plots(report.plots, threads);
  for (std::size_t i = 0; i < report.plots.size(); ++i) {
    const std::string number = std::to_string(i + 1);
    html << "<figure id=\"figure-" << number << "\">\n"
         << prefix_svg_ids(svgs[i], "fig" + number + "-") << "<figcaption>Figure " << number << ". "
         << escape_html(report.plots[i].title) << "</figcaption>\n</figure>\n";
  }
  if (!report.plots.empty()) html << "</section>\n";
  for (const auto& table : report.appendix) render_table(html, table);
  if (!report.notes.empty()) {
    html << "<section class=\"notes\">\n<h2>Notes</h2>\n<ul>\n";
    for (const auto& note : report.notes) html << "<li>" << escape_html(note) << "</li>\n";
    html << "</ul>\n</section>\n";
  }
  html << "</main>\n<footer>Generated by camdyn " CAMDYN_VERSION ".</footer>\n<script>" << kSortScript
       << "</script>\n</body>\n</html>\n";
  return html.str();
}

void write_report(const std::filesystem::path& path, const Report& report) {
  write_file_atomic(path, render_html(report));
}

}  // namespace camdyn
