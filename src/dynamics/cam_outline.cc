#include "dynamics/cam_outline.h"

#include <cassert>
#include <numbers>

#include "contact/profile_pair_tracking.h"

namespace camdyn {

CamOutline cam_outline(const Model& model, int points) {
  assert(points >= 3);
  const ClosedCurveProfile tracked(model.profile());
  const FollowerGeometry& fg = model.follower;
  // The tracked curve is at profile_offset from the circle's centre: the
  // contour lies ρ − profile_offset further in, the pitch curve profile_offset
  // further out (a flat face's tracked curve is the contour itself).
  const InwardOffsetProfile contour(tracked, fg.circle() ? fg.radius - model.profile_offset : 0.0);
  const InwardOffsetProfile pitch(tracked, -model.profile_offset);
  CamOutline outline;
  const auto n = static_cast<std::size_t>(points);
  outline.u.reserve(n);
  outline.contour_x.reserve(n);
  outline.contour_y.reserve(n);
  for (int k = 0; k < points; ++k) {
    const double u = 2.0 * std::numbers::pi * k / points;
    outline.u.push_back(u);
    const Eigen::Vector2d c = contour.at(u).r;
    outline.contour_x.push_back(c.x());
    outline.contour_y.push_back(c.y());
    if (fg.circle()) {
      const Eigen::Vector2d p = pitch.at(u).r;
      outline.pitch_x.push_back(p.x());
      outline.pitch_y.push_back(p.y());
    }
  }
  return outline;
}

}  // namespace camdyn
