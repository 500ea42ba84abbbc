// Shared by the libFuzzer targets (tests/fuzz/*_fuzzer.cc, docs/fuzzing.md):
// a private scratch folder for the files an input names, silenced output
// streams, and the rule for what counts as a finding.
//
// camdyn's own errors (InputError: bad input, exit 2; NumericalError: a
// solver gave up, exit 3) are the expected ways for hostile input to end.
// Anything else is a finding: a crash, a sanitizer report, a leak, a timeout,
// running out of memory, or any other exception (it escapes the target and
// aborts the process, which libFuzzer reports).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace camdyn::fuzz {

/// A folder of its own for this process (under TMPDIR), created on first use
/// and removed at exit. clear() empties it between inputs.
class Scratch {
 public:
  static Scratch& get();
  const std::filesystem::path& dir() const { return dir_; }
  /// Removes every file the previous input left.
  void clear() const;
  /// Writes `text` to dir()/name and returns the full path.
  std::filesystem::path write(const std::string& name, std::string_view text) const;

 private:
  Scratch();
  ~Scratch();
  std::filesystem::path dir_;
};

/// Sends std::cout and std::cerr (what `camdyn validate` prints) nowhere, so
/// the fuzzer's own report on stderr stays readable. Call once.
void silence_streams();

/// Runs `body`; returns normally when it ends or throws a camdyn error
/// (InputError, NumericalError); lets anything else escape.
void expect_camdyn_errors_only(const std::function<void()>& body);

}  // namespace camdyn::fuzz
