// The independent runs of a study (the compare study's runs, the jump map's
// speed ranges) done once each and kept: rank 0 opens the study's journal
// (study/journal.h) and skips the runs already in it; the others run on
// threads, or on MPI ranks when started under mpirun, and each record is
// journalled as it arrives, so a killed study resumes where it stopped.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>

#include "io/config.h"
#include "study/study.h"

namespace camdyn {

struct JournaledRuns {
  std::map<std::size_t, Json> records;  ///< every run's record by index (rank 0), resumed ones included
  std::size_t resumed = 0;              ///< runs found in the journal
  std::size_t resumed_failed = 0;       ///< of which failed (a record whose "status" is not "ok")
  /// Records (of this run and resumed) that a budget cut short (a non-empty
  /// "budget" field: see budget_that_cut in common/study_budget.h).
  std::size_t budget_cut = 0;
  std::string budgets;  ///< the budgets that cut them, comma-separated
};

/// The key of a record's budget: the name of the budget that cut (part of) the
/// run short, absent or empty when none did. run_journaled adds the study's
/// wall-time budget [s] under "study_budget_s" (null: none), and a resumed
/// study runs such a record again when the budget that cut it is larger now.
inline constexpr const char* kBudgetKey = "budget";

/// Runs `run(i)` for every i in [0, count) not yet in `<ctx.out_dir>/journal.jsonl`
/// (a journal of `study` with fingerprint `hash`); `run` returns the run's
/// record, an object with "index" = i and "status" ("ok" or not), and never
/// throws. Returns an exit code when the study must stop before its runs
/// (under MPI, rank 0's reason is shared so that every rank stops); throws
/// otherwise (InputError when the journal belongs to another study).
/// `run_work(i)`, when given, is run i's size in the units its run reports
/// with report_work_done (study/progress.h), e.g. the speeds of a jump map's
/// range; the progress line's time left is estimated from that work rather
/// than from run counts. Without it every run counts one.
std::optional<int> run_journaled(const std::string& study, const std::string& hash, std::size_t count,
                                 const std::function<Json(std::size_t)>& run, const StudyContext& ctx,
                                 JournaledRuns& out, const std::function<double(std::size_t)>& run_work = {});

}  // namespace camdyn
