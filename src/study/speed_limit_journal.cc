#include "study/speed_limit_journal.h"

#include <camdyn/version.h>

#include <vector>

#include "io/hex_doubles.h"

namespace camdyn {

namespace {

/// The study's fingerprint: its resolved config (scene, integrator budgets
/// and speed_limit fields) and the camdyn version.
std::string study_fingerprint(const SpeedLimitStudy& study) {
  const Json identity{{"study", study.resolved}, {"camdyn_version", CAMDYN_VERSION}};
  return fingerprint(identity.dump(-1, ' ', false, Json::error_handler_t::replace));
}

}  // namespace

SpeedLimitJournal::SpeedLimitJournal(const SpeedLimitStudy& study, const StudyContext& ctx)
    : journal_(ctx.out_dir / "journal.jsonl", "speed_limit", study_fingerprint(study),
               static_cast<std::size_t>(study.config.scan) + kMaxBisectionSteps) {}

std::optional<SpeedCheck> SpeedLimitJournal::replay(std::size_t index, double rpm) const {
  const auto it = journal_.done().find(index);
  if (it == journal_.done().end()) return std::nullopt;
  const Json& j = it->second;
  // A record of another shape (a journal changed by hand) is run again, never converted.
  const auto is = [&j](const char* key, bool (Json::*kind)() const noexcept) {
    return j.contains(key) && (j[key].*kind)();
  };
  if (!is("values", &Json::is_string) || !is("in_contact", &Json::is_boolean) || !is("converged", &Json::is_boolean) ||
      !is("message", &Json::is_string))
    return std::nullopt;
  // rpm [rpm], separation fraction [-], smallest and peak contact force [N],
  // float and link float fractions [-], take-up and seat bounces, exact.
  const auto values = doubles_from_hex(j["values"].get<std::string>(), 8);
  if (!values || double_bits({(*values)[0]}) != double_bits({rpm})) return std::nullopt;
  SpeedCheck c;
  c.rpm = rpm;
  c.separation_fraction = (*values)[1];
  c.min_contact_force = (*values)[2];
  c.peak_contact_force = (*values)[3];
  c.float_fraction = (*values)[4];
  c.link_float_fraction = (*values)[5];
  c.take_up_bounces = static_cast<long>((*values)[6]);
  c.seat_bounces = static_cast<long>((*values)[7]);
  c.ok = j["in_contact"].get<bool>();
  c.converged = j["converged"].get<bool>();
  c.message = j["message"].get<std::string>();
  return c;
}

void SpeedLimitJournal::record(std::size_t index, const SpeedCheck& check) {
  if (!check.budget.empty()) return;
  const Json j{{"index", index},
               {"status", check.ok ? "ok" : "failed"},
               {"in_contact", check.ok},
               {"converged", check.converged},
               {"message", check.message},
               {"values",
                doubles_to_hex({check.rpm, check.separation_fraction, check.min_contact_force, check.peak_contact_force,
                                check.float_fraction, check.link_float_fraction,
                                static_cast<double>(check.take_up_bounces), static_cast<double>(check.seat_bounces)})}};
  const std::lock_guard<std::mutex> lock(mutex_);
  journal_.append(j);
}

}  // namespace camdyn
