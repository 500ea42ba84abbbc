// The checks of the arguments the public API takes besides a config
// (Scene::profile's points, Scene::law's angles, SimulateOptions), made as
// the config loader checks a field: an InputError with no file, the
// argument's name as its path and the reason, naming the offending value
// and its index. Private to src/api/.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace camdyn {

/// `count` values of `argument` asked for: at most kMaxPointsPerCall
/// (<camdyn/scene.h>), the cap of `camdyn export --points`.
void check_point_count(const std::string& argument, std::size_t count);

/// Every value finite (not NaN, not ±inf).
void check_finite(const std::string& argument, const std::vector<double>& values, const char* unit);

/// Times [s] that are finite, ascending (each ≥ the one before) and within [0, t_end], at most kMaxPointsPerCall.
void check_times_within_run(const std::string& argument, const std::vector<double>& times, double t_end);

/// A thread count 0 … kMaxJobs (<camdyn/simulate.h>).
void check_jobs(const std::string& argument, int jobs);

}  // namespace camdyn
