// What a run observes of its follower train (docs/model.md §12): the
// smallest link force while its body is off its seat, the largest force at a
// spring's frame end, each body's largest lift error, the time a link is
// open while its body rests on no seat (and of it, in float), the highest
// seat bounce (docs/valvetrain.md), folded in from the same
// samples as the window's other metrics (dynamics/window_observer.h). The
// seat impacts, seating speeds and coil clashes come from the run's events
// (dynamics/simulation.cc). Internal to dynamics/.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "common/constants.h"
#include "dynamics/kinematic_lift.h"
#include "dynamics/metrics.h"
#include "dynamics/model.h"

namespace camdyn {

class TrainObserver {
 public:
  /// Starts the train's metrics in `m` (nothing for a model without a train).
  TrainObserver(const Model& model, const SeparationCauses& causes, Metrics& m)
      : model_(model), train_(model.train), causes_(causes), m_(m) {
    if (!train_.present()) return;
    TrainMetrics t;
    for (const TrainBody& b : train_.bodies) {
      t.links = t.links || b.link >= 0;
      t.seats = t.seats || b.seat >= 0;
      t.springs = t.springs || b.spring_end >= 0;
      t.gas = t.gas || b.gas >= 0;
      t.bodies.push_back(b.name);
    }
    t.springs = t.springs || model.forces.spring().present();
    t.clash = std::any_of(train_.elements.begin(), train_.elements.end(),
                          [](const TrainElement& e) { return e.role == TrainRole::clash; });
    t.max_lift_error.assign(train_.bodies.size(), 0.0);
    t.lash = model.take_up.applies;
    t.held_open = model.take_up.held_open_body >= 0;
    m_.train = std::move(t);
  }

  /// Whether the cam contact's gap is lash at `e`: the follower rests on a seat.
  bool lash(const Evaluation& e) const { return train_.present() && train_.rests_on_seat(e.train, 0); }

  /// Folds the train at the evaluation `e` (a time in the window) into the records.
  void fold(const Evaluation& e) {
    if (!train_.present()) return;
    TrainMetrics& t = *m_.train;
    const ReturnSpring& spring = model_.forces.spring();  // the follower's massless spring, where it has one
    if (spring.present()) t.peak_spring_force = std::max(t.peak_spring_force, std::abs(spring.force(e.y, e.v, 0.0)));
    double kinematic = model_.law->eval(e.theta).s;  // [m | rad]
    for (std::size_t i = 0; i < train_.bodies.size(); ++i) {
      const TrainBody& b = train_.bodies[i];
      kinematic = lift_step(train_, i).carry(kinematic);
      t.max_lift_error[i] = std::max(t.max_lift_error[i], std::abs(e.train.position[i] - kinematic));
      if (b.link >= 0 && !train_.rests_on_seat(e.train, static_cast<int>(i)))
        min_link_ = std::min(min_link_, e.train.link_force[i]);
      if (b.spring_end >= 0) t.peak_spring_force = std::max(t.peak_spring_force, std::abs(e.train.spring_force[i]));
      if (b.gas >= 0) t.peak_gas_force = std::max(t.peak_gas_force, std::abs(e.train.gas_force[i]));
      if (causes_.seat_bouncing[i])
        t.max_seat_bounce_height =
            std::max(t.max_seat_bounce_height, e.train.position[i] - lift_step(train_, i).seat.value_or(0.0));
    }
  }

  /// The step [t0, t] judged at its midpoint `mid`: a link open there while
  /// no body from it on is seated counts as link separation.
  /// The first place the train lets go in the window is recorded.
  void fold_step(const Evaluation& mid, double duration) {
    if (!train_.present() || !(duration > 0.0)) return;
    if (mid.gap > 0.0 && !lash(mid) && floats(causes_.cam)) lets_go_at("cam contact", mid.theta);
    for (std::size_t i = 1; i < train_.bodies.size(); ++i) {
      const TrainElement& link = train_.elements[static_cast<std::size_t>(train_.bodies[i].link)];
      if (link.root < 0 || !(mid.train.gap[static_cast<std::size_t>(link.root)] > 0.0)) continue;
      if (train_.rests_on_seat(mid.train, static_cast<int>(i))) continue;
      link_open_time_ += duration;
      if (floats(causes_.link[i])) {
        link_float_time_ += duration;
        lets_go_at("link ", mid.theta, &train_.bodies[i].name);
      }
      return;
    }
  }

  /// Records the first place the train floats in the window, `where` (and
  /// the body's name after it) at cam angle θ [rad]: take-up and seat
  /// bounces are not where it lets go.
  void lets_go_at(const char* where, double theta, const std::string* body = nullptr) {
    if (!train_.present()) return;
    TrainMetrics& t = *m_.train;
    if (!t.separates_first.empty()) return;
    t.separates_first = where;
    if (body) t.separates_first += *body;
    t.separates_first_deg = std::fmod(theta * kRadToDeg, 360.0);
  }

  /// The metrics that are not extremes, over `evaluated` seconds.
  void finish(double evaluated) {
    if (!train_.present()) return;
    TrainMetrics& t = *m_.train;
    t.link_separation_fraction = evaluated > 0.0 ? link_open_time_ / evaluated : 0.0;
    t.link_float_fraction = evaluated > 0.0 ? link_float_time_ / evaluated : 0.0;
    t.min_link_force = std::isfinite(min_link_) ? min_link_ : 0.0;
  }

 private:
  const Model& model_;
  const FollowerTrain& train_;
  const SeparationCauses& causes_;
  Metrics& m_;
  double min_link_ = std::numeric_limits<double>::infinity();  // [N]
  double link_open_time_ = 0.0;                                // [s]
  double link_float_time_ = 0.0;                               // of it, in float [s]
};

}  // namespace camdyn
