// The compare study's own config fields (docs/config.md, section `compare`):
// the cases (a scene file, an inline config or the study's own scene, with
// `set` overrides), the `grid` axes (cartesian product) and `zip` axes (paired
// lists), the metrics the report shows and the `overlays` (grid points whose
// runs are plotted against cam angle). compare_config.cc reads them once, with
// every check and its message; the rest of the study never sees raw JSON
// fields.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "io/config.h"
#include "study/study.h"

namespace camdyn {

/// Top-level keys of the study part (the rest of the document is the scene).
const std::vector<std::string>& compare_study_keys();

/// Every metric of a run, in the order of the output columns.
const std::vector<std::string>& compare_metric_names();

/// Whether a larger value of `metric` is better (the margin against jump, the
/// curvature radius, the jump speed); for every other metric smaller is better.
bool higher_is_better(const std::string& metric);

/// One `cases[]` entry.
struct CompareCase {   // NOLINT(bugprone-exception-escape): its implicit moves are Json moves, which do not throw
  std::string name;    ///< unique among the cases
  std::string config;  ///< a scene file, made absolute; empty: inline or the study's own scene
  std::vector<std::string> set;  ///< "dotted.path=VALUE" overrides
  Json inline_config;            ///< `config` given as an object (merged over the study's scene); else null
};

/// A `grid` or `zip` axis: a dotted path of the scene and the values it takes.
struct CompareAxis {
  std::string key;
  std::vector<Json> values;  ///< at least one
};

/// One `overlays[]` entry: the (axis, value) pairs a run must match, the axis
/// an index into CompareSpec::keys().
using OverlaySelection = std::vector<std::pair<std::size_t, Json>>;

/// The fields a compare study adds to a scene.
struct CompareSpec {
  std::vector<CompareCase> cases;                             ///< at least one (the study's scene when none is given)
  std::vector<std::string> metrics = compare_metric_names();  ///< shown in the report, in this order
  std::vector<CompareAxis> grid;                              ///< every combination is run
  std::vector<CompareAxis> zip;                               ///< equal lengths; row z of every list is run together
  std::vector<OverlaySelection> overlays;

  /// The grid keys, then the zip keys: the columns of a grid point.
  std::vector<std::string> keys() const;
  /// The values of axis `axis` (an index into keys()).
  const std::vector<Json>& axis_values(std::size_t axis) const;
};

/// Reads the study part (an object holding some of compare_study_keys()).
/// `default_case` names the one case run when `cases` is absent or empty.
/// Throws InputError naming ctx.config_file and the dotted path.
CompareSpec compare_spec_from_json(const Json& study_part, const std::string& default_case, const StudyContext& ctx);

}  // namespace camdyn
