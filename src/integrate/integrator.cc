#include "integrate/integrator.h"

#include <stdexcept>

#include "integrate/arkode_integrator.h"
#include "integrate/cvode_integrator.h"
#include "integrate/rk4_integrator.h"

namespace camdyn {

const std::vector<std::string>& integrator_methods() {
  static const std::vector<std::string> methods = {"cvode_bdf", "cvode_adams", "arkode_erk", "arkode_dirk", "rk4"};
  return methods;
}

std::unique_ptr<Integrator> make_integrator(OdeSystem& system, const IntegratorOptions& options, double t0,
                                            const double* y0, const double* q0) {
  if (options.method == "cvode_bdf" || options.method == "cvode_adams")
    return std::make_unique<CvodeIntegrator>(system, options, t0, y0, q0);
  if (options.method == "arkode_erk" || options.method == "arkode_dirk")
    return std::make_unique<ArkodeIntegrator>(system, options, t0, y0, q0);
  if (options.method == "rk4") return std::make_unique<Rk4Integrator>(system, options, t0, y0, q0);
  throw std::invalid_argument("unknown integration method '" + options.method + "'");
}

}  // namespace camdyn
