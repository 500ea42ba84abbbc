#include "optim/optimize/kinematics.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/constants.h"

namespace camdyn::optim {

LawKinematics law_kinematics(const MotionLaw& law, const std::vector<SegmentConfig>& segments, int samples) {
  LawKinematics k;
  const auto& pieces = law.pieces();
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const MotionLaw::Piece& pc = pieces[i];
    if (!pc.shape) continue;  // a dwell
    const double beta = pc.shape_length();
    const ShapePeaks peaks =
        shape_peaks(*pc.shape, samples, pc.x_begin(), pc.x_end());  // of the normalised shape's derivatives
    const double f1 = peaks.d1, f2 = peaks.d2, f3 = peaks.d3;
    const double h = std::abs(pc.lift);
    k.peak_velocity = std::max(k.peak_velocity, h * f1 / beta);
    k.peak_acceleration = std::max(k.peak_acceleration, h * f2 / (beta * beta));
    k.peak_jerk = std::max(k.peak_jerk, h * f3 / (beta * beta * beta));
    if (i < segments.size() && segments.size() == pieces.size()) {
      k.segments.push_back({i, to_string(segments[i].type), pc.start * kRadToDeg, pc.end * kRadToDeg, h, f1, f2, f3});
    }
  }
  return k;
}

}  // namespace camdyn::optim
