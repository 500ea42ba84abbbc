// Test helpers for running programs (the camdyn executable CAMDYN_BINARY,
// mpiexec, a headless browser) as child processes and reading what they
// wrote: a per-process scratch directory, whole-file reads, spawn and wait
// (so a test can also kill a run), and one run of camdyn with its exit code,
// stdout and stderr. No shell is involved: arguments are passed as they are.
#pragma once

#include <fcntl.h>
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

extern char** environ;  // NOLINT: POSIX

namespace camdyn::test {

namespace fs = std::filesystem;

/// The whole content of a file ("" when it cannot be read).
inline std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// This process's scratch root `<tmp>/camdyn_<suite>_<pid>`. It is removed
/// when the process ends with every test passed, and kept to look at when a
/// test failed.
inline fs::path scratch_root(const std::string& suite) {
  struct Roots {
    std::vector<fs::path> paths;
    Roots() = default;
    Roots(const Roots&) = delete;
    Roots& operator=(const Roots&) = delete;
    ~Roots() {
      if (!::testing::UnitTest::GetInstance()->Passed()) return;
      for (const fs::path& p : paths) {
        std::error_code ignored;  // a root another process still uses is left
        fs::remove_all(p, ignored);
      }
    }
  };
  static Roots roots;  // made after gtest's UnitTest, so destroyed before it
  fs::path root = fs::temp_directory_path() / ("camdyn_" + suite + "_" + std::to_string(::getpid()));
  if (std::find(roots.paths.begin(), roots.paths.end(), root) == roots.paths.end()) roots.paths.push_back(root);
  return root;
}

/// An empty directory `<tmp>/camdyn_<suite>_<pid>/<name>`, made afresh.
inline fs::path scratch_dir(const std::string& suite, const std::string& name) {
  const fs::path dir = scratch_root(suite) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// Starts `argv[0] argv[1...]` (found on PATH) with stdin from /dev/null and
/// stdout/stderr to `out`/`err`; returns the pid (-1 on failure).
inline pid_t spawn(const std::vector<std::string>& argv, const fs::path& out, const fs::path& err) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<std::string> copy = argv;
  std::vector<char*> args;
  for (std::string& a : copy) args.push_back(a.data());
  args.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return rc == 0 ? pid : -1;
}

/// Waits for `pid`; returns its exit code, or 128 + signal if a signal ended it.
inline int wait_for(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/// What one run of a program gave.
struct Outcome {
  int code = -1;  ///< exit code; 128 + signal if a signal ended it; -1 if it could not be started
  std::string out, err;
};

/// Runs `argv` to the end with stdout/stderr to `<dir>/<tag>.out|err`, which are read back.
inline Outcome run_process(const std::vector<std::string>& argv, const fs::path& dir, const std::string& tag) {
  const fs::path out = dir / (tag + ".out"), err = dir / (tag + ".err");
  const pid_t pid = spawn(argv, out, err);
  Outcome o;
  o.code = pid < 0 ? -1 : wait_for(pid);
  o.out = read_text(out);
  o.err = read_text(err);
  return o;
}

/// Runs `camdyn ARGS...` (run_process with CAMDYN_BINARY in front).
inline Outcome run_camdyn(const std::vector<std::string>& args, const fs::path& dir,
                          const std::string& tag = "camdyn") {
  std::vector<std::string> argv = {CAMDYN_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_process(argv, dir, tag);
}

/// A command line split at white space: "run a.json --quiet" → {"run", "a.json", "--quiet"}
/// (no quoting: the tests' paths have no spaces).
inline std::vector<std::string> split_args(const std::string& line) {
  std::istringstream in(line);
  return {std::istream_iterator<std::string>(in), std::istream_iterator<std::string>()};
}

/// Whether `argv` starts and exits with 0 (output discarded): is a tool there and working.
inline bool runs_ok(const std::vector<std::string>& argv) {
  const pid_t pid = spawn(argv, "/dev/null", "/dev/null");
  return pid >= 0 && wait_for(pid) == 0;
}

/// Whether an executable `name` is on PATH (as the shell's `command -v` finds it).
inline bool on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path == nullptr ? "" : path);
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && ::access((fs::path(dir) / name).c_str(), X_OK) == 0) return true;
  return false;
}

/// A CSV file without its last column (run_time_s: the one timing column of comparison.csv).
inline std::string without_last_column(const fs::path& file) {
  std::istringstream in(read_text(file));
  std::string out;
  for (std::string line; std::getline(in, line);) out += line.substr(0, line.rfind(',')) + "\n";
  return out;
}

}  // namespace camdyn::test
