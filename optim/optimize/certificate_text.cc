#include "optim/optimize/certificate_text.h"

#include <cmath>
#include <vector>

#include "output/report.h"

namespace camdyn::optim {

std::string any_law_text(const Certificate& c) {
  if (!c.any_law_unavailable.empty()) return "any law: " + c.any_law_unavailable;
  if (std::isinf(c.any_law_rpm)) return "any law: no limit found (" + c.any_law_binding + ")";
  return "any law " + format_number(c.any_law_rpm, 5) + " rpm (set by " + c.any_law_binding + ")";
}

std::string any_law_convergence_text(const Certificate& c) {
  if (c.model != "held train" || !c.any_law_unavailable.empty()) return "";
  return "any law on the held train: a 16-point cubic spline per segment; with 8 points " +
         format_number(c.any_law_coarse_rpm, 5) + " rpm; up to " + std::to_string(c.train_harmonics) +
         " harmonics, truncation " + format_number(c.train_truncation, 2) + " of the largest force";
}

std::string family_binding_text(const Certificate& c) {
  const std::string binding = c.binding_text();
  return binding.empty() || !std::isfinite(c.family_rpm) ? "" : " (held by " + binding + ")";
}

std::string family_text(const Certificate& c) {
  if (std::isnan(c.family_rpm)) return "not computed (" + c.binding_text() + ")";
  if (std::isinf(c.family_rpm)) return "no limit found";
  return format_number(c.family_rpm, 5) + " rpm" + family_binding_text(c);
}

std::string jump_free_model_text(const Certificate& c) {
  const bool train = c.model == "held train";
  return std::string(train ? "held train, contact and link forces" : "rigid model, contact force") +
         " >= " + format_number(c.min_contact_force) + " " + c.margin_unit;
}

std::string jump_free_text(const OptimizeOutcome& o) {
  const Certificate& c = o.rigid.certificate;
  if (!c.available) return "";
  std::string text = "baseline " + format_number(c.baseline_rpm, 5) + " rpm";
  if (o.rigid.design.have) text += ", rigid design " + format_number(o.rigid.design.jump_free_rpm, 5) + " rpm";
  if (std::isfinite(o.answer_jump_free_rpm) || std::isinf(o.answer_jump_free_rpm))
    text += ", answer (" + std::string(to_string(o.selection.choice.chosen)) + ") " +
            format_number(o.answer_jump_free_rpm, 5) + " rpm";
  return text;
}

std::string speed_text(const OptimizeOutcome& o, std::size_t i) {
  const Certificate& c = o.rigid.certificate;
  const SpeedCertificate& s = c.speeds[i];
  const std::string held = family_binding_text(c);
  if (!s.feasible && !std::isfinite(s.best_margin))
    return "INFEASIBLE, no design of the family meets the linear constraints" + held;
  if (!s.feasible && !std::isfinite(c.family_rpm))
    return "INFEASIBLE (best rigid margin " + format_number(s.best_margin, 4) + " " + c.margin_unit + ")";
  if (!s.feasible) {
    const std::string any = c.any_law_unavailable.empty() ? "; " + any_law_text(c) : "";
    return "INFEASIBLE, above the family's bound " + format_number(c.family_rpm, 5) + " rpm" + any + held;
  }
  std::string text =
      "feasible for the family (best rigid margin " + format_number(s.best_margin, 4) + " " + c.margin_unit + ")";
  const RigidDesign& d = o.rigid.design;
  if (!d.have) return text + "; the stage made no design";
  const double margin = i < d.verified_margin.size() ? d.verified_margin[i] : std::nan("");
  if (design_holds(d, i) && d.jump_free_rpm >= s.rpm)
    return text + "; the rigid design holds it (margin " + format_number(margin, 4) + " " + c.margin_unit + ")";
  // A train's response has resonances: a design can keep P >= P_min at a
  // speed and lose it at a lower one (its jump-free figure is the first).
  if (design_holds(d, i))
    return text + "; the rigid design holds it at this speed (margin " + format_number(margin, 4) + " " +
           c.margin_unit + ") but not at every speed below: it is jump-free to " + format_number(d.jump_free_rpm, 5) +
           " rpm";
  return text + "; the rigid design does NOT (margin " + format_number(margin, 4) + " " + c.margin_unit +
         " on the dense check): it is jump-free to " + format_number(d.jump_free_rpm, 5) + " rpm only";
}

std::string lift_given_up(const OptimizeStudyConfig& config, const DesignEvaluation& baseline,
                          const DesignEvaluation& chosen, CandidateKind kind) {
  if (!config.design.event || config.objective.lift_area > 0.0 || kind == CandidateKind::baseline) return "";
  if (!chosen.valid || !baseline.valid || baseline.highest_lift <= 0.0 || baseline.lift_area <= 0.0) return "";
  const double lift_share = chosen.highest_lift / baseline.highest_lift;
  const double area_share = chosen.lift_area / baseline.lift_area;
  if (lift_share >= kLiftKeptShare && area_share >= kLiftKeptShare) return "";
  return "its highest lift over the event is " + format_number(1e3 * chosen.highest_lift, 4) + " mm against the " +
         "baseline's " + format_number(1e3 * baseline.highest_lift, 4) + " mm (lift area " +
         format_number(100.0 * area_share, 3) + " % of the baseline's): with the nose free and no " +
         "objective.lift_area, it bought its speed with lift nothing in the study keeps; give " +
         "objective.lift_area a weight";
}

}  // namespace camdyn::optim
