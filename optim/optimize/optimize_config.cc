// The optimize study's own config fields, each listed once with its checks
// (io/json_archive.h); checks between fields use `require`.
#include "optim/optimize/optimize_config.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/study_budget.h"
#include "io/json_archive.h"

namespace camdyn::optim {

const std::vector<std::string>& optimize_study_keys() {
  static const std::vector<std::string> keys = {"design",      "operating_rpm", "objective",
                                                "constraints", "optimizer",     "rigid"};
  return keys;
}

const std::vector<std::string>& optimize_algorithms() {
  static const std::vector<std::string> names = {"LN_COBYLA", "LN_BOBYQA", "LN_SBPLX",   "LD_SLSQP",
                                                 "LD_MMA",    "GN_ISRES",  "GN_CRS2_LM", "GN_DIRECT_L"};
  return names;
}

namespace {

/// An optional [lower, upper] pair of angles in (0, 360).
template <class A>
void range_field(A& a, std::string_view key, std::optional<std::vector<double>>& range) {
  a.field(key, range, open_closed(0, 360));
  if (range) {
    a.require(range->size() == 2 && (*range)[0] < (*range)[1], key,
              "expected [lower_deg, upper_deg] with lower < upper");
  }
}

}  // namespace

namespace {

// Memory the derived sizes ask for, estimated from above and held to
// --max-memory (common/study_budget.h) before anything is allocated.

/// Check speeds per operating speed the rigid stage may hold (a damped
/// follower's P ≥ P_min is checked at 16 speeds up to it, plus 0).
constexpr double kCheckSpeedsPerSpeed = 17.0;
/// Bytes per nonzero of a CLP programme: the triplet here, CLP's row and
/// column copies and its factorisation, each an index and a double.
constexpr double kLpBytesPerNonzero = 4.0 * (sizeof(double) + sizeof(int));
/// Nonzeros per row of the any-law programme (a three-point stencil and t).
constexpr double kGridNonzerosPerRow = 4.0;
/// Bytes an evaluation of the search keeps (its history row, journal
/// record and checkpoint entry), past its design vector [bytes].
constexpr double kBytesPerEvaluation = 4096.0;
/// The most operating speeds an optimize study may list.
constexpr std::size_t kMaxOperatingSpeeds = 100;

/// "rigid.samples": N would need about M MB ... : memory_budget_text().
std::string over_budget(const std::string& what, double bytes, const std::string& advice) {
  return what + " would need about " + format_shortest(std::ceil(bytes / kBytesPerMb)) +
         " MB in memory: " + memory_budget_text() + ": " + advice;
}

template <class A>
void require_sizes_in_memory_budget(A& a, const OptimizeStudyConfig& s) {
  const double budget = memory_budget_bytes();
  const double segments = s.design.event ? 1.0 : static_cast<double>(s.design.segments.size());
  const double speeds = std::max<double>(1.0, static_cast<double>(s.operating_rpm.size()));
  // The design programme: a dense row per sample, check speed and linear
  // constraint (pressure angle both ways, monotone, jerk both ways, lift).
  const double columns = s.design.control_points + 8.0;
  const double sample_rows = static_cast<double>(s.rigid.samples) * segments * (speeds * kCheckSpeedsPerSpeed + 6.0);
  const double sample_bytes = sample_rows * columns * kLpBytesPerNonzero;
  a.require(sample_bytes <= budget, "rigid.samples",
            over_budget(std::to_string(s.rigid.samples) + " samples per segment", sample_bytes,
                        "give fewer samples (the default is 121), or raise --max-memory"));
  // The any-law and lift-area programmes: a column and a row per grid point
  // and check speed of the top speed's sweep.
  const double grid_rows = (static_cast<double>(s.rigid.certificate_grid) + 1.0) * segments * kCheckSpeedsPerSpeed;
  const double grid_bytes = grid_rows * kGridNonzerosPerRow * kLpBytesPerNonzero;
  a.require(grid_bytes <= budget, "rigid.certificate_grid",
            over_budget("a certificate grid of " + std::to_string(s.rigid.certificate_grid) + " intervals", grid_bytes,
                        "give a coarser grid (the default is 300), or raise --max-memory"));
  const double evaluation_bytes =
      static_cast<double>(s.optimizer.max_evaluations) * (kBytesPerEvaluation + 2.0 * columns * segments * 8.0);
  a.require(evaluation_bytes <= budget, "optimizer.max_evaluations",
            over_budget(std::to_string(s.optimizer.max_evaluations) + " evaluations", evaluation_bytes,
                        "give fewer, or raise --max-memory"));
}

}  // namespace

template <class A>
void visit(A& a, EndAngleRanges& r) {
  range_field(a, "rise", r.rise);
  range_field(a, "return", r.ret);
}

template <class A>
void visit(A& a, LayoutConfig& l) {
  for (auto [key, range] :
       {std::pair{"base_radius", &l.base_radius}, std::pair{"offset", &l.offset}, std::pair{"pivot_x", &l.pivot_x},
        std::pair{"pivot_y", &l.pivot_y}, std::pair{"arm_length", &l.arm_length}}) {
    a.field(key, *range);
    if (*range)
      a.require((*range)->size() == 2 && (**range)[0] < (**range)[1], key,
                "expected [lower, upper] in metres with lower < upper");
  }
}

template <class A>
void visit(A& a, DesignEventConfig& e) {
  a.field("from_deg", e.from_deg, closed_open(0, 360));
  a.field("to_deg", e.to_deg, open_closed(0, 360));
  a.require(e.to_deg > e.from_deg, "to_deg", "must be greater than from_deg (an event does not wrap past 360 deg)");
}

template <class A>
void visit(A& a, DesignConfig& d) {
  a.field("segments", d.segments, non_empty(), one_of({"rise", "return"}));
  a.field("event", d.event);
  a.field("control_points", d.control_points, at_least(1));
  // Each is a design variable of the search and its rigid-stage LP: beyond
  // a few dozen the law gains nothing a cam can be cut to, and 2e9 of them
  // exhausted the memory before the search began.
  a.require(d.control_points <= kMaxDesignControlPoints, "control_points",
            "must be at most " + std::to_string(kMaxDesignControlPoints) + " per segment, got " +
                std::to_string(d.control_points));
  a.field("degree", d.degree, at_least(3));
  a.require(d.degree <= 9, "degree", "must be at most 9, got " + std::to_string(d.degree));
  a.require(d.control_points + 6 >= d.degree + 1, "control_points",
            "a degree-" + std::to_string(d.degree) + " spline needs at least " + std::to_string(d.degree - 5) +
                " free control points, got " + std::to_string(d.control_points));
  a.field("monotone", d.monotone);
  a.field("end_deg_range", d.end_deg_range);
  a.require(!d.event || (!d.end_deg_range.rise && !d.end_deg_range.ret), "end_deg_range",
            "an event design keeps its span fixed: leave end_deg_range out");
  a.field("spring", d.spring);
  a.field("layout", d.layout);
}

template <class A>
void visit(A& a, ObjectiveConfig& o) {
  // Each term is normalised (1 at the baseline), so only the weights' ratios
  // matter; outside [kMinObjectiveWeight, kMaxObjectiveWeight] the weighted
  // sum overflows to inf or a term underflows to nothing.
  for (auto [key, weight] :
       {std::pair{"separation", &o.separation}, std::pair{"peak_contact_force", &o.peak_contact_force},
        std::pair{"contact_force_margin", &o.contact_force_margin},
        std::pair{"peak_acceleration", &o.peak_acceleration}, std::pair{"peak_jerk", &o.peak_jerk},
        std::pair{"lift_area", &o.lift_area}}) {
    a.field(key, *weight, non_negative());
    a.require(*weight == 0.0 || (*weight >= kMinObjectiveWeight && *weight <= kMaxObjectiveWeight), key,
              "must be 0 or in [" + format_shortest(kMinObjectiveWeight) + ", " + format_shortest(kMaxObjectiveWeight) +
                  "] (the terms are normalised to 1 at the baseline: only the weights' ratios matter), got " +
                  format_shortest(*weight));
  }
  a.field("aggregate", o.aggregate, one_of({"worst", "mean"}));
  const double total =
      o.separation + o.peak_contact_force + o.contact_force_margin + o.peak_acceleration + o.peak_jerk + o.lift_area;
  a.require(total > 0.0, "", "every weight is 0: give at least one term a positive weight");
}

template <class A>
void visit(A& a, ConstraintsConfig& c) {
  // The upper ends are far past any cam (docs/optimize.md "Limits"): a value
  // beyond them is a slip whose products in the rigid stage's programme
  // overflow (CLP takes 1e30 for infinite).
  a.field("max_pressure_angle_deg", c.max_pressure_angle_deg, open_closed(0, 90));
  a.field("min_radius_of_curvature", c.min_radius_of_curvature, open_closed(0, kMaxLengthLimit));
  a.field("max_peak_contact_force", c.max_peak_contact_force, open_closed(0, kMaxForceLimit));
  // A floor of 0 would hold while the follower separates (the smallest force is
  // then 0): use no_separation for that.
  a.field("min_contact_force", c.min_contact_force, open_closed(0, kMaxForceLimit));
  a.field("no_separation", c.no_separation);
  a.field("max_peak_jerk", c.max_peak_jerk, open_closed(0, kMaxJerkLimit));
  a.field("max_contact_stress", c.max_contact_stress, open_closed(0, kMaxStressLimit));
  a.field("max_lift", c.max_lift, open_closed(0, kMaxLengthLimit));
  a.field("face_edge_margin", c.face_edge_margin, closed_open(0, kMaxLengthLimit));
  a.field("max_spring_force", c.max_spring_force, open_closed(0, kMaxForceLimit));
  a.field("max_seating_velocity", c.max_seating_velocity, open_closed(0, kMaxSeatingVelocityLimit));
  a.field("max_seat_bounce_height", c.max_seat_bounce_height, open_closed(0, kMaxLengthLimit));
  a.field("max_take_up_bounces", c.max_take_up_bounces, closed_open(0, kMaxTakeUpBouncesLimit));
}

template <class A>
void visit(A& a, OptimizerConfig& o) {
  a.field("algorithm", o.algorithm, one_of(optimize_algorithms()));
  a.field("max_evaluations", o.max_evaluations, at_least(1));
  a.field("xtol_rel", o.xtol_rel, non_negative());
  a.field("ftol_rel", o.ftol_rel, non_negative());
  a.field("max_time_s", o.max_time_s, positive());
  a.field("starts", o.starts, at_least(1));
  a.field("seed", o.seed, non_negative());
  a.field("initial_step", o.initial_step, open_closed(0, 1));
  a.field("gradient_step", o.gradient_step, open_closed(0, 0.1));
  a.field("evaluation_cycles", o.evaluation_cycles, open_closed(0, kMaxRevolutionsPerRun));
  a.field("evaluation_rtol", o.evaluation_rtol, open_closed(0, 0.1));
  a.field("evaluation_max_wall_time_s", o.evaluation_max_wall_time_s, positive());
  a.field("warm_start", o.warm_start);
  const bool global = o.algorithm.rfind("GN_", 0) == 0;
  a.require(!global || o.starts == 1, "starts",
            "multi-start is for local algorithms (LN_*, LD_*); a global algorithm runs once, got " +
                std::to_string(o.starts));
  a.require(o.max_evaluations >= o.starts, "max_evaluations",
            "must be at least the number of starts (" + std::to_string(o.starts) + ")");
}

template <class A>
void visit(A& a, RigidStageConfig& r) {
  a.field("enabled", r.enabled);
  a.field("samples", r.samples, at_least(11));
  a.field("certificate_grid", r.certificate_grid, at_least(50));
  a.field("min_contact_force", r.min_contact_force, closed_open(0, kMaxForceLimit));
  a.field("speed_factor", r.speed_factor, at_least(1.0));
  a.require(r.speed_factor <= kMaxSpeedFactor, "speed_factor",
            "must be at most " + format_shortest(kMaxSpeedFactor) + ", got " + format_shortest(r.speed_factor));
  a.field("explain_bound", r.explain_bound);
}

template <class A>
void visit(A& a, OptimizeStudyConfig& s) {
  a.field("design", s.design);
  a.field("operating_rpm", s.operating_rpm, non_empty(), at_least(kMinCamRpm), open_closed(0, kMaxCamRpm));
  // Each is simulated at every evaluation and checked by the rigid stage at
  // ten speeds: 5,000 of them kept `validate` busy for minutes.
  a.require(s.operating_rpm.size() <= kMaxOperatingSpeeds, "operating_rpm",
            "must list at most " + std::to_string(kMaxOperatingSpeeds) +
                " speeds (each is simulated at every "
                "evaluation), got " +
                std::to_string(s.operating_rpm.size()));
  a.field("objective", s.objective);
  a.field("constraints", s.constraints);
  a.field("optimizer", s.optimizer);
  a.field("rigid", s.rigid);
  require_sizes_in_memory_budget(a, s);
}

OptimizeStudyConfig optimize_config_from_json(const Json& study_part, const ConfigSource& source) {
  OptimizeStudyConfig config;
  JsonReader reader(study_part, "", source);
  visit(reader, config);
  reader.finish();
  return config;
}

Json to_json(const OptimizeStudyConfig& config) { return JsonWriter::write(config); }

SearchSettings search_settings(const OptimizerConfig& config) { return config; }  // its search part

void resolve_segment_groups(Json& study_part, const MotionLawConfig& baseline_law, const ConfigSource& source) {
  const auto design = study_part.find("design");
  if (design == study_part.end() || !design->is_object()) return;
  const auto segments = design->find("segments");
  if (segments == design->end() || !segments->is_array() || segments->empty() || !segments->front().is_array()) return;
  const std::string at = "design.segments";
  if (segments->size() != 1 || design->contains("event"))
    throw InputError(source.file, at, "give one group of segments to design as one curve (or design.event)");
  std::vector<std::string> group;
  for (const Json& t : segments->front()) {
    if (!t.is_string()) throw InputError(source.file, at + "[0]", "expected segment types, got " + describe_json(t));
    group.push_back(t.get<std::string>());
  }
  const std::vector<SegmentConfig>& segs = baseline_law.segments;
  if (segs.empty() || group.empty())
    throw InputError(source.file, at,
                     "a group of segments needs the baseline motion law as 'segments' (or give design.event)");
  for (std::size_t i = 0; i + group.size() <= segs.size(); ++i) {
    bool match = true;
    for (std::size_t k = 0; k < group.size() && match; ++k) match = to_string(segs[i + k].type) == group[k];
    if (!match) continue;
    (*design)["event"] =
        Json{{"from_deg", i == 0 ? 0.0 : segs[i - 1].end_deg}, {"to_deg", segs[i + group.size() - 1].end_deg}};
    design->erase("segments");
    return;
  }
  throw InputError(source.file, at, "the baseline motion law has no consecutive segments " + segments->front().dump());
}

}  // namespace camdyn::optim
