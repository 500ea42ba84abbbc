// Chatter detection (dynamics/chatter.h) on event lists made by hand: a rigid
// ball's geometric flights are one sequence accumulating where the series
// sums to; flights that do not shrink, or a sequence the follower leaves
// again at once, are not chatter.
#include "dynamics/chatter.h"

#include <gtest/gtest.h>

#include <vector>

namespace camdyn {
namespace {

constexpr double kDegPerS = 360.0;  // one revolution a second

// A jump (take-off at 0.1 s, landing at 0.3 s), then flights τ₁ rⁿ with
// contacts of `contact` seconds between them, then contact until `t_end`.
std::vector<ContactEvent> bounces(double tau1, double r, int flights, double contact) {
  std::vector<ContactEvent> events;
  auto add = [&](double t, bool onset) { events.push_back({t, t * kDegPerS, onset, 0.1, onset, 0.0, false, false}); };
  add(0.1, false);
  double t = 0.3;
  add(t, true);
  double tau = tau1;
  for (int k = 0; k < flights; ++k) {
    t += contact;
    add(t, false);
    t += tau;
    add(t, true);
    tau *= r;
  }
  return events;
}

TEST(Chatter, GeometricFlightsAccumulateWhereTheSeriesSums) {
  const double tau1 = 0.04, r = 0.6;
  const std::vector<ChatterSequence> c = find_chatter(bounces(tau1, r, 8, 0.0), 1.0, kDegPerS);
  ASSERT_EQ(c.size(), 1u);
  // The landings of the 8 bouncing flights (the jump's flight is no term of the series).
  EXPECT_EQ(c[0].impacts, 8u);
  EXPECT_NEAR(c[0].first_impact_time, 0.3 + tau1, 1e-12);
  EXPECT_NEAR(c[0].ratio, r, 1e-12);
  // The jump's landing at 0.3 s, then τ₁ / (1 − r).
  EXPECT_NEAR(c[0].accumulation_time, 0.3 + tau1 / (1.0 - r), 1e-12);
  EXPECT_NEAR(c[0].accumulation_deg, (0.3 + tau1 / (1.0 - r)) * kDegPerS, 1e-9);
}

TEST(Chatter, FlightsThatDoNotShrinkAreNotChatter) {
  EXPECT_TRUE(find_chatter(bounces(0.04, 1.0, 8, 0.0), 1.0, kDegPerS).empty());
  EXPECT_TRUE(find_chatter(bounces(0.04, 0.6, 2, 0.0), 1.0, kDegPerS).empty());  // too few impacts
}

TEST(Chatter, ASequenceTheFollowerLeavesAtOnceIsNotChatter) {
  std::vector<ContactEvent> events = bounces(0.04, 0.6, 8, 0.0);
  const double last = events.back().time;
  // Thrown off again right after the last bounce, for a long flight.
  events.push_back({last + 1e-4, 0.0, false, 0.1, false, 0.0, false, false});
  events.push_back({last + 0.2, 0.0, true, 0.1, true, 0.0, false, false});
  EXPECT_TRUE(find_chatter(events, 1.0, kDegPerS).empty());
}

}  // namespace
}  // namespace camdyn
