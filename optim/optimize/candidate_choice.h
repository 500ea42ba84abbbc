// Which design an optimize study returns (docs/config.md, "The answer of an
// optimize study"): the best of the baseline, the rigid stage's design and the
// dynamic stage's result, each judged by the same verification (the scene's
// settings, the metrics over the steady state at every operating speed, the
// study's own objective and constraints). A design that meets every
// constraint beats one that does not; among those that do, the lowest
// objective wins, and a challenger must be lower than the baseline by more
// than kBeatTolerance (relative) to replace it, so the study never returns a
// design worse than it was given. When nothing meets every constraint, the
// least violation wins (the baseline on ties).
#pragma once

#include <string>
#include <vector>

namespace camdyn::optim {

/// In this order (the index of each in an optimize study's candidate list);
/// `spring`: the best of the others with its spring preload sized (design.spring).
enum class CandidateKind { baseline, rigid, dynamic, spring };

/// "baseline", "rigid", "dynamic", "spring" (result.json `chosen`).
const char* to_string(CandidateKind kind);

/// One candidate as the verification saw it.
struct CandidateScore {
  CandidateKind kind = CandidateKind::baseline;
  bool available = false;             ///< the study produced this candidate (no rigid design: not available)
  bool valid = false;                 ///< it could be built and simulated
  bool feasible = false;              ///< every constraint holds
  double objective = 0.0;             ///< the study's normalised objective
  double violation = 0.0;             ///< Σ max(residual, 0) over the constraints (normalised)
  std::vector<std::string> violated;  ///< names of the constraints it breaks
};

struct CandidateChoice {
  CandidateKind chosen = CandidateKind::baseline;
  bool feasible = false;  ///< the chosen candidate meets every constraint
  /// chosen is not the baseline, and meets every constraint where the
  /// baseline does not, or has the lower objective
  bool beats_baseline = false;
  std::string reason;  ///< one sentence: why this one
};

/// Relative margin by which a challenger's objective must undercut the baseline's.
inline constexpr double kBeatTolerance = 1e-6;

/// The choice among `candidates` (the baseline must be among them and available).
CandidateChoice choose_candidate(const std::vector<CandidateScore>& candidates);

}  // namespace camdyn::optim
