// The follower motion law s(θ): displacement of the follower above its lowest
// position as a function of cam angle, periodic in 2π, with derivatives to
// third order (velocity, acceleration and jerk per unit cam speed). Built from
// piecewise segments (rise / dwell / return with the classic laws or a spline
// segment), a whole-cycle periodic spline, or a lift table (docs/model.md §1,
// docs/config.md `motion_law`).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace camdyn {

/// s and its derivatives with respect to cam angle at one θ.
struct LawSample {
  double s = 0.0;    ///< displacement [m] (or [rad] for an oscillating arm)
  double ds = 0.0;   ///< ds/dθ [m/rad]
  double d2s = 0.0;  ///< d²s/dθ² [m/rad²]
  double d3s = 0.0;  ///< d³s/dθ³ [m/rad³]
  double d4s = 0.0;  ///< d⁴s/dθ⁴ [m/rad⁴] (the flat-faced follower's cam contour needs it to third order)
};

/// A normalised rise f(x) on x ∈ [0, 1] with f(0) = 0, f(1) = 1; derivatives in x.
class NormalisedRise {
 public:
  virtual ~NormalisedRise() = default;
  virtual LawSample eval(double x) const = 0;
};

/// Immutable, periodic motion law. Cheap to evaluate (no allocation); safe to
/// share between threads.
class MotionLaw {
 public:
  /// Evaluates at any real θ [rad]; θ is reduced modulo 2π.
  LawSample eval(double theta) const;

  /// Total lift (max s − min s) [m].
  double lift() const { return max_s_ - min_s_; }

  /// Lowest and highest s over the cycle [m] (sampled densely, exact at piece
  /// ends). Laws built from segments have min_s() = 0.
  double min_s() const { return min_s_; }
  double max_s() const { return max_s_; }

  /// One piece of the law: θ ∈ [start, end) [rad], s = base + sign·lift·f((θ − start)/(end − start)).
  /// A whole-cycle spline or table law is one piece [0, 2π) with base 0 and
  /// lift 1 whose shape returns s itself [m] (it is not a normalised rise).
  struct Piece {
    double start = 0.0, end = 0.0;                ///< [rad]
    double base = 0.0;                            ///< s at the piece start [m]
    double lift = 0.0;                            ///< signed lift over the piece [m] (0 for a dwell)
    std::shared_ptr<const NormalisedRise> shape;  ///< null for a dwell
    /// A piece cut out of a longer one (the parts of a law kept around a
    /// spliced event, geometry/event_spline.h) evaluates its shape over the
    /// longer one's range [origin, origin + length), with the same arithmetic,
    /// so the values are bit for bit those of the law it was cut from.
    /// length 0: the range is [start, end).
    double origin = 0.0, length = 0.0;  ///< [rad]

    /// The shape's angle range: origin and length as evaluated [rad].
    double shape_origin() const { return length > 0.0 ? origin : start; }
    double shape_length() const { return length > 0.0 ? length : end - start; }
    /// The part [x_begin, x_end] ⊆ [0, 1] of the normalised shape the piece uses.
    double x_begin() const { return (start - shape_origin()) / shape_length(); }
    double x_end() const { return (end - shape_origin()) / shape_length(); }
  };

  /// A law made of pieces that cover [0, 2π) in order.
  explicit MotionLaw(std::vector<Piece> pieces);

  const std::vector<Piece>& pieces() const { return pieces_; }

 private:
  std::vector<Piece> pieces_;
  double min_s_ = 0.0, max_s_ = 0.0;
};

/// Peaks of |f'|, |f''|, |f'''| of a normalised shape, sampled at `samples` + 1
/// points of [x0, x1] (both ends included; a piece's x_begin() … x_end()).
struct ShapePeaks {
  double d1 = 0.0, d2 = 0.0, d3 = 0.0;
};
ShapePeaks shape_peaks(const NormalisedRise& shape, int samples, double x0 = 0.0, double x1 = 1.0);

/// Peaks of |s'| [m/rad], |s''| [m/rad²] and |s'''| [m/rad³] over the cycle:
/// every piece's shape_peaks scaled by its lift and length, so a jump at a
/// piece boundary counts on both sides. Dwells contribute 0.
struct LawPeaks {
  double velocity = 0.0, acceleration = 0.0, jerk = 0.0;
};
LawPeaks law_peaks(const MotionLaw& law, int samples = 4000);

/// Builds the law from config. `path` is the dotted path of the motion_law
/// object and `file` the config file, both for InputError messages: segments
/// not covering 360°, lift mismatch between rises and returns, bad spline
/// data, a table whose rows (read by the loader) make no law, etc.
MotionLaw build_motion_law(const MotionLawConfig& config, const std::string& file,
                           const std::string& path = "mechanism.cam.motion_law");

/// The classic normalised rise laws (cycloidal, polynomial_345,
/// polynomial_4567, harmonic, modified_trapezoid, modified_sine).
/// Returns null for a law that is not one of them (none, spline).
std::shared_ptr<const NormalisedRise> classic_rise(SegmentLaw law);

/// The laws classic_rise() makes, for error messages and parameterised tests.
const std::vector<SegmentLaw>& classic_rise_laws();

}  // namespace camdyn
