// Chatter (docs/periodic.md, "How"): an accumulating impact sequence, the follower
// bouncing back onto the cam in ever shorter flights whose durations shrink
// geometrically (a rigid contact of restitution e: τ_{n+1} = e τ_n), so that
// infinitely many impacts would accumulate at a finite time, after which the
// follower stays on the cam. A compliant contact ends the sequence after
// finitely many impacts; the accumulation time is the observed impacts plus
// the geometric tail. A motion that chatters is not chaotic, whatever a
// Lyapunov estimate across its accumulations says.
#pragma once

#include <cstddef>
#include <vector>

#include "dynamics/simulation.h"

namespace camdyn {

struct ChatterSequence {
  std::size_t impacts = 0;         ///< impacts ending the sequence's flights
  double ratio = 0.0;              ///< geometric mean of the ratios of successive flight durations [-]
  double first_impact_time = 0.0;  ///< the landing of its first flight [s]
  double accumulation_time = 0.0;  ///< where the flights' geometric series sums to [s]
  double accumulation_deg = 0.0;   ///< cam angle there, in [0, 360) [deg]
};

/// The chatter sequences of a run's events: at least `min_impacts` impacts in
/// a row, separated only by flights whose durations shrink with ratios in
/// (0, 0.95) that agree within a factor 1.5, the last impact followed by a
/// contact at least 3 times longer than the last flight (or by the run's end
/// at `t_end` [s]). `deg_per_s` turns time into cam angle [deg/s].
std::vector<ChatterSequence> find_chatter(const std::vector<ContactEvent>& events, double t_end, double deg_per_s,
                                          std::size_t min_impacts = 4);

}  // namespace camdyn
