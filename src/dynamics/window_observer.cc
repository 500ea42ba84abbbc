#include "dynamics/window_observer.h"

#include <numbers>

namespace camdyn {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;

}  // namespace

void push_row(const Model& model, const Evaluation& ev, TimeSeries& series, double t) {
  series.time.push_back(t);
  series.cam_angle_deg.push_back(ev.theta * kRadToDeg);
  series.follower_position.push_back(ev.y);
  series.follower_velocity.push_back(ev.v);
  series.follower_acceleration.push_back(ev.acceleration);
  series.kinematic_position.push_back(model.law->eval(ev.theta).s);
  series.gap.push_back(ev.gap);
  series.contact_force.push_back(ev.normal_force);
  series.friction_force.push_back(ev.friction_force);
  series.contact_offset.push_back(ev.contact_offset);
  series.cam_speed_rpm.push_back(ev.cam_speed * 60.0 / kTwoPi);
}

}  // namespace camdyn
