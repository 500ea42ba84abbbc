// Curves reduced to what a plot can show. A plot is a few hundred pixels
// wide; a 200-revolution time series has 10^5 points or more, which only
// make the SVG heavy and gnuplot slow. For each pixel column of the plot the
// points of a curve that fall in it are replaced by their lowest and highest
// (in their original order), so a one-sample impact spike still reaches its
// height, and the line looks the same at that width. The first and last
// points of every piece of the curve are kept as they are, and so are its
// breaks (a non-finite x or y: gnuplot's blank line, a gap in the data).
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <utility>
#include <vector>

namespace camdyn {

/// Pixel columns of a report plot (an 800-pixel-wide SVG whose drawing area
/// is about 700 pixels wide, so a little finer than a pixel).
inline constexpr std::size_t kPlotColumns = 1000;

/// The x axis of a plot cut into `count` columns of equal width, in x or, on
/// a logarithmic axis, in log x. Points left of `lo` share one extra column,
/// and so do points right of `hi`.
struct PlotColumns {
  double lo = 0.0, hi = 1.0;
  std::size_t count = kPlotColumns;
  bool log = false;

  /// The columns over [lo, hi]; on a log axis, lo must be > 0.
  PlotColumns(double lo, double hi, std::size_t count = kPlotColumns, bool log = false);
  /// The columns spanning the finite x values of `x` (the positive ones on a
  /// log axis), or `range` if given and usable.
  static PlotColumns spanning(std::span<const double> x, std::size_t count = kPlotColumns, bool log = false,
                              std::optional<std::pair<double, double>> range = std::nullopt);

  /// Column of `x`: 0 … count−1 inside [lo, hi] (hi in the last), −1 left of it, count right of it.
  long column(double x) const;

 private:
  double offset_ = 0.0, scale_ = 0.0;  // column = floor((t(x) − offset) · scale), t = x or log x
};

/// A curve: x and y of the same length; a non-finite x or y is a break.
struct Curve {
  std::vector<double> x, y;
};

/// `x`, `y` (same length; throws std::invalid_argument otherwise) reduced to
/// the points a plot with `columns` shows: a curve of at most 2·count + 2
/// points is returned as it is; otherwise each run of consecutive points in
/// one column becomes its minimum and maximum of y (in their order, one point
/// if they are the same), the first and last point of every piece between
/// breaks are kept, and every break becomes one NaN point (several in a row
/// collapse into one; breaks at either end are dropped). For x that never
/// goes back (a time axis) and no breaks, at most 2·count + 2 points come
/// out; the result never has more points than the input.
Curve decimate_per_column(std::span<const double> x, std::span<const double> y, const PlotColumns& columns);

}  // namespace camdyn
