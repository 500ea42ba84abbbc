// A linear follower train scene and its independent reference
// (tests/dynamics/linear_train_reference.h), shared by the train tests: a flat
// translating follower on a harmonic rise and return, a Kelvin–Voigt cam
// contact of exponent 1, and a chain of 0–3 bodies with two-sided-held links.
#pragma once

#include <algorithm>
#include <vector>

#include "io/config.h"
#include "tests/dynamics/linear_train_reference.h"

namespace camdyn::test {

inline constexpr double kLift = 0.008;  // [m]

/// A flat translating follower on a harmonic rise and return (s = h/2 (1 − cos θ)),
/// Kelvin–Voigt cam contact of exponent 1, and `bodies` train bodies.
struct LinearTrainCase {
  SceneConfig scene;
  ReferenceTrain reference;
};

inline SpringConfig spring(double k, double preload, double mass = 0.0, int coils = 0, double zeta = 0.0) {
  SpringConfig s;
  s.stiffness = k;
  s.preload = preload;
  if (mass > 0.0) {
    s.mass = mass;
    s.coils = coils;
    s.damping_ratio = zeta;
  }
  return s;
}

inline ReferenceSpring reference_spring(const SpringConfig& s) {
  return {s.stiffness, s.preload, s.mass.value_or(0.0), s.coils.value_or(0), s.damping_ratio.value_or(0.0)};
}

inline LinearTrainCase linear_train_case(int bodies, bool follower_spring_mass = false, int valve_coils = 6) {
  LinearTrainCase c;
  SceneConfig& s = c.scene;
  s.name = "linear-train";
  s.mechanism.cam.base_radius = 0.02;
  s.mechanism.cam.motion_law.segments = {
      {SegmentType::rise, SegmentLaw::harmonic, 180.0, kLift, std::nullopt, 5, {}},
      {SegmentType::return_, SegmentLaw::harmonic, 360.0, kLift, std::nullopt, 5, {}}};
  FollowerConfig& f = s.mechanism.follower;
  f.shape.type = FollowerShape::flat;
  f.shape.face_width = 0.06;
  f.mass = 0.05;
  f.damping = 1.0;
  f.spring = follower_spring_mass ? spring(5000.0, 50.0, 0.02, 5, 0.05) : spring(5000.0, 50.0);
  ContactConfig& contact = s.mechanism.contact;
  contact.model = ContactModel::kelvin_voigt;
  contact.stiffness = 1e8;
  contact.exponent = 1.0;
  contact.damping = 300.0;
  const std::vector<TrainBodyConfig> chain = {
      {"valve",
       0.08,
       2.0,
       {1.5, 2e7, 100.0, 0.0, true},
       valve_coils > 0 ? spring(30000.0, 300.0, 0.04, valve_coils, 0.03) : spring(30000.0, 300.0),
       {},
       {},
       {}},
      {"tip", 0.03, 0.0, {1.0, 5e7, 50.0, 0.0, true}, spring(8000.0, 80.0), {}, {}, {}},
      {"end", 0.02, 0.5, {0.8, 3e7, 60.0, 0.0, true}, spring(4000.0, 40.0), {}, {}, {}}};
  s.mechanism.train.assign(chain.begin(), chain.begin() + bodies);
  s.simulation.cycles = 5;
  s.simulation.discard_cycles = 2;
  s.simulation.output_step_deg = 1.0;
  s.simulation.steady_state = true;
  s.integrator.rtol = 1e-9;
  s.integrator.atol = 1e-13;

  ReferenceTrain& r = c.reference;
  r.mass = f.mass;
  r.damper = f.damping;
  r.spring = reference_spring(f.spring);
  r.contact_stiffness = *contact.stiffness;
  r.contact_damping = *contact.damping;
  for (const TrainBodyConfig& b : s.mechanism.train) {
    ReferenceBody rb;
    rb.ratio = b.link.ratio;
    rb.link_stiffness = b.link.stiffness;
    rb.link_damping = b.link.damping;
    rb.mass = b.mass;
    rb.damper = b.damping;
    rb.spring = reference_spring(b.spring);
    r.bodies.push_back(rb);
  }
  return c;
}

}  // namespace camdyn::test
