// What a contact onset is (docs/model.md §6): an impact only when the contact
// had separated before it and the gap closes at a positive speed; any other
// onset is a graze (no approach) or a re-entry (no separation before it),
// recorded in events.csv with `grazing = 1` and counted in no metric.
#pragma once

namespace camdyn {

struct OnsetClass {
  bool impact = false;   ///< counted in impact_count and max_impact_velocity
  bool grazing = false;  ///< an onset that is not an impact
};

/// The class of an onset after a separation (`separated_before`) or not,
/// with the gap's closing speed `approach` = −ġ [m/s].
constexpr OnsetClass classify_onset(bool separated_before, double approach) {
  const bool impact = separated_before && approach > 0.0;
  return {impact, !impact};
}

}  // namespace camdyn
