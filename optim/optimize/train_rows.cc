#include "optim/optimize/train_rows.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "common/constants.h"
#include "dynamics/model.h"

namespace camdyn::optim {

namespace {

using Kind = HeldQuantity::Kind;

constexpr int kFirstStride = 128;         ///< a programme starts with every 128th angle
constexpr int kCheckAngles = 4096;        ///< the dense check's grid
constexpr std::size_t kRunsPerRound = 4;  ///< rows activated per quantity and speed in one round
constexpr double kViolation = 1e-7;       ///< a row is broken by more than this share of the force scale

/// The signals of the response: law0, then each column, on the response grid.
std::vector<GridSignal> column_signals(const MotionLaw& law0, int columns,
                                       const std::function<void(double, std::vector<LawSample>&)>& column_lift,
                                       int angles) {
  std::vector<GridSignal> out;
  out.push_back(grid_signal([&](double theta) { return law0.eval(theta); }, angles));
  const int n = grid_signal_samples(angles);
  std::vector<std::vector<LawSample>> per_column(static_cast<std::size_t>(columns),
                                                 std::vector<LawSample>(static_cast<std::size_t>(n)));
  std::vector<LawSample> at;
  for (int i = 0; i < n; ++i) {
    column_lift(kTwoPi * i / n, at);
    for (int j = 0; j < columns; ++j) per_column[j][i] = at[static_cast<std::size_t>(j)];
  }
  for (const std::vector<LawSample>& samples : per_column) out.push_back(grid_signal_of_samples(samples, angles));
  return out;
}

/// Whether quantity q has rows under `limits`.
bool has_rows(const HeldQuantity& q, const TrainRowLimits& limits) {
  switch (q.kind) {
    case Kind::contact:
    case Kind::link:
      return true;
    case Kind::spring_end:
      return limits.max_spring_force.has_value();
    case Kind::seat_velocity:
      return limits.max_seating_velocity.has_value();
    case Kind::seat_position:
      return false;
  }
  return false;
}

}  // namespace

TrainRows::TrainRows(const Model& model, const MotionLaw& law0, int columns,
                     const std::function<void(double, std::vector<LawSample>&)>& column_lift, TrainRowLimits limits)
    : columns_(columns), limits_(limits) {
  // Only the quantities that have rows (and a seated body's position, which places its seating rows).
  HeldTrain held = held_train(model);
  std::vector<HeldQuantity> kept;
  for (const HeldQuantity& q : held.quantities)
    if (has_rows(q, limits_) || (q.kind == Kind::seat_position && limits_.max_seating_velocity)) kept.push_back(q);
  held.quantities = std::move(kept);
  response_ = std::make_shared<HeldTrainResponse>(std::move(held), column_signals(law0, columns, column_lift, kAngles),
                                                  kAngles, kTolerance);
  const HeldTrain& train = response_->train();
  active_.resize(train.quantities.size());
  first_.resize(train.quantities.size());
  const SpeedResponse& rest = at(0.0);
  scale_ = 1.0;
  for (std::size_t k = 0; k < train.quantities.size(); ++k) {
    const Kind kind = train.quantities[k].kind;
    if (kind == Kind::contact || kind == Kind::link)
      scale_ = std::max(scale_, (rest.fixed[k] + rest.per_signal[k].col(0)).cwiseAbs().maxCoeff());
    if (has_rows(train.quantities[k], limits_) && kind != Kind::seat_velocity)
      for (int i = 0; i < kAngles; i += kFirstStride) first_[k].insert(i);
  }
}

std::vector<double> TrainRows::check_speeds(double omega) {
  std::vector<double> out;
  for (int k = 1; k <= kSampledSpeeds; ++k) out.push_back(omega * k / kSampledSpeeds);
  return out;
}

const SpeedResponse& TrainRows::at(double omega) {
  const SpeedResponse& r = response_->at(omega);
  truncation_ = std::max(truncation_, r.truncation);
  harmonics_ = std::max(harmonics_, r.harmonics);
  return r;
}

double TrainRows::value(const SpeedResponse& r, std::size_t k, int i, const std::vector<double>& c) const {
  double v = r.fixed[k][i] + r.per_signal[k](i, 0);
  for (int j = 0; j < columns_; ++j) v += r.per_signal[k](i, j + 1) * c[static_cast<std::size_t>(j)];
  return v;
}

void TrainRows::add_rows(LinearProgram& lp, const std::vector<double>& omegas, int t) const {
  const HeldTrain& train = response_->train();
  std::vector<std::pair<int, double>> terms;
  const std::size_t top = static_cast<std::size_t>(std::max_element(omegas.begin(), omegas.end()) - omegas.begin());
  for (std::size_t n = 0; n < omegas.size(); ++n) {
    const SpeedResponse& r = response_->at(omegas[n]);
    for (std::size_t k = 0; k < train.quantities.size(); ++k) {
      const HeldQuantity& q = train.quantities[k];
      for (const int i : angles(k, n, n == top)) {
        terms.clear();
        for (int j = 0; j < columns_; ++j) terms.emplace_back(j, r.per_signal[k](i, j + 1));
        const double known = r.fixed[k][i] + r.per_signal[k](i, 0);
        if (q.held()) {
          if (t >= 0) terms.emplace_back(t, -1.0);
          const double floor = q.kind == Kind::contact ? limits_.contact_floor : limits_.link_floor;
          lp.add_row(terms, floor - known, kLpInfinity);
        } else if (q.kind == Kind::spring_end) {
          lp.add_row(terms, -kLpInfinity, *limits_.max_spring_force - known);
        } else if (q.kind == Kind::seat_velocity) {
          lp.add_row(terms, -*limits_.max_seating_velocity - known, *limits_.max_seating_velocity - known);
        }
      }
    }
  }
}

void TrainRows::add_peak_rows(LinearProgram& lp, double omega, int z) const {
  const SpeedResponse& r = response_->at(omega);
  std::vector<std::pair<int, double>> terms;
  for (const int i : angles(0, kPeakSlot, true)) {  // quantity 0: the cam contact
    terms.clear();
    for (int j = 0; j < columns_; ++j) terms.emplace_back(j, -r.per_signal[0](i, j + 1));
    terms.emplace_back(z, 1.0);
    lp.add_row(terms, r.fixed[0][i] + r.per_signal[0](i, 0), kLpInfinity);
  }
}

int TrainRows::activate_violated(const std::vector<double>& c, double t, const std::vector<double>& omegas) {
  const HeldTrain& train = response_->train();
  const std::size_t top = static_cast<std::size_t>(std::max_element(omegas.begin(), omegas.end()) - omegas.begin());
  int added = 0;
  for (std::size_t n = 0; n < omegas.size(); ++n) {
    const SpeedResponse& r = at(omegas[n]);
    for (std::size_t k = 0; k < train.quantities.size(); ++k) {
      const HeldQuantity& q = train.quantities[k];
      if (!has_rows(q, limits_)) continue;
      // How far each angle breaks its row (≤ 0: it holds), and the worst angle of each run of broken ones.
      auto excess = [&](int i) {
        const double v = value(r, k, i, c);
        if (q.held()) return (q.kind == Kind::contact ? limits_.contact_floor : limits_.link_floor) + t - v;
        if (q.kind == Kind::spring_end) return v - *limits_.max_spring_force;
        // Seating: only where the body crosses its seat on the way down (quantity k − 1 its position).
        const HeldQuantity& pos = train.quantities[k - 1];
        const int next = (i + 1) % kAngles;
        const bool crossing = value(r, k - 1, i, c) > pos.seat && value(r, k - 1, next, c) <= pos.seat;
        return crossing ? std::abs(v) - *limits_.max_seating_velocity : -kInf;
      };
      added += activate_runs(k, n, n == top, excess, q.kind == Kind::seat_velocity);
    }
  }
  return added;
}

const std::set<int>& TrainRows::angles(std::size_t k, std::size_t n, bool top) const {
  static const std::set<int> none;
  const auto it = active_[k].find(n);
  if (it != active_[k].end()) return it->second;
  return top ? first_[k] : none;
}

int TrainRows::activate_runs(std::size_t k, std::size_t n, bool top, const std::function<double(int)>& excess,
                             bool with_next) {
  const double tol = kViolation * scale_;
  const std::set<int>& now = angles(k, n, top);
  std::vector<std::pair<double, int>> runs;  // (excess, angle) of the worst angle of each run
  int worst = -1;
  double worst_excess = tol;
  for (int i = 0; i <= kAngles; ++i) {
    // An active angle's row is in the programme: the solution meets it (to
    // CLP's tolerance), and activating it again would change nothing.
    const double e = i < kAngles && !now.count(i) ? excess(i) : -kInf;
    if (e > worst_excess) {
      worst = i, worst_excess = e;
    } else if (e <= tol && worst >= 0) {  // the run ended
      runs.emplace_back(worst_excess, worst);
      worst = -1, worst_excess = tol;
    }
  }
  if (runs.empty()) return 0;
  // The worst few runs only: a design far from feasible breaks rows almost
  // everywhere, and most of those would never bind again.
  std::sort(runs.begin(), runs.end(), std::greater<>());
  if (runs.size() > kRunsPerRound) runs.resize(kRunsPerRound);
  std::set<int>& active = active_[k].try_emplace(n, top ? first_[k] : std::set<int>{}).first->second;
  int added = 0;
  for (const auto& [e, i] : runs) {
    added += active.insert(i).second ? 1 : 0;
    if (with_next) added += active.insert((i + 1) % kAngles).second ? 1 : 0;
  }
  return added;
}

int TrainRows::activate_peak(const std::vector<double>& c, double omega, double z) {
  const SpeedResponse& r = at(omega);
  return activate_runs(
      0, kPeakSlot, true, [&](int i) { return value(r, 0, i, c) - z; }, false);
}

double TrainRows::worst_margin(const std::vector<double>& c, const std::vector<double>& omegas) {
  const HeldTrain& train = response_->train();
  double least = kInf;
  for (const double w : omegas) {
    const SpeedResponse& r = at(w);
    for (std::size_t k = 0; k < train.quantities.size(); ++k) {
      const HeldQuantity& q = train.quantities[k];
      if (!q.held()) continue;
      const double floor = q.kind == Kind::contact ? limits_.contact_floor : limits_.link_floor;
      for (int i = 0; i < kAngles; ++i) least = std::min(least, value(r, k, i, c) - floor);
    }
  }
  return least;
}

HeldCheck check_held_train(const Model& model, const MotionLaw& law, double omega, const TrainRowLimits& limits) {
  const HeldTrain train = held_train(model);
  const GridSignal signal = grid_signal([&](double theta) { return law.eval(theta); }, kCheckAngles);
  const std::vector<Eigen::VectorXd> v = held_train_values(train, signal, omega);
  HeldCheck out;
  out.margin = kInf;
  for (std::size_t k = 0; k < train.quantities.size(); ++k) {
    const HeldQuantity& q = train.quantities[k];
    if (q.held()) {
      const double floor = q.kind == Kind::contact ? limits.contact_floor : limits.link_floor;
      Eigen::Index i = 0;
      const double m = v[k].minCoeff(&i) - floor;
      if (m < out.margin) {
        out.margin = m;
        out.binding = q.name;
        out.binding_angle_deg = 360.0 * static_cast<double>(i) / kCheckAngles;
      }
    } else if (q.kind == Kind::spring_end) {
      out.peak_spring_force = std::max(out.peak_spring_force, v[k].maxCoeff());
    } else if (q.kind == Kind::seat_velocity) {
      const Eigen::VectorXd& pos = v[k - 1];
      const double p = train.quantities[k - 1].seat;
      for (int i = 0; i < kCheckAngles; ++i)
        if (pos[i] > p && pos[(i + 1) % kCheckAngles] <= p)
          out.seating_velocity = std::max(out.seating_velocity, std::abs(v[k][i]));
    }
  }
  return out;
}

HeldCurves held_train_curves(const Model& model, double rpm) {
  constexpr int kCurveAngles = 1024;
  const HeldTrain train = held_train(model);
  const GridSignal signal = grid_signal([&](double theta) { return model.law->eval(theta); }, kCurveAngles);
  const std::vector<Eigen::VectorXd> v = held_train_values(train, signal, rpm * kTwoPi / 60.0);
  HeldCurves out;
  for (int i = 0; i <= kCurveAngles; ++i) out.angles_deg.push_back(360.0 * i / kCurveAngles);
  for (std::size_t k = 0; k < train.quantities.size(); ++k) {
    if (train.quantities[k].kind == Kind::seat_position) continue;
    out.quantities.push_back(train.quantities[k]);
    std::vector<double> curve(v[k].data(), v[k].data() + v[k].size());
    curve.push_back(curve.front());  // closes the revolution at 360°
    out.values.push_back(std::move(curve));
  }
  return out;
}

double held_jump_free_speed(const Model& model, const MotionLaw& law, const TrainRowLimits& limits, double omega_max) {
  const GridSignal signal = grid_signal([&](double theta) { return law.eval(theta); }, TrainRows::kAngles);
  return held_train_jump_speed(held_train(model), signal, omega_max, limits.contact_floor, limits.link_floor, 1e-5);
}

}  // namespace camdyn::optim
