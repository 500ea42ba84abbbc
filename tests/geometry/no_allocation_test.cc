// MotionLaw::eval and the cam pitch evaluation run in the ODE right-hand side:
// they must not allocate. Counts calls to the global operator new (replaced
// for this test executable) while evaluating every kind of law.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "allocation_counter.h"
#include "geometry/cam_roller.h"
#include "law_checks.h"

namespace camdyn {
namespace {

using test::dwell;
using test::segment;

TEST(NoAllocation, EvaluatingLawsAndPitchCurveDoesNotAllocate) {
  SegmentConfig spline = segment("return", "spline", 300, 0.01);
  spline.control_points = {0.2, 0.5, 0.8};
  MotionLawConfig periodic;
  periodic.spline = PeriodicSplineConfig{5, {0, 60, 120, 180, 240, 300}, {0, 1, 3, 2, 1, 0.5}};
  const std::vector<MotionLaw> laws = {
      test::build(test::segments({segment("rise", "modified_sine", 120, 0.01), dwell(180), spline, dwell(360)})),
      test::build(periodic)};
  for (const MotionLaw& law : laws) {
    TranslatingRollerCam cam;
    cam.law = &law;
    cam.base_radius = 0.04;
    cam.roller_radius = 0.01;
    const long before = camdyn::test::allocation_count();
    double sink = 0.0;
    for (int i = -500; i < 500; ++i) {
      const double th = i * 0.0137;
      sink += law.eval(th).d3s + cam.pitch(th).d3r.x() + cam.pressure_angle(th);
    }
    EXPECT_EQ(camdyn::test::allocation_count(), before);
    EXPECT_TRUE(std::isfinite(sink));
  }
}

}  // namespace
}  // namespace camdyn
