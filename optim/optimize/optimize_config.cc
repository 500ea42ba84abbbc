// The optimize study's own config fields, each listed once with its checks
// (io/json_archive.h); checks between fields use `require`.
#include "optim/optimize/optimize_config.h"

#include <cmath>
#include <string>

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
  a.field("separation", o.separation, non_negative());
  a.field("peak_contact_force", o.peak_contact_force, non_negative());
  a.field("contact_force_margin", o.contact_force_margin, non_negative());
  a.field("peak_acceleration", o.peak_acceleration, non_negative());
  a.field("peak_jerk", o.peak_jerk, non_negative());
  a.field("lift_area", o.lift_area, non_negative());
  a.field("aggregate", o.aggregate, one_of({"worst", "mean"}));
  const double total =
      o.separation + o.peak_contact_force + o.contact_force_margin + o.peak_acceleration + o.peak_jerk + o.lift_area;
  a.require(total > 0.0, "", "every weight is 0: give at least one term a positive weight");
}

template <class A>
void visit(A& a, ConstraintsConfig& c) {
  a.field("max_pressure_angle_deg", c.max_pressure_angle_deg, open_closed(0, 90));
  a.field("min_radius_of_curvature", c.min_radius_of_curvature, positive());
  a.field("max_peak_contact_force", c.max_peak_contact_force, positive());
  // A floor of 0 would hold while the follower separates (the smallest force is
  // then 0): use no_separation for that.
  a.field("min_contact_force", c.min_contact_force, positive());
  a.field("no_separation", c.no_separation);
  a.field("max_peak_jerk", c.max_peak_jerk, positive());
  a.field("max_contact_stress", c.max_contact_stress, positive());
  a.field("max_lift", c.max_lift, positive());
  a.field("face_edge_margin", c.face_edge_margin, non_negative());
  a.field("max_spring_force", c.max_spring_force, positive());
  a.field("max_seating_velocity", c.max_seating_velocity, positive());
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
  a.field("evaluation_cycles", o.evaluation_cycles, positive());
  a.field("evaluation_rtol", o.evaluation_rtol, open_closed(0, 0.1));
  a.field("evaluation_max_wall_time_s", o.evaluation_max_wall_time_s, positive());
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
  a.field("min_contact_force", r.min_contact_force, non_negative());
  a.field("speed_factor", r.speed_factor, at_least(1.0));
  a.field("explain_bound", r.explain_bound);
}

template <class A>
void visit(A& a, OptimizeStudyConfig& s) {
  a.field("design", s.design);
  a.field("operating_rpm", s.operating_rpm, non_empty(), positive());
  a.field("objective", s.objective);
  a.field("constraints", s.constraints);
  a.field("optimizer", s.optimizer);
  a.field("rigid", s.rigid);
}

OptimizeStudyConfig optimize_config_from_json(const Json& study_part, const ConfigSource& source) {
  OptimizeStudyConfig config;
  JsonReader reader(study_part, "", source);
  visit(reader, config);
  reader.finish();
  return config;
}

Json to_json(const OptimizeStudyConfig& config) { return JsonWriter::write(config); }

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
