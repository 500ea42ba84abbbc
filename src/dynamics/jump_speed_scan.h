// The jump-speed scan's settings, shared by the held train (held_train.cc)
// and the linear train response (linear_train_response.cc): both scan the
// cam speed up to ω_max for the first speed at which the train separates,
// with one resolution.
#pragma once

namespace camdyn {

/// Equal steps of the jump-speed scan up to ω_max.
inline constexpr int kJumpScanSpeedSteps = 400;
/// A harmonic whose amplitude is below this share of the largest adds no resonance to the scan [-].
inline constexpr double kJumpScanSignificantHarmonic = 1e-3;

}  // namespace camdyn
