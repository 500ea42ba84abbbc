// The held train (dynamics/held_train.h) against independent references: one
// rigid mass gives the rigid-model force of docs/model.md §9 term by term; on
// a harmonic lift the contact and link forces of a chain of 0–3 bodies with
// massless or lumped springs (0, 4, 16 coils) meet the closed form of
// tests/dynamics/linear_train_reference.h (each coordinate's row written out,
// a compliant Kelvin–Voigt contact of 1e8 N/m, whose compliance shifts the
// forces by (ω/ω_c)² ~ 1e−4), and so does the jump speed.
#include "dynamics/held_train.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "common/constants.h"
#include "dynamics/model.h"
#include "dynamics/train_jump_speed.h"
#include "linear_train_case.h"

namespace camdyn {
namespace {

constexpr int kGridAngles = 512;

GridSignal law_signal(const Model& model) {
  return grid_signal([&](double theta) { return model.law->eval(theta); }, kGridAngles);
}

// Its contact held as a stiff spring (1e8 N/m), one mass follows the rigid
// force within (ω/ω_c)² of it at a slow speed.
TEST(HeldTrain, OneMassIsTheRigidModelForce) {
  test::LinearTrainCase c = test::linear_train_case(0);
  const Model model = build_model(c.scene, "test");
  ASSERT_FALSE(model.train.has_coordinates());
  const HeldTrain held = held_train(model);
  ASSERT_EQ(held.free_coordinates(), 1);
  ASSERT_EQ(held.quantities.size(), 1u);
  const double omega = 150.0;  // [rad/s]
  const std::vector<Eigen::VectorXd> values = held_train_values(held, law_signal(model), omega);
  const FollowerConfig& f = c.scene.mechanism.follower;
  for (int i = 0; i < kGridAngles; i += 7) {
    const LawSample s = model.law->eval(kTwoPi * i / kGridAngles);
    const double rigid = f.mass * omega * omega * s.d2s + f.damping * omega * s.ds + f.spring.stiffness * s.s +
                         f.spring.preload + model.forces.weight(model.mass);
    EXPECT_NEAR(values[0][i], rigid, 1e-3 * std::abs(f.spring.preload));
  }
}

struct ChainCase {
  int bodies;
  int coils;  // of the valve's spring (0: massless)
};

class HeldTrainHarmonic : public ::testing::TestWithParam<ChainCase> {};

TEST_P(HeldTrainHarmonic, ForcesAndJumpSpeedMeetTheClosedForm) {
  const ChainCase p = GetParam();
  const test::LinearTrainCase c = test::linear_train_case(p.bodies, false, p.coils);
  const Model model = build_model(c.scene, "test");
  const HeldTrain held = held_train(model);
  const GridSignal law = law_signal(model);
  const double jump = test::reference_jump_speed(c.reference, test::kLift, 1e4);  // [rad/s]
  ASSERT_TRUE(std::isfinite(jump));
  for (const double fraction : {0.4, 0.9}) {
    const double omega = fraction * jump;
    const test::ReferenceResponse ref = test::reference_response(c.reference, test::kLift, omega);
    const std::vector<Eigen::VectorXd> v = held_train_values(held, law, omega);
    SCOPED_TRACE(testing::Message() << p.bodies << " bodies, " << p.coils << " coils at " << omega << " rad/s");
    const double scale = v[0].cwiseAbs().maxCoeff();
    EXPECT_NEAR(v[0].minCoeff(), ref.min_contact, 2e-3 * scale);
    int link = 0;
    for (std::size_t k = 0; k < held.quantities.size(); ++k) {
      if (held.quantities[k].kind == HeldQuantity::Kind::link) {
        EXPECT_NEAR(v[k].minCoeff(), ref.min_link[static_cast<std::size_t>(link++)], 2e-3 * scale);
      }
    }
    EXPECT_EQ(link, p.bodies);
  }
  const double held_jump = held_train_jump_speed(held, law, 20.0 * jump, 0.0, 0.0);
  EXPECT_NEAR(held_jump, jump, 2e-3 * jump);
  // The scene's jump_speed_rpm is the same figure (physics §8), within 0.2 % of the closed form.
  const double jump_rpm = jump * 30.0 / std::numbers::pi;
  EXPECT_NEAR(model_jump_speed_rpm(model), jump_rpm, 2e-3 * jump_rpm);
}

INSTANTIATE_TEST_SUITE_P(Chains, HeldTrainHarmonic,
                         ::testing::Values(ChainCase{0, 0}, ChainCase{1, 0}, ChainCase{1, 4}, ChainCase{1, 16},
                                           ChainCase{2, 4}, ChainCase{3, 0}, ChainCase{3, 16}),
                         [](const testing::TestParamInfo<ChainCase>& param_info) {
                           return std::to_string(param_info.param.bodies) + "_bodies_" +
                                  std::to_string(param_info.param.coils) + "_coils";
                         });

TEST(HeldTrain, HarmonicsConvergeToTheStatedTolerance) {
  const test::LinearTrainCase c = test::linear_train_case(2, false, 8);
  const Model model = build_model(c.scene, "test");
  HeldTrainResponse response(held_train(model), {law_signal(model)}, kGridAngles, 1e-6);
  const SpeedResponse& r = response.at(300.0);
  EXPECT_LE(r.truncation, 1e-6);
  EXPECT_GE(r.harmonics, 16);
  EXPECT_EQ(&response.at(300.0), &r);  // cached
}

}  // namespace
}  // namespace camdyn
