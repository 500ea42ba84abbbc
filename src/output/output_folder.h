// The state of an output folder (--out) around a run (docs/outputs-and-resume.md):
//   * a lock, so that two camdyn runs never write into one folder at once:
//     an exclusive flock(2) on `<out>/.camdyn.lock`, which holds the owner's
//     process id. The kernel drops the lock when the process exits, however
//     it ends (kill -9 included), so a killed run never blocks the next one;
//   * the completion marker `<out>/complete.json`, written (atomically) only
//     after every output of the study is: a folder without it holds a run
//     that is unfinished, was killed, or failed.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "io/atomic_file.h"

namespace camdyn {

/// The lock file and the completion marker, inside the output folder.
inline constexpr const char* kLockFile = ".camdyn.lock";
inline constexpr const char* kCompleteFile = "complete.json";

class OutputLock {
 public:
  /// Creates `dir` if it is missing and locks it. Throws InputError(dir, "",
  /// ...) naming the process that holds the lock, or when the folder cannot
  /// be created, or when the lock file is a symbolic link, a hard link, a
  /// FIFO or a device (exit 2; it is never written through); std::runtime_error when the lock file cannot be. Where the
  /// file system has no flock (some network file systems) it warns and goes on unlocked.
  explicit OutputLock(std::filesystem::path dir);
  /// Removes the lock file, and the folder if this lock created it and
  /// nothing was written into it (a run that stopped at a bad input), then unlocks.
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  std::filesystem::path dir_, file_;
  int fd_ = -1;
  std::unique_ptr<OutputFolderRoot> root_;
  bool created_dir_ = false;
};

/// Removes `<dir>/complete.json` (at the start of a run: from here on the folder is not finished).
void remove_completion_marker(const std::filesystem::path& dir);

/// Writes `<dir>/complete.json`: {"complete": true, "study", "main_output", "camdyn_version"}.
void write_completion_marker(const std::filesystem::path& dir, const std::string& study,
                             const std::string& main_output);

}  // namespace camdyn
