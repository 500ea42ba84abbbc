#include "common/study_budget.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <thread>

namespace camdyn {

namespace {

using Clock = std::chrono::steady_clock;

constexpr long long kNoDeadline = std::numeric_limits<long long>::max();

/// The deadline as steady_clock nanoseconds since its epoch (kNoDeadline: none).
std::atomic<long long> g_deadline_ns{kNoDeadline};
std::atomic<double> g_seconds{std::numeric_limits<double>::infinity()};
std::atomic<double> g_memory_mb{kDefaultMemoryBudgetMb};

/// The InterruptScope's check (null: none), its thread, and whether it fired.
std::atomic<const std::function<bool()>*> g_interrupt_check{nullptr};
std::thread::id g_interrupt_thread;
std::atomic<bool> g_interrupted{false};

long long now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch()).count();
}

}  // namespace

StudyBudgetScope::StudyBudgetScope(double seconds, double memory_mb)
    : previous_deadline_ns_(g_deadline_ns.load()),
      previous_seconds_(g_seconds.load()),
      previous_memory_mb_(g_memory_mb.load()) {
  g_memory_mb = memory_mb;
  const double max_s = 1e9;  // ~30 years: beyond, no deadline (and no overflow)
  g_seconds = seconds;
  g_deadline_ns =
      std::isfinite(seconds) && seconds < max_s ? now_ns() + static_cast<long long>(seconds * 1e9) : kNoDeadline;
}

StudyBudgetScope::~StudyBudgetScope() {
  g_deadline_ns = previous_deadline_ns_;
  g_seconds = previous_seconds_;
  g_memory_mb = previous_memory_mb_;
}

InterruptScope::InterruptScope(std::function<bool()> interrupted)
    : interrupted_(std::move(interrupted)), previous_deadline_ns_(g_deadline_ns.load()) {
  g_interrupted = false;
  g_interrupt_thread = std::this_thread::get_id();
  g_interrupt_check.store(&interrupted_, std::memory_order_release);
}

InterruptScope::~InterruptScope() {
  g_interrupt_check.store(nullptr, std::memory_order_release);
  if (g_interrupted.exchange(false)) g_deadline_ns = previous_deadline_ns_;
}

void poll_interrupt() {
  const std::function<bool()>* check = g_interrupt_check.load(std::memory_order_acquire);
  if (check == nullptr || std::this_thread::get_id() != g_interrupt_thread || g_interrupted.load()) return;
  if ((*check)()) {
    g_interrupted = true;
    g_deadline_ns = std::numeric_limits<long long>::min();  // used up
  }
}

bool study_interrupted() { return g_interrupted.load(); }

bool study_budget_exhausted() { return study_budget_exhausted(Clock::now()); }

bool study_budget_exhausted(Clock::time_point now) {
  const long long deadline = g_deadline_ns.load(std::memory_order_relaxed);
  return deadline != kNoDeadline &&
         std::chrono::duration_cast<std::chrono::nanoseconds>(now.time_since_epoch()).count() > deadline;
}

double study_budget_s() { return g_seconds.load(); }

std::string study_budget_text() {
  std::ostringstream text;
  if (g_interrupted.load())  // stopped as on its budget (and named so: budget_that_cut)
    text << "the study was interrupted by its user, and stopped as when its wall-time budget (camdyn run "
            "--max-study-time) is used up";
  else
    text << "the study's wall-time budget of " << study_budget_s() << " s (camdyn run --max-study-time) is used up";
  return text.str();
}

std::string study_rerun_advice() {
  return "run the study again into the same --out (with a larger --max-study-time) to finish it";
}

std::string budget_that_cut(std::string_view message) {
  for (const char* budget : {"integrator.max_steps", "integrator.max_wall_time_s", "--max-study-time", "--max-memory"})
    if (message.find(std::string(budget) + ")") != std::string_view::npos) return budget;
  return {};
}

std::string withheld_text(std::size_t cut, std::size_t total, const std::string& runs, const std::string& budgets,
                          const std::string& conclusion) {
  std::ostringstream text;
  text << cut << " of " << total << " " << runs << " were cut short by a budget (" << budgets
       << ") and say nothing about the physics: " << conclusion
       << " is withheld; raise that budget (or simplify the runs) and run again";
  return text.str();
}

double memory_budget_bytes() { return g_memory_mb.load() * kBytesPerMb; }

std::string memory_budget_text() {
  std::ostringstream text;
  text << "more than the memory budget of " << g_memory_mb.load() << " MB (--max-memory)";
  return text.str();
}

}  // namespace camdyn
