// A gas load on a train body (docs/model.md §12, "Gas load"): its pressure
// table against the closed form of linear interpolation, a constant pressure
// against the same force given as a spring preload, the energy balance with
// its work, and the closed forms it turns off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "converged_run.h"
#include "dynamics/free_flight.h"
#include "dynamics/model.h"
#include "dynamics/rigid_jump_speed.h"
#include "dynamics/simulation.h"
#include "dynamics/train_jump_speed.h"
#include "scenes.h"

namespace camdyn {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

GasLoad table_load() {
  GasLoad g;
  g.area = 1e-3;
  g.crank_ratio = 2.0;
  g.tdc_deg = 10.0;
  g.port_pressure = 1e5;
  g.crank_deg = {0.0, 100.0, 400.0};
  g.pressure = {1e5, 5e6, 2e5};
  return g;
}

TEST(GasLoad, PressureIsLinearBetweenRowsAndRepeatsEveryCamTurn) {
  const GasLoad g = table_load();
  const auto force_at_cam_deg = [&](double cam_deg) { return g.force(cam_deg * kDeg); };
  // Crank angle 2 (θ − 10°): the rows, between them, and the closing segment 400° → 720°.
  EXPECT_NEAR(force_at_cam_deg(10.0), 0.0, 1e-9);
  EXPECT_NEAR(force_at_cam_deg(35.0), 1e-3 * (0.5 * (1e5 + 5e6) - 1e5), 1e-6);
  EXPECT_NEAR(force_at_cam_deg(60.0), 1e-3 * (5e6 - 1e5), 1e-6);
  const double closing = 2e5 + (1e5 - 2e5) * (160.0 / 320.0);  // crank 560°
  EXPECT_NEAR(force_at_cam_deg(290.0), 1e-3 * (closing - 1e5), 1e-6);
  // Every cam turn the same, forwards and backwards.
  for (double cam_deg : {35.0, 60.0, 123.0, 290.0})
    for (int turns : {-2, 1, 7})
      EXPECT_NEAR(force_at_cam_deg(cam_deg + 360.0 * turns), force_at_cam_deg(cam_deg), 1e-6);
  // ∂F/∂θ against central differences inside each segment.
  for (double cam_deg : {20.0, 100.0, 250.0, 340.0}) {
    double d_theta = 0.0;
    g.force(cam_deg * kDeg, &d_theta);
    const double h = 1e-6;
    const double fd = (g.force(cam_deg * kDeg + h) - g.force(cam_deg * kDeg - h)) / (2.0 * h);
    EXPECT_NEAR(d_theta, fd, 1e-6 * std::abs(fd)) << cam_deg;
  }
}

/// A valve train (tests/dynamics/scenes.h's cycloidal cam): a follower on its
/// seat driving a valve through a one-sided link, the valve on its own seat
/// with a massless spring.
SceneConfig valve_scene(double rpm) {
  SceneConfig s = test::cycloidal_cam_scene(rpm, ContactModel::hunt_crossley);
  s.mechanism.follower.spring.stiffness = 5000.0;
  s.mechanism.follower.spring.preload = 50.0;
  TrainBodyConfig valve;
  valve.name = "valve";
  valve.mass = 0.06;
  valve.link = {1.0, 2e7, 50.0, 0.0, true};
  valve.spring.stiffness = 30000.0;
  valve.spring.preload = 250.0;
  SeatConfig seat;
  seat.position = 0.0;
  seat.model = ContactModel::hunt_crossley;
  seat.stiffness = 1e9;
  seat.exponent = 1.0;
  seat.restitution = 0.3;
  valve.seat = seat;
  s.mechanism.train = {valve};  // 3 cycles, rtol 1e-9 (the cycloidal scene's)
  return s;
}

GasLoadConfig gas_config(std::vector<double> crank_deg, std::vector<double> pressure) {
  GasLoadConfig g;
  g.area = 7e-4;
  g.pressure = "table";
  g.port_pressure = 1e5;
  g.crank_deg = std::move(crank_deg);
  g.pressure_pa = std::move(pressure);
  return g;
}

using test::converged_run;

const std::vector<double>& column(const SimulationResult& r, const std::string& name) {
  const auto it = std::find(r.series.train_names.begin(), r.series.train_names.end(), name);
  EXPECT_NE(it, r.series.train_names.end()) << name;
  return r.series.train[static_cast<std::size_t>(it - r.series.train_names.begin())];
}

// A constant pressure is a constant force on the valve towards its seat: the
// same motion as a spring preload larger by A (p − p_port), to the
// integrator's tolerance.
TEST(GasLoad, ConstantPressureMovesTheValveAsAPreloadDoes) {
  SceneConfig gas = valve_scene(1500.0);
  gas.mechanism.train[0].gas = gas_config({0.0, 360.0}, {4e5, 4e5});
  SceneConfig preload = valve_scene(1500.0);
  const double force = 7e-4 * (4e5 - 1e5);  // [N]
  preload.mechanism.train[0].spring.preload += force;
  const SimulationResult a = converged_run(gas), b = converged_run(preload);
  const std::vector<double>&xa = column(a, "valve_position"), &xb = column(b, "valve_position");
  ASSERT_EQ(xa.size(), xb.size());
  double largest = 0.0, lift = 0.0;  // [m]
  for (std::size_t i = 0; i < xa.size(); ++i) {
    largest = std::max(largest, std::abs(xa[i] - xb[i]));
    lift = std::max(lift, std::abs(xb[i]));
  }
  // rtol 1e-9 on a lift of ~1e-2 m, with seat impacts re-timed by the
  // event locator: well within 1e-4 of the lift.
  EXPECT_LT(largest, 1e-4 * lift);
  for (double f : column(a, "valve_gas_force")) EXPECT_NEAR(f, force, 1e-9 * force);
  ASSERT_TRUE(a.metrics.train);
  EXPECT_NEAR(a.metrics.train->peak_gas_force, force, 1e-9 * force);
}

// Quasi-statically (20 rpm) the valve is in static balance, link + seat =
// spring + gas: a constant pressure shifts the link and seat forces it
// carries by A (p − p_port), less the valve spring's change k Δx (the valve
// sits lower by the link's and seat's compliance).
TEST(GasLoad, AtQuasiStaticSpeedShiftsTheLinkAndSeatForcesByTheLoad) {
  SceneConfig plain = valve_scene(20.0);
  SceneConfig gas = plain;
  gas.mechanism.train[0].gas = gas_config({0.0, 360.0}, {4e5, 4e5});
  const double load = 7e-4 * (4e5 - 1e5), k = plain.mechanism.train[0].spring.stiffness;  // [N], [N/m]
  const SimulationResult a = converged_run(gas), b = converged_run(plain);
  const std::vector<double>&link_a = column(a, "valve_link_force"), &link_b = column(b, "valve_link_force");
  const std::vector<double>&seat_a = column(a, "valve_seat_force"), &seat_b = column(b, "valve_seat_force");
  const std::vector<double>&x_a = column(a, "valve_position"), &x_b = column(b, "valve_position");
  ASSERT_EQ(link_a.size(), link_b.size());
  // The samples where both runs have the valve on its seat, or both off it,
  // two samples (1°) either side: the loaded valve leaves its seat later
  // and lands on it earlier, and the stiff seat's release is not static.
  const auto steady = [&](std::size_t i) {
    for (std::size_t j = i < 2 ? 0 : i - 2; j <= i + 2 && j < seat_a.size(); ++j)
      if ((seat_a[j] > 0.0) != (seat_b[j] > 0.0)) return false;
    return true;
  };
  double worst = 0.0;  // [N]
  std::size_t compared = 0;
  for (std::size_t i = 0; i < link_a.size(); ++i) {
    if (!steady(i)) continue;
    ++compared;
    const double shift = (link_a[i] + seat_a[i]) - (link_b[i] + seat_b[i]) - k * (x_a[i] - x_b[i]);
    worst = std::max(worst, std::abs(shift - load));
  }
  EXPECT_GT(compared, 9 * link_a.size() / 10);
  // What is left is the valve's inertia m ẍ at 20 rpm and the integrator's
  // error on the forces of stiff elements (K 1e9 N/m × rtol-sized positions).
  EXPECT_LT(worst, 1e-6 * load);
  EXPECT_LT(a.metrics.energy_residual, 100.0 * gas.integrator.rtol);
}

// A pressure that changes over the cam turn does work on the valve (about
// 3 J a turn here, as much as the spring stores), and the energy balance
// counts it (W_external): the residual closes at 100 × rtol, at the level of
// the same run without the load.
TEST(GasLoad, TheEnergyBalanceCountsItsWork) {
  SceneConfig gas = valve_scene(1500.0);
  // Blowdown: 6 bar at the valve's opening (cam 0–180°: crank 0–360°), then near the port's.
  gas.mechanism.train[0].gas = gas_config({0.0, 60.0, 200.0, 360.0, 500.0}, {6e5, 4e5, 1.5e5, 1.1e5, 3e5});
  const SimulationResult with = converged_run(gas), without = converged_run(valve_scene(1500.0));
  const Model model = build_model(gas, "test");
  const std::vector<std::string> quadratures = integrated_quadratures(model);
  EXPECT_NE(std::find(quadratures.begin(), quadratures.end(), "external_work"), quadratures.end());
  EXPECT_LT(with.metrics.energy_residual, 100.0 * gas.integrator.rtol);
  EXPECT_LT(with.metrics.energy_residual, std::max(10.0 * without.metrics.energy_residual, 1e-6));
  // The largest |A (p − p_port)| of the table is at its 6 bar row, which the output samples hit.
  ASSERT_TRUE(with.metrics.train);
  EXPECT_NEAR(with.metrics.train->peak_gas_force, 7e-4 * (6e5 - 1e5), 1e-9);
}

// A force given against the cam angle has no time-invariant linear part: the
// closed forms that sum the linear parts turn off instead of leaving it out.
TEST(GasLoad, TurnsTheClosedFormsOff) {
  SceneConfig scene = valve_scene(1500.0);
  const Model plain = build_model(scene, "test");
  ASSERT_TRUE(std::isfinite(jump_speed_rpm(plain)));
  scene.mechanism.train[0].gas = gas_config({0.0, 360.0}, {4e5, 4e5});
  const Model model = build_model(scene, "test");
  EXPECT_TRUE(model.train.time_dependent());
  EXPECT_FALSE(follower_linear_parts(model));
  EXPECT_FALSE(flight_has_closed_form(model));
  EXPECT_TRUE(std::isnan(jump_speed_rpm(model)));
  EXPECT_TRUE(std::isnan(model.rigid_jump_speed_rpm));
}

TEST(GasLoad, RefusesATableThatIsNotOneCamTurn) {
  SceneConfig scene = valve_scene(1500.0);
  const auto message = [&](std::vector<double> crank, std::vector<double> p) -> std::string {
    scene.mechanism.train[0].gas = gas_config(std::move(crank), std::move(p));
    try {
      build_model(scene, "scene.json");
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message({0.0, 100.0, 100.0}, {1e5, 2e5, 3e5}).find("mechanism.train[0].gas.pressure"), std::string::npos);
  EXPECT_NE(message({0.0, 720.0}, {1e5, 2e5}).find("one cam turn"), std::string::npos);
  EXPECT_NE(message({0.0, 100.0}, {1e5, -2e5}).find(">= 0"), std::string::npos);
  // One crank for the table and the report.
  scene.outputs.valvetrain = ValvetrainOutputConfig{};
  scene.outputs.valvetrain->tdc_deg = 30.0;
  EXPECT_NE(message({0.0, 100.0}, {1e5, 2e5}).find("outputs.valvetrain"), std::string::npos);
}

}  // namespace
}  // namespace camdyn
