// What a run observes of its follower train (docs/model.md §12): the
// smallest link force while its body is off its seat, the largest force at a
// spring's frame end, each body's largest lift error, and the time a link is
// open while no body from it on rests on its seat, folded in from the same
// samples as the window's other metrics (dynamics/window_observer.h). The
// seat impacts, seating speeds and coil clashes come from the run's events
// (dynamics/simulation.cc). Internal to dynamics/.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "dynamics/kinematic_lift.h"
#include "dynamics/metrics.h"
#include "dynamics/model.h"

namespace camdyn {

class TrainObserver {
 public:
  /// Starts the train's metrics in `m` (nothing for a model without a train).
  TrainObserver(const Model& model, Metrics& m) : model_(model), train_(model.train), m_(m) {
    if (!train_.present()) return;
    TrainMetrics t;
    for (const TrainBody& b : train_.bodies) {
      t.links = t.links || b.link >= 0;
      t.seats = t.seats || b.seat >= 0;
      t.springs = t.springs || b.spring_end >= 0;
      t.bodies.push_back(b.name);
    }
    t.springs = t.springs || model.forces.spring.present();
    t.clash = std::any_of(train_.elements.begin(), train_.elements.end(),
                          [](const TrainElement& e) { return e.role == TrainRole::clash; });
    t.max_lift_error.assign(train_.bodies.size(), 0.0);
    m_.train = std::move(t);
  }

  /// Whether the cam contact's gap is lash at `e`: some body rests on its seat.
  bool lash(const Evaluation& e) const { return train_.present() && train_.seated_from(e.train, 0); }

  /// Folds the train at the evaluation `e` (a time in the window) into the records.
  void fold(const Evaluation& e) {
    if (!train_.present()) return;
    TrainMetrics& t = *m_.train;
    const ReturnSpring& spring = model_.forces.spring;  // the follower's massless spring, where it has one
    if (spring.present()) t.peak_spring_force = std::max(t.peak_spring_force, std::abs(spring.force(e.y, e.v, 0.0)));
    double kinematic = model_.law->eval(e.theta).s;  // [m | rad]
    for (std::size_t i = 0; i < train_.bodies.size(); ++i) {
      const TrainBody& b = train_.bodies[i];
      kinematic = lift_step(train_, i).carry(kinematic);
      t.max_lift_error[i] = std::max(t.max_lift_error[i], std::abs(e.train.position[i] - kinematic));
      if (b.link >= 0 && !train_.seated_from(e.train, static_cast<int>(i)))
        min_link_ = std::min(min_link_, e.train.link_force[i]);
      if (b.spring_end >= 0) t.peak_spring_force = std::max(t.peak_spring_force, std::abs(e.train.spring_force[i]));
    }
  }

  /// The step [t0, t] judged at its midpoint `mid`: a link open there while
  /// no body from it on is seated counts as link separation.
  /// The first place the train lets go in the window is recorded.
  void fold_step(const Evaluation& mid, double duration) {
    if (!train_.present() || !(duration > 0.0)) return;
    TrainMetrics& t = *m_.train;
    constexpr double kDegPerRad = 180.0 / 3.14159265358979323846;
    if (t.separates_first.empty() && mid.gap > 0.0 && !lash(mid)) {
      t.separates_first = "cam contact";
      t.separates_first_deg = std::fmod(mid.theta * kDegPerRad, 360.0);
    }
    for (std::size_t i = 1; i < train_.bodies.size(); ++i) {
      const TrainElement& link = train_.elements[static_cast<std::size_t>(train_.bodies[i].link)];
      if (link.root < 0 || !(mid.train.gap[static_cast<std::size_t>(link.root)] > 0.0)) continue;
      if (train_.seated_from(mid.train, static_cast<int>(i))) continue;
      link_open_time_ += duration;
      if (t.separates_first.empty()) {
        t.separates_first = "link " + train_.bodies[i].name;
        t.separates_first_deg = std::fmod(mid.theta * kDegPerRad, 360.0);
      }
      return;
    }
  }

  /// The metrics that are not extremes, over `evaluated` seconds.
  void finish(double evaluated) {
    if (!train_.present()) return;
    TrainMetrics& t = *m_.train;
    t.link_separation_fraction = evaluated > 0.0 ? link_open_time_ / evaluated : 0.0;
    t.min_link_force = std::isfinite(min_link_) ? min_link_ : 0.0;
  }

 private:
  const Model& model_;
  const FollowerTrain& train_;
  Metrics& m_;
  double min_link_ = std::numeric_limits<double>::infinity();  // [N]
  double link_open_time_ = 0.0;                                // [s]
};

}  // namespace camdyn
