// Measuring a gnuplot SVG (output/report.h render_svg) in pixels: the bounding
// box of the curves drawn in one colour or of one titled series, for tests
// that check a plot is to scale (a circle in the data must come out as round
// on the page); and reading its axis labels back. Works on gnuplot's own SVG
// and on the same SVG as a browser's DOM dump prints it.
#pragma once

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace camdyn::test {

/// The pixel extent of a set of curves.
struct PixelBox {
  double x0 = std::numeric_limits<double>::infinity(), x1 = -std::numeric_limits<double>::infinity();
  double y0 = std::numeric_limits<double>::infinity(), y1 = -std::numeric_limits<double>::infinity();
  int points = 0;
  double width() const { return x1 - x0; }
  double height() const { return y1 - y0; }
};

/// The stroke colour gnuplot writes for a linetype of `lc rgb '#rrggbb'`: "rgb(r, g, b)" (spaces removed).
inline std::string gnuplot_stroke(const std::string& hex) {
  const auto channel = [&](int i) {
    return std::to_string(std::strtol(hex.substr(1 + 2 * i, 2).c_str(), nullptr, 16));
  };
  return "rgb(" + channel(0) + "," + channel(1) + "," + channel(2) + ")";
}

namespace svg_detail {
inline std::string attribute(const std::string& tag, const std::string& name) {
  for (const char quote : {'\'', '"'}) {
    const std::string key = " " + name + "=" + quote;
    const std::size_t at = tag.find(key);
    if (at == std::string::npos) continue;
    const std::size_t begin = at + key.size();
    return tag.substr(begin, tag.find(quote, begin) - begin);
  }
  return {};
}
inline std::string without_spaces(std::string s) {
  s.erase(std::remove(s.begin(), s.end(), ' '), s.end());
  return s;
}
}  // namespace svg_detail

/// The bounding box of every path stroked in `stroke` (see gnuplot_stroke)
/// within `svg`, leaving out the first subpath: the key's sample line, which
/// gnuplot draws before the data. Empty when nothing is drawn in that colour.
inline std::optional<PixelBox> stroke_box(const std::string& svg, const std::string& stroke) {
  PixelBox box;
  bool key_skipped = false;
  for (std::size_t at = svg.find("<path"); at != std::string::npos; at = svg.find("<path", at + 1)) {
    const std::string tag = svg.substr(at, svg.find('>', at) - at);
    if (svg_detail::without_spaces(svg_detail::attribute(tag, "stroke")) != stroke) continue;
    const std::string d = svg_detail::attribute(tag, "d");
    const char* p = d.c_str();
    bool skipping = false;
    while (*p != '\0') {
      const char c = *p;
      if (c == 'M' || c == 'L') {
        if (c == 'M') {
          skipping = !key_skipped;
          key_skipped = true;
        }
        char* end = nullptr;
        const double x = std::strtod(p + 1, &end);
        if (end == nullptr || *end != ',') break;
        const double y = std::strtod(end + 1, &end);
        p = end;
        if (skipping) continue;
        box.x0 = std::min(box.x0, x);
        box.x1 = std::max(box.x1, x);
        box.y0 = std::min(box.y0, y);
        box.y1 = std::max(box.y1, y);
        ++box.points;
        continue;
      }
      ++p;
    }
  }
  if (box.points == 0) return std::nullopt;
  return box;
}

/// The bounding box of the series gnuplot titled `title` in the key (its
/// group `<g id="...gnuplot_plot_N"><title>TITLE</title>`), in the colour
/// of its first stroked path, leaving out the key's sample line. Empty when
/// there is no such series.
inline std::optional<PixelBox> series_box(const std::string& svg, const std::string& title) {
  const std::size_t at = svg.find("<title>" + title + "</title>");
  if (at == std::string::npos) return std::nullopt;
  const std::string group = svg.substr(at, svg.find("gnuplot_plot_", at) - at);
  for (std::size_t path = group.find("<path"); path != std::string::npos; path = group.find("<path", path + 1)) {
    const std::string stroke = svg_detail::attribute(group.substr(path, group.find('>', path) - path), "stroke");
    if (!stroke.empty() && stroke != "currentColor") return stroke_box(group, svg_detail::without_spaces(stroke));
  }
  return std::nullopt;
}

/// The axis labels of a gnuplot SVG: the centred texts of one piece (tick
/// labels are enhanced text, in a <tspan>; the key's entries are aligned
/// right; the report draws no title), the rotated one on the y axis.
struct AxisLabels {
  std::vector<std::string> x, y;
};
inline AxisLabels axis_labels(const std::string& svg) {
  AxisLabels labels;
  for (std::size_t at = svg.find("<g "); at != std::string::npos; at = svg.find("<g ", at + 1)) {
    const std::size_t close = svg.find('>', at);
    const std::string tag = svg.substr(at, close - at);
    if (svg_detail::attribute(tag, "text-anchor") != "middle") continue;
    std::size_t text = close + 1;
    while (text < svg.size() && std::isspace(static_cast<unsigned char>(svg[text]))) ++text;
    if (svg.compare(text, 6, "<text>") != 0) continue;
    const std::size_t end = svg.find("</text>", text);
    const std::string content = svg.substr(text + 6, end - text - 6);
    if (content.find('<') != std::string::npos) continue;  // a tick label
    (tag.find("rotate(") != std::string::npos ? labels.y : labels.x).push_back(content);
  }
  return labels;
}

/// Whether an axis label ends with its unit in brackets: "force [N]", "iteration [-]".
inline bool has_unit(const std::string& label) {
  const std::size_t open = label.rfind(" [");
  return open != std::string::npos && !label.empty() && label.back() == ']' && label.size() > open + 3;
}

}  // namespace camdyn::test
