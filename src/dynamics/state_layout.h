// Where each state of a model lives in its state vector (the list is in
// model.h's header comment). The follower coordinate q and its rate are
// always first; every other state is a slot that a model has or has not, so
// that an absent state has no index to read by mistake.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <vector>

namespace camdyn {

/// One state's index in the state vector, if the model has that state.
class StateSlot {
 public:
  constexpr StateSlot() = default;
  constexpr explicit StateSlot(int index) : index_(index) {}
  /// Whether the model has this state.
  constexpr explicit operator bool() const { return index_ >= 0; }
  /// Its index; only for a state the model has.
  constexpr int operator*() const {
    assert(index_ >= 0 && "a state the model does not have");
    return index_;
  }

 private:
  int index_ = -1;
};

/// The states of one model, in order, with their names (summary.json `model`).
struct StateLayout {
  static constexpr int kCore = 9;        ///< the most states of the follower, the contact pair, the spin and the drive
  static constexpr int kMaxTrain = 112;  ///< the most states of a follower train (dynamics/follower_train.h)
  static constexpr int kMax = kCore + kMaxTrain;  ///< the most states any model has
  static constexpr int kQ = 0;                    ///< follower coordinate q [m | rad]
  static constexpr int kQDot = 1;                 ///< its rate q̇

  int size = 2;
  int core_size = 2;               ///< the states before the train's (the exact Jacobian's dual numbers cover these)
  StateSlot u;                     ///< contact pair parameter [rad] (differential tracking)
  StateSlot v;                     ///< follower profile parameter [rad | m] (general pair form, differential tracking)
  StateSlot spin;                  ///< roller spin Ω [rad/s]
  StateSlot cam_angle, cam_speed;  ///< θ_c [rad], ω_c [rad/s] (shaft drive)
  StateSlot motor_angle, motor_speed;  ///< θ_m [rad], ω_m [rad/s] (torque–speed motor)
  std::vector<std::string> names;      ///< one per state, in order

  /// The layout with q and q̇ only, named for the follower's coordinate.
  static StateLayout follower_only(bool oscillating) {
    StateLayout layout;
    layout.names = oscillating ? std::vector<std::string>{"arm_angle", "arm_angular_velocity"}
                               : std::vector<std::string>{"follower_position", "follower_velocity"};
    return layout;
  }
  /// Appends a state named `name`; returns its slot.
  StateSlot add(std::string name) {
    assert(size < kCore && size == core_size && "core states come before the train's");
    ++core_size;
    names.push_back(std::move(name));
    return StateSlot(size++);
  }
  /// Appends a train state (after every core state); returns its index.
  int add_train(std::string name) {
    assert(size < kMax);
    names.push_back(std::move(name));
    return size++;
  }
};

}  // namespace camdyn
