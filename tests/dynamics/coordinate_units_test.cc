// The follower coordinate's units (dynamics/coordinate_units.h): metres for a
// translating follower, radians for an oscillating arm, and the lift a
// position is judged against in the same unit.
#include "dynamics/coordinate_units.h"

#include <gtest/gtest.h>

#include <numbers>
#include <string>

#include "scenes.h"

namespace camdyn {
namespace {

/// The test cams' lift: 20 mm, or 12° for an arm (tests/dynamics/scenes.h).
constexpr double kUnitsLift = 0.02;                                // [m]
constexpr double kUnitsArmLift = 12.0 * std::numbers::pi / 180.0;  // [rad]
/// A lift built from segments is the sum of their rises, exact up to rounding.
constexpr double kLiftRounding = 1e-14;

TEST(CoordinateUnits, TranslatingFollowerIsInMetresAndNewtons) {
  const Model model = build_model(test::follower_scene("translating_roller", 1000.0), "test");
  const CoordinateUnits u = coordinate_units(model);
  EXPECT_FALSE(u.oscillating);
  EXPECT_STREQ(u.position, "m");
  EXPECT_STREQ(u.velocity, "m/s");
  EXPECT_STREQ(u.acceleration, "m/s²");
  EXPECT_STREQ(u.force, "N");
  EXPECT_STREQ(u.position_name, "follower position");
  EXPECT_EQ(u.per_cam_radian(3, true), "m/rad^3");
  EXPECT_EQ(u.per_cam_radian(2), "m/rad²");
  EXPECT_NEAR(coordinate_lift(model), kUnitsLift, kLiftRounding);
}

TEST(CoordinateUnits, OscillatingArmIsInRadiansAndNewtonMetres) {
  const Model model = build_model(test::follower_scene("oscillating_roller", 1000.0), "test");
  const CoordinateUnits u = coordinate_units(model);
  EXPECT_TRUE(u.oscillating);
  EXPECT_STREQ(u.position, "rad");
  EXPECT_STREQ(u.velocity, "rad/s");
  EXPECT_STREQ(u.acceleration, "rad/s²");
  EXPECT_STREQ(u.force, "N m");
  EXPECT_STREQ(u.position_name, "arm angle");
  EXPECT_EQ(u.per_cam_radian(3, true), "rad/rad^3");
  // The lift is the arm's rotation in rad, not the arc its roller travels.
  EXPECT_NEAR(coordinate_lift(model), kUnitsArmLift, kLiftRounding);
}

TEST(CoordinateUnits, SceneAndModelAgree) {
  for (const std::string& kind : test::follower_kinds()) {
    const SceneConfig scene = test::follower_scene(kind, 1000.0);
    EXPECT_STREQ(coordinate_units(scene).position, coordinate_units(build_model(scene, "test")).position) << kind;
  }
}

TEST(CoordinateUnits, ValueAndAxisCarryTheUnit) {
  EXPECT_EQ(CoordinateUnits::with_unit(0.00638, "rad"), "0.00638 rad");
  EXPECT_EQ(CoordinateUnits::axis("arm angle", "rad"), "arm angle [rad]");
}

TEST(CoordinateUnits, FollowerFieldsAlongTheCoordinateTakeTheArmsUnits) {
  const CoordinateUnits arm = coordinate_units(FollowerMotion::oscillating);
  const CoordinateUnits slider = coordinate_units(FollowerMotion::translating);
  EXPECT_EQ(coordinate_field_unit("mechanism.follower.spring.stiffness", arm), "N m/rad");
  EXPECT_EQ(coordinate_field_unit("mechanism.follower.spring.stiffness", slider), "N/m");
  EXPECT_EQ(coordinate_field_unit("mechanism.follower.spring.preload", arm), "N m");
  EXPECT_EQ(coordinate_field_unit("mechanism.follower.damping", arm), "N m s/rad");
  EXPECT_EQ(coordinate_field_unit("mechanism.follower.initial.velocity", arm), "rad/s");
  EXPECT_EQ(coordinate_field_unit("mechanism.contact.stiffness", arm), "");  // at the contact: not q's
}

}  // namespace
}  // namespace camdyn
