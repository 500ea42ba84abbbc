// Event location for camdyn's own one-step methods (rk4, dop853;
// docs/model.md §6): the sign changes of the root functions over the step
// just taken, located on the method's dense output by the Illinois method
// (regula falsi that halves the end kept twice) to SUNDIALS' root tolerance,
// 100 ε (|t| + |h|). The root is the bracket's end past the change, so the
// root functions have changed sign there; after a restart at a root their
// value there is ~0, and the next step judges their signs just after its
// start.
#pragma once

#include <vector>

#include "integrate/integrator.h"

namespace camdyn {

class StepRootLocator {
 public:
  StepRootLocator(OdeSystem& system, int state_size);

  /// (Re)starts at (t, y): the root functions there.
  void restart(double t, const double* y);
  /// The step [t0, t1] `integrator` just took (its dense output valid there,
  /// y1 at t1): true with the earliest root in `t_root` when a root
  /// function changed sign, the integrator then to stand there.
  bool locate(const Integrator& integrator, double t0, double t1, const double* y1, double& t_root);
  /// At the last root: +1 rising, −1 falling, 0 no change, for each function.
  void directions(int* out) const;

 private:
  void roots_at(const Integrator& integrator, double t, std::vector<double>& g);
  double earliest_root(const Integrator& integrator, double t0, double t1);

  OdeSystem& system_;
  const int roots_;
  std::vector<double> g_start_, g_end_, g_probe_, state_;
  std::vector<int> directions_;
  bool restarted_ = true;
};

}  // namespace camdyn
