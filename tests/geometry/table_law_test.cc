// Lift tables of measurement size (geometry/motion_law.h, the table route;
// geometry/bspline.h's banded solve above kDenseCollocation rows): a table
// sampled from an analytic periodic lift gives that lift back within the
// interpolation error, and its interpolation passes through every row.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "common/constants.h"
#include "common/errors.h"
#include "geometry/bspline.h"
#include "geometry/motion_law.h"
#include "tolerance.h"

namespace camdyn {
namespace {

/// A smooth periodic lift [m] of θ [rad] and its first two derivatives.
struct Source {
  double s(double t) const { return 0.01 * (1.0 - std::cos(t)) + 0.002 * std::sin(3.0 * t); }
  double ds(double t) const { return 0.01 * std::sin(t) + 0.006 * std::cos(3.0 * t); }
  double d2s(double t) const { return 0.01 * std::cos(t) - 0.018 * std::sin(3.0 * t); }
};

MotionLawConfig table_of(int rows) {
  TableConfig t;
  t.file = "encoder.csv";
  const Source src;
  for (int i = 0; i < rows; ++i) {
    const double deg = 360.0 * i / rows;
    t.angle_deg.push_back(deg);
    t.lift.push_back(src.s(deg * std::numbers::pi / 180.0));
    t.lines.push_back(i + 2);
  }
  MotionLawConfig c;
  c.table = t;
  return c;
}

// 0.01° encoder data: 36,000 rows. A quintic's interpolation error at this
// spacing (h = 1.7e-4 rad) is far below round-off, so the law must give the
// source back to round-off of its 0.02 m lift, and s', s'' to round-off
// amplified by 1/h and 1/h² of the differentiation of the interpolant.
TEST(TableLaw, EncoderTableGivesItsSourceBack) {
  const Source src;
  const MotionLaw law = build_motion_law(table_of(36000), "cam.json");
  const double h = kTwoPi / 36000;
  for (int k = 0; k < 997; ++k) {
    const double t = kTwoPi * (k + 0.37) / 997;  // between the rows
    const LawSample s = law.eval(t);
    EXPECT_NEAR(s.s, src.s(t), 1e3 * test::kEps * 0.02) << t;
    EXPECT_NEAR(s.ds, src.ds(t), 1e3 * test::kEps * 0.02 / h) << t;
    EXPECT_NEAR(s.d2s, src.d2s(t), 1e3 * test::kEps * 0.02 / (h * h)) << t;
  }
}

// Above kDenseCollocation the banded solve takes over: the interpolant passes
// through every row, at every degree, for a table just above the switch and a
// large one; and the coarse table still gives the source back within the
// quintic's interpolation error O(h⁶).
TEST(TableLaw, BandedSolvePassesThroughEveryRow) {
  for (const int rows : {PeriodicBSpline::kDenseCollocation + 1, 20000}) {
    for (const int degree : {3, 4, 5}) {
      SCOPED_TRACE(std::to_string(rows) + " rows, degree " + std::to_string(degree));
      MotionLawConfig c = table_of(rows);
      c.table->degree = degree;
      const MotionLaw law = build_motion_law(c, "cam.json");
      for (int i = 0; i < rows; i += 37) {
        const double t = c.table->angle_deg[i] * std::numbers::pi / 180.0;
        ASSERT_NEAR(law.eval(t).s, c.table->lift[i], test::kAmplifiedRoundoff * 0.02) << "row " << i;
      }
    }
  }
  const Source src;
  const MotionLaw coarse = build_motion_law(table_of(PeriodicBSpline::kDenseCollocation + 1), "cam.json");
  const double h = kTwoPi / (PeriodicBSpline::kDenseCollocation + 1);
  for (int k = 0; k < 101; ++k) {
    const double t = kTwoPi * (k + 0.5) / 101;
    // A quintic interpolant's error is below 0.1 |s⁽⁶⁾| h⁶, |s⁽⁶⁾| ≤ 729 · 0.002 + 0.01 m.
    EXPECT_NEAR(coarse.eval(t).s, src.s(t), 0.1 * 1.468 * std::pow(h, 6)) << t;
  }
}

}  // namespace
}  // namespace camdyn
