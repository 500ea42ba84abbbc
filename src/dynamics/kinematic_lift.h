// A follower train body's kinematic lift (docs/model.md §12,
// docs/valvetrain.md "Lift at the valve"): the steps of geometry/lift_chain.h
// read off the assembled train, so that every user carries the law to a body
// the same way (the lift error, the train's plots, its kinematic start, the
// valve figures).
#pragma once

#include <cstddef>

#include "dynamics/follower_train.h"
#include "geometry/lift_chain.h"

namespace camdyn {

/// Body `body`'s step: its link's ratio and lash (1 and 0 for the follower,
/// body 0) and its seat's position. A train without bodies has the
/// follower's identity step.
LiftStep lift_step(const FollowerTrain& train, std::size_t body);

/// The steps from the follower to `body`.
LiftChain lift_chain(const FollowerTrain& train, std::size_t body);

/// The last body of the train (the valve), 0 (the follower) without a train.
std::size_t last_body(const FollowerTrain& train);

}  // namespace camdyn
