// Building a Model (dynamics/model.h): the geometry of the design
// (dynamics/cam_geometry.h) and, on it, the bodies and force elements of one
// cam speed, with the checks the loader cannot make (docs/warnings.md); the
// speed set in place; the list of elements summary.json names.
#include <atomic>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/constants.h"
#include "common/errors.h"
#include "contact/hertz_pressure.h"
#include "dynamics/contact_stress.h"
#include "dynamics/held_train_force.h"
#include "dynamics/model.h"
#include "dynamics/plausibility.h"
#include "dynamics/rigid_jump_speed.h"
#include "dynamics/train_jump_speed.h"
#include "geometry/check_text.h"
#include "scene/follower_shape.h"

namespace camdyn {

namespace {

/// `cam_radius` [m]: the cam's radius for stiffness from materials (its base radius).
ForceLaw build_force_law(const SceneConfig& scene, double cam_radius, const std::string& file) {
  const ContactConfig& c = scene.mechanism.contact;
  ForceLaw law;
  law.model = c.model;
  law.exponent = c.exponent;
  law.restitution = c.restitution;
  law.reference_velocity = c.reference_velocity;
  law.damping = c.damping.value_or(0.0);
  if (c.from_materials) {
    const MaterialsConfig& m = *c.from_materials;
    const bool line = m.width.has_value();
    const double implied_exponent = line ? 1.0 : 1.5;
    if (std::abs(c.exponent - implied_exponent) > 1e-12)
      throw InputError(file, "mechanism.contact.exponent",
                       std::string("stiffness from materials is for ") + (line ? "line" : "point") +
                           " contact, which needs exponent " + (line ? "1" : "1.5"));
    // A circle has radius of curvature ρ, a flat face's line an infinite one.
    const ShapeConfig& shape = scene.mechanism.follower.shape;
    const double r2 =
        follower_shape_traits(shape.type).circle() ? shape.radius : std::numeric_limits<double>::infinity();
    law.stiffness = stiffness_from_materials(m.E1, m.nu1, m.E2, m.nu2, cam_radius, r2, line, m.width.value_or(0.0));
  } else if (c.stiffness) {
    law.stiffness = *c.stiffness;
  } else {
    throw InputError(file, "mechanism.contact.stiffness", "a stiffness or { \"from_materials\": ... } is required");
  }
  if (!(law.stiffness > 0.0) || !std::isfinite(law.stiffness))
    throw InputError(file, "mechanism.contact.stiffness", "must be a finite number > 0");
  return law;
}

FrictionLaw friction_law(double mu, double regularization_velocity, FrictionRegularization regularization) {
  FrictionLaw law;
  law.mu = mu;
  law.regularization_velocity = regularization_velocity;
  law.linear_ramp = regularization == FrictionRegularization::linear;
  return law;
}

}  // namespace

namespace {

/// Throws InputError naming `mechanism.cam.limits.max_contact_stress` when
/// the rigid-model Hertz pressure at the scene's speed exceeds it (on a
/// follower train the held train's: dynamics/held_train_force.h, so the
/// model's train must be built), or when the scene gives no line-contact
/// materials to compute it from.
void check_contact_stress_limit(const MechanismConfig& mech, const Model& model, const std::string& file) {
  const std::optional<double>& limit = mech.cam.limits.max_contact_stress;
  if (!limit) return;
  const std::string at = "mechanism.cam.limits.max_contact_stress";
  const LineContact contact = require_line_contact(mech.contact, file, at);
  const PressurePeak peak = peak_rigid_contact_pressure(model, contact, model.omega);
  if (std::isnan(peak.pressure))
    throw InputError(
        file, at,
        std::string("cannot be checked: the rigid-model contact pressure is not available: ") + kNoLinearPart);
  if (peak.pressure > *limit)
    throw InputError(file, at,
                     std::string(rigid_figures_held(model) ? "the held train's " : "the ") +
                         "rigid-model Hertz contact pressure reaches " + check_text::num(peak.pressure) +
                         " Pa at cam angle " + check_text::num(peak.at_deg) + " deg at " +
                         check_text::num(mech.cam.rpm) + " rpm, above the limit " + check_text::num(*limit) + " Pa");
}

/// Which friction elements and states the scene's numbers give a follower of
/// `fg`: assemble_elements builds them, and set_scene_parameters compares
/// them with a model's.
struct FollowerStructure {
  bool spin = false;      ///< the roller's spin state
  bool friction = false;  ///< sliding friction at the contact
  bool guide = false;     ///< guide friction (translating)
  bool pivot = false;     ///< pivot friction (oscillating)

  bool operator==(const FollowerStructure&) const = default;
};

FollowerStructure follower_structure(const SceneConfig& scene, const FollowerGeometry& fg) {
  const FollowerConfig& f = scene.mechanism.follower;
  const double mu = scene.mechanism.contact.friction.mu;
  const bool roller = fg.rolls(), oscillating = fg.oscillating();
  FollowerStructure s;
  // A roller without inertia rolls freely: friction can do no work, so neither
  // the spin state nor the friction force is assembled (docs/model.md §4). A flat
  // face or a mushroom slides: friction acts whenever μ > 0.
  s.spin = roller && f.shape.inertia > 0.0 && mu > 0.0;
  s.friction = mu > 0.0 && (!roller || s.spin);
  s.guide = !oscillating && f.guide_friction && f.guide_friction->mu > 0.0;
  s.pivot = oscillating && f.pivot_friction && f.pivot_friction->mu > 0.0;
  return s;
}

/// The mass, spring, damper, gravity, contact law, friction and drive of the
/// mechanism (the model's geometry is already built).
void assemble_elements(const SceneConfig& scene, const std::string& file, Model& model) {
  const MechanismConfig& mech = scene.mechanism;
  const FollowerConfig& f = mech.follower;
  const FollowerGeometry& fg = model.follower;
  const bool oscillating = fg.oscillating();
  model.mass = oscillating ? f.inertia : f.mass;
  if (!(model.mass > 0.0))
    throw InputError(file, oscillating ? "mechanism.follower.inertia" : "mechanism.follower.mass", "must be > 0");
  model.forces = follower_forces(scene);

  model.contact = build_force_law(scene, fg.base_radius, file);
  model.hertz.reset();
  if (const std::optional<MaterialsConfig>& m = mech.contact.from_materials)
    model.hertz = HertzContact{effective_modulus(m->E1, m->nu1, m->E2, m->nu2), m->width.value_or(0.0)};
  const FrictionConfig& fc = mech.contact.friction;
  model.friction.law = friction_law(fc.mu, fc.regularization_velocity, fc.regularization);
  model.friction.roller_inertia = fg.rolls() ? f.shape.inertia : 0.0;
  const FollowerStructure structure = follower_structure(scene, fg);
  model.friction.spin = structure.spin;
  model.friction.present = structure.friction;
  if (structure.guide) {
    model.support.guide = true;
    model.support.guide_law =
        friction_law(f.guide_friction->mu, f.guide_friction->regularization_velocity, fc.regularization);
  }
  if (structure.pivot) {
    model.support.pivot = true;
    model.support.pivot_law =
        friction_law(f.pivot_friction->mu, f.pivot_friction->regularization_velocity, fc.regularization);
    model.support.pin_radius = f.pivot_friction->pin_radius;
  }

  model.drive = shaft_drive(mech.cam.drive);
}

/// The state layout of model.h's header comment: q, q̇, then only what this
/// model needs (pair parameters, roller spin, cam and motor angles and speeds).
void assign_state_layout(Model& model) {
  StateLayout& layout = model.layout;
  layout = StateLayout::follower_only(model.follower.oscillating());
  if (model.tracking == Tracking::differential) {
    layout.u = layout.add("contact_parameter_u");
    if (model.pair_form == PairForm::general) layout.v = layout.add("contact_parameter_v");
  }
  model.friction.declare_states(layout);
  model.drive.declare_states(layout);
}

}  // namespace

namespace {

/// The speed-dependent parts of the model: the nominal speed and the
/// tracking gain (check_contact_stress_limit follows once the train is built).
void assign_cam_speed(const SceneConfig& scene, Model& model) {
  model.omega = scene.mechanism.cam.rpm * kTwoPi / 60.0;
  // Drift of f decays with time constant 1/α, well below a cam degree.
  model.tracking_gain = 1000.0 + 100.0 * model.omega;
}

/// The take-up windows of the train (dynamics/separation_cause.h); throws
/// InputError where the law never lifts a body off its seat (lash or a seat
/// beyond the lift), naming the lash or the seat.
void assign_take_up_window(const SceneConfig& scene, const std::string& file, Model& model) {
  std::optional<std::pair<double, double>> ramp_end;
  if (scene.outputs.valvetrain && scene.outputs.valvetrain->ramp_end_deg.size() == 2)
    ramp_end = std::pair(scene.outputs.valvetrain->ramp_end_deg[0] * std::numbers::pi / 180.0,
                         scene.outputs.valvetrain->ramp_end_deg[1] * std::numbers::pi / 180.0);
  model.take_up = take_up_window(model.train, *model.law, ramp_end);
  const int body = model.take_up.never_lifted_body;
  if (body < 0) return;
  std::string at = scene.mechanism.follower.lash ? "mechanism.follower.lash" : "mechanism.follower.seat.position";
  if (body > 0) {
    const std::string train = "mechanism.train[" + std::to_string(body - 1) + "]";
    at = train +
         (scene.mechanism.train[static_cast<std::size_t>(body - 1)].link.lash > 0.0 ? ".link.lash" : ".seat.position");
  }
  throw InputError(file, at, take_up_window_problem(model.train, model.take_up));
}

/// What is made from the train and the follower's parameters once the train
/// is built: the take-up windows, the rigid and held-train jump speeds, and
/// the contact stress limit's check (docs/model.md §12).
void assign_train_figures(const SceneConfig& scene, const std::string& file, Model& model) {
  assign_take_up_window(scene, file, model);
  model.rigid_jump_speed_rpm = jump_speed_rpm(model);
  model.train_jump_speed_rpm = 0.0;
  if (model.train.has_coordinates()) {
    try {
      model.train_jump_speed_rpm = train_jump_speed_rpm(model);
    } catch (const std::invalid_argument& e) {
      // Every coordinate is held by validation; a stiffness matrix that is
      // still singular lost its rank in floating point (a stiffness of 5e-324
      // N/m, a lever ratio of 1e300: found by probe_fields.py and run_fuzzer).
      throw InputError(
          file, "mechanism.train",
          std::string("a stiffness or lever ratio of the train is too extreme for double precision: ") + e.what());
    }
  }
  check_contact_stress_limit(scene.mechanism, model, file);
}

/// Whether two trains have the same bodies, lumps, elements, states and roots
/// (their numbers may differ).
bool same_train_structure(const FollowerTrain& a, const FollowerTrain& b) {
  if (a.coordinates.size() != b.coordinates.size() || a.elements.size() != b.elements.size() ||
      a.bodies.size() != b.bodies.size() || a.roots != b.roots || a.follower_spring_lumped != b.follower_spring_lumped)
    return false;
  for (std::size_t i = 0; i < a.coordinates.size(); ++i)
    if (a.coordinates[i].position != b.coordinates[i].position ||
        a.coordinates[i].velocity != b.coordinates[i].velocity)
      return false;
  for (std::size_t i = 0; i < a.elements.size(); ++i) {
    const TrainElement &x = a.elements[i], &y = b.elements[i];
    if (x.law != y.law || x.role != y.role || x.body != y.body || x.a != y.a || x.b != y.b || x.root != y.root ||
        (x.law == TrainElement::Law::contact && x.contact.model != y.contact.model))
      return false;
  }
  for (std::size_t i = 0; i < a.bodies.size(); ++i) {
    const TrainBody &x = a.bodies[i], &y = b.bodies[i];
    if (x.name != y.name || x.coordinate != y.coordinate || x.link != y.link || x.seat != y.seat || x.stop != y.stop ||
        x.spring_end != y.spring_end || x.spring_coils != y.spring_coils || x.spring_lumps != y.spring_lumps)
      return false;
  }
  return true;
}

Model assemble_model(const CamGeometry& geometry, const SceneConfig& scene, const std::string& file) {
  const MechanismConfig& mech = scene.mechanism;
  Model model;
  static_cast<CamGeometry&>(model) = geometry;
  const FollowerGeometry& fg = model.follower;
  model.theta0 = mech.cam.initial_angle_deg * std::numbers::pi / 180.0;
  assemble_elements(scene, file, model);
  model.tracking = mech.contact.tracking;
  assign_cam_speed(scene, model);
  // Beyond this the compliant-contact model no longer describes the contact.
  model.penetration_limit = fg.circle() ? 0.5 * fg.radius : 0.1 * fg.base_radius;

  assign_state_layout(model);
  model.train = build_follower_train(scene, file, model.layout);
  // A spring with mass is the train's lumped chain, not the follower's massless spring.
  if (model.train.follower_spring_lumped) model.forces.spring() = ReturnSpring{};
  assign_train_figures(scene, file, model);
  list_elements(model);
  // Refuses what the solver could not run (docs/warnings.md), naming the field.
  check_plausibility(scene, model, file);
  return model;
}

}  // namespace

Model build_model(const SceneConfig& scene, const std::string& file) {
  return build_model(*build_cam_geometry(scene, file), scene, file);
}

namespace {

std::atomic<long> model_assemblies{0};  ///< model_builds()

}  // namespace

Model build_model(const CamGeometry& geometry, const SceneConfig& scene, const std::string& file) {
  ++model_assemblies;
  try {
    return assemble_model(geometry, scene, file);
  } catch (const InputError& e) {
    // A contact or a spring that cannot be assembled for a length in millimetres: name the slip.
    rethrow_naming_unit_slip(scene, file, e);
  }
}

Model build_model(const std::shared_ptr<const CamGeometry>& geometry, const SceneConfig& scene,
                  const std::string& file) {
  return geometry ? build_model(*geometry, scene, file) : build_model(scene, file);
}

long model_builds() { return model_assemblies.load(); }

void set_cam_speed(Model& model, const SceneConfig& scene, const std::string& file) {
  try {
    assign_cam_speed(scene, model);
    check_contact_stress_limit(scene.mechanism, model, file);
    check_plausibility(scene, model, file);
  } catch (const InputError& e) {
    rethrow_naming_unit_slip(scene, file, e);
  }
}

void list_elements(Model& model) {
  const bool oscillating = model.follower.oscillating();
  model.elements.clear();
  model.elements.push_back(oscillating ? "arm_inertia" : "follower_mass");
  model.forces.for_each([&](const auto& element) {
    if (element.present()) model.elements.push_back(element.name(oscillating));
  });
  model.elements.push_back("contact:" + to_string(model.contact.model));
  model.friction.add_names(model.elements);
  model.support.add_names(model.elements);
  model.drive.add_names(model.elements);
  add_train_names(model.train, model.elements);
}

namespace {

/// Which of the optional force elements list_elements() lists.
unsigned element_flags(const Model& m) {
  return (m.forces.spring().present() ? 1u : 0u) | (m.forces.damper().present() ? 2u : 0u) |
         (m.forces.gravity().present() ? 4u : 0u) | (m.drive.damping > 0.0 ? 8u : 0u);
}

/// The follower structure the model was assembled with.
FollowerStructure follower_structure(const Model& m) {
  return {m.friction.spin, m.friction.present, m.support.guide, m.support.pivot};
}

}  // namespace

std::optional<FollowerTrain> train_of_same_structure(const Model& model, const SceneConfig& scene,
                                                     const std::string& file) {
  StateLayout layout = model.layout;  // its core states, the train's appended again
  layout.size = layout.core_size;
  layout.names.resize(static_cast<std::size_t>(layout.core_size));
  FollowerTrain train = build_follower_train(scene, file, layout);
  if (layout.names != model.layout.names || !same_train_structure(model.train, train)) return std::nullopt;
  return train;
}

void set_train(Model& model, FollowerTrain train, const SceneConfig& scene, const std::string& file) {
  model.train = std::move(train);
  if (model.train.follower_spring_lumped) model.forces.spring() = ReturnSpring{};
  try {
    assign_train_figures(scene, file, model);
    check_plausibility(scene, model, file);
  } catch (const InputError& e) {
    rethrow_naming_unit_slip(scene, file, e);
  }
}

bool set_scene_parameters(Model& model, const SceneConfig& scene, const std::string& file) {
  if (follower_structure(scene, model.follower) != follower_structure(model)) return false;
  // The train first, so that a structure it changes leaves the model untouched.
  std::optional<FollowerTrain> train;
  if (model.train.present()) {
    train = train_of_same_structure(model, scene, file);
    if (!train) return false;
  }
  const unsigned elements_before = element_flags(model);
  try {
    // build_model's own assembly: the same numbers, to the bit.
    model.theta0 = scene.mechanism.cam.initial_angle_deg * std::numbers::pi / 180.0;
    assemble_elements(scene, file, model);
    assign_cam_speed(scene, model);
  } catch (const InputError& e) {
    rethrow_naming_unit_slip(scene, file, e);
  }
  if (train) {
    set_train(model, std::move(*train), scene, file);  // the jump speeds and the checks, with the new elements
  } else {
    model.rigid_jump_speed_rpm = jump_speed_rpm(model);  // the mass, spring and weight may have changed
  }
  if (element_flags(model) != elements_before) list_elements(model);
  return true;
}

}  // namespace camdyn
