// The journal of a speed_limit study (docs/outputs-and-resume.md): every
// simulated speed that finished is one record, so a killed or budget-stopped
// study resumes without simulating those speeds again. The scan's speeds are
// records 0 … scan−1 and the bisection's k-th speed is record scan + k; the
// bisection is deterministic, so a resumed study asks for the same speeds in
// the same order, and a record is replayed only when its speed is the one
// asked for, to the bit. A check a budget cut short is not journaled: it
// says nothing about the physics and is simulated again.
#pragma once

#include <cstddef>
#include <mutex>
#include <optional>

#include "study/journal.h"
#include "study/speed_limit.h"

namespace camdyn {

/// The most bisection steps a journal has room for (a bracket of 1e9
/// tolerances, the widest validation allows, needs 30).
inline constexpr std::size_t kMaxBisectionSteps = 200;

class SpeedLimitJournal {
 public:
  /// Opens `<ctx.out_dir>/journal.jsonl` for `study`; throws InputError when
  /// it belongs to another study or is not a regular file.
  SpeedLimitJournal(const SpeedLimitStudy& study, const StudyContext& ctx);

  /// The check journaled as record `index` when it simulated `rpm`, else nothing.
  std::optional<SpeedCheck> replay(std::size_t index, double rpm) const;

  /// Journals `check` as record `index` unless a budget cut it short. Thread-safe.
  void record(std::size_t index, const SpeedCheck& check);

  /// Records found when the journal was opened.
  std::size_t found() const { return journal_.done().size(); }

 private:
  Journal journal_;
  std::mutex mutex_;
};

}  // namespace camdyn
