// The exceptions camdyn throws, part of its public API (<camdyn/camdyn.h>):
// the library throws these very types, so a caller catches what it throws.
// Three kinds of failure are distinguished (docs/architecture.md, "Three kinds
// of failure"): bad input (InputError, the CLI's exit 2), a numerical method that gave up
// (NumericalError, exit 3), and internal invariants (assert). Input errors
// name the file, the dotted config path (or CSV line) and the reason, so a
// user can fix the input without reading code.
#pragma once

#include <stdexcept>
#include <string>

namespace camdyn {

/// Invalid input: config, data file, or a geometry that cannot be built. Exit code 2.
class InputError : public std::runtime_error {
 public:
  /// `file` may be empty when the input came from the command line; `path` is
  /// the dotted config path (`mechanism.cam.rpm`) or `line N` of a CSV file.
  InputError(std::string file, std::string path, std::string reason);

  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  const std::string& reason() const { return reason_; }

 private:
  std::string file_, path_, reason_;
};

/// A solver (integrator, optimiser, least squares) gave up. Exit code 3.
/// `where` says what it was doing and the time / cam angle reached.
class NumericalError : public std::runtime_error {
 public:
  explicit NumericalError(const std::string& where) : std::runtime_error(where) {}
};

}  // namespace camdyn
