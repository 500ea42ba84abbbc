// The cam's drive as an element (docs/model.md §5): constant speed, or the
// cam's inertia J_c on a torsional shaft (k_s, c_s) from a motor that turns at
// constant speed or follows a torque–speed line. It owns its parameters and
// says in one place the states it adds (cam angle and speed; motor angle and
// speed), its rates, the energy it stores, the power it delivers and
// dissipates and its names in summary.json `model.elements`. The model's
// right-hand side (double, and dual numbers for the exact Jacobian), the
// energy balance and the state layout call it (docs/architecture.md, "Adding
// a force element").
#pragma once

#include <numbers>
#include <string>
#include <vector>

#include "common/constants.h"
#include "dynamics/state_layout.h"
#include "scene/scene.h"

namespace camdyn {

/// The drive's twist, torques and accelerations at one state, in scalar S.
template <class S>
struct DriveRates {
  S twist, shaft_torque;                   ///< θ_m − θ_c [rad], torque of the shaft on the cam [N m]
  S motor_speed, motor_torque;             ///< ω_m [rad/s], T_m [N m]
  S cam_acceleration, motor_acceleration;  ///< [rad/s²]
};

struct ShaftDrive {
  Drive kind = Drive::constant_speed;
  double cam_inertia = 0.0;  ///< J_c [kg m²]
  double stiffness = 0.0;    ///< k_s [N m/rad]
  double damping = 0.0;      ///< c_s [N m s/rad]
  Motor motor = Motor::constant_speed;
  double stall_torque = 0.0;   ///< T₀ [N m]
  double no_load_speed = 0.0;  ///< ω₀ [rad/s]
  double motor_inertia = 0.0;  ///< J_m [kg m²]

  /// The cam turns on a shaft (its angle and speed are states).
  bool shaft() const { return kind == Drive::shaft; }
  /// The motor follows its torque–speed line (its angle and speed are states).
  bool torque_motor() const { return shaft() && motor == Motor::torque_speed; }

  /// Adds the drive's states to the layout, in order.
  void declare_states(StateLayout& layout) const {
    if (!shaft()) return;
    layout.cam_angle = layout.add("cam_angle");
    layout.cam_speed = layout.add("cam_speed");
    if (motor == Motor::torque_speed) {
      layout.motor_angle = layout.add("motor_angle");
      layout.motor_speed = layout.add("motor_speed");
    }
  }

  /// The rates at state x (layout `l`): the motor's nominal angle
  /// `motor_angle` [rad] and speed `omega` [rad/s] unless it is a state; the
  /// cam's angle θ_c and speed ω_c; the contact's torque on the cam [N m].
  template <class S>
  void rates(const StateLayout& l, const S* x, double motor_angle, double omega, const S& theta, const S& omega_c,
             const S& cam_torque, DriveRates<S>& o) const {
    o.twist = S(0.0);
    o.shaft_torque = S(0.0);
    o.motor_speed = S(omega);
    o.motor_torque = S(0.0);
    o.cam_acceleration = S(0.0);
    o.motor_acceleration = S(0.0);
    if (!shaft()) return;
    S angle = S(motor_angle);
    if (motor == Motor::torque_speed) {
      angle = x[*l.motor_angle];
      o.motor_speed = x[*l.motor_speed];
      o.motor_torque = stall_torque * (1.0 - o.motor_speed / no_load_speed);
    }
    o.twist = angle - theta;
    o.shaft_torque = stiffness * o.twist + damping * (o.motor_speed - omega_c);
    o.cam_acceleration = (o.shaft_torque + cam_torque) / cam_inertia;
    if (motor == Motor::torque_speed) o.motor_acceleration = (o.motor_torque - o.shaft_torque) / motor_inertia;
  }

  /// Power the drive delivers [W]: constant speed, what holds the cam at ω_c
  /// against the contact torque; a shaft, the motor's.
  double drive_power(const DriveRates<double>& r, double cam_torque, double omega_c) const {
    if (!shaft()) return -cam_torque * omega_c;
    return motor == Motor::torque_speed ? r.motor_torque * r.motor_speed : r.shaft_torque * r.motor_speed;
  }
  /// Power the shaft's damper dissipates [W].
  double damper_power(double motor_speed, double omega_c) const {
    const double slip = motor_speed - omega_c;
    return shaft() ? damping * slip * slip : 0.0;
  }
  /// Adds the cam's and motor's kinetic energy and the shaft's twist energy [J].
  void add_energy(double cam_speed, double motor_speed, double twist, double& kinetic, double& spring) const {
    if (!shaft()) return;
    kinetic += 0.5 * cam_inertia * cam_speed * cam_speed;
    if (motor == Motor::torque_speed) kinetic += 0.5 * motor_inertia * motor_speed * motor_speed;
    spring += 0.5 * stiffness * twist * twist;
  }
  /// Whether the drive delivers work (the drive-work quadrature is reported).
  bool works(double omega) const { return omega != 0.0 || shaft(); }
  /// Whether the shaft dissipates (the damper-work quadrature includes it).
  bool dissipates() const { return shaft() && damping > 0.0; }

  /// Its names in summary.json `model.elements`.
  void add_names(std::vector<std::string>& elements) const {
    if (!shaft()) return;
    elements.push_back("cam_inertia");
    elements.push_back("shaft_spring");
    if (damping > 0.0) elements.push_back("shaft_damper");
    elements.push_back(motor == Motor::torque_speed ? "motor:torque_speed" : "motor:constant_speed");
  }
};

/// The drive of a scene's cam.
inline ShaftDrive shaft_drive(const DriveConfig& dc) {
  ShaftDrive d;
  if (dc.type != Drive::shaft) return d;
  d.kind = Drive::shaft;
  d.cam_inertia = dc.inertia;
  d.stiffness = dc.torsional_stiffness;
  d.damping = dc.torsional_damping;
  if (dc.motor.type == Motor::torque_speed) {
    d.motor = Motor::torque_speed;
    d.stall_torque = dc.motor.stall_torque;
    d.no_load_speed = dc.motor.no_load_rpm * kTwoPi / 60.0;
    d.motor_inertia = dc.motor.inertia;
  }
  return d;
}

}  // namespace camdyn
