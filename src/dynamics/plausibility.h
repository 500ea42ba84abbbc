// Plausibility of a scene and of a run's results (docs/warnings.md): the
// values that are legal but almost surely a slip (a lift in millimetres, a
// contact stiffness of 10 N/m^n), the ones the solver cannot run at all
// (refused before the run, naming the field), and the results that should
// not be trusted (an energy balance that does not close, numerical chatter).
// The unit slip, which building the cam geometry names before any model
// exists, is dynamics/unit_slip.h (below the model: no include cycle).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/errors.h"
#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "dynamics/unit_slip.h"
#include "scene/scene.h"

namespace camdyn {

/// The contact load a scene asks its contact to carry, from the rigid model
/// (docs/model.md §9) sampled over a revolution.
struct ContactLoad {
  double static_force = 0.0;       ///< max rigid normal force with the cam turned slowly (ω = 0) [N]
  double peak_force = 0.0;         ///< max rigid normal force at the scene's speed [N]
  double effective_mass = 0.0;     ///< follower inertia seen at the contact, M / (∂g/∂q)² [kg]
  double contact_frequency = 0.0;  ///< linearised contact at peak_force, sqrt(k_c / m) / 2π [Hz]
  double peak_penetration = 0.0;   ///< static penetration (F_peak / K)^(1/n) [m]
};
ContactLoad contact_load(const Model& model);

/// What the solver cannot run, refused before it starts: throws InputError
/// naming the field when the contact penetrates beyond Model::penetration_limit
/// under the spring load alone (`mechanism.contact.stiffness`, or
/// `mechanism.follower.shape.radius` for a circle below a millimetre), or
/// when the penetration under the peak load is below what the integrator's
/// tolerances resolve (`mechanism.contact.stiffness`).
void check_plausibility(const SceneConfig& scene, const Model& model, const std::string& file);

/// Inputs that are legal but almost surely a slip: lengths above 1 m,
/// pressure angle above 30°, a contact stiffness outside 1e7 ... 1e13 N/m^n,
/// an acceleration that jumps, a restitution the contact law ignores; in a
/// follower train, a seat softer than the spring it holds, a link far softer
/// than the cam contact, a spring with mass in fewer than 4 lumps, a
/// follower.lash that the seat and link lash given with it contradict.
std::vector<PlausibilityWarning> input_warnings(const SceneConfig& scene, const Model& model);

/// Results that should not be trusted: an energy residual too large for the
/// tolerance, penetration large against the lift or the circle's radius,
/// chatter (a high impact count, separation below the rigid-model jump speed),
/// a large Richardson error estimate.
std::vector<PlausibilityWarning> result_warnings(const SceneConfig& scene, const Model& model,
                                                 const SimulationResult& result);

/// input_warnings then result_warnings: summary.json `warnings`.
std::vector<PlausibilityWarning> run_warnings(const SceneConfig& scene, const Model& model,
                                              const SimulationResult& result);

/// "warning: FIELD: MESSAGE" (or without the field), as printed.
std::string warning_line(const PlausibilityWarning& w);

}  // namespace camdyn
