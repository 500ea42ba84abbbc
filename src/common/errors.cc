#include "common/errors.h"

#include <utility>

#include "common/printable_text.h"

namespace camdyn {

namespace {
// The parts come from the user's files: printed as data (common/printable_text.h).
std::string compose(const std::string& file, const std::string& path, const std::string& reason) {
  std::string message;
  if (!file.empty()) message += file + ": ";
  if (!path.empty()) message += path + ": ";
  return printable_text(message + reason);
}
}  // namespace

InputError::InputError(std::string file, std::string path, std::string reason)
    : std::runtime_error(compose(file, path, reason)),
      file_(std::move(file)),
      path_(std::move(path)),
      reason_(std::move(reason)) {}

}  // namespace camdyn
