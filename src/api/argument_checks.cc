#include "api/argument_checks.h"

#include <camdyn/scene.h>
#include <camdyn/simulate.h>

#include <cmath>

#include "common/errors.h"
#include "io/json_archive.h"
#include "scene/scene.h"

namespace camdyn {

static_assert(kMaxPointsPerCall == ProfileOutputConfig::kMaxPoints, "the API's cap is camdyn export --points's");

namespace {

// A value as the messages print it: the shortest round-trip digits, or nan / inf / -inf.
std::string value_text(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  return format_shortest(x);
}

std::string element(const std::string& argument, std::size_t i) { return argument + "[" + std::to_string(i) + "]"; }

}  // namespace

void check_point_count(const std::string& argument, std::size_t count) {
  if (count > static_cast<std::size_t>(kMaxPointsPerCall))
    throw InputError("", argument,
                     std::to_string(count) + " values asked for: at most " + std::to_string(kMaxPointsPerCall) +
                         " in one call (the cap of camdyn export --points)");
}

void check_finite(const std::string& argument, const std::vector<double>& values, const char* unit) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i]))
      throw InputError("", argument,
                       element(argument, i) + " is " + value_text(values[i]) + ": must be a finite number " + unit);
  }
}

void check_times_within_run(const std::string& argument, const std::vector<double>& times, double t_end) {
  check_point_count(argument, times.size());
  check_finite(argument, times, "[s]");
  for (std::size_t i = 0; i < times.size(); ++i) {
    const double t = times[i];  // [s]
    if (t < 0.0)
      throw InputError("", argument,
                       element(argument, i) + " = " + value_text(t) + " s is before the run's start at 0 s");
    if (t > t_end)
      throw InputError("", argument,
                       element(argument, i) + " = " + value_text(t) + " s is after the run's end at " +
                           value_text(t_end) + " s (simulation.duration or simulation.cycles)");
    if (i > 0 && t < times[i - 1])
      throw InputError("", argument,
                       element(argument, i) + " = " + value_text(t) + " s comes before " + element(argument, i - 1) +
                           " = " + value_text(times[i - 1]) + " s: the times must be ascending");
  }
}

void check_jobs(const std::string& argument, int jobs) {
  if (jobs < 0 || jobs > kMaxJobs)
    throw InputError("", argument,
                     "must be 0 (one per core) … " + std::to_string(kMaxJobs) + ", got " + std::to_string(jobs));
}

}  // namespace camdyn
