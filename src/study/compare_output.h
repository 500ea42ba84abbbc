// What a compare study found, and the files it writes from it: comparison.csv
// and comparison.json (one row per run, in (case, grid point) order, so a
// resumed study writes exactly what an uninterrupted one does), report.html
// (compare_report.cc, with the cam of the first case) and the one-line summary on stdout.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "io/config.h"
#include "study/compare_config.h"

namespace camdyn {

/// One run: a case at one grid point.
struct ComparePoint {
  std::size_t case_index = 0;
  std::vector<Json> values;  ///< one per axis (grid axes, then zip axes)
  bool overlay = false;      ///< its contact force and follower motion are plotted
};

/// A run's outcome, read back from its journal record. (clang-tidy reads the
/// implicit noexcept move of its Json member as able to throw; it cannot.)
struct CompareOutcome {  // NOLINT(bugprone-exception-escape)
  bool ok = false;
  std::string error;
  std::vector<double> metrics;        ///< one per compare_metric_names(); NaN where not available
  double run_time_s = 0.0;            ///< [s]
  Json overlay;                       ///< the last revolution (cam_angle_deg, follower_position, contact_force) or null
  std::string coordinate_unit = "m";  ///< of its follower coordinate: "m", or "rad" for an arm (coordinate_units.h)
};

/// Everything the outputs are written from.
struct CompareResult {
  std::string name;                      ///< the study's name
  const CompareSpec* spec = nullptr;     ///< cases, axes, metrics and overlays
  std::vector<std::string> keys;         ///< spec->keys()
  std::vector<ComparePoint> points;      ///< every run, in (case, grid point) order
  std::vector<CompareOutcome> outcomes;  ///< one per point
  std::size_t failed = 0;                ///< runs that failed
  std::size_t resumed = 0;               ///< runs read from the journal of an earlier invocation
  double wall_time_s = 0.0;              ///< this invocation's wall time [s]
  int mpi_ranks = 1;                     ///< > 1 when the runs were spread over MPI ranks
  /// The first case's scene before the grid's values: the cam the report draws.
  std::optional<SceneConfig> design = std::nullopt;
  std::string config_file;  ///< the study's config, for messages

  const std::string& case_name(std::size_t point) const { return spec->cases[points[point].case_index].name; }
};

/// A grid value as table text: strings without quotes, anything else as JSON.
std::string cell_text(const Json& value);

/// Writes comparison.csv and comparison.json into `out_dir`.
void write_comparison(const CompareResult& result, const std::filesystem::path& out_dir);

/// Writes report.html into `out_dir` (compare_report.cc).
void write_compare_report(const CompareResult& result, const std::filesystem::path& out_dir);

/// The summary line on stdout: runs, failures, wall time and where the report is.
void print_compare_summary(const CompareResult& result, const std::filesystem::path& out_dir);

}  // namespace camdyn
