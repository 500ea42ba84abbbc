// Follower kinematics (docs/model.md §5, docs/config.md `mechanism.follower`): one
// generalised coordinate q and the world pose of the follower's contact
// element as a function of q.
//
// World frame = cam frame at cam angle 0; the cam turns about the origin.
//  * translating: q = y [m], the follower moves along +y on the line x = e.
//    Circle (roller, mushroom of radius ρ): centre c = (e, y₀ + q),
//    y₀ = √((r_b + ρ)² − e²). Flat face: the line y = r_b + q, its normal
//    m = (0, −1) pointing from the face towards the cam.
//  * oscillating: q = φ [rad], the arm's rotation away from its lowest
//    position; the arm turns about the pivot A, its angle is ψ = ψ₀ + κ q with
//    κ = ±1 chosen so that q > 0 moves the follower away from the cam.
//    Circle: centre c = A + L (cos ψ, sin ψ) (L = arm_length) at distance
//    r_b + ρ from the cam centre at q = 0. Flat face: a line through the pivot
//    with direction d = (cos ψ, sin ψ), tangent to the base circle at q = 0;
//    the face's centre is at distance L from the pivot along d.
//    Of the two lowest positions that satisfy this, the one with the higher
//    contact point (larger y) is used.
// All functions are templates over the scalar (double or dual numbers).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <string>

#include "geometry/vec2.h"
#include "scene/follower_shape.h"
#include "scene/scene.h"

namespace camdyn {

struct FollowerGeometry {
  FollowerMotion motion = FollowerMotion::translating;
  FollowerShape shape = FollowerShape::roller;
  double base_radius = 0.0;                         ///< r_b [m]
  double radius = 0.0;                              ///< ρ: roller / mushroom radius [m] (0 for flat)
  double face_width = 0.0;                          ///< flat face width [m] (0 otherwise)
  double offset = 0.0;                              ///< e [m], translating
  Eigen::Vector2d pivot = Eigen::Vector2d::Zero();  ///< A [m], oscillating
  double arm_length = 0.0;                          ///< L [m], oscillating
  // Derived by make_follower_geometry:
  double y0 = 0.0;    ///< translating: circle centre height (circle) or face height r_b (flat) at q = 0 [m]
  double psi0 = 0.0;  ///< oscillating: arm (circle) or face (flat) direction angle at q = 0 [rad]
  int kappa = 1;      ///< oscillating: ψ = ψ₀ + κ q
  int face_side = 1;  ///< oscillating flat: m = face_side · J d

  /// The shape's description (follower_shape.h).
  constexpr FollowerShapeTraits traits() const { return follower_shape_traits(shape); }
  /// Touches the cam with a circle of radius ρ (else with a flat face's line).
  bool circle() const { return traits().circle(); }
  /// Spins on an axle (a roller): friction acts at the axle and on a spin state.
  bool rolls() const { return traits().rolls; }
  bool oscillating() const { return motion == FollowerMotion::oscillating; }

  /// Circle centre c(q) and dc/dq in the world.
  template <class S>
  void centre(const S& q, Vec2<S>& c, Vec2<S>& c_q) const {
    using std::cos;
    using std::sin;
    if (!oscillating()) {
      c = Vec2<S>(S(offset), S(y0) + q);
      c_q = Vec2<S>(S(0.0), S(1.0));
      return;
    }
    const S psi = psi0 + kappa * q;
    const Vec2<S> u(cos(psi), sin(psi));
    c = Vec2<S>(pivot) + arm_length * u;
    c_q = (kappa * arm_length) * perp(u);
  }

  /// Flat face: a point p(q) of the face line and its unit normal m(q)
  /// (pointing from the face towards the cam), with their q-derivatives.
  template <class S>
  void face(const S& q, Vec2<S>& p, Vec2<S>& m, Vec2<S>& p_q, Vec2<S>& m_q) const {
    using std::cos;
    using std::sin;
    if (!oscillating()) {
      p = Vec2<S>(S(offset), S(y0) + q);
      m = Vec2<S>(S(0.0), S(-1.0));
      p_q = Vec2<S>(S(0.0), S(1.0));
      m_q = Vec2<S>(S(0.0), S(0.0));
      return;
    }
    const S psi = psi0 + kappa * q;
    const Vec2<S> d(cos(psi), sin(psi));
    p = Vec2<S>(pivot);
    m = static_cast<double>(face_side) * perp(d);
    p_q = Vec2<S>(S(0.0), S(0.0));
    m_q = static_cast<double>(-kappa * face_side) * d;  // d(J d)/dψ = J J d = −d
  }

  /// dX/dq of a point X (world) fixed to the follower body.
  template <class S>
  Vec2<S> body_point_rate(const Vec2<S>& X) const {
    if (!oscillating()) return Vec2<S>(S(0.0), S(1.0));
    return static_cast<double>(kappa) * perp(X - Vec2<S>(pivot));
  }

  /// Reference point and unit direction across the follower face, for the
  /// reported contact offset (X − origin)·dir: translating: (e, ·) and +x;
  /// oscillating flat: the face centre A + L d and d; oscillating circle: the
  /// circle centre and the direction J u across the arm.
  template <class S>
  void face_frame(const S& q, Vec2<S>& origin, Vec2<S>& dir) const {
    using std::cos;
    using std::sin;
    if (!oscillating()) {
      origin = Vec2<S>(S(offset), S(0.0));
      dir = Vec2<S>(S(1.0), S(0.0));
      return;
    }
    const S psi = psi0 + kappa * q;
    const Vec2<S> u(cos(psi), sin(psi));
    if (circle()) {
      origin = Vec2<S>(pivot) + arm_length * u;
      dir = perp(u);
    } else {
      origin = Vec2<S>(pivot) + arm_length * u;
      dir = u;
    }
  }
};

/// Builds and checks the follower geometry of a scene. Throws InputError
/// (`file`, dotted path under `path`, reason) when the lowest position does
/// not exist (offset too large, arm too short or too long, pivot inside the
/// base circle) or the arm cannot lift the follower (arm radial to the cam).
FollowerGeometry make_follower_geometry(const FollowerConfig& config, double base_radius, const std::string& file,
                                        const std::string& path = "mechanism.follower");

}  // namespace camdyn
