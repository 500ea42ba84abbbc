// The wall-time budget of a whole study (`camdyn run --max-study-time`,
// default 24 h): every run of a study has its own budget
// (integrator.max_wall_time_s), and this one caps them all together, so a
// compare of a thousand runs or an optimise of many evaluations cannot run
// without end either. It is process-wide, like a signal: the simulation
// loop stops a run when it is used up (Termination::wall_time_budget, saying
// it was the study's budget), and the studies stop starting work, keep
// what finished (journals) and exit 3 saying where they stopped.
#pragma once

#include <string>

namespace camdyn {

/// The study budget's default [s]: a day.
inline constexpr double kDefaultStudyWallTimeS = 86400.0;

/// Sets the study's budget for its lifetime (`seconds` from now; +inf: none)
/// and restores the one before when it ends. Not for concurrent studies in
/// one process (one runs at a time).
class StudyBudgetScope {
 public:
  explicit StudyBudgetScope(double seconds);
  ~StudyBudgetScope();
  StudyBudgetScope(const StudyBudgetScope&) = delete;
  StudyBudgetScope& operator=(const StudyBudgetScope&) = delete;

 private:
  long long previous_deadline_ns_;
  double previous_seconds_;
};

/// Whether the study's budget is used up (false without one). Cheap: one
/// clock read; thread-safe.
bool study_budget_exhausted();

/// The budget [s] (+inf without one).
double study_budget_s();

/// "the study's wall-time budget of N s (camdyn run --max-study-time) is used up".
std::string study_budget_text();

}  // namespace camdyn
