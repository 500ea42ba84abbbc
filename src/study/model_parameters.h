// The parameter block of a Model: the numbers that do not change its
// structure (state layout, geometry, the force elements it assembles), so that
// a study that varies them (identification's residuals and finite
// differences) sets them in place on a model built once instead of building
// a new one from the scene (Pinocchio's model / parameters split).
// set_parameters() checks every value as the config loader does (same
// messages) and writes it with build_model()'s arithmetic: the model is then
// the one build_model() would make from the scene with those values, to the
// last bit (tests/study/model_parameters_test.cc). Geometry, the cam
// speed and the friction coefficients' on/off (which decide whether friction
// or a roller spin state is assembled) are structure: change those in the
// scene and build the model again.
#pragma once

#include <string>

#include "dynamics/model.h"
#include "scene/scene.h"

namespace camdyn {

/// In the scene's units; the config path of each is in model_parameters().
struct ModelParameters {
  double mass = 0.0;              ///< M: follower.mass [kg] or, oscillating, follower.inertia [kg m²]; > 0
  double spring_stiffness = 0.0;  ///< k [N/m | N m/rad], ≥ 0
  double spring_preload = 0.0;    ///< [N | N m], ≥ 0
  double damping = 0.0;           ///< c [N s/m | N m s/rad], ≥ 0
  double gravity = 0.0;           ///< g [m/s²]; 0 for an oscillating arm

  double contact_stiffness = 0.0;                  ///< K [N/m^n], > 0 (from materials: the derived value)
  double contact_exponent = 1.5;                   ///< n [-], in (0, 5]
  double restitution = 0.8;                        ///< e [-], in (0, 1]; the hysteresis damping follows from it
  double contact_damping = 0.0;                    ///< kelvin_voigt c [N s/m], ≥ 0; 0 for the other laws
  double reference_velocity = 0.01;                ///< floor of v₀ [m/s], > 0
  double friction_mu = 0.0;                        ///< μ at the contact [-], ≥ 0
  double friction_regularization_velocity = 1e-4;  ///< [m/s], > 0

  double guide_mu = 0.0;                        ///< μ_g [-], ≥ 0 (translating, with guide_friction)
  double guide_regularization_velocity = 1e-4;  ///< [m/s], > 0
  double pivot_mu = 0.0;                        ///< μ_p [-], ≥ 0 (oscillating, with pivot_friction)
  double pivot_regularization_velocity = 1e-4;  ///< [m/s], > 0
  double pin_radius = 0.0;                      ///< r_pin [m], > 0 with pivot friction
  double roller_inertia = 0.0;                  ///< [kg m²], ≥ 0 (roller only)

  double cam_inertia = 0.0;      ///< J_c [kg m²], > 0 (shaft drive)
  double shaft_stiffness = 0.0;  ///< k_s [N m/rad], > 0 (shaft drive)
  double shaft_damping = 0.0;    ///< c_s [N m s/rad], ≥ 0 (shaft drive)
  double stall_torque = 0.0;     ///< T₀ [N m], > 0 (torque-speed motor)
  double no_load_rpm = 0.0;      ///< [rpm], > 0 (torque-speed motor)
  double motor_inertia = 0.0;    ///< J_m [kg m²], > 0 (torque-speed motor)
};

/// The parameter block of `scene`, for the model built from a scene of the
/// same structure (its contact stiffness when that comes from materials).
ModelParameters model_parameters(const SceneConfig& scene, const Model& model);

/// Whether `parameters` leave the model's structure as it is: the same
/// friction elements and roller spin state (μ and the roller inertia on the
/// same side of zero), and no follower train with bodies of its own (its
/// matrices and jump speed come from the scene: set_scene_parameters()).
/// Otherwise build the model again.
bool same_structure(const Model& model, const ModelParameters& parameters);

/// Sets the parameter block in place. Throws InputError (file, config path,
/// the config loader's reason) for a value the scene would reject; requires
/// same_structure(). Allocates nothing unless the list of force elements
/// changes (a damper, spring, gravity or shaft damper set to or from zero).
void set_parameters(Model& model, const ModelParameters& parameters, const std::string& file);

/// Sets every parameter of `scene` in place on a model built from a scene of
/// the same structure and geometry: the block, and a follower train's
/// masses, stiffnesses, dampings, lashes and seats (its train built again on
/// the model's states: dynamics/model.h set_train). Returns false, the model
/// untouched, when `scene` changes the structure (a friction element, the
/// spin state, a train's bodies, lumps or elements): build the model again.
/// Throws InputError as set_parameters() and build_model() do.
bool set_scene_parameters(Model& model, const SceneConfig& scene, const std::string& file);

}  // namespace camdyn
