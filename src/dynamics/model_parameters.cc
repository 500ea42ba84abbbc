#include "dynamics/model_parameters.h"

#include <cassert>
#include <charconv>
#include <cmath>
#include <numbers>

#include "common/errors.h"
#include "contact/force_law.h"

namespace camdyn {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Shortest round-trip text, as the config loader prints numbers.
std::string shortest(double x) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

/// Checks one value with the config loader's rules and messages.
class Checker {
 public:
  explicit Checker(const std::string& file) : file_(file) {}
  void positive(const char* path, double x) const { check(path, x, x > 0.0, "must be > 0"); }
  void non_negative(const char* path, double x) const { check(path, x, x >= 0.0, "must be >= 0"); }
  void up_to(const char* path, double x, double high, const char* range) const {
    check(path, x, x > 0.0 && x <= high, range);
  }
  void finite(const char* path, double x) const { check(path, x, true, ""); }

 private:
  void check(const char* path, double x, bool ok, const char* requirement) const {
    if (!std::isfinite(x)) throw InputError(file_, path, "expected a finite number, got " + shortest(x));
    if (!ok) throw InputError(file_, path, std::string(requirement) + ", got " + shortest(x));
  }
  const std::string& file_;
};

void check_parameters(const Model& model, const ModelParameters& p, const std::string& file) {
  const Checker c(file);
  const bool oscillating = model.follower.oscillating();
  c.positive(oscillating ? "mechanism.follower.inertia" : "mechanism.follower.mass", p.mass);
  c.non_negative("mechanism.follower.spring.stiffness", p.spring_stiffness);
  c.non_negative("mechanism.follower.spring.preload", p.spring_preload);
  c.non_negative("mechanism.follower.damping", p.damping);
  c.finite("gravity", p.gravity);
  if (oscillating && p.gravity != 0.0)
    throw InputError(file, "gravity",
                     "gravity on an oscillating arm is not modelled (its centre of mass is not known): set it to 0 and "
                     "fold the arm's weight into the spring preload");
  c.positive("mechanism.contact.stiffness", p.contact_stiffness);
  c.up_to("mechanism.contact.exponent", p.contact_exponent, 5.0, "must be in (0, 5]");
  c.up_to("mechanism.contact.restitution", p.restitution, 1.0, "must be in (0, 1]");
  c.non_negative("mechanism.contact.damping", p.contact_damping);
  if (force_form(model.contact.model) != ForceForm::viscous && p.contact_damping != 0.0)
    throw InputError(file, "mechanism.contact.damping",
                     "only model " + law_words(ForceForm::viscous) + " uses 'damping' (model '" +
                         to_string(model.contact.model) + "' derives it from 'restitution'); set it to null");
  c.positive("mechanism.contact.reference_velocity", p.reference_velocity);
  c.non_negative("mechanism.contact.friction.mu", p.friction_mu);
  c.positive("mechanism.contact.friction.regularization_velocity", p.friction_regularization_velocity);
  c.non_negative("mechanism.follower.shape.inertia", p.roller_inertia);
  if (model.has_guide_friction) {
    c.non_negative("mechanism.follower.guide_friction.mu", p.guide_mu);
    c.positive("mechanism.follower.guide_friction.regularization_velocity", p.guide_regularization_velocity);
  }
  if (model.has_pivot_friction) {
    c.non_negative("mechanism.follower.pivot_friction.mu", p.pivot_mu);
    c.positive("mechanism.follower.pivot_friction.pin_radius", p.pin_radius);
    c.positive("mechanism.follower.pivot_friction.regularization_velocity", p.pivot_regularization_velocity);
  }
  if (model.drive == Drive::shaft) {
    c.positive("mechanism.cam.drive.inertia", p.cam_inertia);
    c.positive("mechanism.cam.drive.torsional_stiffness", p.shaft_stiffness);
    c.non_negative("mechanism.cam.drive.torsional_damping", p.shaft_damping);
    if (model.motor == Motor::torque_speed) {
      c.positive("mechanism.cam.drive.motor.stall_torque", p.stall_torque);
      c.positive("mechanism.cam.drive.motor.no_load_rpm", p.no_load_rpm);
      c.positive("mechanism.cam.drive.motor.inertia", p.motor_inertia);
    }
  }
}

/// Which of the optional force elements list_elements() lists.
unsigned element_flags(const Model& m) {
  return (m.spring_stiffness > 0.0 || m.spring_preload > 0.0 ? 1u : 0u) | (m.damping > 0.0 ? 2u : 0u) |
         (m.gravity != 0.0 ? 4u : 0u) | (m.shaft_damping > 0.0 ? 8u : 0u);
}

}  // namespace

ModelParameters model_parameters(const SceneConfig& scene, const Model& model) {
  const MechanismConfig& mech = scene.mechanism;
  const FollowerConfig& f = mech.follower;
  const ContactConfig& c = mech.contact;
  ModelParameters p;
  p.mass = model.follower.oscillating() ? f.inertia : f.mass;
  p.spring_stiffness = f.spring.stiffness;
  p.spring_preload = f.spring.preload;
  p.damping = f.damping;
  p.gravity = scene.gravity;
  p.contact_stiffness = c.stiffness ? *c.stiffness : model.contact.stiffness;
  p.contact_exponent = c.exponent;
  p.restitution = c.restitution;
  p.contact_damping = c.damping.value_or(0.0);
  p.reference_velocity = c.reference_velocity;
  p.friction_mu = c.friction.mu;
  p.friction_regularization_velocity = c.friction.regularization_velocity;
  if (f.guide_friction) {
    p.guide_mu = f.guide_friction->mu;
    p.guide_regularization_velocity = f.guide_friction->regularization_velocity;
  }
  if (f.pivot_friction) {
    p.pivot_mu = f.pivot_friction->mu;
    p.pivot_regularization_velocity = f.pivot_friction->regularization_velocity;
    p.pin_radius = f.pivot_friction->pin_radius;
  }
  p.roller_inertia = f.shape.inertia;
  const DriveConfig& d = mech.cam.drive;
  p.cam_inertia = d.inertia;
  p.shaft_stiffness = d.torsional_stiffness;
  p.shaft_damping = d.torsional_damping;
  p.stall_torque = d.motor.stall_torque;
  p.no_load_rpm = d.motor.no_load_rpm;
  p.motor_inertia = d.motor.inertia;
  return p;
}

bool same_structure(const Model& model, const ModelParameters& p) {
  // As build_model() decides them.
  const bool roller = model.follower.rolls();
  const bool has_spin = roller && p.roller_inertia > 0.0 && p.friction_mu > 0.0;
  const bool contact_friction = p.friction_mu > 0.0 && (!roller || has_spin);
  // μ of an absent guide or pivot friction block is 0 (model_parameters()).
  return has_spin == model.has_spin && contact_friction == model.contact_friction &&
         model.has_guide_friction == (p.guide_mu > 0.0) && model.has_pivot_friction == (p.pivot_mu > 0.0);
}

void set_parameters(Model& model, const ModelParameters& p, const std::string& file) {
  check_parameters(model, p, file);
  assert(same_structure(model, p));
  const unsigned elements_before = element_flags(model);
  // build_model()'s assignments, in its arithmetic.
  const bool oscillating = model.follower.oscillating();
  model.mass = p.mass;
  model.spring_stiffness = p.spring_stiffness;
  model.spring_preload = p.spring_preload;
  model.damping = p.damping;
  model.gravity = oscillating ? 0.0 : p.gravity;
  model.contact.stiffness = p.contact_stiffness;
  model.contact.exponent = p.contact_exponent;
  model.contact.restitution = p.restitution;
  model.contact.damping = p.contact_damping;
  model.contact.reference_velocity = p.reference_velocity;
  model.friction.mu = p.friction_mu;
  model.friction.regularization_velocity = p.friction_regularization_velocity;
  model.roller_inertia = model.follower.rolls() ? p.roller_inertia : 0.0;
  if (model.has_guide_friction) {
    model.guide_friction.mu = p.guide_mu;
    model.guide_friction.regularization_velocity = p.guide_regularization_velocity;
  }
  if (model.has_pivot_friction) {
    model.pivot_friction.mu = p.pivot_mu;
    model.pivot_friction.regularization_velocity = p.pivot_regularization_velocity;
    model.pin_radius = p.pin_radius;
  }
  if (model.drive == Drive::shaft) {
    model.cam_inertia = p.cam_inertia;
    model.shaft_stiffness = p.shaft_stiffness;
    model.shaft_damping = p.shaft_damping;
    if (model.motor == Motor::torque_speed) {
      model.stall_torque = p.stall_torque;
      model.no_load_speed = p.no_load_rpm * kTwoPi / 60.0;
      model.motor_inertia = p.motor_inertia;
    }
  }
  if (element_flags(model) != elements_before) list_elements(model);
}

}  // namespace camdyn
