// Scenes built in code for the physics tests.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace camdyn::test {

/// The acceptance level of the rigid-model comparisons: a simulated contact
/// force within 0.5 % of the rigid model's.
inline constexpr double kRigidForceAcceptance = 5e-3;
/// Relative accuracy of the tests' rigid-model jump speeds: the minimum over
/// 36000 sampled angles misses a smooth minimum between samples by
/// ≈ (π/36000)²·|ω''/ω| ≪ 1e-6.
inline constexpr double kRigidJumpGrid = 1e-6;

/// A cam with a 20 mm cycloidal rise over 120°, dwell, cycloidal return over
/// 120°, dwell; base radius 40 mm, roller 10 mm, follower 0.3 kg on a 5 kN/m
/// spring with 40 N preload; Hertz-type contact K = 1e10 N/m^1.5.
inline SceneConfig cycloidal_cam_scene(double rpm, ContactModel model = ContactModel::hertz) {
  SceneConfig s;
  s.name = "test-cycloidal";
  CamConfig& cam = s.mechanism.cam;
  cam.base_radius = 0.04;
  cam.rpm = rpm;
  SegmentConfig rise{SegmentType::rise, SegmentLaw::cycloidal, 120.0, 0.02, std::nullopt, 5, {}};
  SegmentConfig dwell1{SegmentType::dwell, SegmentLaw::none, 180.0, std::nullopt, std::nullopt, 5, {}};
  SegmentConfig ret{SegmentType::return_, SegmentLaw::cycloidal, 300.0, 0.02, std::nullopt, 5, {}};
  SegmentConfig dwell2{SegmentType::dwell, SegmentLaw::none, 360.0, std::nullopt, std::nullopt, 5, {}};
  cam.motion_law.segments = {rise, dwell1, ret, dwell2};
  FollowerConfig& f = s.mechanism.follower;
  f.shape.radius = 0.01;
  f.mass = 0.3;
  f.spring.stiffness = 5000.0;
  f.spring.preload = 40.0;
  ContactConfig& c = s.mechanism.contact;
  c.model = model;
  c.stiffness = 1e10;
  c.exponent = 1.5;
  c.restitution = 0.8;
  s.simulation.cycles = 3;
  s.simulation.discard_cycles = 1;
  s.simulation.output_step_deg = 0.5;
  s.integrator.rtol = 1e-9;
  s.integrator.atol = 1e-13;
  return s;
}

/// A drop test: the cam held still with its base circle under the roller,
/// no spring, no gravity; the follower starts `gap` above contact moving
/// towards the cam at `v0`.
inline SceneConfig drop_scene(ContactModel model, double restitution, double v0 = 1.0, double gap = 1e-4) {
  SceneConfig s = cycloidal_cam_scene(0.0, model);
  s.name = "test-drop";
  s.mechanism.cam.initial_angle_deg = 330.0;  // base-circle dwell under the roller
  s.mechanism.follower.spring = {};
  s.mechanism.follower.mass = 0.1;
  s.mechanism.follower.initial.position = gap;
  s.mechanism.follower.initial.velocity = -v0;
  s.mechanism.contact.stiffness = 1e9;
  s.mechanism.contact.restitution = restitution;
  s.simulation.cycles.reset();
  s.simulation.duration = 1.5e-3;
  s.simulation.output_step = 1e-6;
  s.integrator.rtol = 1e-10;
  s.integrator.atol = 1e-14;
  return s;
}

}  // namespace camdyn::test

namespace camdyn::test {

/// The follower types of issue 4 on the cycloidal cam of cycloidal_cam_scene
/// (rise, dwell, return, dwell; base radius 40 mm; Hertz-type K = 1e10):
///   "translating_roller"    roller r = 10 mm (the scene above)
///   "translating_flat"      flat face 60 mm wide
///   "translating_mushroom"  mushroom face R = 25 mm
///   "oscillating_roller"    arm 80 mm from a pivot at (100, 60) mm, roller 10 mm,
///                           12° rise, I = 2e-3 kg m², torsional spring 50 N m/rad, 5 N m preload
///   "oscillating_flat"      face through the same pivot, face centre 110 mm from it, 80 mm wide
///   "oscillating_mushroom"  as the oscillating roller with a mushroom R = 25 mm
inline SceneConfig follower_scene(const std::string& kind, double rpm, ContactModel model = ContactModel::hertz) {
  SceneConfig s = cycloidal_cam_scene(rpm, model);
  s.name = "test-" + kind;
  FollowerConfig& f = s.mechanism.follower;
  const bool oscillating = kind.rfind("oscillating", 0) == 0;
  if (kind.find("flat") != std::string::npos) {
    f.shape = {};
    f.shape.type = FollowerShape::flat;
    f.shape.face_width = oscillating ? 0.08 : 0.06;
  } else if (kind.find("mushroom") != std::string::npos) {
    f.shape = {};
    f.shape.type = FollowerShape::mushroom;
    f.shape.radius = 0.025;
  }
  if (oscillating) {
    f.motion = FollowerMotion::oscillating;
    f.pivot = {0.1, 0.06};
    f.arm_length = f.shape.type == FollowerShape::flat ? 0.11 : 0.08;
    f.mass = 0.0;
    f.inertia = 2e-3;
    f.spring.stiffness = 50.0;
    f.spring.preload = 5.0;
    for (SegmentConfig& seg : s.mechanism.cam.motion_law.segments) {
      if (!seg.lift) continue;
      seg.lift.reset();
      seg.lift_deg = 12.0;
    }
  }
  return s;
}

/// A contour cam: a circular disc of radius R whose centre is ε below the cam
/// axis, as n points (its lowest point under the follower at cam angle 0).
inline std::vector<std::vector<double>> eccentric_disc(double radius, double eccentricity, int n = 120) {
  std::vector<std::vector<double>> points;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * 3.141592653589793 * i / n;
    points.push_back({radius * std::cos(a), -eccentricity + radius * std::sin(a)});
  }
  return points;
}

/// Replaces a scene's cam by that disc (R = 30 mm, ε = 4 mm) given as a contour.
inline void use_eccentric_disc_contour(SceneConfig& s, int n = 120) {
  s.mechanism.cam.base_radius = 0.0;
  s.mechanism.cam.motion_law = {};
  s.mechanism.cam.motion_law.contour = ContourConfig{};
  s.mechanism.cam.motion_law.contour->points = eccentric_disc(0.03, 0.004, n);
}

inline const std::vector<std::string>& follower_kinds() {
  static const std::vector<std::string> kinds = {"translating_roller", "translating_flat", "translating_mushroom",
                                                 "oscillating_roller", "oscillating_flat", "oscillating_mushroom"};
  return kinds;
}

/// follower_scene(kind) with every optional element: contact friction μ = 0.1
/// (a roller with spin inertia 1e-6 kg m²), guide or pivot friction μ = 0.1,
/// and a shaft drive (J_c = 0.01 kg m², k_s = 1e4 N m/rad) from a torque-speed
/// motor (10 N m stall, 2000 rpm no load, J_m = 1e-3 kg m²).
inline SceneConfig fully_loaded_scene(const std::string& kind, double rpm, ContactModel model) {
  SceneConfig scene = follower_scene(kind, rpm, model);
  FollowerConfig& f = scene.mechanism.follower;
  scene.mechanism.contact.friction.mu = 0.1;
  if (f.shape.type == FollowerShape::roller) f.shape.inertia = 1e-6;
  if (f.motion == FollowerMotion::oscillating)
    f.pivot_friction = PivotFrictionConfig{0.1, 0.005, 1e-4};
  else
    f.guide_friction = GuideFrictionConfig{0.1, 1e-4};
  scene.mechanism.cam.drive.type = Drive::shaft;
  scene.mechanism.cam.drive.inertia = 0.01;
  scene.mechanism.cam.drive.torsional_stiffness = 1e4;
  scene.mechanism.cam.drive.motor = MotorConfig{Motor::torque_speed, 10.0, 2000.0, 1e-3};
  return scene;
}

/// A valve seat with Hunt–Crossley contact (linear, n = 1) at `position` [m]
/// below the train's rest position, of stiffness [N/m] and restitution [-].
inline SeatConfig hunt_crossley_seat(double position, double stiffness = 5e8, double restitution = 0.3) {
  SeatConfig seat;
  seat.position = position;
  seat.model = ContactModel::hunt_crossley;
  seat.stiffness = stiffness;
  seat.exponent = 1.0;
  seat.restitution = restitution;
  return seat;
}

}  // namespace camdyn::test
