#include "optim/identify/measured_record.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "common/errors.h"
#include "io/csv_reader.h"
#include "io/json_archive.h"

namespace camdyn::optim {

double estimate_noise(const std::vector<double>& y) {
  if (y.size() < 3) return 0.0;
  std::vector<double> d(y.size() - 1);
  for (std::size_t i = 0; i + 1 < y.size(); ++i) d[i] = y[i + 1] - y[i];
  auto median = [](std::vector<double> v) {
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
  };
  const double m = median(d);
  for (double& x : d) x = std::abs(x - m);
  // Differences of white noise have variance 2σ²; 1.4826 MAD estimates a Gaussian σ.
  return 1.4826 * median(d) / std::sqrt(2.0);
}

MeasuredRecord read_reference(const ReferenceSpec& reference, double t_end) {
  std::vector<std::string> columns{reference.time_column};
  for (const auto& [signal, file_column] : reference.signals) {
    if (file_column == reference.time_column)
      throw InputError(reference.file, "column " + file_column,
                       "is the time column and cannot also be signal " + signal);
    columns.push_back(file_column);
  }
  const CsvColumns csv = read_csv(reference.file, columns, 1, "reference.file");
  MeasuredRecord rec;
  rec.time = csv.values[0];
  rec.lines = csv.lines;
  if (rec.time.size() < kMinSamples)
    throw InputError(reference.file, "line " + std::to_string(rec.lines.back()),
                     "the record ends after " + std::to_string(rec.time.size()) + " samples; at least " +
                         std::to_string(kMinSamples) + " are needed");
  for (std::size_t i = 0; i < rec.time.size(); ++i) {
    const std::string line = "line " + std::to_string(rec.lines[i]);
    if (i > 0 && !(rec.time[i] > rec.time[i - 1]))
      throw InputError(reference.file, line,
                       "time (column " + reference.time_column + ") must increase: " + format_shortest(rec.time[i]) +
                           " s follows " + format_shortest(rec.time[i - 1]) + " s on line " +
                           std::to_string(rec.lines[i - 1]));
    if (rec.time[i] < 0.0)
      throw InputError(reference.file, line,
                       "time " + format_shortest(rec.time[i]) + " s is before the start of the simulation (0 s)");
    if (rec.time[i] > t_end * (1.0 + 1e-12))
      throw InputError(reference.file, line,
                       "time " + format_shortest(rec.time[i]) + " s is after the end of the simulated run (" +
                           format_shortest(t_end) + " s): lengthen simulation.duration or simulation.cycles");
  }
  for (std::size_t k = 0; k < reference.signals.size(); ++k) {
    const auto& [signal, file_column] = reference.signals[k];
    const std::vector<double>& y = csv.values[k + 1];
    // A value whose square (in the RMS and the least-squares cost) is not a
    // finite number is a corrupt sample, not a measurement.
    for (std::size_t i = 0; i < y.size(); ++i)
      if (!(std::abs(y[i]) <= kMaxMeasuredValue))
        throw InputError(reference.file, "line " + std::to_string(rec.lines[i]) + ", column " + file_column,
                         "the value " + format_shortest(y[i]) + " is beyond " + format_shortest(kMaxMeasuredValue) +
                             " in magnitude: a corrupt sample (the fit squares it)");
    double sum2 = 0.0;
    for (double v : y) sum2 += v * v;
    const double rms = std::sqrt(sum2 / static_cast<double>(y.size()));
    double weight = 0.0;
    for (const auto& [name, w] : reference.weights)
      if (name == signal) weight = w;
    const double largest = y.empty() ? 0.0 : std::abs(*std::max_element(y.begin(), y.end(), [](double a, double b) {
      return std::abs(a) < std::abs(b);
    }));
    if (weight != 0.0 && !std::isfinite(weight * largest * weight * largest * static_cast<double>(y.size())))
      throw InputError(reference.file, "reference.weights." + signal,
                       "the weight " + format_shortest(weight) + " times the largest value " +
                           format_shortest(largest) + " squared and summed overflows: give a smaller weight");
    if (weight == 0.0) {
      if (!(rms > 0.0))
        throw InputError(reference.file, "column " + file_column,
                         "is zero everywhere, so it has no scale to weight it by: give reference.weights." + signal);
      weight = 1.0 / rms;
    }
    rec.signals.push_back(signal);
    rec.values.push_back(y);
    rec.weights.push_back(weight);
    rec.scale.push_back(rms);
    rec.noise.push_back(estimate_noise(y));
  }
  return rec;
}

}  // namespace camdyn::optim
