// The optimiser's words agree with each other (docs/optimize.md "The
// certificate"): one "jump-free to" figure per design, the same wherever it
// is printed; "any law" is a figure or the reason it is not computed, never
// "inf" beside a figure; an operating speed the family keeps but the stage's
// design does not says so; the lift-area certificate is computed or names
// what blocks it; the seat's constraints need a seat.
#include "optim/optimize/certificate_text.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "common/errors.h"
#include "io/config.h"
#include "optim/optimize/design.h"
#include "optim/optimize/objectives.h"
#include "optim/optimize/optimize.h"
#include "optim/optimize/rigid_design.h"
#include "optim/simulation_pool.h"
#include "output/report.h"

namespace camdyn::optim {
namespace {

const std::string kDohcStudy = std::string(CAMDYN_SOURCE_DIR) + "/studies/valvetrain/optimize_dohc_lash.json";
const std::string kJumpStudy = std::string(CAMDYN_SOURCE_DIR) + "/studies/optimize_jump.json";

OptimizeStudy study_from(const std::string& path, const std::vector<std::string>& overrides = {}) {
  return read_optimize_study(load_config_json(path, overrides),
                             ConfigSource{path, std::filesystem::path(path).parent_path()});
}

// An event design on the DOHC lash train: (a) is not computed, and no text
// shows a figure for it ("inf" beside the coarse "0" was the old wording);
// the baseline's and the design's jump-free figures are stage_jump_free_rpm's.
TEST(CertificateText, AnEventDesignOnATrainHasOneJumpFreeFigureAndNoInfiniteAnyLaw) {
  const OptimizeStudy study = study_from(kDohcStudy);
  const DesignSpace space(study.baseline, study.config.design, kDohcStudy);
  OptimizeOutcome o;
  o.config = study.config;
  o.rigid = run_rigid_stage(study.baseline, study.config, space, kDohcStudy);
  const Certificate& c = o.rigid.certificate;
  ASSERT_TRUE(c.available);
  ASSERT_TRUE(o.rigid.design.have);
  EXPECT_EQ(c.model, "held train");
  EXPECT_FALSE(c.any_law_unavailable.empty());
  EXPECT_TRUE(std::isnan(c.any_law_rpm));
  EXPECT_TRUE(std::isnan(c.any_law_coarse_rpm));
  const std::string any = any_law_text(c);
  EXPECT_NE(any.find("not computed"), std::string::npos) << any;
  EXPECT_EQ(any.find("inf"), std::string::npos) << any;
  EXPECT_EQ(any_law_convergence_text(c), "");  // no "with 8 points 0 rpm"

  // One figure: the certificate's baseline and the design's own equal the
  // function that also gives the answer's.
  EXPECT_EQ(stage_jump_free_rpm(study.baseline, study.config, kDohcStudy), c.baseline_rpm);
  EXPECT_EQ(stage_jump_free_rpm(space.scene(o.rigid.design.x), study.config, kDohcStudy), o.rigid.design.jump_free_rpm);
  o.answer_jump_free_rpm = o.rigid.design.jump_free_rpm;
  const std::string line = jump_free_text(o);
  EXPECT_NE(line.find("baseline " + format_number(c.baseline_rpm, 5) + " rpm"), std::string::npos) << line;
  EXPECT_NE(line.find("rigid design " + format_number(o.rigid.design.jump_free_rpm, 5) + " rpm"), std::string::npos)
      << line;
  EXPECT_NE(jump_free_model_text(c).find("held train"), std::string::npos);

  // Each operating speed: "feasible" promises the design holds it, or says it does not.
  for (std::size_t i = 0; i < c.speeds.size(); ++i) {
    const std::string text = speed_text(o, i);
    if (!c.speeds[i].feasible) continue;
    const bool holds = design_holds(o.rigid.design, i);
    EXPECT_EQ(holds, text.find("the rigid design holds it") != std::string::npos) << text;
    EXPECT_EQ(!holds, text.find("does NOT") != std::string::npos) << text;
    // A design that holds a speed is jump-free at least to it on the same
    // model, or the words say it is not at every speed below (a resonance).
    if (holds && o.rigid.design.jump_free_rpm < c.speeds[i].rpm) {
      EXPECT_NE(
          text.find("not at every speed below: it is jump-free to " + format_number(o.rigid.design.jump_free_rpm, 5)),
          std::string::npos)
          << text;
    }
  }
}

// A speed the family keeps and the stage's design does not: the words say the
// design falls short, with its one jump-free figure.
TEST(CertificateText, AFeasibleSpeedTheDesignMissesIsSaid) {
  OptimizeOutcome o;
  Certificate& c = o.rigid.certificate;
  c.available = true;
  c.speeds = {{3500.0, true, 12.0}};
  o.rigid.design.have = true;
  o.rigid.design.verified_margin = {-3.0};
  o.rigid.design.jump_free_rpm = 3284.8;
  const std::string text = speed_text(o, 0);
  EXPECT_NE(text.find("feasible for the family"), std::string::npos) << text;
  EXPECT_NE(text.find("does NOT"), std::string::npos) << text;
  EXPECT_NE(text.find("3284.8"), std::string::npos) << text;
  o.rigid.design.verified_margin = {4.0};
  EXPECT_NE(speed_text(o, 0).find("holds it"), std::string::npos);
}

// (a) without a limit below the bracket says so instead of "inf rpm".
TEST(CertificateText, AnUnboundedAnyLawIsWordsNotInf) {
  Certificate c;
  c.any_law_rpm = std::numeric_limits<double>::infinity();
  c.any_law_binding = "segments[0]";
  const std::string text = any_law_text(c);
  EXPECT_NE(text.find("no limit found"), std::string::npos) << text;
  EXPECT_EQ(text.find("inf"), std::string::npos) << text;
  c.any_law_rpm = 2015.0;
  EXPECT_EQ(any_law_text(c), "any law 2015 rpm (set by segments[0])");
}

// On a train the lift-area bound (a one-mass rigid model's) is not computed,
// and the reason says why: never a follower-alone figure on a train.
TEST(CertificateText, TheLiftAreaCertificateOnATrainIsExplained) {
  const OptimizeStudy study = study_from(kDohcStudy, {"objective={\"lift_area\": 1.0}"});
  const DesignSpace space(study.baseline, study.config.design, kDohcStudy);
  const RigidStageResult r = run_rigid_stage(study.baseline, study.config, space, kDohcStudy);
  EXPECT_FALSE(r.certificate.lift_area.available);
  EXPECT_NE(r.certificate.lift_area.reason.find("not computed on a train"), std::string::npos)
      << r.certificate.lift_area.reason;
}

// A lift-area bound that no lift meets names the constraint that blocks it:
// 5 kN of contact force that a 250 N spring cannot give even at rest leaves
// no lift, and without that floor alone one exists.
TEST(CertificateText, AnInfeasibleLiftAreaBoundNamesItsBlocker) {
  const std::string valve = std::string(CAMDYN_SOURCE_DIR) + "/studies/optimize_valve_lobe.json";
  const OptimizeStudy study = study_from(valve, {"rigid.min_contact_force=5000"});
  const DesignSpace space(study.baseline, study.config.design, valve);
  const RigidStageResult r = run_rigid_stage(study.baseline, study.config, space, valve);
  const LiftAreaCertificate& a = r.certificate.lift_area;
  ASSERT_FALSE(a.available);
  EXPECT_NE(a.reason.find("blocked by the contact-force floor"), std::string::npos) << a.reason;
}

// An event design frees the nose: an answer that buys its speed by giving
// the lift up (the DOHC search once returned 0.92 mm of a 9.36 mm lobe) is
// no green answer unless the study keeps the lift (objective.lift_area).
// The baseline's highest lift is the profile's: 9.3616 mm at its nose knot.
TEST(CertificateText, AnAnswerThatGivesTheLiftUpIsNoGreenAnswer) {
  const OptimizeStudy study = study_from(kDohcStudy, {"objective={\"separation\": 1.0}"});
  SimulationPool pool(1, kDohcStudy);
  const DesignEvaluator evaluator(study.config, kDohcStudy, pool);
  const DesignEvaluation base = evaluator.evaluate(study.baseline, EvaluationSettings{}, false);
  ASSERT_TRUE(base.valid) << base.error;
  EXPECT_NEAR(base.highest_lift, 9.3616e-3, 2e-6);  // the spline's nose between knots 1 deg apart
  EXPECT_GT(base.lift_area, 0.0);
  DesignEvaluation low = base;
  low.highest_lift = 0.921e-3;  // [m]
  low.lift_area = 0.1 * base.lift_area;
  const std::string why = lift_given_up(study.config, base, low, CandidateKind::dynamic);
  EXPECT_NE(why.find("0.921 mm"), std::string::npos) << why;
  EXPECT_NE(why.find("objective.lift_area"), std::string::npos) << why;
  // Kept within kLiftKeptShare, chosen as the baseline, or with the area in the objective: nothing to say.
  DesignEvaluation kept = base;
  kept.highest_lift = 0.95 * base.highest_lift;
  kept.lift_area = 0.95 * base.lift_area;
  EXPECT_EQ(lift_given_up(study.config, base, kept, CandidateKind::dynamic), "");
  EXPECT_EQ(lift_given_up(study.config, base, low, CandidateKind::baseline), "");
  OptimizeStudyConfig with_area = study.config;
  with_area.objective.lift_area = 1.0;
  EXPECT_EQ(lift_given_up(with_area, base, low, CandidateKind::dynamic), "");
  // The banner: everything met and better than the baseline, but the lift given up: not green.
  Selection sel;
  sel.choice.chosen = CandidateKind::dynamic;
  sel.choice.feasible = sel.choice.beats_baseline = true;
  for (CandidateKind k : {CandidateKind::baseline, CandidateKind::rigid, CandidateKind::dynamic}) {
    CandidateVerification c;
    c.kind = k;
    c.available = true;
    c.verified = kept;
    sel.candidates.push_back(c);
  }
  EXPECT_TRUE(sel.good());
  sel.lift_given_up = why;
  EXPECT_FALSE(sel.good());
}

// The seat's constraints on a scene without a seat are bad input naming them.
TEST(CertificateText, SeatConstraintsNeedASeat) {
  for (const char* name : {"max_seat_bounce_height", "max_take_up_bounces"}) {
    const OptimizeStudy study = study_from(kJumpStudy, {std::string("constraints.") + name + "=1e-3"});
    try {
      check_optimize(study.baseline, study.config, kJumpStudy);
      ADD_FAILURE() << name << " accepted without a seat";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("constraints.") + name), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("needs a seat"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace camdyn::optim

namespace camdyn::optim {
namespace {

// The seat's constraints read the train's metrics at every operating speed:
// the highest seat bounce [m], and the take-up bounces per revolution — over
// the window, or over the orbit's period when the metrics are the orbit's
// (SimulationResult::metrics_duration).
TEST(SeatConstraints, BounceHeightAndTakeUpsPerRevolutionAreHeld) {
  const OptimizeStudy study =
      study_from(kDohcStudy, {"constraints.max_seat_bounce_height=1e-6", "constraints.max_take_up_bounces=2"});
  SimulationPool pool(1, kDohcStudy);
  DesignEvaluator evaluator(study.config, kDohcStudy, pool);
  DesignEvaluation e;
  e.valid = e.simulated = true;
  auto speed = [](double rpm, long take_ups, double height, double window_s, double orbit_s) {
    SpeedResult s;
    s.rpm = rpm;
    s.result.metrics.train.emplace();
    s.result.metrics.train->take_up_bounces = take_ups;
    s.result.metrics.train->max_seat_bounce_height = height;
    s.result.evaluated_from = 0.02;
    s.result.end_time = 0.02 + window_s;
    s.result.orbit_duration = orbit_s;
    return s;
  };
  // 3000 rpm: 6 take-ups over a 3-revolution window (0.06 s) is 2 a revolution;
  // 3500 rpm: 3 over one period of its orbit (60/3500 s) is 3 a revolution.
  e.speeds = {speed(3000, 6, 0.5e-6, 0.06, 0.0), speed(3500, 3, 2e-6, 0.06, 60.0 / 3500.0),
              speed(3800, 0, 0.0, 0.06, 0.0)};
  evaluator.score(e);
  const std::vector<ConstraintSpec>& specs = evaluator.constraints();
  bool saw_height = false, saw_take_ups = false;
  for (std::size_t i = 0; i < specs.size(); ++i) {
    if (specs[i].name == "max_seat_bounce_height") {
      saw_height = true;
      EXPECT_DOUBLE_EQ(e.constraints[i].value, 2e-6);
      EXPECT_FALSE(e.constraints[i].holds);
    }
    if (specs[i].name == "max_take_up_bounces") {
      saw_take_ups = true;
      EXPECT_NEAR(e.constraints[i].value, 3.0, 1e-9);
      EXPECT_FALSE(e.constraints[i].holds);
    }
  }
  EXPECT_TRUE(saw_height && saw_take_ups);
  EXPECT_FALSE(e.feasible);
  // Within both limits: they hold.
  e.speeds = {speed(3000, 6, 0.5e-6, 0.06, 0.0)};
  e.speeds.push_back(speed(3500, 2, 1e-6, 0.06, 60.0 / 3500.0));
  e.speeds.push_back(speed(3800, 0, 0.0, 0.06, 0.0));
  evaluator.score(e);
  for (std::size_t i = 0; i < specs.size(); ++i)
    if (specs[i].name == "max_seat_bounce_height" || specs[i].name == "max_take_up_bounces") {
      EXPECT_TRUE(e.constraints[i].holds) << specs[i].name << " " << e.constraints[i].value;
    }
}

}  // namespace
}  // namespace camdyn::optim
