// Camshaft drive (mechanism.cam.drive.type = Drive::shaft): a cam with inertia on a
// torsionally compliant shaft from a constant-speed or torque–speed motor.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "dynamics/simulation.h"
#include "scenes.h"

namespace camdyn {
namespace {

SceneConfig shaft_scene(double inertia, double stiffness, ContactModel model = ContactModel::lankarani_nikravesh) {
  SceneConfig s = test::cycloidal_cam_scene(700.0, model);
  DriveConfig& d = s.mechanism.cam.drive;
  d.type = Drive::shaft;
  d.inertia = inertia;
  d.torsional_stiffness = stiffness;
  return s;
}

/// Largest difference of the follower position over the evaluated cycles [m].
double position_difference(const SimulationResult& a, const SimulationResult& b) {
  double worst = 0.0;
  for (size_t i = 0; i < std::min(a.series.time.size(), b.series.time.size()); ++i)
    if (a.series.time[i] >= a.evaluated_from)
      worst = std::max(worst, std::abs(a.series.follower_position[i] - b.series.follower_position[i]));
  return worst;
}

TEST(ShaftDrive, StiffHeavyShaftConvergesToConstantSpeed) {
  const SimulationResult reference =
      simulate_scene(test::cycloidal_cam_scene(700.0, ContactModel::lankarani_nikravesh), "test");
  const SimulationResult soft = simulate_scene(shaft_scene(0.02, 2e3), "test");
  const SimulationResult stiff = simulate_scene(shaft_scene(2.0, 2e5), "test");
  const double e_soft = position_difference(soft, reference), e_stiff = position_difference(stiff, reference);
  const double f_soft = std::abs(soft.metrics.peak_contact_force / reference.metrics.peak_contact_force - 1.0);
  const double f_stiff = std::abs(stiff.metrics.peak_contact_force / reference.metrics.peak_contact_force - 1.0);
  RecordProperty("position_difference_soft_m", std::to_string(e_soft));
  RecordProperty("position_difference_stiff_m", std::to_string(e_stiff * 1e9) + "e-9");
  RecordProperty("peak_force_difference_soft", std::to_string(f_soft));
  RecordProperty("peak_force_difference_stiff", std::to_string(f_stiff * 1e6) + "e-6");
  // Speed fluctuation ∝ 1/J and twist ∝ 1/k: 100× stiffer and heavier, ~100× closer.
  EXPECT_GT(e_soft, 20.0 * e_stiff);
  EXPECT_LT(e_stiff, 1e-6);  // [m], against a 20 mm lift
  EXPECT_LT(f_stiff, 1e-3);
  EXPECT_GT(f_soft, f_stiff);
  // The cam speed follows the motor's on average, and fluctuates.
  const auto [lo, hi] = std::minmax_element(soft.series.cam_speed_rpm.begin(), soft.series.cam_speed_rpm.end());
  EXPECT_LT(*lo, 700.0);
  EXPECT_GT(*hi, 700.0);
}

TEST(ShaftDrive, EnergyBalanceClosesWithMotorWork) {
  // Conservative everywhere except the motor: Hertz contact, no dampers.
  for (const char* motor : {"constant_speed", "torque_speed"}) {
    SceneConfig scene = shaft_scene(0.01, 500.0, ContactModel::hertz);
    if (std::string(motor) == "torque_speed")
      scene.mechanism.cam.drive.motor = MotorConfig{Motor::torque_speed, 5.0, 1000.0, 2e-3};
    const SimulationResult r = simulate_scene(scene, "test");
    const auto [lo, hi] = std::minmax_element(r.series.cam_speed_rpm.begin(), r.series.cam_speed_rpm.end());
    EXPECT_GT(*hi - *lo, 1.0) << motor;  // the shaft is really compliant
    EXPECT_LT(r.metrics.energy_residual, 1e-6) << motor;
    RecordProperty(std::string("energy_residual_") + motor, std::to_string(r.metrics.energy_residual * 1e9) + "e-9");
  }
  // With a shaft damper its work enters the balance too.
  SceneConfig damped = shaft_scene(0.01, 500.0, ContactModel::lankarani_nikravesh);
  damped.mechanism.cam.drive.torsional_damping = 0.05;
  EXPECT_LT(simulate_scene(damped, "test").metrics.energy_residual, 1e-6);
}

}  // namespace
}  // namespace camdyn
