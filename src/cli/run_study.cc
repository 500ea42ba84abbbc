#include "cli/run_study.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "common/errors.h"
#include "common/study_budget.h"
#include "io/atomic_file.h"
#include "io/config.h"
#include "io/json_archive.h"
#include "optim/identify/identify_study.h"
#include "optim/optimize/optimize_study.h"
#include "output/output_folder.h"
#include "scene/study_kind.h"
#include "study/compare_study.h"
#include "study/convergence_study.h"
#include "study/jump_map.h"
#include "study/mpi_runner.h"
#include "study/periodic_study.h"
#include "study/simulate_study.h"
#include "study/speed_limit.h"
#include "study/study.h"

namespace camdyn {

namespace {

constexpr int kExitOk = 0;

/// A study's runner: reads its config from the document, runs it (or checks
/// it, with ctx.validate_only) and writes its outputs to ctx.out_dir.
struct StudyRunner {
  int (*run)(const Json& doc, const StudyContext& ctx);
  /// Runs on every MPI rank (it spreads its runs over them or keeps them in
  /// step); the others run on rank 0 alone.
  bool every_rank = false;
  /// Its ranks wait for each other's results as it runs (the starts of
  /// optimize and identify): under MPI, a failure on one rank ends them all.
  bool in_step = false;
};

// The runners table: one case per registered study (scene/study_kind.h). A
// study without its case does not compile (-Wswitch is an error in the ci preset).
StudyRunner runner_of(StudyKind kind) {
  switch (kind) {
    case StudyKind::simulate:
      return {run_simulate_study};
    case StudyKind::optimize:
      return {optim::run_optimize_study, true, true};
    case StudyKind::identify:
      return {optim::run_identify_study, true, true};
    case StudyKind::compare:
      return {run_compare_study, true};
    case StudyKind::convergence:
      return {run_convergence_study, true};
    case StudyKind::periodic:
      return {run_periodic_study};
    case StudyKind::jump_map:
      return {run_jump_map_study, true};
    case StudyKind::speed_limit:
      return {run_speed_limit_study};
  }
  throw std::invalid_argument("not a StudyKind value");
}

// A word the registry does not know runs as simulate, whose scene loader
// reports it with every study's name (io/config.cc).
StudyKind study_kind(const std::string& study) {
  return enum_from_name<StudyKind>(study).value_or(StudyKind::simulate);
}

/// Runs a study whose ranks wait for each other: an exception on any rank
/// ends every rank (mpi::abort_all) with the exit code main() would give it
/// (docs/config.md "Exit codes"), after that rank says why.
int run_in_step(const StudyRunner& runner, const Json& doc, const StudyContext& ctx) {
  if (mpi::size() == 1) return runner.run(doc, ctx);
  int code = 1;
  try {
    return runner.run(doc, ctx);
  } catch (const InputError& e) {
    code = 2;
    std::cerr << "camdyn: error: rank " << mpi::rank() << ": " << e.what() << "\n";
  } catch (const NumericalError& e) {
    code = 3;
    std::cerr << "camdyn: numerical failure: rank " << mpi::rank() << ": " << e.what() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "camdyn: error: rank " << mpi::rank() << ": " << e.what() << "\n";
  }
  mpi::abort_all(code);
}

int dispatch(const std::string& study, const Json& doc, const StudyContext& ctx) {
  const StudyRunner runner = runner_of(study_kind(study));
  if (runner.in_step) return run_in_step(runner, doc, ctx);
  if (runner.every_rank) return runner.run(doc, ctx);
  const bool root = mpi::rank() == 0;
  if (mpi::size() > 1 && !ctx.validate_only) {
    // Only compare, convergence, jump map, optimize and identify studies use the ranks; the others run on rank 0.
    if (!root) return kExitOk;
    std::cerr << "camdyn: note: only compare, convergence, jump_map, optimize and identify studies use the MPI "
                 "ranks; this "
              << study << " study runs on rank 0 alone\n";
  }
  return runner.run(doc, ctx);
}

/// Sends what the process writes on stdout to /dev/null while it lives (the
/// study runners print their summaries there). Process-wide: output another
/// thread prints meanwhile is lost too.
class SilencedStdout {
 public:
  SilencedStdout() {
    std::fflush(stdout);
    saved_ = ::dup(STDOUT_FILENO);
    const int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (saved_ >= 0 && null >= 0) ::dup2(null, STDOUT_FILENO);
    if (null >= 0) ::close(null);
  }
  ~SilencedStdout() {
    std::fflush(stdout);
    if (saved_ < 0) return;
    ::dup2(saved_, STDOUT_FILENO);
    ::close(saved_);
  }
  SilencedStdout(const SilencedStdout&) = delete;
  SilencedStdout& operator=(const SilencedStdout&) = delete;

 private:
  int saved_ = -1;
};

Json request_json(const StudyRequest& request, ConfigSource& source) {
  if (!request.config_file.empty()) {
    source = config_source(request.config_file);
    return load_config_json(request.config_file, request.overrides);
  }
  Json doc = parse_json_text(request.json_text, "");
  for (const std::string& assignment : request.overrides) apply_assignment(doc, assignment);
  source = ConfigSource{
      "", std::filesystem::absolute(request.base_dir.empty() ? "." : request.base_dir).lexically_normal().string()};
  return doc;
}

}  // namespace

std::string main_output_name(const std::string& study) {
  return std::string(study_info(study_kind(study)).main_output);
}

StudyOutcome run_study(const StudyRequest& request) {
  // From the first file read: a config and what it extends are held to --max-memory too (io/input_file.h).
  const StudyBudgetScope budget(request.max_study_time_s, request.max_memory_mb);
  StudyContext ctx;
  const Json doc = request_json(request, ctx.source);
  ctx.config_file = request.config_file;
  const std::string name = doc.contains("name") && doc["name"].is_string() ? doc["name"].get<std::string>() : "camdyn";
  ctx.out_dir = request.out_dir.empty() ? std::filesystem::path("out") / name : std::filesystem::path(request.out_dir);
  ctx.jobs = request.jobs;
  ctx.progress = request.progress;
  ctx.validate_only = request.validate_only;
  ctx.strict = request.strict;
  StudyOutcome outcome;
  outcome.study = doc.contains("study") && doc["study"].is_string() ? doc["study"].get<std::string>() : "simulate";
  outcome.out_dir = ctx.out_dir;
  outcome.main_output = ctx.out_dir / main_output_name(outcome.study);
  // One run at a time per output folder (rank 0 writes for all ranks); the
  // completion marker goes first and comes back only once every output is written.
  std::optional<OutputLock> lock;
  if (!ctx.validate_only && mpi::rank() == 0) {
    lock.emplace(ctx.out_dir);
    remove_stale_temporary_files(ctx.out_dir);
    remove_completion_marker(ctx.out_dir);
  }
  try {
    std::optional<SilencedStdout> silenced;
    if (!request.summary) silenced.emplace();
    outcome.exit_code = dispatch(outcome.study, doc, ctx);
  } catch (const InputError& e) {
    // Errors raised below the config layer may not know the file: name it here.
    if (!e.file().empty() || request.config_file.empty()) throw;
    throw InputError(request.config_file, e.path(), e.reason());
  }
  if (lock && outcome.exit_code == kExitOk)
    write_completion_marker(ctx.out_dir, outcome.study, main_output_name(outcome.study));
  return outcome;
}

}  // namespace camdyn
