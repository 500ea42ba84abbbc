#include "study/journaled_runs.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <set>
#include <vector>

#include "common/errors.h"
#include "common/parallel.h"
#include "common/study_budget.h"
#include "study/journal.h"
#include "study/mpi_runner.h"
#include "study/progress.h"

namespace camdyn {

namespace {

/// The key under which a record carries its wall time to rank 0 [s].
constexpr const char* kRunTimeKey = "_progress_run_s";
/// The status of a run not started because the study's budget was used up.
constexpr const char* kNotStarted = "not_started";

/// The study's wall-time budget as journaled [s] (null: none).
Json budget_json(double seconds) { return std::isfinite(seconds) ? Json(seconds) : Json(nullptr); }

/// The budget that cut `record` short ("" when none did).
std::string record_budget(const Json& record) {
  const auto it = record.find(kBudgetKey);
  return it != record.end() && it->is_string() ? it->get<std::string>() : std::string();
}

/// Whether a budget cut `record` short and that budget is larger now, so
/// that running it again may finish it: only the study's wall time and
/// memory can differ between two runs of one study (integrator.max_steps and
/// max_wall_time_s are part of its fingerprint).
bool budget_larger_now(const Json& record) {
  const std::string budget = record_budget(record);
  if (budget != "--max-study-time" && budget != "--max-memory") return false;
  const Json then = record.value("study_budget_s", Json(nullptr));
  const double then_s = then.is_number() ? then.get<double>() : std::numeric_limits<double>::infinity();
  return budget == "--max-memory" || study_budget_s() > then_s;
}

/// Drops the records whose "status" is not a string (every record
/// run_journaled writes has one): a record edited and its checksum
/// recomputed (tests/fuzz/journal_fuzzer.cc) is run again, not read as a
/// result.
void drop_records_without_status(std::map<std::size_t, Json>& records, const std::filesystem::path& journal) {
  for (auto it = records.begin(); it != records.end();) {
    const auto status = it->second.find("status");
    if (status != it->second.end() && status->is_string()) {
      ++it;
      continue;
    }
    std::cerr << "camdyn: warning: " << journal.string() << ": the record of run " << it->first
              << " has no status; that run is done again\n";
    it = records.erase(it);
  }
}

/// Counts the records a budget cut short and names their budgets.
void count_budget_cuts(JournaledRuns& out) {
  std::set<std::string> names;
  out.budget_cut = 0;
  for (const auto& [i, record] : out.records)
    if (const std::string budget = record_budget(record); !budget.empty()) {
      ++out.budget_cut;
      names.insert(budget);
    }
  out.budgets.clear();
  for (const std::string& name : names) out.budgets += (out.budgets.empty() ? "" : ", ") + name;
}

/// The runs of this invocation: the journal (rank 0) with the records already
/// done, and the runs still to do (every rank).
struct RunState {
  std::unique_ptr<Journal> journal;
  std::vector<std::size_t> pending;
  std::size_t stopped = 0;  ///< runs not done because the study's budget was used up (not journaled)
};

/// Rank 0 opens the journal and reads the runs already done; the runs still to
/// do go to every rank. Returns an exit code when the study must stop (under
/// MPI, rank 0's reason is shared so that every rank stops); throws otherwise.
std::optional<int> open_journal(const std::string& study, const std::string& hash, std::size_t count,
                                const StudyContext& ctx, RunState& state, JournaledRuns& out) {
  const bool root = mpi::rank() == 0;
  const bool distributed = mpi::size() > 1;
  std::string failure;  // rank 0's reason to stop: the exit code digit, then the message
  if (root) {
    try {
      std::filesystem::create_directories(ctx.out_dir);
      state.journal = std::make_unique<Journal>(ctx.out_dir / "journal.jsonl", study, hash, count);
      out.records = state.journal->done();
      drop_records_without_status(out.records, state.journal->path());
      std::size_t rerun = 0;
      for (auto it = out.records.begin(); it != out.records.end();)
        it = budget_larger_now(it->second) ? (++rerun, out.records.erase(it)) : std::next(it);
      if (rerun > 0)
        std::cerr << "camdyn: " << rerun << " journaled runs were cut short by a smaller budget; they are run again\n";
    } catch (const InputError& e) {
      if (!distributed) throw;
      failure = std::string("2") + e.what();
    } catch (const std::exception& e) {
      if (!distributed) throw;
      failure = std::string("1") + e.what();
    }
    for (std::size_t i = 0; i < count; ++i)
      if (!out.records.count(i)) state.pending.push_back(i);
  }
  if (distributed) {
    Json shared{{"failure", failure}, {"pending", state.pending}};
    shared = Json::parse(mpi::broadcast(shared.dump()));
    failure = shared["failure"].get<std::string>();
    state.pending = shared["pending"].get<std::vector<std::size_t>>();
    if (!failure.empty()) {
      if (root) std::cerr << "camdyn: error: " << failure.substr(1) << "\n";  // the other ranks: rank 0 says why
      return failure[0] - '0';
    }
  }
  for (const auto& [i, record] : out.records)
    if (string_or(record, "status", "") != "ok") ++out.resumed_failed;
  out.resumed = count - state.pending.size();
  if (root && out.resumed > 0)
    std::cerr << "camdyn: resuming: " << out.resumed << " of " << count << " runs already done ("
              << (ctx.out_dir / "journal.jsonl").string() << "), skipped\n";
  return std::nullopt;
}

/// Runs the pending runs on threads (one process) or MPI ranks; rank 0
/// journals each record as it arrives.
void run_pending(const std::string& study, std::size_t count, const std::function<Json(std::size_t)>& run,
                 const std::function<double(std::size_t)>& run_work, const StudyContext& ctx, RunState& state,
                 JournaledRuns& out) {
  const bool distributed = mpi::size() > 1;
  const std::size_t workers =
      distributed ? static_cast<std::size_t>(mpi::size()) : static_cast<std::size_t>(ctx.threads());
  const auto work = [&run_work](std::size_t i) { return run_work ? run_work(i) : 1.0; };
  double session_work = 0.0;  // [the units of run_work]
  for (const std::size_t i : state.pending) session_work += work(i);
  ProgressMeter progress(study, count, out.resumed, out.resumed_failed, workers, ctx.progress && mpi::rank() == 0,
                         session_work);
  std::mutex mutex;
  // Each record brings its wall time [s] to rank 0 (the meter's run time);
  // it is taken out before the record is journalled.
  auto timed_run = [&run](std::size_t i) {
    if (study_budget_exhausted()) return Json{{"index", i}, {"status", kNotStarted}};
    const auto t0 = std::chrono::steady_clock::now();
    Json record = run(i);
    record[kRunTimeKey] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return record;
  };
  auto finished = [&](Json record) {  // rank 0, serialised by the caller
    const std::size_t i = record["index"].get<std::size_t>();
    const bool failed = record["status"] != "ok";
    // A run the budget stopped (or never started) is not a result: left out
    // of the journal, so that a re-run does it.
    if (failed && (record["status"] == kNotStarted || study_budget_exhausted())) {
      ++state.stopped;
      return;
    }
    const double run_s = record.value(kRunTimeKey, 0.0);
    record.erase(kRunTimeKey);
    if (!record_budget(record).empty()) record["study_budget_s"] = budget_json(study_budget_s());
    state.journal->append(record);
    out.records[i] = std::move(record);
    progress.finished(failed, run_s, work(i));
  };
  try {
    if (distributed) {
      mpi::distribute_runs(
          state.pending,
          [&](std::size_t i) { return timed_run(i).dump(-1, ' ', false, Json::error_handler_t::replace); },
          [&](const std::string& text) { finished(Json::parse(text)); });
    } else {
      parallel_for(state.pending.size(), ctx.threads(), [&](std::size_t k) {
        Json record = timed_run(state.pending[k]);
        const std::lock_guard<std::mutex> lock(mutex);
        finished(std::move(record));
      });
    }
  } catch (const std::exception& e) {
    if (!distributed) throw;
    // The other ranks may wait for rank 0 (or it for them): end them all.
    std::cerr << "camdyn: error: rank " << mpi::rank() << ": " << e.what() << "\n";
    mpi::abort_all(1);
  }
}

}  // namespace

std::optional<int> run_journaled(const std::string& study, const std::string& hash, std::size_t count,
                                 const std::function<Json(std::size_t)>& run, const StudyContext& ctx,
                                 JournaledRuns& out, const std::function<double(std::size_t)>& run_work) {
  RunState state;
  if (const std::optional<int> code = open_journal(study, hash, count, ctx, state, out)) return code;
  run_pending(study, count, run, run_work, ctx, state, out);
  count_budget_cuts(out);
  if (state.stopped == 0) return std::nullopt;
  if (mpi::rank() == 0)
    std::cerr << "camdyn: error: " << study_budget_text() << " after " << count - state.stopped << " of " << count
              << " runs of the " << study << " study; the finished runs are kept in "
              << (ctx.out_dir / "journal.jsonl").string() << ": " << study_rerun_advice() << '\n';
  return 3;  // the exit code of a budget that stopped the study
}

}  // namespace camdyn
