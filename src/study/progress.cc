#include "study/progress.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <utility>

namespace camdyn {

namespace {

/// The meter of the runs in flight, for report_work_done.
std::atomic<ProgressMeter*> g_active_meter{nullptr};
/// The work the run on this thread reported so far [units], so that its
/// `finished` does not count it twice.
thread_local double t_reported_work = 0.0;

/// `seconds` rounded up to a multiple of `step`.
double round_up(double seconds, double step) { return std::ceil(seconds / step) * step; }

}  // namespace

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long s = std::lround(seconds);
  char buf[32];
  if (s >= 3600)
    std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else
    std::snprintf(buf, sizeof buf, "%02ld:%02ld", s / 60, s % 60);
  return buf;
}

std::string format_time_left(double seconds) {
  if (!(seconds >= 0.0) || !std::isfinite(seconds)) return "estimating time left";
  double rounded = 0.0;
  if (seconds < 60.0)
    rounded = std::max(5.0, round_up(seconds, 5.0));
  else if (seconds < 600.0)
    rounded = round_up(seconds, 15.0);
  else if (seconds < 3600.0)
    rounded = round_up(seconds, 60.0);
  else
    rounded = round_up(seconds, 300.0);
  return "~" + format_duration(rounded) + " left";
}

std::string progress_line(const std::string& what, std::size_t done, std::size_t total, std::size_t failed,
                          double elapsed_s, double remaining_s) {
  std::string line = what + ": " + std::to_string(done) + "/" + std::to_string(total) + " runs, " +
                     std::to_string(failed) + " failed, " + format_duration(elapsed_s) + " elapsed";
  if (done >= total) return line + ", done";
  return line + ", " + format_time_left(remaining_s);
}

double remaining_iterations_s(long done, long max, double elapsed_s) {
  if (done <= 0) return -1.0;
  if (done >= max) return 0.0;
  return elapsed_s / static_cast<double>(done) * static_cast<double>(max - done);
}

double remaining_work_s(double elapsed_s, double done_work, double session_work, std::size_t workers,
                        std::size_t session_runs, std::size_t runs_left) {
  if (done_work >= session_work || runs_left == 0) return 0.0;
  if (!(done_work > 0.0) || done_work < kMinWorkForEstimate * session_work || !(elapsed_s > 0.0)) return -1.0;
  const auto lanes = [workers](std::size_t runs) {
    return static_cast<double>(std::max<std::size_t>(1, std::min(std::max<std::size_t>(1, workers), runs)));
  };
  const double rate_per_worker = done_work / (elapsed_s * lanes(session_runs));  // [units/s]
  return (session_work - done_work) / (rate_per_worker * lanes(runs_left));
}

ProgressMeter::ProgressMeter(std::string what, std::size_t total, std::size_t already_done, std::size_t already_failed,
                             std::size_t workers, bool enabled, double session_work)
    : what_(std::move(what)),
      total_(total),
      done_(already_done),
      failed_(already_failed),
      resumed_(already_done),
      workers_(workers),
      session_work_(session_work >= 0.0 ? session_work : static_cast<double>(total - std::min(total, already_done))),
      enabled_(enabled),
      start_(std::chrono::steady_clock::now()) {
  g_active_meter.store(this);
}

ProgressMeter::~ProgressMeter() {
  ProgressMeter* self = this;
  g_active_meter.compare_exchange_strong(self, nullptr);
}

void ProgressMeter::finished(bool failed, double run_s, double work) {
  (void)run_s;  // the estimate goes by the work done over the elapsed time: parallel runs overlap
  const std::lock_guard<std::mutex> lock(mutex_);
  ++done_;
  if (failed) ++failed_;
  if (std::isfinite(work)) done_work_ += std::max(0.0, work - t_reported_work);
  t_reported_work = 0.0;
  draw(done_ >= total_);
}

void ProgressMeter::work_done(double units) {
  if (!std::isfinite(units) || units <= 0.0) return;
  const std::lock_guard<std::mutex> lock(mutex_);
  done_work_ += units;
  t_reported_work += units;
  draw(false);
}

void ProgressMeter::set_total(std::size_t total) {
  const std::lock_guard<std::mutex> lock(mutex_);
  total = std::max(total, done_);
  if (total == total_) return;  // nothing changes (its last line, if any, is drawn)
  session_work_ += static_cast<double>(total) - static_cast<double>(total_);
  total_ = total;
  drawn_s_ = -1.0;
  draw(done_ >= total_);
}

void ProgressMeter::draw(bool last) {
  if (!enabled_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  // At most five redraws a second; the last run always shows.
  if (!last && drawn_s_ >= 0.0 && elapsed - drawn_s_ < 0.2) return;
  drawn_s_ = elapsed;
  const double remaining = done_ >= total_ ? 0.0
                                           : remaining_work_s(elapsed, done_work_, session_work_, workers_,
                                                              total_ - std::min(total_, resumed_), total_ - done_);
  std::fprintf(stderr, "\r  %s   ", progress_line(what_, done_, total_, failed_, elapsed, remaining).c_str());
  if (last) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

void report_work_done(double units) {
  if (ProgressMeter* meter = g_active_meter.load()) meter->work_done(units);
}

std::size_t ProgressMeter::failed() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return failed_;
}

std::size_t ProgressMeter::total() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return total_;
}

double ProgressMeter::work_done_so_far() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return done_work_;
}

double ProgressMeter::session_work() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return session_work_;
}

}  // namespace camdyn
