// Test helpers for driving the camdyn executable (CAMDYN_BINARY) and reading
// what it wrote: a per-process scratch directory, whole-file reads, and one
// run of the command with its exit code, stdout and stderr.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace camdyn::test {

namespace fs = std::filesystem;

/// The whole content of a file ("" when it cannot be read).
inline std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// An empty directory `<tmp>/camdyn_<suite>_<pid>/<name>`, made afresh.
inline fs::path scratch_dir(const std::string& suite, const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("camdyn_" + suite + "_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// What one run of the command gave.
struct Outcome {
  int code = -1;  ///< exit code; -1 when it did not exit normally
  std::string out, err;
};

/// Runs `camdyn ARGS` with stdin from /dev/null; stdout and stderr go through
/// files in `log_dir`, which are read back.
inline Outcome run_camdyn(const std::string& args, const fs::path& log_dir) {
  const std::string cmd = std::string(CAMDYN_BINARY) + " " + args + " >" + (log_dir / "stdout").string() + " 2>" +
                          (log_dir / "stderr").string() + " </dev/null";
  const int status = std::system(cmd.c_str());
  Outcome o;
  o.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  o.out = slurp(log_dir / "stdout");
  o.err = slurp(log_dir / "stderr");
  return o;
}

}  // namespace camdyn::test
