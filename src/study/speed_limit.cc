#include "study/speed_limit.h"

#include <camdyn/version.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <set>
#include <vector>

#include "common/errors.h"
#include "common/parallel.h"
#include "common/study_budget.h"
#include "dynamics/model.h"
#include "dynamics/rigid_jump_speed.h"
#include "dynamics/simulation.h"
#include "dynamics/train_jump_speed.h"
#include "io/json_archive.h"
#include "io/json_writer.h"
#include "output/cam_plots.h"
#include "output/report.h"
#include "study/progress.h"
#include "study/speed_limit_journal.h"

namespace camdyn {

namespace {

const std::vector<std::string> kSpeedLimitKeys = {"speed_limit"};

/// The scene's metrics at `rpm`, on `model` (the worker's copy of the
/// study's model, its speed set here) or, without one, a model assembled for it.
SpeedCheck check_speed(const SpeedLimitStudy& study, double rpm, double min_force, const std::string& file,
                       Model* model) {
  SpeedCheck c;
  c.rpm = rpm;
  if (study_budget_exhausted()) {  // not started: the study's wall time is used up
    c.converged = c.ok = false;
    c.message = study_budget_text();
    c.budget = "--max-study-time";
    return c;
  }
  SceneConfig s = study.scene;
  s.mechanism.cam.rpm = rpm;
  SimulationOptions options;
  options.record_series = false;
  if (model) set_cam_speed(*model, s, file);
  const SimulationResult r = model            ? simulate_scene(*model, s, options)
                             : study.geometry ? simulate_scene(*study.geometry, s, file, options)
                                              : simulate_scene(s, file, options);
  c.converged = r.solver.termination == Termination::converged;
  c.message = c.converged ? "" : r.solver.message;
  if (r.solver.termination == Termination::step_budget || r.solver.termination == Termination::wall_time_budget) {
    c.budget = budget_that_cut(c.message);
    if (c.budget.empty()) c.budget = std::string(enum_name(r.solver.termination));
  }
  const Metrics& m = r.metrics;
  c.separation_fraction = m.separation_fraction;
  c.min_contact_force = m.min_contact_force;
  c.peak_contact_force = m.peak_contact_force;
  // A train also jumps where a link opens off its seats; the lash's take-up
  // and seat bounces are not a jump (docs/valvetrain.md).
  c.float_fraction = m.float_fraction.value_or(m.separation_fraction);
  if (m.train) {
    c.link_float_fraction = m.train->link_float_fraction;
    c.take_up_bounces = m.train->take_up_bounces;
    c.seat_bounces = m.train->seat_bounces;
  }
  c.ok = c.converged && !separates(m) && (min_force <= 0.0 || c.min_contact_force >= min_force);
  return c;
}

/// What failed at the first failing speed (SpeedLimitResult::limit_cause),
/// and the lowest simulated speed with a seat bounce.
void classify_limit(SpeedLimitResult& r) {
  for (const SpeedCheck& check : r.checks) {
    if (check.seat_bounces > 0 && (!r.seat_bounce_rpm || check.rpm < *r.seat_bounce_rpm)) r.seat_bounce_rpm = check.rpm;
    if (!r.limited || check.rpm != r.first_failure_rpm) continue;
    r.limit_cause = !check.converged                  ? "solver"
                    : check.float_fraction > 0.0      ? "float"
                    : check.link_float_fraction > 0.0 ? "link"
                                                      : "force";
  }
}

/// The most bisection steps that narrow a bracket `width_rpm` wide to
/// `tolerance_rpm`: ⌈log2(width / tolerance)⌉, 0 when it is narrow enough.
std::size_t bisection_steps(double width_rpm, double tolerance_rpm) {
  if (!(width_rpm > tolerance_rpm) || !(tolerance_rpm > 0.0)) return 0;
  return static_cast<std::size_t>(std::ceil(std::log2(width_rpm / tolerance_rpm)));
}

/// The scan speeds of the first batch: up to and including the first grid
/// speed above `jump_rpm` (all of them when none is, `threads` when the jump
/// speed is not finite), at least `threads`.
std::size_t first_scan_batch(double low_rpm, double high_rpm, int scan, double jump_rpm, std::size_t threads) {
  const auto speeds = static_cast<std::size_t>(scan);
  std::size_t reach = threads;
  if (std::isfinite(jump_rpm)) {
    reach = speeds;
    for (std::size_t i = 0; i < speeds; ++i)
      if (low_rpm + (high_rpm - low_rpm) * static_cast<double>(i) / (scan - 1) > jump_rpm) {
        reach = i + 1;
        break;
      }
  }
  return std::clamp<std::size_t>(reach, std::min(speeds, std::max<std::size_t>(1, threads)), speeds);
}

}  // namespace

/// The largest speed_limit.min_contact_force [N]: far past any cam; beyond
/// it the margin's arithmetic with the spring force loses every digit.
constexpr double kMaxContactForceFloor = 1e9;
/// The most speeds the coarse scan may simulate.
constexpr int kMaxScanSpeeds = 10000;
/// The finest tolerance_rpm relative to the bracket's speeds [-] (doubles
/// resolve ~1e-16 of a speed; this leaves room for the simulations' own noise).
constexpr double kToleranceResolution = 1e-9;

template <class A>
void visit(A& a, SpeedLimitConfig& c) {
  a.field("low_rpm", c.low_rpm, at_least(kMinCamRpm), open_closed(0, kMaxCamRpm));
  a.field("high_rpm", c.high_rpm, at_least(kMinCamRpm), open_closed(0, kMaxCamRpm));
  a.field("scan", c.scan, at_least(2));
  // Each is a simulation: 2e9 of them asked for 16 GB before the first ran.
  a.require(c.scan <= kMaxScanSpeeds, "scan",
            "must be at most " + std::to_string(kMaxScanSpeeds) + " speeds, got " + std::to_string(c.scan));
  a.field("tolerance_rpm", c.tolerance_rpm, positive());
  // Below this the bracket cannot narrow in floating point: the bisection
  // would run until the study's budget.
  const double fastest = std::max(c.low_rpm, c.high_rpm.value_or(c.low_rpm));
  a.require(c.tolerance_rpm >= kToleranceResolution * fastest, "tolerance_rpm",
            "must be at least " + format_shortest(kToleranceResolution) + " × the bracket's speeds (" +
                format_number(kToleranceResolution * fastest, 3) + " rpm here), got " +
                format_shortest(c.tolerance_rpm) + ": no bisection can resolve a speed that finely");
  a.field("min_contact_force", c.min_contact_force, closed_open(0, kMaxContactForceFloor));
  a.require(!c.high_rpm || *c.high_rpm > c.low_rpm, "high_rpm", "must be above low_rpm");
}

SpeedLimitStudy read_speed_limit_study(const Json& doc, const StudyContext& ctx) {
  SpeedLimitStudy study;
  Json part;
  study.scene = scene_from_study_json(doc, ctx.source, kSpeedLimitKeys, part);
  const Json fields = read_study_fields(part, "speed_limit", ctx.source, study.config);
  // The geometry and contact law are checked here, before any run.
  study.geometry = build_cam_geometry(study.scene, ctx.config_file);
  {
    study.model = std::make_shared<const Model>(build_model(*study.geometry, study.scene, ctx.config_file));
    const Model& model = *study.model;
    study.rigid_jump_speed_rpm = model_jump_speed_rpm(model);
    study.jump_speed_name = jump_speed_name(model);
    study.train = model.train.has_coordinates();
    study.lash = model.take_up.applies;
    // A valve the law cannot seat has no speed limit to find (docs/valvetrain.md).
    if (model.take_up.held_open_body >= 0)
      throw InputError(ctx.config_file, "mechanism", take_up_window_problem(model.train, model.take_up));
  }
  study.resolved = resolved_study_json(study.scene, "speed_limit", Json{{"speed_limit", fields}});
  return study;
}

SpeedLimitResult run_speed_limit(const SpeedLimitStudy& study, const StudyContext& ctx) {
  const auto t0 = std::chrono::steady_clock::now();
  const SpeedLimitConfig& c = study.config;
  SpeedLimitResult r;
  r.rigid_jump_speed_rpm = study.rigid_jump_speed_rpm;
  r.jump_speed_name = study.jump_speed_name;
  r.train = study.train;
  r.lash = study.lash;
  const double high =
      c.high_rpm.value_or(std::isfinite(r.rigid_jump_speed_rpm) ? 2.0 * r.rigid_jump_speed_rpm : 10.0 * c.low_rpm);
  const double hi = std::max(high, 1.01 * c.low_rpm);

  // Each finished speed is journaled; a re-run replays it (docs/outputs-and-resume.md).
  // (None without an output folder: a library caller's in-memory study.)
  std::unique_ptr<SpeedLimitJournal> journal;
  if (!ctx.out_dir.empty()) {
    std::filesystem::create_directories(ctx.out_dir);
    journal = std::make_unique<SpeedLimitJournal>(study, ctx);
    r.resumed = journal->found();
  }
  if (r.resumed > 0)
    std::cerr << "camdyn: resuming: " << r.resumed << " simulated speeds already done ("
              << (ctx.out_dir / "journal.jsonl").string() << "), not simulated again\n";
  // Each worker thread's copy of the study's model, made at its first speed (the bisection's: worker 0's).
  std::vector<std::optional<Model>> models(static_cast<std::size_t>(std::max(ctx.threads(), 1)));
  auto check_or_replay = [&](int worker, std::size_t index, double rpm) {
    if (std::optional<SpeedCheck> done = journal ? journal->replay(index, rpm) : std::nullopt) return *done;
    std::optional<Model>& model = models[static_cast<std::size_t>(worker)];
    if (study.model && !model) model = *study.model;
    SpeedCheck fresh = check_speed(study, rpm, c.min_contact_force, ctx.config_file, model ? &*model : nullptr);
    if (journal) journal->record(index, fresh);
    return fresh;
  };

  // The scan: low_rpm … hi evenly, in batches from the bottom, in parallel
  // within a batch. The first batch reaches the first grid speed above the
  // rigid-model jump speed (where the follower is expected to leave the cam);
  // the next ones go on `threads` speeds at a time only while every speed so
  // far kept contact. The speeds above the first that fails cannot change
  // the answer, so they are not simulated; the grid, and so each speed's
  // journal record, is the full scan's.
  const std::size_t threads = static_cast<std::size_t>(ctx.threads());
  const std::size_t first_batch = first_scan_batch(c.low_rpm, hi, c.scan, r.rigid_jump_speed_rpm, threads);
  std::vector<SpeedCheck> scan;
  ProgressMeter progress(
      "speed_limit",
      static_cast<std::size_t>(c.scan) + bisection_steps((hi - c.low_rpm) / (c.scan - 1), c.tolerance_rpm), 0, 0,
      threads, ctx.progress);
  for (std::size_t from = 0; from < static_cast<std::size_t>(c.scan);) {
    const std::size_t to =
        std::min<std::size_t>(static_cast<std::size_t>(c.scan), from == 0 ? first_batch : from + threads);
    scan.resize(to);
    parallel_for_workers(to - from, ctx.threads(), [&](int worker, std::size_t j) {
      const std::size_t i = from + j;
      scan[i] = check_or_replay(worker, i, c.low_rpm + (hi - c.low_rpm) * static_cast<double>(i) / (c.scan - 1));
      progress.finished(!scan[i].converged, 0.0);  // a speed that separates is an answer, not a failure
    });
    if (std::any_of(scan.begin(), scan.end(), [](const SpeedCheck& s) { return !s.ok; })) break;
    from = to;
  }
  r.scan_skipped = static_cast<std::size_t>(c.scan) - scan.size();
  progress.set_total(scan.size() + bisection_steps((hi - c.low_rpm) / (c.scan - 1), c.tolerance_rpm));
  r.checks = scan;
  const auto failed = std::find_if(scan.begin(), scan.end(), [](const SpeedCheck& s) { return !s.ok; });
  if (failed == scan.end()) {
    r.speed_limit_rpm = hi;
  } else if (!failed->budget.empty()) {
    r.withheld = "the first scan speed that did not keep contact, " + format_shortest(failed->rpm) + " rpm";
  } else if (failed == scan.begin()) {
    r.limited = true;
    r.first_failure_rpm = failed->rpm;
  } else {
    // Bisect between the last speed that kept contact and the first that did not.
    double lo = (failed - 1)->rpm, up = failed->rpm;
    for (std::size_t k = 0; up - lo > c.tolerance_rpm && r.withheld.empty() && k < kMaxBisectionSteps; ++k) {
      const double mid = 0.5 * (lo + up);
      if (mid <= lo || mid >= up) break;  // the bracket cannot narrow further in floating point
      r.checks.push_back(check_or_replay(0, scan.size() + k, mid));
      progress.finished(!r.checks.back().converged, 0.0);
      if (!r.checks.back().budget.empty()) r.withheld = "the bisection's speed " + format_shortest(mid) + " rpm";
      (r.checks.back().ok ? lo : up) = mid;
    }
    r.limited = r.withheld.empty();
    r.speed_limit_rpm = lo;
    r.first_failure_rpm = up;
  }
  progress.set_total(r.checks.size());  // no bisection, or one cut short: the line ends here
  classify_limit(r);
  std::set<std::string> budgets;
  for (const SpeedCheck& check : r.checks)
    if (!check.budget.empty()) {
      ++r.budget_cut;
      budgets.insert(check.budget);
    }
  if (!r.withheld.empty()) {
    std::string names;
    for (const std::string& name : budgets) names += (names.empty() ? "" : ", ") + name;
    r.withheld = withheld_text(r.budget_cut, r.checks.size(), "simulated speeds", names,
                               "the speed limit (it rests on " + r.withheld + ", which was cut short)");
    r.limited = false;
  }
  r.run_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

Json speed_limit_json(const SpeedLimitStudy& study, const SpeedLimitResult& r) {
  Json checks = Json::array();
  for (const SpeedCheck& s : r.checks) {
    Json j{{"rpm", s.rpm},
           {"in_contact", s.ok},
           {"converged", s.converged},
           {"separation_fraction", s.separation_fraction},
           {"float_fraction", s.float_fraction},
           {"min_contact_force", s.min_contact_force},
           {"peak_contact_force", s.peak_contact_force},
           {"status", s.ok               ? "ok"
                      : s.budget.empty() ? "failed"
                                         : "failed: budget"}};
    if (!s.converged) j["message"] = s.message;
    if (!s.budget.empty()) j["budget"] = s.budget;
    if (r.train) j["link_float_fraction"] = s.link_float_fraction;
    if (r.lash) {
      j["take_up_bounces"] = s.take_up_bounces;
      j["seat_bounces"] = s.seat_bounces;
    }
    checks.push_back(j);
  }
  const bool stands = r.withheld.empty();  // else no limit, no verdict: nulls
  return Json{{"name", study.scene.name},
              {"study", "speed_limit"},
              {"camdyn_version", CAMDYN_VERSION},
              {"speed_limit_rpm", stands ? Json(r.speed_limit_rpm) : Json(nullptr)},
              {"limited", stands ? Json(r.limited) : Json(nullptr)},
              {"first_failure_rpm", r.limited ? Json(r.first_failure_rpm) : Json(nullptr)},
              {"limit_cause", r.limited ? Json(r.limit_cause) : Json(nullptr)},
              {"seat_bounce_rpm", r.seat_bounce_rpm ? Json(*r.seat_bounce_rpm) : Json(nullptr)},
              {"budget_cut_runs", r.budget_cut},
              {"resumed_checks", r.resumed},
              {"scan_skipped", r.scan_skipped},
              {"conclusion_withheld", stands ? Json(nullptr) : Json(r.withheld)},
              {"tolerance_rpm", study.config.tolerance_rpm},
              {r.train ? "train_jump_speed_rpm" : "rigid_jump_speed_rpm",
               std::isfinite(r.rigid_jump_speed_rpm) ? Json(r.rigid_jump_speed_rpm) : Json()},
              {"min_contact_force", study.config.min_contact_force},
              {"checks", checks},
              {"run_time_s", r.run_time_s}};
}

namespace {

/// The rigid (or held-train) jump speed for the report: 5 digits, or why there is none.
std::string rigid_text(double rpm) {
  return std::isfinite(rpm) ? format_number(rpm, 5) + " rpm" : jump_speed_text(rpm, 5);
}

/// The words for SpeedLimitResult::limit_cause.
std::string limit_cause_text(const std::string& cause) {
  if (cause == "float") return "the follower floats off the cam above the ramps (a jump)";
  if (cause == "link") return "a link of the train opens above the ramps (the train floats)";
  if (cause == "force") return "the contact force falls below speed_limit.min_contact_force";
  return "the simulation did not finish";
}

/// report.html: separation fraction and smallest contact force against
/// speed, then the cam with its SVAJ per radian of cam angle (many speeds).
Report speed_limit_report(const SpeedLimitStudy& study, const SpeedLimitResult& r, const std::string& file) {
  std::vector<SpeedCheck> sorted = r.checks;
  std::sort(sorted.begin(), sorted.end(), [](const SpeedCheck& a, const SpeedCheck& b) { return a.rpm < b.rpm; });
  Series sep{"separation fraction", {}, {}, "linespoints"}, force{"smallest contact force", {}, {}, "linespoints"};
  Table table{"Simulated speeds",
              {"rpm", "in contact", "separation fraction", "float fraction", "take-up bounces", "seat bounces",
               "min contact force [N]", "peak contact force [N]"},
              {}};
  for (const SpeedCheck& s : sorted) {
    sep.x.push_back(s.rpm);
    sep.y.push_back(s.separation_fraction);
    force.x.push_back(s.rpm);
    force.y.push_back(s.min_contact_force);
    table.rows.push_back({format_number(s.rpm), s.ok ? "yes" : "NO", format_number(s.separation_fraction),
                          format_number(s.float_fraction), r.lash ? std::to_string(s.take_up_bounces) : "–",
                          r.lash ? std::to_string(s.seat_bounces) : "–", format_number(s.min_contact_force),
                          format_number(s.peak_contact_force)});
  }
  Report rep;
  rep.title = "camdyn speed_limit: " + study.scene.name;
  rep.subtitle = "How fast can this go? The highest speed at which the follower stays on the cam";
  rep.verdict =
      Verdict{r.limited ? Verdict::Tone::warning : Verdict::Tone::good,
              r.limited ? "stays on the cam up to " + format_number(r.speed_limit_rpm, 5) + " rpm, separates at " +
                              format_number(r.first_failure_rpm, 5) + " rpm"
                        : "stays on the cam at every speed up to " + format_number(r.speed_limit_rpm, 5) + " rpm",
              {r.jump_speed_name + " " + rigid_text(r.rigid_jump_speed_rpm)}};
  if (r.limited) rep.verdict->details.push_back("what fails there: " + limit_cause_text(r.limit_cause));
  if (r.lash)
    rep.verdict->details.push_back(
        r.seat_bounce_rpm ? "a valve bounces off its seat from " + format_number(*r.seat_bounce_rpm, 5) +
                                " rpm (the lowest simulated speed with a seat bounce)"
                          : "no seat bounce at any simulated speed; take-up bounces are counted, not a jump");
  rep.facts = {
      {"speed limit (simulated)", r.limited ? format_number(r.speed_limit_rpm, 5) + " rpm (fails at " +
                                                  format_number(r.first_failure_rpm, 5) + " rpm)"
                                            : "none found up to " + format_number(r.speed_limit_rpm, 5) + " rpm"},
      {r.jump_speed_name, rigid_text(r.rigid_jump_speed_rpm)},
      {"simulations", std::to_string(r.checks.size()) + " in " + format_number(r.run_time_s, 3) + " s"}};
  rep.appendix.push_back(table);
  rep.plots.push_back(Plot{"Separation against speed", "cam speed [rpm]", "separation fraction [-]", {sep}});
  rep.plots.push_back(Plot{"Smallest contact force against speed", "cam speed [rpm]", "force [N]", {force}});
  std::optional<Model> built;  // a study read from its config has its model
  const Model& model = study.model ? *study.model : built.emplace(build_model(study.geometry, study.scene, file));
  for (Plot& p : cam_plots(model, study.scene.mechanism.cam.limits, 0.0)) rep.plots.push_back(std::move(p));
  return rep;
}

}  // namespace

int run_speed_limit_study(const Json& doc, const StudyContext& ctx) {
  const SpeedLimitStudy study = read_speed_limit_study(doc, ctx);
  if (ctx.validate_only) {
    std::cout << dump_json(study.resolved);
    return 0;
  }
  const SpeedLimitResult r = run_speed_limit(study, ctx);
  std::filesystem::create_directories(ctx.out_dir);
  write_json_atomic(ctx.out_dir / "speed_limit.json", speed_limit_json(study, r));
  if (!r.withheld.empty()) {
    std::filesystem::remove(ctx.out_dir / "report.html");  // an earlier run's verdict must not stand
    std::fprintf(stderr, "camdyn: error: %s: %s\n", study.scene.name.c_str(), r.withheld.c_str());
    return 3;
  }
  write_report(ctx.out_dir / "report.html", speed_limit_report(study, r, ctx.config_file));
  if (r.limited && r.speed_limit_rpm == 0.0)
    std::printf("%s: the follower leaves the cam already at %.6g rpm (the lowest speed checked)\n",
                study.scene.name.c_str(), r.first_failure_rpm);
  else if (r.limited)
    std::printf("%s: stays on the cam up to %.6g rpm (simulated; leaves it at %.6g rpm); %s %s\n",
                study.scene.name.c_str(), r.speed_limit_rpm, r.first_failure_rpm, r.jump_speed_name.c_str(),
                jump_speed_text(r.rigid_jump_speed_rpm, 6).c_str());
  else
    std::printf("%s: stays on the cam at every speed checked, up to %.6g rpm; %s %s\n", study.scene.name.c_str(),
                r.speed_limit_rpm, r.jump_speed_name.c_str(), jump_speed_text(r.rigid_jump_speed_rpm, 6).c_str());
  std::printf("  %zu simulations, %.3g s; report: %s\n", r.checks.size(), r.run_time_s,
              std::filesystem::absolute(ctx.out_dir / "report.html").lexically_normal().c_str());
  return 0;
}

}  // namespace camdyn
