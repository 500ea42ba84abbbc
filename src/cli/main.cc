// camdyn command line (interface.md): `camdyn run CONFIG`, `camdyn validate
// CONFIG`, `--version`. Exit codes: 0 success, 2 invalid input, 3 numerical
// failure, 1 anything else. Progress goes to stderr on a terminal; results to
// files; stdout gets a short summary.
#include <camdyn/version.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "cli/run_study.h"
#include "common/errors.h"
#include "study/mpi_runner.h"

namespace {

constexpr int kExitOk = 0, kExitOther = 1, kExitInput = 2, kExitNumerical = 3;

struct RunArgs {
  std::string config;
  std::string out;
  int jobs = 0;
  bool quiet = false;
  std::vector<std::string> overrides;
};

int report_input_error(const camdyn::InputError& e, const std::string& config) {
  // Errors raised below the config layer may not know the file: name it here.
  if (e.file().empty())
    std::cerr << "camdyn: error: " << config << ": " << e.what() << "\n";
  else
    std::cerr << "camdyn: error: " << e.what() << "\n";
  return kExitInput;
}

// The command line: parse, dispatch the study, map its errors to exit codes.
int run_command(int argc, char** argv) {
  // Under mpirun (built with -DCAMDYN_WITH_MPI=ON) a compare study spreads its
  // runs over the ranks; rank 0 alone prints and writes outputs.
  const camdyn::mpi::Session mpi_session(&argc, &argv);
  const bool root = camdyn::mpi::rank() == 0;
  CLI::App app{"camdyn: cam-follower mechanisms that do not jump and do not hammer"};
  app.set_version_flag("--version", std::string("camdyn ") + CAMDYN_VERSION);
  app.require_subcommand(1);

  RunArgs run_args;
  CLI::App* run = app.add_subcommand("run", "Run the study a config describes (simulate)");
  run->add_option("config", run_args.config, "Config file (JSON)")->required();
  run->add_option("--out", run_args.out, "Output folder (default out/<name>)");
  run->add_option("--jobs", run_args.jobs, "Parallel jobs for studies with many runs (default: cores)")
      ->check(CLI::NonNegativeNumber);
  run->add_flag("--quiet", run_args.quiet, "No progress on stderr");
  run->add_option("--set", run_args.overrides, "Override a field: --set contact.stiffness=2e9 (repeatable)");

  RunArgs validate_args;
  CLI::App* validate = app.add_subcommand("validate", "Check a config and print it fully resolved");
  validate->add_option("config", validate_args.config, "Config file (JSON)")->required();
  validate->add_option("--set", validate_args.overrides, "Override a field (repeatable)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitInput;
  }

  const RunArgs& args = run->parsed() ? run_args : validate_args;
  try {
    camdyn::StudyRequest request;
    request.config_file = args.config;
    request.overrides = args.overrides;
    request.out_dir = args.out;
    request.jobs = args.jobs;
    request.progress = !args.quiet && isatty(STDERR_FILENO) && root;
    request.validate_only = validate->parsed();
    return camdyn::run_study(request).exit_code;
  } catch (const camdyn::InputError& e) {
    if (!root) return kExitInput;  // every rank reads the same input: rank 0 says what is wrong
    return report_input_error(e, args.config);
  } catch (const camdyn::NumericalError& e) {
    if (!root) return kExitNumerical;
    std::cerr << "camdyn: numerical failure: " << args.config << ": " << e.what() << "\n";
    return kExitNumerical;
  } catch (const std::exception& e) {
    std::cerr << "camdyn: error: " << e.what() << "\n";
    return kExitOther;
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Nothing escapes: what the command's own handlers did not catch (set-up,
  // or a handler's output failing) is reported without iostreams.
  try {
    return run_command(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "camdyn: internal error: %s\n", e.what());
  } catch (...) {
    std::fprintf(stderr, "camdyn: internal error\n");
  }
  return kExitOther;
}
