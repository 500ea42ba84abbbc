#include "study/model_parameters.h"

#include <cassert>
#include <deque>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

#include "common/constants.h"
#include "common/errors.h"
#include "dynamics/rigid_jump_speed.h"
#include "io/typed_archive.h"
#include "scene/contact_law_form.h"

namespace camdyn {

namespace {

/// A field of the parameter block: its path in a config (docs/config.md)
/// and its member.
struct ParameterField {
  const char* path;
  double ModelParameters::*value;
};

constexpr ParameterField kParameterFields[] = {
    {"mechanism.follower.mass", &ModelParameters::mass},
    {"mechanism.follower.inertia", &ModelParameters::mass},
    {"mechanism.follower.spring.stiffness", &ModelParameters::spring_stiffness},
    {"mechanism.follower.spring.preload", &ModelParameters::spring_preload},
    {"mechanism.follower.damping", &ModelParameters::damping},
    {"gravity", &ModelParameters::gravity},
    {"mechanism.contact.stiffness", &ModelParameters::contact_stiffness},
    {"mechanism.contact.exponent", &ModelParameters::contact_exponent},
    {"mechanism.contact.restitution", &ModelParameters::restitution},
    {"mechanism.contact.damping", &ModelParameters::contact_damping},
    {"mechanism.contact.reference_velocity", &ModelParameters::reference_velocity},
    {"mechanism.contact.friction.mu", &ModelParameters::friction_mu},
    {"mechanism.contact.friction.regularization_velocity", &ModelParameters::friction_regularization_velocity},
    {"mechanism.follower.shape.inertia", &ModelParameters::roller_inertia},
    {"mechanism.follower.guide_friction.mu", &ModelParameters::guide_mu},
    {"mechanism.follower.guide_friction.regularization_velocity", &ModelParameters::guide_regularization_velocity},
    {"mechanism.follower.pivot_friction.mu", &ModelParameters::pivot_mu},
    {"mechanism.follower.pivot_friction.pin_radius", &ModelParameters::pin_radius},
    {"mechanism.follower.pivot_friction.regularization_velocity", &ModelParameters::pivot_regularization_velocity},
    {"mechanism.cam.drive.inertia", &ModelParameters::cam_inertia},
    {"mechanism.cam.drive.torsional_stiffness", &ModelParameters::shaft_stiffness},
    {"mechanism.cam.drive.torsional_damping", &ModelParameters::shaft_damping},
    {"mechanism.cam.drive.motor.stall_torque", &ModelParameters::stall_torque},
    {"mechanism.cam.drive.motor.no_load_rpm", &ModelParameters::no_load_rpm},
    {"mechanism.cam.drive.motor.inertia", &ModelParameters::motor_inertia},
};

/// The choices of a model that decide which of these fields its scene has
/// and which checks the loader gives them.
struct Structure {
  FollowerMotion motion;
  FollowerShape shape;
  ContactModel law;
  Drive drive;
  Motor motor;
  bool guide_friction, pivot_friction;
  bool operator==(const Structure&) const = default;
};

Structure structure_of(const Model& m) {
  return {m.follower.motion, m.follower.shape, m.contact.model, m.drive.kind,
          m.drive.motor,     m.support.guide,  m.support.pivot};
}

/// The loader's checks of the parameter block of the models of one structure.
struct ParameterChecks {
  Structure structure;
  std::vector<std::pair<double ModelParameters::*, SceneField>> fields;  ///< the fields their scene has
};

/// Found through the loader's visit (io/typed_archive.h) on a scene with
/// `s`'s choices and every optional parameter given.
ParameterChecks find_parameter_checks(const Structure& s) {
  SceneConfig scene;
  FollowerConfig& f = scene.mechanism.follower;
  f.motion = s.motion;
  f.shape.type = s.shape;
  if (s.guide_friction) f.guide_friction.emplace();
  if (s.pivot_friction) f.pivot_friction.emplace();
  ContactConfig& c = scene.mechanism.contact;
  c.model = s.law;
  c.stiffness = 1.0;
  c.damping = 0.0;  // given, so that a law without damping shows how it refuses one
  scene.mechanism.cam.drive.type = s.drive;
  scene.mechanism.cam.drive.motor.type = s.motor;
  ParameterChecks checks{s, {}};
  for (const ParameterField& p : kParameterFields) {
    std::optional<SceneField> field = try_find_scene_field(scene, p.path);
    if (!field) continue;
    field->value = nullptr;  // it points into `scene`
    checks.fields.emplace_back(p.value, std::move(*field));
  }
  return checks;
}

/// Those of `model`'s structure: found once per structure and thread, so
/// that setting parameters on a model allocates nothing after the first time.
const ParameterChecks& parameter_checks(const Model& model) {
  thread_local std::deque<ParameterChecks> found;  // a deque keeps the references it returned
  const Structure s = structure_of(model);
  for (const ParameterChecks& c : found)
    if (c.structure == s) return c;
  return found.emplace_back(find_parameter_checks(s));
}

/// Checks every value with the config loader's checks (io/config.cc), so
/// that set_parameters() accepts what a config may give and nothing else.
void check_parameters(const Model& model, const ModelParameters& p, const std::string& file) {
  const bool viscous = force_form(model.contact.model) == ForceForm::viscous;
  for (const auto& [member, field] : parameter_checks(model).fields) {
    const double x = p.*member;
    // Another law's damping is 0 when the scene gives none (model_parameters()): only a value is refused.
    if (member == &ModelParameters::contact_damping && !viscous && x == 0.0) continue;
    if (std::string reason = field.reason(x); !reason.empty()) throw InputError(file, field.path, std::move(reason));
  }
}

/// Which of the optional force elements list_elements() lists.
unsigned element_flags(const Model& m) {
  return (m.forces.spring().present() ? 1u : 0u) | (m.forces.damper().present() ? 2u : 0u) |
         (m.forces.gravity().present() ? 4u : 0u) | (m.drive.damping > 0.0 ? 8u : 0u);
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

namespace {

/// build_model()'s assignments of the block, in its arithmetic.
void assign_parameters(Model& model, const ModelParameters& p) {
  const bool oscillating = model.follower.oscillating();
  model.mass = p.mass;
  model.forces.spring() = {p.spring_stiffness, p.spring_preload};
  model.forces.damper() = {p.damping};
  model.forces.gravity() = {oscillating ? 0.0 : p.gravity};
  model.contact.stiffness = p.contact_stiffness;
  model.contact.exponent = p.contact_exponent;
  model.contact.restitution = p.restitution;
  model.contact.damping = p.contact_damping;
  model.contact.reference_velocity = p.reference_velocity;
  model.friction.law.mu = p.friction_mu;
  model.friction.law.regularization_velocity = p.friction_regularization_velocity;
  model.friction.roller_inertia = model.follower.rolls() ? p.roller_inertia : 0.0;
  if (model.support.guide) {
    model.support.guide_law.mu = p.guide_mu;
    model.support.guide_law.regularization_velocity = p.guide_regularization_velocity;
  }
  if (model.support.pivot) {
    model.support.pivot_law.mu = p.pivot_mu;
    model.support.pivot_law.regularization_velocity = p.pivot_regularization_velocity;
    model.support.pin_radius = p.pin_radius;
  }
  if (model.drive.shaft()) {
    model.drive.cam_inertia = p.cam_inertia;
    model.drive.stiffness = p.shaft_stiffness;
    model.drive.damping = p.shaft_damping;
    if (model.drive.motor == Motor::torque_speed) {
      model.drive.stall_torque = p.stall_torque;
      model.drive.no_load_speed = p.no_load_rpm * kTwoPi / 60.0;
      model.drive.motor_inertia = p.motor_inertia;
    }
  }
}

/// Whether `p` leaves the follower's elements and states as they are (the train aside).
bool same_follower_structure(const Model& model, const ModelParameters& p) {
  // As build_model() decides them.
  const bool roller = model.follower.rolls();
  const bool has_spin = roller && p.roller_inertia > 0.0 && p.friction_mu > 0.0;
  const bool contact_friction = p.friction_mu > 0.0 && (!roller || has_spin);
  // μ of an absent guide or pivot friction block is 0 (model_parameters()).
  return has_spin == model.friction.spin && contact_friction == model.friction.present &&
         model.support.guide == (p.guide_mu > 0.0) && model.support.pivot == (p.pivot_mu > 0.0);
}

}  // namespace

bool same_structure(const Model& model, const ModelParameters& p) {
  // A follower train's matrices and jump speed are made from the scene at
  // assembly (docs/model.md §12), from masses and stiffnesses this block
  // does not carry: set_scene_parameters() sets them.
  return !model.train.has_coordinates() && same_follower_structure(model, p);
}

void set_parameters(Model& model, const ModelParameters& p, const std::string& file) {
  check_parameters(model, p, file);
  assert(same_structure(model, p));
  const unsigned elements_before = element_flags(model);
  assign_parameters(model, p);
  model.rigid_jump_speed_rpm = jump_speed_rpm(model);  // the mass, spring and weight may have changed
  if (element_flags(model) != elements_before) list_elements(model);
}

bool set_scene_parameters(Model& model, const SceneConfig& scene, const std::string& file) {
  const ModelParameters p = model_parameters(scene, model);
  if (!same_follower_structure(model, p)) return false;
  if (!model.train.present()) {
    set_parameters(model, p, file);
    return true;
  }
  // The train first, so that a structure it changes leaves the model untouched.
  std::optional<FollowerTrain> train = train_of_same_structure(model, scene, file);
  if (!train) return false;
  check_parameters(model, p, file);
  const unsigned elements_before = element_flags(model);
  assign_parameters(model, p);
  set_train(model, std::move(*train), scene, file);  // the jump speeds and checks, with the new block
  if (element_flags(model) != elements_before) list_elements(model);
  return true;
}

}  // namespace camdyn
