#include "optim/identify/identify_study.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <optional>
#include <string>

#include "io/json_writer.h"
#include "optim/identify/identify.h"
#include "optim/identify/identify_journal.h"
#include "optim/identify/identify_output.h"
#include "study/mpi_runner.h"
#include "study/progress.h"

namespace camdyn::optim {

namespace {

/// What the journal of a killed run holds, on stderr.
void say_resumed(const IdentifyJournal& journal) {
  const IdentifyJournal::Resumed& r = journal.resumed();
  if (r.points == 0) return;
  std::cerr << "camdyn: resuming from " << journal.path().string() << ": " << r.points << " simulated point"
            << (r.points == 1 ? "" : "s");
  if (r.stage)
    std::cerr << ", stage " << *r.stage + 1 << " reached iteration " << r.iteration << " (cost " << r.cost << ")";
  std::cerr << "; the fit is replayed from the start with these simulations\n";
}

/// A progress printer for stderr: the continuation stage (and its smoothing
/// window), the iteration of the stage and its cost, and the time left if
/// every stage uses all its iterations (study/progress.h); at most one line
/// per 0.2 s, and always the first iteration of a stage.
std::function<void(const IdentifyProgress&)> identify_progress_printer(int max_iterations) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point t0 = Clock::now();
  return [max_iterations, t0, last = Clock::time_point{}](const IdentifyProgress& p) mutable {
    const Clock::time_point now = Clock::now();
    if (p.iteration > 0 && now - last < std::chrono::milliseconds(200)) return;
    last = now;
    char stage[64];
    if (p.smoothing > 0.0)
      std::snprintf(stage, sizeof stage, "smoothed over %g ms", p.smoothing * 1e3);
    else
      std::snprintf(stage, sizeof stage, "raw signals");
    const long done = static_cast<long>(p.stage - 1) * max_iterations + p.iteration;
    const double left_s = remaining_iterations_s(done, static_cast<long>(p.stages) * max_iterations,
                                                 std::chrono::duration<double>(now - t0).count());
    const std::string eta = left_s < 0.0 ? format_time_left(left_s) : format_time_left(left_s) + " at most";
    std::fprintf(stderr, "\r  identify: stage %d/%d (%s), iteration %d of at most %d, cost %.6g, %s    ", p.stage,
                 p.stages, stage, p.iteration, max_iterations, p.cost, eta.c_str());
    std::fflush(stderr);
  };
}

}  // namespace

int run_identify_study(const Json& doc, const StudyContext& ctx) {
  Json resolved;
  const IdentifyProblem problem = load_identify_problem(doc, ctx.source, &resolved);
  if (ctx.validate_only) {
    std::cout << dump_json(resolved);
    std::cerr << "camdyn: " << ctx.config_file << " is valid (" << problem.parameters.size() << " parameter"
              << (problem.parameters.size() == 1 ? "" : "s") << ", " << problem.experiments.size() << " record"
              << (problem.experiments.size() == 1 ? "" : "s") << ", " << problem.residual_count()
              << " measured values, estimated memory "
              << std::llround(static_cast<double>(estimated_memory_bytes(problem)) / 1e6) << " MB)\n";
    return 0;
  }

  // Under MPI the starts spread over the ranks (docs/optimize.md "MPI ranks"); one start runs on rank 0 alone.
  const bool root = mpi::rank() == 0;
  const bool over_ranks = mpi::size() > 1 && problem.solver.starts.value_or(2) > 1;
  if (mpi::size() > 1 && !over_ranks) {
    if (!root) return 0;
    std::cerr << "camdyn: note: solver.starts is 1: this identify study runs on rank 0 alone\n";
  }
  std::optional<IdentifyJournal> journal;  // rank 0 alone journals and writes
  if (root) {
    journal.emplace(ctx.out_dir, problem);
    say_resumed(*journal);
  }
  IdentifyOptions options;
  options.threads = ctx.threads();
  options.journal = journal ? &*journal : nullptr;
  options.over_ranks = over_ranks;
  if (ctx.progress && root) options.progress = identify_progress_printer(problem.solver.max_iterations);
  const IdentifyResult result = identify(problem, options);
  if (!root) return 0;
  if (ctx.progress) std::fprintf(stderr, "\n");
  write_identify_outputs(ctx.out_dir, problem, result, resolved);

  std::printf("%s: %s after %d iterations (%s), %ld simulations (%ld points reused), %.3g s\n",
              problem.scene.name.c_str(), result.identifiable ? "identified" : "NOT IDENTIFIABLE", result.iterations,
              result.termination.c_str(), result.simulations, result.reused_points, result.run_time_s);
  if (result.resumed_simulations > 0)
    std::printf("  resumed: %ld of the simulations taken from %s\n", result.resumed_simulations,
                journal->path().c_str());
  for (const ParameterEstimate& p : result.parameters) {
    if (p.std_error)
      std::printf("  %-28s %.8g ± %.3g (%.3g %%)\n", p.name.c_str(), p.value, *p.std_error,
                  p.value != 0.0 ? 100.0 * *p.std_error / std::abs(p.value) : 0.0);
    else
      std::printf("  %-28s %.8g ± undetermined\n", p.name.c_str(), p.value);
  }
  std::printf("  rms_residual %.4g (weighted), final_cost %.6g\n", result.rms_residual, result.final_cost);
  for (const std::string& w : result.warnings) std::printf("  warning: %s\n", w.c_str());
  std::printf("  report: %s\n", std::filesystem::absolute(ctx.out_dir / "report.html").lexically_normal().c_str());
  return 0;
}

}  // namespace camdyn::optim
