// Progress on stderr, redrawn in place (only drawn when enabled, i.e. on a
// terminal, as the CLI decides in StudyContext::progress): a study with many
// runs shows runs done out of the total, failures, elapsed and estimated
// remaining time, e.g.
//   compare: 12/40 runs, 1 failed, 00:31 elapsed, ~01:12 left
// and the iterative studies (optimise, identify) use the estimates and
// formatting here for their own lines.
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

/// Estimated time left [s] for `remaining` runs of a batch on `workers`
/// parallel workers, from the durations of the runs this session finished:
/// mean duration × remaining / min(workers, remaining). Each finished run
/// counts with its own duration: a run stopped by its wall-time budget
/// counts at its budget (the time it took), one that failed at once at
/// almost nothing, so neither turns the estimate into the elapsed time of
/// whatever happened to finish first. -1 when no run finished yet; 0 when
/// none remain.
double remaining_runs_s(double finished_run_s, std::size_t finished, std::size_t remaining, std::size_t workers);

/// Estimated time left [s] of a loop that runs at most `max` iterations and
/// did `done` of them in `elapsed_s`: (max − done) × elapsed / done, an upper
/// bound when the loop may stop early. -1 when nothing is done yet.
double remaining_iterations_s(long done, long max, double elapsed_s);

/// Counts finished runs and redraws the line. Thread-safe.
class ProgressMeter {
 public:
  /// `already_done` runs (resumed from a journal) count as done but not
  /// towards the estimate, so it reflects this session's speed; `workers`
  /// runs go at a time.
  ProgressMeter(std::string what, std::size_t total, std::size_t already_done, std::size_t already_failed,
                std::size_t workers, bool enabled);
  /// One more run finished (failed or not) after `run_s` seconds of wall
  /// time; redraws the line at most five times a second, and always the last.
  void finished(bool failed, double run_s);
  std::size_t failed() const;

 private:
  std::string what_;
  std::size_t total_, done_, failed_, resumed_, workers_;
  double run_s_ = 0.0;     ///< summed durations of this session's finished runs [s]
  double drawn_s_ = -1.0;  ///< elapsed time of the last redraw [s], < 0 before the first
  bool enabled_;
  std::chrono::steady_clock::time_point start_;
  mutable std::mutex mutex_;
};

}  // namespace camdyn
