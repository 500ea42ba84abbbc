#include "output/curve_decimation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "common/constants.h"

namespace camdyn {
namespace {

bool is_point(double x, double y) { return std::isfinite(x) && std::isfinite(y); }

}  // namespace

PlotColumns::PlotColumns(double lo_, double hi_, std::size_t count_, bool log_)
    : lo(lo_), hi(hi_), count(std::max<std::size_t>(count_, 1)), log(log_) {
  const double a = log ? std::log10(lo) : lo, b = log ? std::log10(hi) : hi;
  offset_ = a;
  // A range of one value (or an unusable one) puts every point in column 0.
  scale_ = std::isfinite(a) && std::isfinite(b) && b > a ? static_cast<double>(count) / (b - a) : 0.0;
}

PlotColumns PlotColumns::spanning(std::span<const double> x, std::size_t count, bool log,
                                  std::optional<std::pair<double, double>> range) {
  if (range) {
    const auto [lo, hi] = *range;
    if (std::isfinite(lo) && std::isfinite(hi) && lo < hi && !(log && lo <= 0.0)) return {lo, hi, count, log};
  }
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const double v : x) {
    if (!std::isfinite(v) || (log && v <= 0.0)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  if (lo > hi) return log ? PlotColumns{1.0, 10.0, count, log} : PlotColumns{0.0, 1.0, count, log};
  return {lo, hi, count, log};
}

long PlotColumns::column(double x) const {
  if (log && !(x > 0.0)) return -1;
  const double t = log ? std::log10(x) : x;
  const double c = std::floor((t - offset_) * scale_);
  if (!(c >= 0.0)) return c < 0.0 ? -1 : 0;  // NaN (only from a non-finite x, which callers skip): column 0
  if (c >= static_cast<double>(count)) {
    // hi itself belongs to the last column; beyond it, the column right of the range.
    return x <= hi ? static_cast<long>(count) - 1 : static_cast<long>(count);
  }
  return static_cast<long>(c);
}

Curve decimate_per_column(std::span<const double> x, std::span<const double> y, const PlotColumns& columns) {
  if (x.size() != y.size()) {
    throw std::invalid_argument("decimate_per_column: " + std::to_string(x.size()) + " x values for " +
                                std::to_string(y.size()) + " y values");
  }
  const std::size_t n = x.size();
  Curve out;
  if (n <= 2 * columns.count + 2) {
    out.x.assign(x.begin(), x.end());
    out.y.assign(y.begin(), y.end());
    return out;
  }
  out.x.reserve(std::min(n, 2 * columns.count + 16));
  out.y.reserve(out.x.capacity());

  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  std::size_t last_emitted = kNone;  // indices go out in increasing order
  const auto emit = [&](std::size_t i) {
    if (last_emitted != kNone && i <= last_emitted) return;
    out.x.push_back(x[i]);
    out.y.push_back(y[i]);
    last_emitted = i;
  };

  std::size_t piece_last = kNone;  // last point of the current piece (kNone between pieces)
  long run_column = 0;
  std::size_t run_min = kNone, run_max = kNone;
  const auto flush_run = [&] {
    if (run_min == kNone) return;
    emit(std::min(run_min, run_max));
    emit(std::max(run_min, run_max));
    run_min = run_max = kNone;
  };
  const auto end_piece = [&] {
    flush_run();
    if (piece_last != kNone) emit(piece_last);
    piece_last = kNone;
  };

  for (std::size_t i = 0; i < n; ++i) {
    if (!is_point(x[i], y[i])) {
      end_piece();
      if (!out.x.empty() && !std::isnan(out.x.back())) {
        out.x.push_back(kBreak);
        out.y.push_back(kBreak);
      }
      continue;
    }
    if (piece_last == kNone) emit(i);  // a piece starts where it starts
    piece_last = i;
    const long c = columns.column(x[i]);
    if (run_min != kNone && c == run_column) {
      if (y[i] < y[run_min]) run_min = i;
      if (y[i] > y[run_max]) run_max = i;
      continue;
    }
    flush_run();
    run_column = c;
    run_min = run_max = i;
  }
  end_piece();
  if (!out.x.empty() && std::isnan(out.x.back())) {
    out.x.pop_back();
    out.y.pop_back();
  }
  return out;
}

}  // namespace camdyn
