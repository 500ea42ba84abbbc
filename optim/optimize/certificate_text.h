// The rigid stage's figures in words, one wording for stdout and the report
// (docs/optimize.md "The certificate"): "any law" as a figure or as the
// reason it is not computed (never "inf" beside a figure), the one
// "jump-free to" figure of each design, and what each operating speed's
// "feasible" promises of the family and of the stage's design.
#pragma once

#include <cstddef>
#include <string>

#include "optim/optimize/optimize.h"
#include "optim/optimize/rigid_design.h"

namespace camdyn::optim {

/// "any law 3284.8 rpm (set by segments[0])", "any law: no limit below
/// 1e+07 rpm", or "any law: not computed (why)".
std::string any_law_text(const Certificate& c);

/// On a train, the coarse figure beside (a) as its convergence evidence,
/// or "" when (a) is not computed.
std::string any_law_convergence_text(const Certificate& c);

/// What holds (b) down, " (held by …)", or "" when not worked out or (b) is not computed.
std::string family_binding_text(const Certificate& c);

/// (b): "4905.9 rpm (held by …)" or "not computed".
std::string family_text(const Certificate& c);

/// The model and force floor the jump-free figures are of: "held train,
/// contact and link forces >= 10 N" or "rigid model, contact force >= 10 N".
std::string jump_free_model_text(const Certificate& c);

/// "baseline 3470.4 rpm, rigid design 3913.2 rpm, answer 4100 rpm": each
/// design's one jump-free figure (stage_jump_free_rpm), "" without a certificate.
std::string jump_free_text(const OptimizeOutcome& o);

/// Operating speed `i` of the certificate: the family's answer and whether
/// the stage's design holds it on the dense check ("feasible (best rigid
/// margin 214.6 N); the rigid design holds it (margin 180 N)").
std::string speed_text(const OptimizeOutcome& o, std::size_t i);

/// Share of the baseline's highest lift, and of its lift area, under which
/// an event design's answer has given the lift up.
inline constexpr double kLiftKeptShare = 0.9;

/// On a design.event (its nose free) without objective.lift_area: when
/// the `chosen` answer's highest lift or lift area over the event is below
/// kLiftKeptShare of the baseline's, why it is no green answer (it bought
/// its speed with lift nothing asked it to keep); "" otherwise.
std::string lift_given_up(const OptimizeStudyConfig& config, const DesignEvaluation& baseline,
                          const DesignEvaluation& chosen, CandidateKind kind);

}  // namespace camdyn::optim
