#include "optim/optimize/optimize_journal.h"

#include <camdyn/version.h>

#include <iostream>
#include <optional>
#include <utility>

#include "io/hex_doubles.h"

namespace camdyn::optim {

namespace {

constexpr const char* kJournalFile = "journal.jsonl";
/// The journal's record count bound (study/journal.h checks indices against it).
constexpr std::size_t kMaxRecords = std::size_t{1} << 40;

/// `<dir>/journal.jsonl`, the folder created if missing.
std::filesystem::path journal_path(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  return dir / kJournalFile;
}

/// A hex field of `record` as `count` doubles; nothing if it is missing or malformed.
std::optional<std::vector<double>> hex_field(const Json& record, const char* key, std::size_t count) {
  const auto it = record.find(key);
  if (it == record.end() || !it->is_string()) return std::nullopt;
  return doubles_from_hex(it->get_ref<const std::string&>(), count);
}

/// The evaluation of a record, checked against the study's sizes; nothing if it does not fit.
std::optional<JournaledEvaluation> evaluation_of(const Json& record, std::size_t constraints) {
  const auto objective = hex_field(record, "objective", 1);
  const auto values = hex_field(record, "constraints", 3 * constraints);
  const auto holds = record.find("holds");
  if (!objective || !values || holds == record.end() || !holds->is_array() || holds->size() != constraints)
    return std::nullopt;
  JournaledEvaluation e;
  e.valid = record.value("valid", false);
  e.error = record.value("error", std::string());
  e.objective = objective->front();
  e.feasible = record.value("feasible", false);
  e.simulations = record.value("simulations", 0L);
  for (std::size_t i = 0; i < constraints; ++i) {
    if (!(*holds)[i].is_boolean()) return std::nullopt;
    e.constraints.push_back(
        ConstraintValue{(*values)[3 * i], (*values)[3 * i + 1], (*values)[3 * i + 2], (*holds)[i].get<bool>()});
  }
  return e;
}

}  // namespace

std::string optimize_fingerprint(const SceneConfig& baseline, const OptimizeStudyConfig& config) {
  const Json identity{
      {"camdyn_version", CAMDYN_VERSION}, {"baseline", to_json(baseline)}, {"optimize", to_json(config)}};
  return fingerprint(identity.dump(-1, ' ', false, Json::error_handler_t::replace));
}

OptimizeJournal::OptimizeJournal(const std::filesystem::path& dir, const std::string& fingerprint,
                                 std::size_t dimension, std::size_t constraints)
    : journal_(journal_path(dir), "optimize", fingerprint, kMaxRecords),
      dimension_(dimension),
      constraint_count_(constraints) {
  for (const auto& [index, record] : journal_.done()) {
    next_index_ = index + 1;
    if (record.value("kind", std::string()) != "evaluation") continue;
    const auto x = hex_field(record, "x", dimension_);
    auto e = evaluation_of(record, constraint_count_);
    if (!x || !e) {
      std::cerr << "camdyn: warning: " << path().string() << ": record " << index
                << " is not an evaluation of this study; the design is evaluated again\n";
      continue;
    }
    if (evaluations_.emplace(double_bits(*x), std::move(*e)).second) ++resumed_;
  }
}

const JournaledEvaluation* OptimizeJournal::find(const std::vector<double>& x) const {
  const auto hit = evaluations_.find(double_bits(x));
  return hit == evaluations_.end() ? nullptr : &hit->second;
}

void OptimizeJournal::add(const std::vector<double>& x, const JournaledEvaluation& e) {
  if (x.size() != dimension_ || e.constraints.size() != constraint_count_) return;  // not of this study
  Key key = double_bits(x);
  if (evaluations_.contains(key)) return;
  std::vector<double> values;
  Json holds = Json::array();
  for (const ConstraintValue& c : e.constraints) {
    values.insert(values.end(), {c.value, c.margin, c.residual});
    holds.push_back(c.holds);
  }
  journal_.append(Json{{"index", next_index_++},
                       {"kind", "evaluation"},
                       {"x", doubles_to_hex(x)},
                       {"valid", e.valid},
                       {"error", e.error},
                       {"objective", doubles_to_hex({e.objective})},
                       {"feasible", e.feasible},
                       {"constraints", doubles_to_hex(values)},
                       {"holds", std::move(holds)},
                       {"simulations", e.simulations}});
  evaluations_.emplace(std::move(key), e);
}

}  // namespace camdyn::optim
