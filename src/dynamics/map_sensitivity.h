// The Jacobian of the Poincaré map P^k (dynamics/poincare_map.h) by forward
// sensitivities (docs/periodic.md, "How the Jacobian is taken"): Φ(t) =
// ∂x(t)/∂x(0) for the section's coordinates, carried beside the state by
// CVODES' staggered corrector with the model's exact state Jacobian
// (ṡ_j = ∂f/∂x s_j + ∂f/∂v₀ ∂v₀/∂x(0)_j), and made to jump at every event by
// the saltation matrix
//   S = I + (f⁺ − f⁻) (∇g)ᵀ / (∇g·f⁻ + ∂g/∂t),
// where f⁻ and f⁺ are the right-hand sides before and after the event (the
// state itself is continuous; what jumps is the force law's approach speed
// v₀, reset at a contact onset, whose own sensitivity is carried as a row
// beside Φ). One CVODES run replaces the 2n runs of central differences.
//
// The run is the map's own (same start, same events) but integrated flights
// and no drift projection: where it cannot be trusted — a model it does not
// cover (friction, which can stick; the general pair form; Newton tracking;
// a shaft drive), two roots at once, a grazing event, accumulating impacts,
// a drifting pair, a failing step — it says why instead of giving a
// Jacobian, and the caller falls back to finite differences.
#pragma once

#include <Eigen/Core>
#include <string>

#include "dynamics/poincare_map.h"

namespace camdyn {

/// One sensitivity run of P^k.
struct MapJacobian {
  bool ok = false;     ///< the Jacobian can be trusted
  std::string reason;  ///< why not (empty when ok)
  /// ∂P^k/∂x, dimension() × dimension(), coordinates as PoincareMap [SI]
  /// (sensitivity_product: (∂P^k/∂x) D, dimension() × D's columns).
  Eigen::MatrixXd jacobian;
  SectionPoint end;  ///< P^k(x) as this run found it
  long impacts = 0;  ///< contact onsets after a separation (as MapResult counts them)
  long events = 0;   ///< roots located
  long steps = 0;    ///< integrator steps
};

/// Why the sensitivity Jacobian does not cover this map's model; empty when it does.
std::string sensitivity_unsupported(const PoincareMap& map);

/// ∂P^k/∂x at p by forward sensitivities, on `ws` (one per thread). Never
/// throws for a run that fails: `ok` false and `reason` say so.
MapJacobian sensitivity_jacobian(const PoincareMap& map, const SectionPoint& p, int k, Workspace& ws);

/// (∂P^k/∂x) D at p for the directions D (dimension() × c, each column a
/// change of the coordinates [SI], of about their scales' size, which the
/// error control assumes) by one run with c sensitivities instead of
/// dimension(): the tangent of a Lyapunov estimate is one column. As
/// sensitivity_jacobian otherwise.
MapJacobian sensitivity_product(const PoincareMap& map, const SectionPoint& p, int k, const Eigen::MatrixXd& directions,
                                Workspace& ws);

}  // namespace camdyn
