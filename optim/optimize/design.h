// The design vector of an optimize study: the free interior control points of
// the spline segments that replace the baseline's designed rise / return
// segments (docs/config.md `motion_law` spline segments: the boundary control
// points that keep s, s', s'' continuous with the neighbours are added by the
// geometry code), plus optional segment end angles; or, with design.event,
// the free control points of one spline over a span of any baseline law
// (geometry/event_spline.h). Every variable has finite
// bounds, so NLopt's global algorithms can use them as they are.
//
// With `monotone` the control points of a segment are parametrised by
// "stick breaking": variable w_j ∈ [0, 1] moves control point j the share w_j
// of the way from the previous control point to the segment's top boundary
// level, c_j = c_{j−1} + w_j (c_hi − c_{j−1}). Any w in the box gives an
// ordered control polygon, hence (B-spline variation diminishing property) a
// monotone lift, with bounds alone and no extra constraint.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "io/config.h"
#include "optim/optimize/optimize_config.h"

namespace camdyn {
struct EventSplineBasis;
}

namespace camdyn::optim {

struct DesignVariable {
  std::string name;    ///< e.g. "segments[0].control_points[2]", "segments[0].end_deg"
  double lower = 0.0;  ///< bound (normalised: control points in lift units, angles as a share of their range)
  double upper = 1.0;
};

/// How closely the initial design (least-squares fit) reproduces the baseline law
/// (a type of its own: identify's FitQuality, optim/identify/fit_quality.h, is another).
struct BaselineFit {
  double max_lift_error = 0.0;          ///< max |f_fit − f_base| over designed segments, share of the lift [-]
  double max_acceleration_error = 0.0;  ///< max |f''_fit − f''_base| / max |f''_base| [-]
};

class DesignSpace {
 public:
  /// Throws InputError (naming `file` and `design.*` or the segment) when the
  /// baseline has no segment of a designed type, an end-angle range is
  /// inconsistent with its neighbours, or the baseline law cannot be built.
  DesignSpace(const SceneConfig& baseline, const DesignConfig& config, const std::string& file);

  int dimension() const { return static_cast<int>(variables_.size()); }
  const std::vector<DesignVariable>& variables() const { return variables_; }
  std::vector<double> lower() const;
  std::vector<double> upper() const;

  /// The design that reproduces the baseline as closely as the spline allows:
  /// control points fitted by least squares to the baseline law (value and
  /// its first two derivatives), end angles at their baseline values.
  const std::vector<double>& initial() const { return initial_; }
  const BaselineFit& fit_quality() const { return fit_; }

  /// The baseline scene with the designed segments replaced by the spline
  /// segments of design `x` (dimension() values within the bounds).
  SceneConfig scene(const std::vector<double>& x) const;

  /// Indices (into motion_law.segments) of the designed segments; for an
  /// event design, the index of the event's piece in the built law.
  std::vector<std::size_t> designed_segments() const;

  // An event design (design.event): one spline over [from, to] of any
  // baseline law (geometry/event_spline.h); its variables, and its raw
  // control points as well, are the free control points divided by the
  // baseline's lift event_scale() (the config holds them in metres).
  bool is_event() const { return event_ != nullptr; }
  /// The baseline's lift h [m] (is_event() only).
  double event_scale() const;
  /// The event's spline basis (is_event() only).
  const EventSplineBasis& event_basis() const;
  /// Index of the first free control point among the spline's coefficients
  /// (3 for a segment; the join order + 1 for an event), and their number.
  int free_offset() const;
  int spline_size() const;

  // The raw control points: the free control points c of every designed
  // segment (control_points per segment, in segment order; normalised lift),
  // with the end angles at their baseline values. The lift is affine in c,
  // which the rigid-model stage (optim/optimize/rigid_design.h) uses.

  int control_point_count() const { return config_.control_points * (event_ ? 1 : static_cast<int>(designed_.size())); }
  /// Levels (c_2, c_{n−3}) of each designed segment: with `monotone` its free
  /// control points lie ordered between them.
  std::vector<std::pair<double, double>> control_point_levels() const;
  /// The baseline with the designed segments' free control points set to c.
  SceneConfig scene_with_control_points(const std::vector<double>& c) const;
  /// The design vector of c; with `monotone` c must be ordered within the
  /// levels (it is clamped into the box otherwise).
  std::vector<double> design_from_control_points(const std::vector<double>& c) const;

 private:
  struct Designed {
    std::size_t index = 0;              ///< segment index
    int first_variable = 0;             ///< index of its first control-point variable
    int angle_variable = -1;            ///< index of its end-angle variable, or −1
    double end_lo = 0.0, end_hi = 0.0;  ///< end-angle range [deg]
  };
  /// Control-point levels c_2 and c_{n−3}: the free ones lie between them.
  struct Levels {
    double low = 0.0, high = 1.0;
  };

  /// The baseline with spline segments (control points all 0) and the end angles of `x`.
  SceneConfig skeleton(const std::vector<double>& x) const;
  std::vector<Levels> levels(const SceneConfig& skeleton) const;
  std::vector<double> control_points(const Designed& d, const Levels& lv, const std::vector<double>& x) const;

  // Construction steps, in the order the constructor takes them.
  /// designed_ from config_.segments; throws when the baseline lacks a designed type.
  void select_segments(const std::vector<SegmentConfig>& segs);
  /// End-angle ranges [deg] from config_.end_deg_range (one segment per type).
  void read_end_ranges(const std::vector<SegmentConfig>& segs);
  /// Each range lies strictly inside the neighbours' reach, so the segments
  /// keep their order for any value in the box.
  void check_end_ranges(const std::vector<SegmentConfig>& segs) const;
  /// Variables: per designed segment its control points, then its end angle.
  void number_variables();
  /// The boundary levels move with the end angles only where a designed
  /// segment meets a classic law that is moving (its rates scale with the
  /// segment length).
  bool levels_move_with_angles(const std::vector<SegmentConfig>& segs) const;
  /// Bounds of the control-point variables of `d`: [0, 1] when monotone,
  /// else its levels widened by half their span.
  void set_bounds(const Designed& d, const Levels& lv);
  /// The fitted control points c (lift units) of `d` into x as variables,
  /// clamped to the box.
  void set_initial_control_points(const Designed& d, const Levels& lv, const std::vector<double>& c,
                                  std::vector<double>& x) const;

  struct Event;
  /// The event design's construction (called by the constructor).
  void make_event(const SceneConfig& baseline);
  SceneConfig event_scene(const std::vector<double>& c) const;

  std::shared_ptr<const Event> event_;
  SceneConfig baseline_;
  DesignConfig config_;
  std::string file_;
  std::vector<Designed> designed_;
  std::vector<DesignVariable> variables_;
  std::vector<double> initial_;
  BaselineFit fit_;
  bool levels_vary_ = false;  ///< the boundary levels depend on the end angles
  std::vector<Levels> fixed_levels_;
};

}  // namespace camdyn::optim
