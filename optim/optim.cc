#include "optim/optim.h"

#include <nlopt.hpp>

namespace camdyn::optim {

std::string nlopt_version() {
  return std::to_string(nlopt::version_major()) + "." + std::to_string(nlopt::version_minor()) + "." +
         std::to_string(nlopt::version_bugfix());
}

}  // namespace camdyn::optim
