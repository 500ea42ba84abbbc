#include "output/curve_decimation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <vector>

namespace camdyn {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// n samples of a slow sine on x = 0 … n−1 (a time axis).
Curve sine(std::size_t n) {
  Curve c;
  for (std::size_t i = 0; i < n; ++i) {
    c.x.push_back(static_cast<double>(i));
    c.y.push_back(std::sin(static_cast<double>(i) * 1e-3));
  }
  return c;
}

Curve decimate(const Curve& c, std::size_t columns = 1000, bool log = false) {
  return decimate_per_column(c.x, c.y, PlotColumns::spanning(c.x, columns, log));
}

std::size_t breaks(const Curve& c) {
  return static_cast<std::size_t>(std::count_if(c.x.begin(), c.x.end(), [](double v) { return std::isnan(v); }));
}

TEST(PlotColumns, CutTheRangeIntoEqualColumns) {
  const PlotColumns c(0.0, 10.0, 10);
  EXPECT_EQ(c.column(0.0), 0);
  EXPECT_EQ(c.column(0.99), 0);
  EXPECT_EQ(c.column(1.0), 1);
  EXPECT_EQ(c.column(9.99), 9);
  EXPECT_EQ(c.column(10.0), 9);  // the right end belongs to the last column
  EXPECT_EQ(c.column(-0.5), -1);
  EXPECT_EQ(c.column(10.5), 10);
  const PlotColumns log(1.0, 1000.0, 3, true);
  EXPECT_EQ(log.column(5.0), 0);
  EXPECT_EQ(log.column(50.0), 1);
  EXPECT_EQ(log.column(500.0), 2);
  EXPECT_EQ(log.column(0.0), -1);
}

TEST(PlotColumns, SpanTheFiniteDataOrTheGivenRange) {
  const std::vector<double> x = {kNaN, 2.0, -1.0, 5.0, std::numeric_limits<double>::infinity()};
  const PlotColumns data = PlotColumns::spanning(x, 100);
  EXPECT_EQ(data.lo, -1.0);
  EXPECT_EQ(data.hi, 5.0);
  const PlotColumns log = PlotColumns::spanning(x, 100, true);
  EXPECT_EQ(log.lo, 2.0);  // the positive values only
  const PlotColumns given = PlotColumns::spanning(x, 100, false, std::make_pair(0.0, 360.0));
  EXPECT_EQ(given.lo, 0.0);
  EXPECT_EQ(given.hi, 360.0);
  const PlotColumns unusable = PlotColumns::spanning(x, 100, false, std::make_pair(3.0, 3.0));
  EXPECT_EQ(unusable.lo, -1.0);
  const PlotColumns one_value = PlotColumns::spanning(std::vector<double>{4.0, 4.0}, 100);
  EXPECT_EQ(one_value.column(4.0), 0);
}

TEST(CurveDecimation, ASingleSampleSpikeSurvives) {
  Curve c = sine(200000);
  c.y[123457] = 1000.0;  // a one-sample impact spike
  c.y[54321] = -500.0;   // and a one-sample dip
  const Curve d = decimate(c);
  ASSERT_EQ(d.x.size(), d.y.size());
  EXPECT_EQ(*std::max_element(d.y.begin(), d.y.end()), 1000.0);
  EXPECT_EQ(*std::min_element(d.y.begin(), d.y.end()), -500.0);
  // At its own time, not smeared over its column.
  const auto peak = std::max_element(d.y.begin(), d.y.end()) - d.y.begin();
  EXPECT_EQ(d.x[static_cast<std::size_t>(peak)], 123457.0);
}

TEST(CurveDecimation, AtMostTwoPointsPerColumnPlusTheEnds) {
  for (const std::size_t columns : {1, 7, 100, 1000}) {
    for (const std::size_t n : {2 * columns + 3, 10 * columns + 1, std::size_t{144001}}) {
      Curve c = sine(n);
      for (std::size_t i = 0; i < n; i += 3) c.y[i] += 0.5;  // jagged: every column has a distinct min and max
      const Curve d = decimate(c, columns);
      EXPECT_LE(d.x.size(), 2 * columns + 2) << n << " points in " << columns << " columns";
      EXPECT_GE(d.x.size(), std::min(n, columns)) << n << " points in " << columns << " columns";
      EXPECT_TRUE(std::is_sorted(d.x.begin(), d.x.end()));
    }
  }
}

TEST(CurveDecimation, AShortCurveIsLeftAsItIs) {
  const Curve c = sine(2002);
  const Curve d = decimate(c, 1000);
  EXPECT_EQ(d.x, c.x);
  EXPECT_EQ(d.y, c.y);
}

TEST(CurveDecimation, AMonotoneCurveKeepsItsEndpoints) {
  Curve c;
  for (int i = 0; i <= 100000; ++i) {
    c.x.push_back(1e-5 * i);
    c.y.push_back(std::exp(1e-5 * i));
  }
  const Curve d = decimate(c);
  ASSERT_FALSE(d.x.empty());
  EXPECT_EQ(d.x.front(), c.x.front());
  EXPECT_EQ(d.y.front(), c.y.front());
  EXPECT_EQ(d.x.back(), c.x.back());
  EXPECT_EQ(d.y.back(), c.y.back());
  EXPECT_TRUE(std::is_sorted(d.y.begin(), d.y.end()));
  EXPECT_LE(d.x.size(), 2002u);
  // Every point kept is a point of the curve.
  for (std::size_t i = 0; i < d.x.size(); ++i) {
    const auto k = static_cast<std::size_t>(std::lround(d.x[i] * 1e5));
    EXPECT_EQ(d.y[i], c.y[k]);
  }
}

TEST(CurveDecimation, BreaksAreKept) {
  Curve c = sine(100000);
  // Two gaps in the data: a single blank and a run of them (one break out).
  c.x[30000] = kNaN;
  for (std::size_t i = 60000; i < 60500; ++i) c.y[i] = kNaN;
  // A break at either end carries nothing: it is dropped.
  c.x.front() = kNaN;
  c.y.back() = kNaN;
  const Curve d = decimate(c);
  EXPECT_EQ(breaks(d), 2u);
  EXPECT_FALSE(std::isnan(d.x.front()));
  EXPECT_FALSE(std::isnan(d.x.back()));
  // No line bridges a gap: the points either side of each break are the
  // last point before it and the first point after it.
  for (std::size_t i = 0; i < d.x.size(); ++i) {
    if (!std::isnan(d.x[i])) continue;
    ASSERT_GT(i, 0u);
    ASSERT_LT(i + 1, d.x.size());
    const double before = d.x[i - 1], after = d.x[i + 1];
    EXPECT_TRUE((before == 29999.0 && after == 30001.0) || (before == 59999.0 && after == 60500.0))
        << before << " | " << after;
  }
  EXPECT_EQ(d.x.front(), 1.0);
  EXPECT_EQ(d.x.back(), 99998.0);
}

TEST(CurveDecimation, NeverMorePointsThanTheInput) {
  // A parametric curve (x goes back and forth): runs per column, not columns.
  Curve c;
  for (int i = 0; i < 20000; ++i) {
    const double t = 2e-3 * i;
    c.x.push_back(std::cos(t) * (1.0 + 0.001 * i));
    c.y.push_back(std::sin(t));
  }
  const Curve d = decimate(c, 100);
  EXPECT_LE(d.x.size(), c.x.size());
  EXPECT_EQ(*std::max_element(d.y.begin(), d.y.end()), *std::max_element(c.y.begin(), c.y.end()));
}

TEST(CurveDecimation, LengthsMustMatch) {
  const std::vector<double> x = {1.0, 2.0}, y = {1.0};
  EXPECT_THROW(decimate_per_column(x, y, PlotColumns(0.0, 1.0)), std::invalid_argument);
}

}  // namespace
}  // namespace camdyn
