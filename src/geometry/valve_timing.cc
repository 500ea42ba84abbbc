#include "geometry/valve_timing.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/constants.h"

namespace camdyn {

namespace {

constexpr int kGridSteps = 7200;     // 0.05° brackets: an excursion across a height narrower than this may be missed
constexpr int kMaxBisections = 200;  // more than enough to reach adjacent doubles
/// A law dwelling at full lift: grid points within this fraction of the lift of the maximum form a plateau [-].
constexpr double kPlateauFraction = 1e-12;
constexpr double kRampFraction = 0.5;  // a ramp rises less than half the event's lift

/// The grid the crossings are bracketed on: equal steps plus every piece boundary, in [0, 2π], both ends.
std::vector<double> bracket_grid(const MotionLaw& law) {
  std::vector<double> grid;
  grid.reserve(kGridSteps + law.pieces().size() + 1);
  for (int i = 0; i < kGridSteps; ++i) grid.push_back(kTwoPi * i / kGridSteps);
  for (const MotionLaw::Piece& piece : law.pieces())
    if (piece.start > 0.0 && piece.start < kTwoPi) grid.push_back(piece.start);
  std::sort(grid.begin(), grid.end());
  grid.erase(std::unique(grid.begin(), grid.end()), grid.end());
  grid.push_back(kTwoPi);
  return grid;
}

/// The angle in (lo, hi] where `predicate` changes from its value at lo, by
/// bisection down to adjacent doubles [rad].
template <class Predicate>
double bisect(double lo, double hi, Predicate predicate) {
  const bool at_lo = predicate(lo);
  for (int i = 0; i < kMaxBisections; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (predicate(mid) == at_lo ? lo : hi) = mid;
  }
  return hi;
}

/// The lift whose figures are taken: the law carried through `chain` (the
/// law itself for an empty chain), above `datum` [m].
struct Lift {
  const MotionLaw& law;
  const LiftChain& chain;
  double datum = 0.0;  // [m]

  double of_s(double s) const { return chain.at(s) - datum; }
  double operator()(double theta) const { return of_s(law.eval(theta).s); }
  /// d(lift)/dθ from the law's s and ds/dθ there [m/rad].
  double rate(double s, double ds) const { return chain.slope(s) * ds; }
};

double wrap(double theta) {
  double t = std::fmod(theta, kTwoPi);
  if (t < 0.0) t += kTwoPi;
  return t >= kTwoPi ? 0.0 : t;
}

CheckingHeightTiming timing_at(const Lift& lift, const std::vector<double>& grid, double height) {
  CheckingHeightTiming timing;
  timing.height = height;
  auto above = [&](double theta) { return lift(theta) >= height; };
  struct Crossing {
    double angle;
    bool up;
  };
  std::vector<Crossing> crossings;
  bool previous = above(grid.front());
  const bool first = previous;
  for (std::size_t i = 1; i < grid.size(); ++i) {
    const bool now = i + 1 == grid.size() ? first : above(grid[i]);  // 2π is θ = 0 again
    if (now != previous) crossings.push_back({bisect(grid[i - 1], grid[i], above), now});
    previous = now;
  }
  if (crossings.empty()) {
    if (first) {
      timing.intervals.push_back({0.0, kTwoPi});
      timing.duration = kTwoPi;
      timing.event = timing.intervals.front();
      timing.midpoint = std::numbers::pi;
    }
    return timing;
  }
  // Crossings alternate up and down; start from an up crossing, closing at the next down one (cyclically).
  const auto up = std::find_if(crossings.begin(), crossings.end(), [](const Crossing& c) { return c.up; });
  std::rotate(crossings.begin(), up, crossings.end());
  for (std::size_t i = 0; i + 1 < crossings.size(); i += 2) {
    const double opening = crossings[i].angle;
    double closing = crossings[i + 1].angle;
    if (closing <= opening) closing += kTwoPi;
    timing.intervals.push_back({wrap(opening), wrap(opening) + (closing - opening)});
    timing.duration += closing - opening;
  }
  timing.event = *std::max_element(timing.intervals.begin(), timing.intervals.end(), [](const auto& a, const auto& b) {
    return a.closing - a.opening < b.closing - b.opening;
  });
  timing.midpoint = wrap(0.5 * (timing.event->opening + timing.event->closing));
  return timing;
}

/// The cam angle of maximum lift, and the lift there: a plateau's middle, or the root of ds/dθ around the peak.
void find_lobe_centre(const Lift& lift, const std::vector<double>& grid, ValveTiming& timing) {
  const MotionLaw& law = lift.law;
  std::size_t best = 0;
  for (std::size_t i = 0; i + 1 < grid.size(); ++i)
    if (lift(grid[i]) > lift(grid[best])) best = i;
  const std::size_t n = grid.size() - 1;  // distinct grid points (grid[n] = 2π)
  const double peak = lift(grid[best]);
  const double scale = lift.of_s(law.max_s()) - lift.of_s(law.min_s());  // the lift's range [m]
  const double top_floor = peak - kPlateauFraction * std::max(scale, 1e-300);
  auto on_top = [&](double theta) { return lift(theta) >= top_floor; };
  auto at = [&](std::size_t i, int k) {  // grid point k steps from i, unwrapped [rad]
    const auto j = static_cast<long>(i) + k;
    const long m = static_cast<long>(n);
    const long wrapped = ((j % m) + m) % m;
    const long turns = (j - wrapped) / m;  // exact: j − wrapped is a multiple of m
    return grid[static_cast<std::size_t>(wrapped)] + kTwoPi * static_cast<double>(turns);
  };
  int left = 0, right = 0;
  while (left > -static_cast<int>(n) && on_top(at(best, left - 1))) --left;
  while (right < static_cast<int>(n) && on_top(at(best, right + 1))) ++right;
  timing.max_lift = peak;
  if (right - left >= static_cast<int>(n)) {  // no lobe at all: a circle
    timing.lobe_centre = 0.0;
    return;
  }
  if (right - left >= 2) {  // a dwell at full lift: its middle
    const double start = bisect(at(best, left - 1), at(best, left), on_top);
    const double end = bisect(at(best, right), at(best, right + 1), on_top);
    timing.lobe_centre = wrap(0.5 * (start + end));
    return;
  }
  const double lo = at(best, -1), hi = at(best, 1);
  const auto rising = [&](double theta) { return law.eval(theta).ds > 0.0; };
  double centre = grid[best];
  if (rising(lo) && !rising(hi)) centre = bisect(lo, hi, rising);
  timing.lobe_centre = wrap(centre);
  timing.max_lift = std::max(peak, lift(centre));
}

/// ds/dθ of a piece at its own normalised position x [m/rad] (a one-sided value at a piece boundary).
double piece_velocity(const MotionLaw::Piece& piece, double x) {
  return piece.shape ? piece.lift * piece.shape->eval(x).ds / piece.shape_length() : 0.0;
}

/// The ramp ends are the law's (its pieces); their height and velocity the lift's there.
void find_ramps_from_pieces(const Lift& lift, ValveTiming& timing) {
  const MotionLaw& law = lift.law;
  const auto& pieces = law.pieces();
  const std::size_t n = pieces.size();
  if (n < 3) return;
  auto rises = [&](std::size_t i) { return pieces[i % n].shape && pieces[i % n].lift > 0.0; };
  auto returns = [&](std::size_t i) { return pieces[i % n].shape && pieces[i % n].lift < 0.0; };
  const double ramp_limit = kRampFraction * law.lift();
  for (std::size_t i = 0; i < n; ++i) {
    const MotionLaw::Piece& piece = pieces[i];
    if (!timing.opening_ramp && rises(i) && !rises(i + n - 1) && rises(i + 1) && piece.lift < ramp_limit) {
      const double s = piece.base + piece.lift;  // [m]
      timing.opening_ramp = RampEnd{piece.end, lift.of_s(s), lift.rate(s, piece_velocity(piece, piece.x_end()))};
    }
    if (returns(i) && !returns(i + 1) && returns(i + n - 1) && -piece.lift < ramp_limit) {
      const double s = piece.base;  // [m]
      timing.closing_ramp = RampEnd{piece.start, lift.of_s(s), lift.rate(s, piece_velocity(piece, piece.x_begin()))};
    }
  }
}

}  // namespace

double lift_above_base(const MotionLaw& law, double theta) { return law.eval(theta).s - law.min_s(); }

ValveTiming valve_timing(const MotionLaw& law, std::span<const double> heights,
                         std::optional<std::pair<double, double>> ramp_end, const LiftChain& chain) {
  const std::vector<double> grid = bracket_grid(law);
  ValveTiming timing;
  timing.datum = chain.steps.empty() ? law.min_s() : chain.datum(law.min_s());
  const Lift lift{law, chain, timing.datum};
  find_lobe_centre(lift, grid, timing);
  for (const double height : heights) timing.heights.push_back(timing_at(lift, grid, height));
  if (ramp_end) {
    auto ramp_at = [&](double theta) {
      const double t = wrap(theta);
      const LawSample e = law.eval(t);
      return RampEnd{t, lift.of_s(e.s), lift.rate(e.s, e.ds)};
    };
    timing.opening_ramp = ramp_at(ramp_end->first);
    timing.closing_ramp = ramp_at(ramp_end->second);
  } else {
    find_ramps_from_pieces(lift, timing);
  }
  return timing;
}

}  // namespace camdyn
