// A scene's numbers set in place (dynamics/model.h set_scene_parameters) give
// the model build_model() makes from the scene with those values, to the last
// bit, and a workspace reused across runs gives the runs of a fresh one.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/errors.h"
#include "dynamics/model.h"
#include "dynamics/rigid_jump_speed.h"
#include "dynamics/simulation.h"
#include "io/config.h"
#include "tests/dynamics/linear_train_case.h"
#include "tests/dynamics/scenes.h"

namespace camdyn {
namespace {

/// Every double of two runs is equal (EXPECT_EQ: identical, not close).
void expect_identical(const SimulationResult& a, const SimulationResult& b, const std::string& what) {
  const std::vector<const std::vector<double>*> ca = a.series.columns(), cb = b.series.columns();
  ASSERT_EQ(ca.size(), cb.size());
  for (std::size_t k = 0; k < ca.size(); ++k) {
    ASSERT_EQ(ca[k]->size(), cb[k]->size()) << what << " column " << k;
    for (std::size_t i = 0; i < ca[k]->size(); ++i) ASSERT_EQ((*ca[k])[i], (*cb[k])[i]) << what << " column " << k;
  }
  EXPECT_EQ(a.metrics.peak_contact_force, b.metrics.peak_contact_force) << what;
  EXPECT_EQ(a.metrics.max_penetration, b.metrics.max_penetration) << what;
  EXPECT_EQ(a.metrics.energy_residual, b.metrics.energy_residual) << what;
  EXPECT_EQ(a.metrics.impact_count, b.metrics.impact_count) << what;
  EXPECT_EQ(a.metrics.jump_speed_rpm, b.metrics.jump_speed_rpm) << what;
  EXPECT_EQ(a.solver.counters.steps, b.solver.counters.steps) << what;
  EXPECT_EQ(a.solver.tracking_resets, b.solver.tracking_resets) << what;
  EXPECT_EQ(a.events.size(), b.events.size()) << what;
}

/// The scene with every parameter-block value changed (structure kept).
SceneConfig with_other_parameters(SceneConfig s) {
  FollowerConfig& f = s.mechanism.follower;
  (f.motion == FollowerMotion::oscillating ? f.inertia : f.mass) *= 1.3;
  f.spring.stiffness *= 0.9;
  f.spring.preload *= 1.1;
  f.damping = 7.5;
  ContactConfig& c = s.mechanism.contact;
  c.stiffness = 2.5e9;
  c.exponent = 1.4;
  c.restitution = 0.65;
  if (c.damping) c.damping = 300.0;
  c.reference_velocity = 0.02;
  if (c.friction.mu > 0.0) c.friction.mu = 0.15;
  c.friction.regularization_velocity = 2e-4;
  if (f.guide_friction) *f.guide_friction = {0.2, 3e-4};
  if (f.pivot_friction) *f.pivot_friction = {0.2, 0.004, 3e-4};
  if (f.shape.type == FollowerShape::roller && f.shape.inertia > 0.0) f.shape.inertia = 2e-6;
  s.mechanism.cam.rpm *= 1.1;
  s.mechanism.cam.initial_angle_deg += 3.0;
  DriveConfig& d = s.mechanism.cam.drive;
  if (d.type == Drive::shaft) {
    d.inertia = 0.012;
    d.torsional_stiffness = 2e4;
    d.torsional_damping = 0.5;
    if (d.motor.type == Motor::torque_speed) d.motor = MotorConfig{Motor::torque_speed, 12.0, 2100.0, 2e-3};
  }
  return s;
}

/// In place on a model of `base` against build_model(changed), both simulated.
void expect_in_place_equals_built(const SceneConfig& base, const std::string& what) {
  const SceneConfig changed = with_other_parameters(base);
  Model in_place = build_model(base, "test");
  Workspace ws = make_workspace(in_place);
  simulate(base, in_place, ws);  // the reused workspace has run before
  const long builds = model_builds();
  ASSERT_TRUE(set_scene_parameters(in_place, changed, "test")) << what;
  EXPECT_EQ(model_builds(), builds) << what;
  const Model built = build_model(changed, "test");
  EXPECT_EQ(in_place.mass, built.mass) << what;
  EXPECT_EQ(in_place.contact.stiffness, built.contact.stiffness) << what;
  EXPECT_EQ(in_place.contact.chi(), built.contact.chi()) << what;
  EXPECT_EQ(in_place.drive.no_load_speed, built.drive.no_load_speed) << what;
  EXPECT_EQ(in_place.elements, built.elements) << what;
  // The jump speed made once per model is renewed with the mass and spring it depends on.
  EXPECT_EQ(in_place.rigid_jump_speed_rpm, built.rigid_jump_speed_rpm) << what;
  EXPECT_EQ(built.rigid_jump_speed_rpm, jump_speed_rpm(built)) << what;
  Workspace fresh;
  expect_identical(simulate(changed, in_place, ws), simulate(changed, built, fresh), what);
}

TEST(SceneParameters, SetInPlaceGivesTheBuiltModelForEveryContactLaw) {
  for (const ContactModel law : {ContactModel::hertz, ContactModel::hunt_crossley, ContactModel::lankarani_nikravesh,
                                 ContactModel::flores, ContactModel::kelvin_voigt}) {
    SceneConfig scene = test::cycloidal_cam_scene(1300.0, law);
    if (law == ContactModel::kelvin_voigt) scene.mechanism.contact.damping = 100.0;
    scene.mechanism.follower.damping = 0.0;  // the damper element appears in place
    scene.simulation.cycles = 1.2;
    scene.simulation.discard_cycles = 0;
    expect_in_place_equals_built(scene, to_string(law));
  }
}

TEST(SceneParameters, SetInPlaceGivesTheBuiltModelForAnyFollowerFrictionOrDrive) {
  for (const std::string& kind : test::follower_kinds()) {
    SceneConfig scene = test::fully_loaded_scene(kind, 1000.0, ContactModel::lankarani_nikravesh);
    scene.simulation.cycles = 1.1;
    scene.simulation.discard_cycles = 0;
    expect_in_place_equals_built(scene, kind);
  }
}

TEST(SceneParameters, SetInPlaceGivesTheBuiltModelForADrop) {
  expect_in_place_equals_built(test::drop_scene(ContactModel::lankarani_nikravesh, 0.8), "drop");
}

TEST(SceneParameters, FrictionSwitchedOnOrOffIsAChangeOfStructure) {
  SceneConfig scene = test::follower_scene("translating_flat", 1000.0);
  scene.mechanism.follower.guide_friction = GuideFrictionConfig{0.0, 1e-4};
  Model model = build_model(scene, "test");
  EXPECT_TRUE(set_scene_parameters(model, scene, "test"));
  const std::vector<std::string> elements = model.elements;
  scene.mechanism.contact.friction.mu = 0.1;
  EXPECT_FALSE(set_scene_parameters(model, scene, "test"));
  scene.mechanism.contact.friction.mu = 0.0;
  scene.mechanism.follower.guide_friction->mu = 0.1;
  EXPECT_FALSE(set_scene_parameters(model, scene, "test"));
  EXPECT_EQ(model.elements, elements);  // untouched
  SceneConfig roller = test::cycloidal_cam_scene(1000.0);
  roller.mechanism.contact.friction.mu = 0.1;
  roller.mechanism.follower.shape.inertia = 1e-6;
  Model spinning = build_model(roller, "test");
  roller.mechanism.follower.shape.inertia = 0.0;  // a free roller: no spin state
  EXPECT_FALSE(set_scene_parameters(spinning, roller, "test"));
}

/// Every number of a follower train changed, its structure kept.
SceneConfig with_other_train(SceneConfig s) {
  s.mechanism.follower.mass *= 1.1;
  s.mechanism.follower.spring.preload *= 1.2;
  for (TrainBodyConfig& b : s.mechanism.train) {
    b.mass *= 0.9;
    b.damping *= 1.5;  // from 0 to a value is one more element: structure
    b.link.stiffness *= 1.7;
    b.link.damping *= 0.6;
    b.link.ratio *= 1.05;
    b.link.lash *= 1.05;
    b.spring.stiffness *= 0.95;
    b.spring.preload *= 1.1;
    if (b.spring.mass) *b.spring.mass *= 1.3;
    if (b.spring.damping_ratio) *b.spring.damping_ratio *= 2.0;
    if (b.seat) {
      b.seat->stiffness *= 2.0;
      b.seat->restitution = 0.5;
    }
  }
  return s;
}

// A follower train's parameters (docs/model.md §12) set in place: the train
// is built again on the model's states and the jump speeds made again, and
// the model is the one build_model() makes, to the bit; a change of the
// train's structure leaves the model as it was and asks for a build.
void expect_train_in_place_equals_built(const std::string& file) {
  SceneConfig base = load_scene(file, {"mechanism.cam.rpm=1500", "simulation.cycles=1.2", "simulation.discard_cycles=0",
                                       "simulation.output_step_deg=2"});
  const SceneConfig changed = with_other_train(base);
  Model in_place = build_model(base, file);
  ASSERT_TRUE(in_place.train.has_coordinates());
  Workspace ws = make_workspace(in_place);
  simulate(base, in_place, ws);
  const long builds = model_builds();
  ASSERT_TRUE(set_scene_parameters(in_place, changed, file));
  EXPECT_EQ(model_builds(), builds);
  const Model built = build_model(changed, file);
  EXPECT_NE(in_place.train_jump_speed_rpm, build_model(base, file).train_jump_speed_rpm);
  EXPECT_EQ(in_place.train_jump_speed_rpm, built.train_jump_speed_rpm);
  EXPECT_EQ(in_place.rigid_jump_speed_rpm, built.rigid_jump_speed_rpm);
  EXPECT_EQ(in_place.take_up.take_up, built.take_up.take_up);
  EXPECT_EQ(in_place.take_up.opening_end, built.take_up.opening_end);
  EXPECT_EQ(in_place.elements, built.elements);
  EXPECT_EQ(in_place.layout.names, built.layout.names);
  Workspace fresh;
  expect_identical(simulate(changed, in_place, ws), simulate(changed, built, fresh), file);

  SceneConfig lumps = changed;
  SpringConfig& spring = lumps.mechanism.train.back().spring;
  spring.lumps = spring.lump_count() + 1;  // other states
  const Model before = in_place;
  EXPECT_FALSE(set_scene_parameters(in_place, lumps, file));
  EXPECT_EQ(in_place.layout.names, before.layout.names);
  EXPECT_EQ(in_place.train_jump_speed_rpm, before.train_jump_speed_rpm);
}

TEST(SceneParameters, ATrainsParametersSetInPlaceGiveTheBuiltModel) {
  for (const char* scene : {"pushrod_rocker.json", "dohc_bucket_lash.json"})
    expect_train_in_place_equals_built(std::string(CAMDYN_SOURCE_DIR) + "/studies/valvetrain/" + scene);
}

TEST(Workspace, ReusedAcrossRunsGivesTheRunsOfAFreshOne) {
  for (const PairFormChoice form : {PairFormChoice::automatic, PairFormChoice::general}) {
    for (const Tracking tracking : {Tracking::differential, Tracking::newton}) {
      SceneConfig scene = test::cycloidal_cam_scene(1300.0, ContactModel::lankarani_nikravesh);
      scene.mechanism.contact.pair_form = form;
      scene.mechanism.contact.tracking = tracking;
      scene.simulation.cycles = 1.1;
      scene.simulation.discard_cycles = 0;
      const Model model = build_model(scene, "test");
      Workspace reused = make_workspace(model);
      const auto* search = reused.pair_search.get();
      simulate(scene, model, reused);
      const SimulationResult second = simulate(scene, model, reused);
      EXPECT_EQ(reused.pair_search.get(), search) << "the search samples are made once";
      Workspace fresh;
      expect_identical(second, simulate(scene, model, fresh), to_string(form) + " " + to_string(tracking));
    }
  }
}

TEST(Workspace, MadeForAnotherModelIsRemadeNotReused) {
  SceneConfig scene = test::cycloidal_cam_scene(1300.0, ContactModel::lankarani_nikravesh);
  scene.mechanism.contact.pair_form = PairFormChoice::general;
  scene.mechanism.contact.tracking = Tracking::newton;
  scene.simulation.cycles = 1.1;
  scene.simulation.discard_cycles = 0;
  const Model first = build_model(scene, "test");
  Workspace ws = make_workspace(first);
  scene.mechanism.follower.shape.radius = 0.012;
  const Model second = build_model(scene, "test");
  const SimulationResult reused = simulate(scene, second, ws);
  EXPECT_EQ(ws.pair_search_cam, second.pair_cam);
  Workspace fresh;
  expect_identical(reused, simulate(scene, second, fresh), "another model");
}

}  // namespace
}  // namespace camdyn
