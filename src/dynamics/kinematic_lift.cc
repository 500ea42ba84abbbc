#include "dynamics/kinematic_lift.h"

namespace camdyn {

LiftStep lift_step(const FollowerTrain& train, std::size_t body) {
  LiftStep step;
  if (body >= train.bodies.size()) return step;
  const TrainBody& b = train.bodies[body];
  if (body > 0) {
    step.ratio = b.ratio;
    step.lash = b.lash;
  }
  if (b.seat >= 0) step.seat = train.elements[static_cast<std::size_t>(b.seat)].offset;  // δ = p − x: the offset is p
  return step;
}

LiftChain lift_chain(const FollowerTrain& train, std::size_t body) {
  LiftChain chain;
  for (std::size_t i = 0; i <= body; ++i) chain.steps.push_back(lift_step(train, i));
  return chain;
}

std::size_t last_body(const FollowerTrain& train) { return train.bodies.empty() ? 0 : train.bodies.size() - 1; }

}  // namespace camdyn
