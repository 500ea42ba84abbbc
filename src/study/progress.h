// Progress of a study with many runs, on stderr: runs done out of the total,
// failures, elapsed and estimated remaining time, e.g.
//   compare: 12/40 runs, 1 failed, 00:31 elapsed, ~01:12 left
// redrawn in place (only drawn when enabled, i.e. on a terminal, as the CLI
// decides in StudyContext::progress).
#pragma once

#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace camdyn {

/// "mm:ss", or "h:mm:ss" from an hour on; "--:--" if not finite or negative.
std::string format_duration(double seconds);

/// The progress text. `remaining_s` < 0 means not known yet (no run finished).
std::string progress_line(const std::string& what, std::size_t done, std::size_t total, std::size_t failed,
                          double elapsed_s, double remaining_s);

/// Counts finished runs and redraws the line. Thread-safe.
class ProgressMeter {
 public:
  /// `already_done` runs (resumed from a journal) count as done but not
  /// towards the rate, so the estimate reflects this session's speed.
  ProgressMeter(std::string what, std::size_t total, std::size_t already_done, std::size_t already_failed,
                bool enabled);
  /// One more run finished (failed or not).
  void finished(bool failed);
  std::size_t failed() const;

 private:
  std::string what_;
  std::size_t total_, done_, failed_, resumed_;
  bool enabled_;
  std::chrono::steady_clock::time_point start_;
  mutable std::mutex mutex_;
};

}  // namespace camdyn
