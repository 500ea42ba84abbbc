// camdyn command line (docs/config.md, "Commands"): `camdyn run CONFIG`, `camdyn validate
// CONFIG`, `camdyn export CONFIG` (the cam profile, docs/export.md),
// `--version`. Exit codes: 0 success, 2 invalid input, 3 numerical failure, 1
// anything else. Progress goes to stderr on a terminal; results to files;
// stdout gets a short summary.
#include <camdyn/version.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <new>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/run_study.h"
#include "common/errors.h"
#include "common/printable_text.h"
#include "common/study_budget.h"
#include "dynamics/model.h"
#include "io/config.h"
#include "io/json_archive.h"
#include "output/profile_export.h"
#include "scene/study_kind.h"
#include "study/mpi_runner.h"

namespace {

constexpr int kExitOk = 0, kExitOther = 1, kExitInput = 2, kExitNumerical = 3;

struct RunArgs {
  std::string config;
  std::string out;
  int jobs = 0;
  bool quiet = false;
  bool strict = false;
  double max_study_time_s = camdyn::kDefaultStudyWallTimeS;
  double max_memory_mb = camdyn::kDefaultMemoryBudgetMb;
  std::vector<std::string> overrides;
};

// `camdyn export`: lengths in millimetres, as in the files written.
struct ExportArgs {
  std::string config;
  std::string out;
  std::vector<std::string> formats;
  std::vector<std::string> overrides;
  int points = 0;  // 0: by chord tolerance
  double chord_tolerance_mm = camdyn::ProfileOutputConfig::kDefaultChordToleranceMm;
  double cutter_radius_mm = 0.0;    // 0: no tool path
  double follower_radius_mm = 0.0;  // 0: no follower lift table
  double angle_step_deg = 1.0;      // of the follower lift table
};

// Messages carry the user's text (file names, keys, values): printed as data.
std::string shown(const std::string& text) { return camdyn::printable_text(text); }

int report_input_error(const camdyn::InputError& e, const std::string& config,
                       const std::vector<std::string>& overrides) {
  // A value given with --set is not in the file: name the argument instead.
  const std::optional<std::string> assignment =
      e.file() == "--set" || e.path().empty() ? std::nullopt : camdyn::assignment_setting(overrides, e.path());
  if (assignment)
    std::cerr << "camdyn: error: --set " << shown(*assignment) << ": " << shown(e.path()) << ": " << shown(e.reason())
              << "\n";
  // Errors raised below the config layer may not know the file: name it here.
  else if (e.file().empty())
    std::cerr << "camdyn: error: " << shown(config) << ": " << e.what() << "\n";
  else
    std::cerr << "camdyn: error: " << e.what() << "\n";
  return kExitInput;
}

/// What an internal error adds to its message.
constexpr const char* kBug = "this is a bug in camdyn; please report it with the config and the command line";
/// What running out of memory adds: validation checks what an input asks to
/// hold against --max-memory, so an allocation failing is an estimate missed.
constexpr const char* kMissedEstimate =
    "the input asked for more memory than the machine has, past the checks against --max-memory; please report "
    "it with the config, and meanwhile ask for less work (fewer speeds, points or rows)";

int report_out_of_memory(const std::string& config, const char* what) {
  std::cerr << "camdyn: out of memory: " << shown(config) << ": " << what << ": " << kMissedEstimate << "\n";
  return kExitNumerical;  // a budget (the machine's memory) ran out
}

int report_bug(const char* what) {
  std::cerr << "camdyn: internal error: " << shown(what) << ": " << kBug << "\n";
  return kExitOther;
}

// Maps what a command throws to the exit codes of docs/config.md, "Exit codes".
template <class Body>
int with_exit_codes(const std::string& config, const std::vector<std::string>& overrides, bool root, Body body) {
  try {
    return body();
  } catch (const camdyn::InputError& e) {
    if (!root) return kExitInput;  // every rank reads the same input: rank 0 says what is wrong
    return report_input_error(e, config, overrides);
  } catch (const camdyn::NumericalError& e) {
    if (!root) return kExitNumerical;
    std::cerr << "camdyn: numerical failure: " << shown(config) << ": " << shown(e.what()) << "\n";
    return kExitNumerical;
  } catch (const std::bad_alloc& e) {
    return report_out_of_memory(config, e.what());
  } catch (const std::length_error& e) {  // a container asked for more than it can hold: the same
    return report_out_of_memory(config, e.what());
  } catch (const std::logic_error& e) {  // a broken precondition (out_of_range, invalid_argument, ...)
    return report_bug(e.what());
  } catch (const nlohmann::detail::exception& e) {  // a JSON value read as the wrong type
    return report_bug(e.what());
  } catch (const std::exception& e) {  // the environment: a file that cannot be written, MPI
    std::cerr << "camdyn: error: " << shown(e.what()) << "\n";
    return kExitOther;
  }
}

std::filesystem::path out_dir(const camdyn::Json& doc, const std::string& out) {
  const std::string name = doc.contains("name") && doc["name"].is_string() ? doc["name"].get<std::string>() : "camdyn";
  return out.empty() ? std::filesystem::path("out") / name : std::filesystem::path(out);
}

// `camdyn run` and `camdyn validate`: the study the config names
/// A check of a number option: finite and in (low, high] ([low, high] with
/// `low_inclusive`). CLI11's own range checks compare, which NaN passes.
CLI::Validator finite_in(double low, double high, bool low_inclusive = false) {
  const std::string range = std::string(low_inclusive ? "[" : "(") + camdyn::format_shortest(low) + ", " +
                            camdyn::format_shortest(high) + "]";
  return CLI::Validator(
      [=](const std::string& text) {
        double x = 0.0;
        try {
          std::size_t used = 0;
          x = std::stod(text, &used);
          if (used != text.size()) return "expected a number, got '" + text + "'";
        } catch (const std::exception&) {  // not a number, or beyond a double's range
          return "must be a finite number in " + range + ", got '" + text + "'";
        }
        const bool ok = std::isfinite(x) && (low_inclusive ? x >= low : x > low) && x <= high;
        return ok ? std::string() : "must be a finite number in " + range + ", got '" + text + "'";
      },
      "in " + range);
}

// (cli/run_study.h, shared with the Python module).
// --max-memory: `validate` refuses what `run` would refuse, so both take it.
void add_memory_option(CLI::App& command, RunArgs& args) {
  command
      .add_option("--max-memory", args.max_memory_mb,
                  "Memory budget [MB] (default 2048): a time series or data file that would need more is refused "
                  "(exit 2)")
      ->check(finite_in(0.0, 1e9));
}

int run_study(const RunArgs& args, bool validate_only, bool root) {
  camdyn::StudyRequest request;
  request.config_file = args.config;
  request.overrides = args.overrides;
  request.out_dir = args.out;
  request.jobs = args.jobs;
  request.progress = !args.quiet && isatty(STDERR_FILENO) && root;
  request.validate_only = validate_only;
  request.strict = args.strict;
  request.max_study_time_s = args.max_study_time_s;
  request.max_memory_mb = args.max_memory_mb;
  return camdyn::run_study(request).exit_code;
}

// The scene of any config with a mechanism: a simulate config (optimized.json
// is one) as it is; of another study, its mechanism and run settings (an
// optimize config's baseline), read as a simulate scene.
camdyn::SceneConfig export_scene(const camdyn::Json& doc, const std::string& config) {
  const std::string study =
      doc.contains("study") && doc["study"].is_string() ? doc["study"].get<std::string>() : "simulate";
  if (study == "simulate") return camdyn::scene_from_json(doc, camdyn::config_source(config));
  camdyn::Json scene = camdyn::Json::object();
  for (const char* key : {"name", "description", "mechanism", "gravity", "simulation", "integrator", "outputs"})
    if (doc.contains(key)) scene[key] = doc[key];
  scene["study"] = "simulate";
  return camdyn::scene_from_json(scene, camdyn::config_source(config));
}

// `camdyn export --follower-radius`: the lift a roller of that radius reads on the cam (docs/export.md);
// computed before any file is written, so a radius that does not fit writes nothing.
std::optional<camdyn::FollowerLiftTable> follower_lift(const ExportArgs& args, const camdyn::Model& model) {
  if (!(args.follower_radius_mm > 0.0)) return std::nullopt;
  return camdyn::follower_lift_table(model, args.follower_radius_mm * 1e-3,
                                     args.angle_step_deg * std::numbers::pi / 180.0, "");
}

// `camdyn export`: the cam profile as CSV and/or DXF (docs/export.md).
int run_export(const ExportArgs& args) {
  const camdyn::Json doc = camdyn::load_config_json(args.config, args.overrides);
  const camdyn::SceneConfig scene = export_scene(doc, args.config);
  const camdyn::Model model = camdyn::build_model(scene, args.config);
  camdyn::ProfileOptions options;
  if (args.points > 0) options.points = args.points;
  options.chord_tolerance = args.chord_tolerance_mm * 1e-3;
  // Any value given (0 is the default): NaN reaches the check and is refused.
  if (args.cutter_radius_mm != 0.0) options.cutter_radius = args.cutter_radius_mm * 1e-3;
  const camdyn::ProfileOptionNames names{"", "--cutter-radius", "--points", "--chord-tolerance"};
  const camdyn::SampledCamProfile profile = camdyn::sample_cam_profile(model, options, names);
  std::vector<camdyn::ProfileFormat> formats;
  for (const std::string& f : args.formats) formats.push_back(*camdyn::enum_from_name<camdyn::ProfileFormat>(f));
  if (formats.empty()) formats = camdyn::ProfileOutputConfig{}.formats;
  const std::optional<camdyn::FollowerLiftTable> lift_table = follower_lift(args, model);
  auto written = camdyn::write_profile_files(out_dir(doc, args.out), profile, scene.name, formats);
  if (lift_table) {
    written.push_back(out_dir(doc, args.out) / "follower_lift.csv");
    camdyn::write_follower_lift_csv(written.back(), *lift_table, scene.name);
  }
  std::printf("%s: cam profile, %zu points, largest chord deviation %.3g mm\n", scene.name.c_str(),
              profile.points.size(), profile.max_chord_error * 1e3);
  for (const auto& path : written)
    std::printf("  wrote %s\n", std::filesystem::absolute(path).lexically_normal().c_str());
  return kExitOk;
}

void add_follower_lift_options(CLI::App& command, ExportArgs& args) {
  CLI::Option* radius = command
                            .add_option("--follower-radius", args.follower_radius_mm,
                                        "Also write follower_lift.csv: the lift a roller of this radius [mm] on the "
                                        "follower's axis reads on the cam (a grinder or checking fixture)")
                            ->check(finite_in(0.0, 1e4));
  command
      .add_option("--angle-step-deg", args.angle_step_deg, "Cam-angle increment of follower_lift.csv [deg] (default 1)")
      ->check(finite_in(1e-4, 360.0, true))
      ->needs(radius);
}

void add_export_command(CLI::App& app, ExportArgs& args) {
  CLI::App* command = app.add_subcommand(
      "export", "Write the cam contour, pitch curve and tool path for manufacturing (profile.csv, profile.dxf; mm)");
  command->add_option("config", args.config, "Config file (JSON; a simulate config such as optimized.json)")
      ->required();
  command->add_option("--format", args.formats, "csv, dxf, or both (default: both; repeat or separate with ',')")
      ->check(CLI::IsMember({"csv", "dxf"}))
      ->delimiter(',');
  CLI::Option* points =
      command->add_option("--points", args.points, "Points at equal cam-angle steps")
          ->check(CLI::Range(camdyn::ProfileOutputConfig::kMinPoints, camdyn::ProfileOutputConfig::kMaxPoints));
  CLI::Option* tolerance = command
                               ->add_option("--chord-tolerance", args.chord_tolerance_mm,
                                            "Largest deviation of the chords from the curves [mm] (default 0.001)")
                               ->check(finite_in(camdyn::ProfileOutputConfig::kMinChordToleranceMm, 1e3, true));
  points->excludes(tolerance);
  command
      ->add_option("--cutter-radius", args.cutter_radius_mm,
                   "Radius of the cutter or grinding wheel [mm]: also write its centre path")
      ->check(finite_in(0.0, 1e4));
  command->add_option("--out", args.out, "Output folder (default out/<name>)");
  command->add_option("--set", args.overrides, "Override a field (repeatable)");
  add_follower_lift_options(*command, args);
}

constexpr const char* kExitCodesHelp = R"(
Exit codes:
  0  success
  2  invalid input (config, data file, geometry that cannot be built; the
     message names the file or the --set argument, the field and the reason)
  3  numerical failure (an integrator or optimiser gave up, a budget ran out,
     or with --strict a run whose results carry warnings)
  1  anything else)";

// `camdyn run --help` ends with every study type of the registry
// (scene/study_kind.h), an example of each, and the exit codes.
std::string run_footer() {
  std::string text = "\nStudy types (the config's \"study\"; examples from the repository's studies/):\n";
  for (const camdyn::StudyInfo& study : camdyn::kStudies) {
    constexpr std::size_t kNameWidth = 13;  // the longest name and two spaces
    std::string name(study.name);
    name.resize(std::max(kNameWidth, name.size() + 1), ' ');
    text += "  " + name + std::string(study.help) + "\n                 camdyn run " + std::string(study.example);
    if (!study.example_args.empty()) text += " " + std::string(study.example_args);
    text += "\n";
  }
  return text + kExitCodesHelp;
}

// The command line: parse, dispatch the command, map its errors to exit codes.
int run_command(int argc, char** argv) {
  // Under mpirun (built with -DCAMDYN_WITH_MPI=ON) a compare study spreads its
  // runs over the ranks; rank 0 alone prints and writes outputs.
  const camdyn::mpi::Session mpi_session(&argc, &argv);
  const bool root = camdyn::mpi::rank() == 0;
  CLI::App app{"camdyn: cam-follower mechanisms that do not jump and do not hammer"};
  app.set_version_flag("--version", std::string("camdyn ") + CAMDYN_VERSION);
  app.require_subcommand(1);

  RunArgs run_args;
  CLI::App* run = app.add_subcommand(
      "run", "Run the study a config describes (simulate, optimize, identify, compare, convergence, ...)");
  run->add_option("config", run_args.config, "Config file (JSON)")->required();
  run->add_option("--out", run_args.out, "Output folder (default out/<name>)")
      ->check([](const std::string& out) { return out.empty() ? std::string("the folder name is empty") : ""; }, "");
  run->add_option("--jobs", run_args.jobs, "Parallel jobs for studies with many runs (default: cores)")
      ->check(CLI::NonNegativeNumber);
  run->add_flag("--quiet", run_args.quiet, "No progress on stderr");
  run->add_flag("--strict", run_args.strict,
                "Exit 3 when the run's results carry plausibility warnings (docs/warnings.md)");
  run->add_option("--set", run_args.overrides, "Override a field: --set contact.stiffness=2e9 (repeatable)");
  run->add_option("--max-study-time", run_args.max_study_time_s,
                  "Wall-time budget of the whole study [s] (default 86400; each run also has "
                  "integrator.max_wall_time_s): past it the study stops, keeps what finished and exits 3")
      ->check(finite_in(0.0, 1e12));
  add_memory_option(*run, run_args);
  run->footer(run_footer());

  RunArgs validate_args;
  CLI::App* validate = app.add_subcommand("validate", "Check a config and print it fully resolved");
  validate->add_option("config", validate_args.config, "Config file (JSON)")->required();
  validate->add_option("--set", validate_args.overrides, "Override a field (repeatable)");
  add_memory_option(*validate, validate_args);

  ExportArgs export_args;
  add_export_command(app, export_args);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitInput;
  }

  if (!run->parsed() && !validate->parsed()) {
    if (!root) return kExitOk;
    return with_exit_codes(export_args.config, export_args.overrides, root, [&] { return run_export(export_args); });
  }
  const RunArgs& args = run->parsed() ? run_args : validate_args;
  return with_exit_codes(args.config, args.overrides, root, [&] { return run_study(args, validate->parsed(), root); });
}

}  // namespace

int main(int argc, char** argv) {
  // Nothing escapes: what the command's own handlers did not catch (set-up,
  // or a handler's output failing) is reported without iostreams.
  try {
    return run_command(argc, argv);
  } catch (const std::bad_alloc& e) {
    std::fprintf(stderr, "camdyn: out of memory: %s: %s\n", e.what(), kMissedEstimate);
    return kExitNumerical;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "camdyn: internal error: %s\n", shown(e.what()).c_str());
  } catch (...) {
    std::fprintf(stderr, "camdyn: internal error: %s\n", kBug);
  }
  return kExitOther;
}
