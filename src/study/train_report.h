// The report's pages on a follower train (docs/model.md §12): the last
// revolution against crank angle (study/train_revolution.h), then over the
// whole run each body's lift against its kinematic lift (the loft), each
// spring's force at its frame end against the static force of a massless
// spring at the same position (surge), and the seat forces with the seatings
// marked.
#pragma once

#include "dynamics/model.h"
#include "dynamics/simulation.h"
#include "output/report.h"
#include "scene/scene.h"

namespace camdyn {

/// Adds the train's plots to `report` (nothing for a model without a train
/// or a run without a time series).
void add_train_plots(const SceneConfig& scene, const Model& model, const SimulationResult& result, Report& report);

}  // namespace camdyn
