// Progress on stderr, redrawn in place (only drawn when enabled, i.e. on a
// terminal, as the CLI decides in StudyContext::progress): a study with many
// runs shows runs done out of the total, failures, elapsed and estimated
// remaining time, e.g.
//   compare: 12/40 runs, 1 failed, 00:31 elapsed, ~01:15 left
// and the iterative studies (optimise, identify) use the estimates and
// formatting here for their own lines. The time left comes from the work
// finished in this session (runs, or finer units such as a jump map's
// speeds when runs differ in size), is rounded to what it can tell, and
// reads "estimating time left" until enough work is done to tell anything
// (docs/config.md, "Commands").
#pragma once

#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace camdyn {

/// "mm:ss", or "h:mm:ss" from an hour on; "--:--" if not finite or negative.
std::string format_duration(double seconds);

/// A time left [s] as the progress line shows it: "~" and format_duration of
/// `seconds` rounded up to 5 s below a minute, to 15 s below ten minutes,
/// to a minute below an hour, else to five minutes; "estimating time left"
/// (without "left" appended by the caller) when `seconds` < 0.
std::string format_time_left(double seconds);

/// The progress text. `remaining_s` < 0 means not known yet (too little work finished).
std::string progress_line(const std::string& what, std::size_t done, std::size_t total, std::size_t failed,
                          double elapsed_s, double remaining_s);

/// Estimated time left [s] of a loop that runs at most `max` iterations and
/// did `done` of them in `elapsed_s`: (max − done) × elapsed / done, an upper
/// bound when the loop may stop early. -1 when nothing is done yet.
double remaining_iterations_s(long done, long max, double elapsed_s);

/// The least share of this session's work that must be finished before a
/// time left is shown (before it, one slow or fast run would decide it).
inline constexpr double kMinWorkForEstimate = 0.05;

/// Estimated time left [s] from the work finished in this session: the rate
/// per worker, `done_work` / (`elapsed_s` × the workers busy so far,
/// min(`workers`, `session_runs`)), applied to the work left on the workers
/// still busy, min(`workers`, `runs_left`), so that the last runs of a
/// batch, fewer than the workers, are not counted at the whole batch's pace.
/// A run stopped by its wall-time budget counts with the time it took, one
/// that failed at once with almost none; runs of different sizes count by
/// their work. -1 while `done_work` is below kMinWorkForEstimate of
/// `session_work` or nothing is done; 0 when nothing remains.
double remaining_work_s(double elapsed_s, double done_work, double session_work, std::size_t workers,
                        std::size_t session_runs, std::size_t runs_left);

/// Counts finished runs and redraws the line. Thread-safe.
class ProgressMeter {
 public:
  /// `already_done` runs (resumed from a journal) count as done but not
  /// towards the estimate, so it reflects this session's speed; `workers`
  /// runs go at a time. `session_work` is the work of the runs still to do in
  /// units of the caller's choosing (< 0: one unit per run); runs may report
  /// parts of it as they go (work_done) and report the rest when they finish.
  ProgressMeter(std::string what, std::size_t total, std::size_t already_done, std::size_t already_failed,
                std::size_t workers, bool enabled, double session_work = -1.0);
  ~ProgressMeter();
  ProgressMeter(const ProgressMeter&) = delete;
  ProgressMeter& operator=(const ProgressMeter&) = delete;
  /// One more run finished (failed or not) after `run_s` seconds of wall
  /// time (not needed by the estimate, which measures the elapsed time),
  /// `work` units in all (those it reported with work_done on this thread
  /// are not counted twice); redraws the line at most five times a second,
  /// and always the last.
  void finished(bool failed, double run_s, double work = 1.0);
  /// `units` of a running run's work done (e.g. one speed of a jump map's
  /// range); redraws the line like `finished`.
  void work_done(double units);
  /// The study needs `total` runs after all (not below those done), e.g. a
  /// bisection that needs fewer steps than the most its bracket allows; a
  /// meter of one unit per run follows with its work. Redraws the line, the
  /// last one when every run is done.
  void set_total(std::size_t total);
  std::size_t failed() const;
  std::size_t total() const;
  double work_done_so_far() const;  ///< this session's work done [units]
  double session_work() const;      ///< this session's work in all [units]

 private:
  void draw(bool last);  ///< with mutex_ held
  std::string what_;
  std::size_t total_, done_, failed_, resumed_, workers_;
  double session_work_;     ///< the work of this session's runs [units]
  double done_work_ = 0.0;  ///< of which done [units]
  double drawn_s_ = -1.0;   ///< elapsed time of the last redraw [s], < 0 before the first
  bool enabled_;
  std::chrono::steady_clock::time_point start_;
  mutable std::mutex mutex_;
};

/// Reports `units` of work done inside a run to the ProgressMeter of the runs
/// in flight (the one most recently made and not yet destroyed), from any
/// thread; nothing when there is none. For run functions that cannot be
/// handed the meter (a jump map's range reports each speed).
void report_work_done(double units);

}  // namespace camdyn
