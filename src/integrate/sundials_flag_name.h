// SUNDIALS' CVodeGetReturnFlagName and ARKStepGetReturnFlagName return a
// string allocated with malloc that the caller must free; this takes it over.
#pragma once

#include <cstdlib>
#include <string>

namespace camdyn {

/// The flag's name as a std::string; frees SUNDIALS' copy.
inline std::string take_flag_name(char* name) {
  std::string text = name != nullptr ? name : "unknown flag";
  std::free(name);
  return text;
}

}  // namespace camdyn
