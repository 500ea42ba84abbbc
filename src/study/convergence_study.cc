#include "study/convergence_study.h"

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "common/errors.h"
#include "common/study_budget.h"
#include "io/json_writer.h"
#include "study/convergence.h"
#include "study/convergence_config.h"
#include "study/convergence_output.h"

namespace camdyn {

int run_convergence_study(const Json& doc, const StudyContext& ctx) {
  const ConvergenceStudy study = read_convergence_study(doc, ctx);
  if (ctx.validate_only) {
    std::cout << dump_json(study.resolved);
    return 0;
  }
  const ConvergenceResult result = run_convergence(study, ctx);
  const double wall = write_convergence_outputs(ctx.out_dir, study, result, ctx.config_file);
  const long failed = result.failed();
  std::printf("%s: %zu runs (%ld failed) in %.3g s\n  work_precision.csv and report: %s\n", study.base.name.c_str(),
              result.runs.size(), failed, wall,
              std::filesystem::absolute(ctx.out_dir / "report.html").lexically_normal().c_str());
  // Everything finished is written; a missing reference is still a solver that gave up: exit 3.
  std::string missing;
  for (std::size_t k = 0; k < result.reference_missing.size(); ++k)
    if (!result.reference_missing[k].empty())
      missing +=
          (missing.empty() ? "" : "; ") + ("the reference run of scene '" + study.config.scenes[k].name + "' failed (" +
                                           result.reference_note[k] + "): " + result.reference_missing[k]);
  if (!missing.empty()) throw NumericalError(missing + "; the runs that finished are written without errors");
  // Runs the study's wall-time budget cut or never started: the study is not
  // finished (docs/outputs-and-resume.md, "Budgets").
  std::size_t cut = 0;
  for (const ConvergenceRun& r : result.runs) cut += budget_that_cut(r.error) == "--max-study-time" ? 1 : 0;
  if (cut > 0) {
    std::cerr << "camdyn: error: " << study_budget_text() << ": " << cut << " of " << result.runs.size()
              << " runs were cut short or not started; the runs that finished are written. Run the study again "
                 "with a larger --max-study-time to finish it\n";
    return 3;
  }
  return 0;
}

}  // namespace camdyn
