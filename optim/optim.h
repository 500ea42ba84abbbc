// Design optimisation (NLopt) and contact identification (Ceres), built on the
// simulator core. Filled in by the optimisation and identification issues.
#pragma once

#include <string>

namespace camdyn::optim {

/// NLopt version string (proves the dependency is linked).
std::string nlopt_version();

}  // namespace camdyn::optim
