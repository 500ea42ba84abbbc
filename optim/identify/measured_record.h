// A measured record of an identification (optim/identify/identify.h): its
// signals read from a CSV file and checked, each with its weight, its scale
// and the noise estimated from the record itself.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "optim/identify/identify_config.h"

namespace camdyn::optim {

/// A measured record read from its CSV file.
struct MeasuredRecord {
  std::vector<double> time;                 ///< [s], strictly increasing, within the simulated run
  std::vector<int> lines;                   ///< CSV line of each sample (for messages)
  std::vector<std::string> signals;         ///< timeseries columns
  std::vector<std::vector<double>> values;  ///< values[k][i]: signal k at time[i] [unit of the signal]
  std::vector<double> weights;              ///< per signal [1/unit]
  std::vector<double> scale;                ///< RMS of each measured signal [unit]
  std::vector<double> noise;                ///< noise standard deviation estimated from the record [unit]
};

/// Fewest samples a record may have: fewer cannot carry a transient.
inline constexpr std::size_t kMinSamples = 10;
/// The largest magnitude of a recorded value: its square summed over the
/// record must stay finite (a larger one is a corrupt sample).
inline constexpr double kMaxMeasuredValue = 1e100;

/// Reads and checks a reference file: the named columns exist and are numeric
/// (no NaN), time strictly increases, lies in [0, t_end] (the simulated run,
/// [s]) and there are at least kMinSamples rows. Throws InputError naming the
/// file and the CSV line (or column).
MeasuredRecord read_reference(const ReferenceSpec& reference, double t_end);

/// Noise standard deviation of a sampled signal estimated from its
/// sample-to-sample differences: 1.4826 · median|Δy − median Δy| / √2 (robust
/// to the few large differences at impacts). 0 for fewer than 3 samples.
double estimate_noise(const std::vector<double>& y);

}  // namespace camdyn::optim
