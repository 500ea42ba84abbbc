// The study registry: every study a config can name with `study`, and what
// is known of each without its code: its config word, the file its main
// result is written to, one line of help and an example config in studies/.
// The loader checks `study` against this table (io/config.cc), `camdyn run
// --help` prints it (cli/main.cc) and cli/run_study.cc maps each kind to its
// runner with an exhaustive switch, so a study missing from any of them does
// not compile or fails a test (docs/architecture.md, "Adding a study").
#pragma once

#include <array>
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string_view>

#include "scene/enum_names.h"

namespace camdyn {

enum class StudyKind { simulate, optimize, identify, compare, convergence, periodic, jump_map, speed_limit };

/// What the registry knows of a study.
struct StudyInfo {
  StudyKind kind;
  std::string_view name;          ///< the config's `study` word
  std::string_view main_output;   ///< its main result in the output folder (run_study.h's StudyOutcome)
  std::string_view help;          ///< one line for `camdyn run --help`
  std::string_view example;       ///< an example config, relative to the repository root
  std::string_view example_args;  ///< the example command's arguments after the config ("" for none)
};

/// Every study, in the order `camdyn run --help` lists them.
inline constexpr std::array<StudyInfo, 8> kStudies = {{
    {StudyKind::simulate, "simulate", "summary.json", "one run: metrics, time series, report",
     "studies/quickstart.json", "--set mechanism.cam.rpm=1500"},
    {StudyKind::optimize, "optimize", "result.json", "spline cam design against jump and contact force",
     "studies/optimize_jump.json", ""},
    {StudyKind::identify, "identify", "identified.json", "fit contact and follower parameters to measured records",
     "studies/identify_drop/identify_drop.json", ""},
    {StudyKind::compare, "compare", "comparison.json", "cases over a grid of settings, one table and report",
     "studies/compare_laws.json", "--jobs 2"},
    {StudyKind::convergence, "convergence", "work_precision.csv",
     "error against run time of every integrator and tolerance", "studies/work_precision.json", ""},
    {StudyKind::periodic, "periodic", "periodic.json", "the steady motion by shooting on the Poincare map",
     "studies/periodic/bouncing_ball.json", ""},
    {StudyKind::jump_map, "jump_map", "jump_map.json", "the steady motion over a range of cam speeds",
     "studies/periodic/bouncing_ball_jump_map.json", ""},
    {StudyKind::speed_limit, "speed_limit", "speed_limit.json",
     "the highest cam speed that keeps the follower on the cam", "studies/quickstart.json", "--set study=speed_limit"},
}};

/// The name table of StudyKind (scene/enum_names.h), made from kStudies.
inline constexpr auto kStudyKindNames = [] {
  std::array<EnumName<StudyKind>, kStudies.size()> names{};
  for (std::size_t i = 0; i < kStudies.size(); ++i) names[i] = {kStudies[i].kind, kStudies[i].name};
  return names;
}();
constexpr std::span<const EnumName<StudyKind>> enum_names(StudyKind) { return kStudyKindNames; }

// Each kind once, in the enum's order (study_info and the help rely on it).
static_assert([] {
  for (std::size_t i = 0; i < kStudies.size(); ++i)
    if (static_cast<std::size_t>(kStudies[i].kind) != i) return false;
  return true;
}());

/// The registry's entry of `kind`.
constexpr const StudyInfo& study_info(StudyKind kind) {
  for (const StudyInfo& info : kStudies)
    if (info.kind == kind) return info;
  throw std::invalid_argument("a StudyKind missing from kStudies");
}

}  // namespace camdyn
