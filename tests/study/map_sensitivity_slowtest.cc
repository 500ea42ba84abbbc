// The Poincaré map's Jacobian by forward sensitivities on the bucket tappet
// with its 8-coil valve spring (studies/valvetrain/bucket_tappet.json: 18
// section coordinates; the train's Jacobian, dynamics/follower_train.h,
// carries the sensitivities) against Richardson differences of the map
// itself. Without its seat: with it the valve bounces on the seat 14 times a
// revolution, and the map bends so sharply that central differences agree
// with the sensitivities only as h → 1e-5 (to 4e-4), below which the
// integration error takes over. (The saltation at impacts is checked on the
// bouncing ball and the long-flight cam, map_sensitivity_test.cc.) Without
// the seat the cam keeps contact, no event falls in the revolution, and the
// check is of the train's Jacobian carried through the run.
//
// Tolerance (tests/study/map_jacobian_reference.h, with one level changed):
// at rtol = 1e-10 (rtol = 1e-12 takes minutes per reference here) the map's
// runs differ from one another by ε ≈ 1e-9 of the scales: the integration
// error and the drift projections of the contact pair (each snaps the pair
// parameter by up to 1e-9 rad, where the sensitivity run follows the
// tracking law smoothly). Over the smallest step the map's bending allows,
// h = 1e-5, that leaves the reference good to about ε/h ≈ 1e-4 of ‖J‖, so
// its measured spread may be up to 1e-3 ‖J‖ (not 1e-5); the sensitivities
// must agree to 1e-6 ‖J‖ beyond it. A train Jacobian missing a term, or
// sensitivities not carried through it, is off by order one.
#include <gtest/gtest.h>

#include <string>

#include "map_jacobian_reference.h"

namespace camdyn {
namespace {

using namespace test;  // NOLINT(google-build-using-namespace): the shared reference

TEST(MapSensitivity, EightCoilValveSpringJacobianMatchesRichardsonDifferences) {
  const std::string file = kSource + "/studies/valvetrain/bucket_tappet.json";
  const MapAt s = map_at(read_tight(file,
                                    [](Json& doc) {
                                      doc["mechanism"]["follower"].erase("seat");
                                      doc["integrator"]["rtol"] = 1e-10;  // see the header comment
                                      doc["integrator"]["atol"] = 1e-14;
                                    }),
                         2);
  ASSERT_EQ(s.map->dimension(), 18) << "the follower and 8 coil lumps, each a position and a rate";
  constexpr double kTrainReferenceSpread = 1e-3;  // ε/h with ε ≈ 1e-9, h = 1e-5, and a margin of ten
  expect_sensitivity_matches_reference(s, 1, 1e-5, nullptr, kTrainReferenceSpread);
}

}  // namespace
}  // namespace camdyn
