// The root functions declared by their owners (docs/model.md §6,
// dynamics/root_roles.h): the cam contact's gap, its force clamp switch only
// for a law with damping, then the train's gaps; root_slot() and root_of()
// inverse to each other; root_functions() writing each root by its role.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "dynamics/initial_state.h"
#include "dynamics/model.h"
#include "scenes.h"

namespace camdyn {
namespace {

/// The cycloidal cam's roller follower resting on a seat, driving a valve
/// through a one-sided link with lash; the valve resting on its own seat.
SceneConfig seated_valve_scene(ContactModel law) {
  SceneConfig s = test::cycloidal_cam_scene(1500.0, law);
  SeatConfig seat;
  seat.position = 2e-5;
  seat.model = ContactModel::lankarani_nikravesh;
  seat.stiffness = 1e9;
  seat.exponent = 1.5;
  s.mechanism.follower.seat = seat;
  TrainBodyConfig valve{"valve", 0.06, 1.0, {1.5, 2e7, 50.0, 1e-5, true}, {}, {}, {}, {}};
  valve.spring.stiffness = 30000.0;
  valve.spring.preload = 200.0;
  SeatConfig valve_seat;
  valve_seat.position = 5e-5;
  valve_seat.model = ContactModel::kelvin_voigt;
  valve_seat.stiffness = 5e8;
  valve_seat.exponent = 1.0;
  valve_seat.damping = 2000.0;
  valve.seat = valve_seat;
  s.mechanism.train = {valve};
  return s;
}

/// Checks every slot of the model against the declared order (the contact's
/// gap, its clamp switch where `clamp`, the train's gaps) and root_of() back.
void expect_declared_roots(const Model& model, bool clamp) {
  const int contact = clamp ? 2 : 1;
  ASSERT_EQ(model.root_count(), contact + model.train.roots);
  EXPECT_EQ(model.root_slot(0), (RootSlot{RootRole::contact_gap, 0}));
  EXPECT_EQ(model.root_of(RootRole::contact_gap, 0), 0);
  if (clamp) {
    EXPECT_EQ(model.root_slot(1), (RootSlot{RootRole::contact_clamp, 0}));
    EXPECT_EQ(model.root_of(RootRole::contact_clamp, 0), 1);
  } else {
    EXPECT_EQ(model.root_of(RootRole::contact_clamp, 0), -1);
  }
  for (int k = 0; k < model.train.roots; ++k) {
    EXPECT_EQ(model.root_slot(contact + k), (RootSlot{RootRole::train_gap, k})) << "train root " << k;
    EXPECT_EQ(model.root_of(RootRole::train_gap, k), contact + k) << "train root " << k;
  }
  for (int r = 0; r < model.root_count(); ++r) {
    const RootSlot slot = model.root_slot(r);
    EXPECT_EQ(model.root_of(slot.role, slot.index), r) << "root " << r;
  }
  EXPECT_EQ(model.root_of(RootRole::contact_gap, 1), -1);
  EXPECT_EQ(model.root_of(RootRole::train_gap, -1), -1);
  EXPECT_EQ(model.root_of(RootRole::train_gap, model.train.roots), -1);
}

/// root_functions() at the scene's initial state: each root written at its
/// slot with its owner's value, and nothing past root_count().
void expect_root_values(const SceneConfig& scene, const Model& model) {
  Workspace ws = make_workspace(model);
  std::vector<double> y(StateLayout::kMax, 0.0);
  ASSERT_FALSE(initial_state(scene, model, ws, y.data()));
  Evaluation ev;
  evaluate(model, ws, 0.0, y.data(), ev);
  const double unset = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> g(static_cast<std::size_t>(model.root_count()) + 1, unset);
  root_functions(model, ws, ev, g.data());
  const auto at = [&](RootRole role, int index) { return g[static_cast<std::size_t>(model.root_of(role, index))]; };
  EXPECT_EQ(at(RootRole::contact_gap, 0), ev.gap);
  if (model.contact.has_clamp_switch()) {
    EXPECT_EQ(at(RootRole::contact_clamp, 0), model.contact.clamp_switch(ev.delta, ev.delta_rate, ws.v0));
  }
  for (int k = 0; k < model.train.roots; ++k)
    EXPECT_EQ(at(RootRole::train_gap, k), ev.train.gap[static_cast<std::size_t>(k)]) << "train root " << k;
  EXPECT_TRUE(std::isnan(g.back())) << "written past root_count()";
}

TEST(RootRoles, ElasticContactDeclaresItsGapOnly) {
  const SceneConfig scene = test::cycloidal_cam_scene(1500.0, ContactModel::hertz);
  const Model model = build_model(scene, "test");
  ASSERT_FALSE(model.contact.has_clamp_switch());
  EXPECT_EQ(model.root_count(), 1);
  expect_declared_roots(model, false);
  expect_root_values(scene, model);
}

TEST(RootRoles, DampedContactDeclaresItsClampSwitch) {
  for (const ContactModel law :
       {ContactModel::kelvin_voigt, ContactModel::hunt_crossley, ContactModel::lankarani_nikravesh}) {
    SCOPED_TRACE(static_cast<int>(law));
    SceneConfig scene = test::cycloidal_cam_scene(1500.0, law);
    if (law == ContactModel::kelvin_voigt) {
      scene.mechanism.contact.exponent = 1.0;
      scene.mechanism.contact.damping = 50.0;
    }
    const Model model = build_model(scene, "test");
    ASSERT_TRUE(model.contact.has_clamp_switch());
    EXPECT_EQ(model.root_count(), 2);
    expect_declared_roots(model, true);
    expect_root_values(scene, model);
  }
}

TEST(RootRoles, TrainGapsFollowTheContactsRoots) {
  for (const ContactModel law : {ContactModel::hertz, ContactModel::hunt_crossley}) {
    SCOPED_TRACE(static_cast<int>(law));
    const SceneConfig scene = seated_valve_scene(law);
    const Model model = build_model(scene, "test");
    ASSERT_GE(model.train.roots, 3);  // the follower's seat, the link, the valve's seat
    expect_declared_roots(model, model.contact.has_clamp_switch());
    expect_root_values(scene, model);
  }
}

}  // namespace
}  // namespace camdyn
