// The budgets of a whole study, process-wide like a signal:
//
// * wall time (`camdyn run --max-study-time`, default 24 h): every run of a
//   study has its own budget (integrator.max_wall_time_s), and this one caps
//   them all together, so a compare of a thousand runs or an optimise of
//   many evaluations cannot run without end either. The simulation loop
//   stops a run when it is used up (Termination::wall_time_budget, saying it
//   was the study's budget), and the studies stop starting work, keep what
//   finished (journals) and exit 3 saying where they stopped;
// * memory (`camdyn run|validate --max-memory`, default 2048 MB): what the
//   inputs ask to be held in memory (the time series a run would record,
//   the rows of a data file) is checked against it before it is allocated,
//   and refused with exit 2 naming the field or file.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>

namespace camdyn {

/// The study budget's default [s]: a day.
inline constexpr double kDefaultStudyWallTimeS = 86400.0;
/// The memory budget's default [MB].
inline constexpr double kDefaultMemoryBudgetMb = 2048.0;
/// The most revolutions one run may ask for (simulation.cycles, a jump
/// map's transient and samples, a periodic study's runs): more is almost
/// surely a slip (a duration in ms, cycles in degrees) and would not finish.
inline constexpr double kMaxRevolutionsPerRun = 1e5;
/// Bytes in the MB of the memory budget (and of every size it prints).
inline constexpr double kBytesPerMb = 1024.0 * 1024.0;

/// Sets the study's budget for its lifetime (`seconds` from now; +inf: none)
/// and restores the one before when it ends. Not for concurrent studies in
/// one process (one runs at a time).
class StudyBudgetScope {
 public:
  explicit StudyBudgetScope(double seconds, double memory_mb = kDefaultMemoryBudgetMb);
  ~StudyBudgetScope();
  StudyBudgetScope(const StudyBudgetScope&) = delete;
  StudyBudgetScope& operator=(const StudyBudgetScope&) = delete;

 private:
  long long previous_deadline_ns_;
  double previous_seconds_, previous_memory_mb_;
};

/// A check for an interrupt by the user (Ctrl-C in the Python module:
/// docs/python.md), for the scope's lifetime. The simulation loop calls
/// poll_interrupt() at most every 0.25 s of a run; on the thread that made
/// the scope it runs `interrupted`, and when that returns true the study's
/// budget counts as used up: every run stops as on --max-study-time and the
/// studies keep what finished (journals) and exit 3. The scope restores the
/// budget when it ends. One at a time, like StudyBudgetScope.
class InterruptScope {
 public:
  explicit InterruptScope(std::function<bool()> interrupted);
  ~InterruptScope();
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;

 private:
  std::function<bool()> interrupted_;
  long long previous_deadline_ns_;
};

/// Runs the InterruptScope's check when called on its thread (else nothing).
void poll_interrupt();

/// Whether an InterruptScope's check has interrupted the study.
bool study_interrupted();

/// Whether the study's budget is used up (false without one). Cheap: one
/// clock read; thread-safe.
bool study_budget_exhausted();
/// The same at `now` (for a loop that has read the clock already).
bool study_budget_exhausted(std::chrono::steady_clock::time_point now);

/// The budget [s] (+inf without one).
double study_budget_s();

/// "the study's wall-time budget of N s (camdyn run --max-study-time) is used up".
std::string study_budget_text();

/// "run the study again into the same --out (with a larger --max-study-time)
/// to finish it": what to do after a study stopped on its budget.
std::string study_rerun_advice();

/// The budget a failed run's message says cut it short: "integrator.max_steps",
/// "integrator.max_wall_time_s", "--max-study-time" or "--max-memory"; empty
/// when the run failed for another reason (a run that ran out of a budget
/// proves nothing about the physics: docs/outputs-and-resume.md, "Budgets").
/// Keyed to the field each budget message names (dynamics/simulation.cc,
/// study_budget_text, memory_budget_text).
std::string budget_that_cut(std::string_view message);

/// "N of M <runs> were cut short by a budget (<budgets>) ...: <conclusion> is
/// withheld; raise that budget and run again": the message of a study that
/// exits 3 rather than conclude from runs that did not finish.
std::string withheld_text(std::size_t cut, std::size_t total, const std::string& runs, const std::string& budgets,
                          const std::string& conclusion);

/// The memory budget [bytes] (kDefaultMemoryBudgetMb outside a scope).
double memory_budget_bytes();

/// "more than the memory budget of N MB (--max-memory)".
std::string memory_budget_text();

}  // namespace camdyn
