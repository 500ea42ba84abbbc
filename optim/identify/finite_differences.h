// Finite differences of whole simulations (optim/identify/identify.h): the
// weighted residuals of a fit and their Jacobian in the scaled parameters
// (z = ln p for a log-scale parameter, z = p otherwise), forward or central,
// one-sided at a bound. Every simulation of one point's differences runs in
// parallel (optim/identify/fit_simulator.h).
#pragma once

#include <cmath>
#include <cstddef>
#include <exception>
#include <limits>
#include <mutex>
#include <string>
#include <vector>

#include "optim/identify/fit_residuals.h"
#include "optim/identify/fit_simulator.h"
#include "optim/identify/identify.h"

namespace camdyn::optim {

/// Parameter transforms: the solver works on z = ln p (log scale) or z = p.
inline double to_value(const FitParameter& p, double z) { return p.log_scale ? std::exp(z) : z; }
inline double to_scaled(const FitParameter& p, double value) { return p.log_scale ? std::log(value) : value; }
inline double scaled_lower(const FitParameter& p) {
  if (p.log_scale)
    return p.lower > 0.0 && std::isfinite(p.lower) ? std::log(p.lower) : -std::numeric_limits<double>::infinity();
  return p.lower;
}
inline double scaled_upper(const FitParameter& p) { return p.log_scale ? std::log(p.upper) : p.upper; }

/// The weighted residual vector and its Jacobian in the scaled parameters,
/// by finite differences whose simulations all run in parallel: forward
/// (E·(p+1) simulations) in the solver's iterations when solver.differences
/// is "forward", central (E·(2p+1)) otherwise and always at the optimum,
/// whose Jacobian gives the covariance. Steps near a bound turn one-sided so
/// that no simulation runs outside the bounds (where the scene may be invalid). The last point is cached: Ceres
/// asks for every residual block at the same point, evaluates the cost at a
/// trial point and then, once it is accepted, the Jacobian there.
class FitEvaluator {
 public:
  FitEvaluator(const IdentifyProblem& problem, FitSimulator& simulator, double smoothing)
      : problem_(problem),
        simulator_(simulator),
        smoothing_(smoothing),
        assembler_(problem),
        n_(problem.residual_count()),
        p_(problem.parameters.size()) {}

  /// Residuals (and the Jacobian) at z; false if a simulation failed there.
  /// Exceptions are kept, not thrown: they must not cross Ceres.
  /// `central` asks for central differences whatever solver.differences says.
  bool evaluate(const double* z, bool jacobian, bool central = false);

  const std::vector<double>& residuals() const { return r_; }
  /// Row-major n × p.
  const std::vector<double>& jacobian() const { return j_; }

  /// The first InputError met (a parameter value the scene rejects), or null.
  std::exception_ptr input_error() const { return input_error_; }
  std::exception_ptr exception() const { return exception_; }
  const std::string& last_failure() const { return last_failure_; }
  std::size_t failures() const { return failures_; }

 private:
  bool compute(const double* z, bool jacobian, bool have_residuals, bool central);

  const IdentifyProblem& problem_;
  FitSimulator& simulator_;
  double smoothing_;  ///< [s], 0 for the raw signals
  ResidualAssembler assembler_;
  std::size_t n_, p_;
  std::mutex mutex_;
  std::vector<double> z_, r_, j_;
  bool ok_ = false;
  bool j_central_ = false;  // j_ is by central differences
  std::exception_ptr exception_, input_error_;
  std::string last_failure_;
  std::size_t failures_ = 0;
};

}  // namespace camdyn::optim
