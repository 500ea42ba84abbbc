#include "dynamics/window_observer.h"

#include <numbers>

#include "common/constants.h"
#include "dynamics/series_columns.h"

namespace camdyn {

namespace {

/// Calls f(name, value) for each train column of the evaluation, in order.
template <class F>
void for_each_train_column(const FollowerTrain& train, const TrainEvaluation& e, F&& f) {
  for (std::size_t i = 0; i < train.bodies.size(); ++i) {
    const TrainBody& b = train.bodies[i];
    if (i > 0) {
      f(train_column_name(b.name, TrainColumn::position), e.position[i]);
      f(train_column_name(b.name, TrainColumn::velocity), e.velocity[i]);
    }
    if (b.link >= 0) f(train_column_name(b.name, TrainColumn::link_force), e.link_force[i]);
    if (b.seat >= 0) f(train_column_name(b.name, TrainColumn::seat_force), e.seat_force[i]);
    if (b.stop >= 0) f(train_column_name(b.name, TrainColumn::stop_force), e.stop_force[i]);
    if (b.spring_end >= 0) f(train_column_name(b.name, TrainColumn::spring_force), e.spring_force[i]);
    if (b.gas >= 0) f(train_column_name(b.name, TrainColumn::gas_force), e.gas_force[i]);
  }
}

void push_train_row(const FollowerTrain& train, const TrainEvaluation& e, TimeSeries& series) {
  if (series.train_names.empty())
    for_each_train_column(train, e, [&](std::string name, double) { series.train_names.push_back(std::move(name)); });
  series.train.resize(series.train_names.size());
  std::size_t k = 0;
  for_each_train_column(train, e, [&](const std::string&, double value) { series.train[k++].push_back(value); });
}

}  // namespace

std::vector<std::string> series_column_names(const Model& model) {
  std::vector<std::string> names = TimeSeries::column_names();
  const TrainEvaluation none;
  if (model.train.present())
    for_each_train_column(model.train, none, [&](std::string name, double) { names.push_back(std::move(name)); });
  return names;
}

bool is_train_column_name(const std::string& name) { return train_column_of(name) != nullptr; }

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
  series.cam_torque.push_back(cam_drive_torque(ev));
  if (model.drive.shaft())
    series.motor_torque.push_back(model.drive.torque_motor() ? ev.drive.motor_torque : ev.drive.shaft_torque);
  if (model.hertz) series.contact_stress.push_back(contact_pressure(model, *model.hertz, ev));
  if (model.train.present()) push_train_row(model.train, ev.train, series);
}

}  // namespace camdyn
