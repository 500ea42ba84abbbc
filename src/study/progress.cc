#include "study/progress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace camdyn {

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

std::string progress_line(const std::string& what, std::size_t done, std::size_t total, std::size_t failed,
                          double elapsed_s, double remaining_s) {
  std::string line = what + ": " + std::to_string(done) + "/" + std::to_string(total) + " runs, " +
                     std::to_string(failed) + " failed, " + format_duration(elapsed_s) + " elapsed";
  if (done >= total) return line + ", done";
  return line + ", ~" + (remaining_s < 0 ? std::string("--:--") : format_duration(remaining_s)) + " left";
}

double remaining_runs_s(double finished_run_s, std::size_t finished, std::size_t remaining, std::size_t workers) {
  if (remaining == 0) return 0.0;
  if (finished == 0) return -1.0;
  const std::size_t lanes = std::max<std::size_t>(1, std::min(workers, remaining));
  return finished_run_s / static_cast<double>(finished) * static_cast<double>(remaining) / static_cast<double>(lanes);
}

double remaining_iterations_s(long done, long max, double elapsed_s) {
  if (done <= 0) return -1.0;
  if (done >= max) return 0.0;
  return elapsed_s / static_cast<double>(done) * static_cast<double>(max - done);
}

ProgressMeter::ProgressMeter(std::string what, std::size_t total, std::size_t already_done, std::size_t already_failed,
                             std::size_t workers, bool enabled)
    : what_(std::move(what)),
      total_(total),
      done_(already_done),
      failed_(already_failed),
      resumed_(already_done),
      workers_(workers),
      enabled_(enabled),
      start_(std::chrono::steady_clock::now()) {}

void ProgressMeter::finished(bool failed, double run_s) {
  const std::lock_guard<std::mutex> lock(mutex_);
  ++done_;
  if (failed) ++failed_;
  if (std::isfinite(run_s) && run_s > 0.0) run_s_ += run_s;
  if (!enabled_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  // At most five redraws a second; the last run always shows.
  if (done_ < total_ && drawn_s_ >= 0.0 && elapsed - drawn_s_ < 0.2) return;
  drawn_s_ = elapsed;
  const double remaining = remaining_runs_s(run_s_, done_ - resumed_, total_ - done_, workers_);
  std::fprintf(stderr, "\r  %s   ", progress_line(what_, done_, total_, failed_, elapsed, remaining).c_str());
  if (done_ >= total_) std::fprintf(stderr, "\n");
  std::fflush(stderr);
}

std::size_t ProgressMeter::failed() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return failed_;
}

}  // namespace camdyn
