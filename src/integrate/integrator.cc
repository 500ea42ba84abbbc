#include "integrate/integrator.h"

#include <stdexcept>
#include <string>

#include "integrate/arkode_integrator.h"
#include "integrate/cvode_integrator.h"
#include "integrate/dop853_integrator.h"
#include "integrate/rk4_integrator.h"

namespace camdyn {

std::unique_ptr<Integrator> make_integrator(OdeSystem& system, const IntegratorOptions& options, double t0,
                                            const double* y0) {
  switch (options.method) {
    case IntegrationMethod::cvode_bdf:
    case IntegrationMethod::cvode_adams:
      return std::make_unique<CvodeIntegrator>(system, options, t0, y0);
    case IntegrationMethod::arkode_erk:
    case IntegrationMethod::arkode_dirk:
      return std::make_unique<ArkodeIntegrator>(system, options, t0, y0);
    case IntegrationMethod::rk4:
      return std::make_unique<Rk4Integrator>(system, options, t0, y0);
    case IntegrationMethod::dop853:
      return std::make_unique<Dop853Integrator>(system, options, t0, y0);
  }
  throw std::invalid_argument("unknown integration method " + std::to_string(static_cast<int>(options.method)));
}

}  // namespace camdyn
