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

/// "warm_end" of a record: per speed, the section point as hex (coordinates,
/// approach speed, motor phase) or "" for none.
Json warm_end_json(const std::vector<std::optional<SectionPoint>>& points) {
  Json out = Json::array();
  for (const std::optional<SectionPoint>& p : points) {
    if (!p) {
      out.push_back("");
      continue;
    }
    std::vector<double> values = p->x;
    values.insert(values.end(), {p->approach_speed, p->motor_phase});
    out.push_back(doubles_to_hex(values));
  }
  return out;
}

/// The section points of "warm_end"; nothing if it is malformed (missing: none).
std::optional<std::vector<std::optional<SectionPoint>>> warm_end_of(const Json& record) {
  std::vector<std::optional<SectionPoint>> points;
  const auto it = record.find("warm_end");
  if (it == record.end()) return points;
  if (!it->is_array()) return std::nullopt;
  constexpr std::size_t kHexDigits = 16;
  for (const Json& item : *it) {
    if (!item.is_string()) return std::nullopt;
    const std::string& text = item.get_ref<const std::string&>();
    if (text.empty()) {
      points.emplace_back();
      continue;
    }
    const auto values = doubles_from_hex(text, text.size() / kHexDigits);
    if (!values || values->size() < 2) return std::nullopt;
    SectionPoint p;
    p.x.assign(values->begin(), values->end() - 2);
    p.approach_speed = (*values)[values->size() - 2];
    p.motor_phase = values->back();
    points.push_back(std::move(p));
  }
  return points;
}

}  // namespace

void fill_evaluation(const JournaledEvaluation& j, DesignEvaluation& e) {
  e.valid = j.valid;
  e.error = j.error;
  e.objective = j.objective;
  e.feasible = j.feasible;
  e.constraints = j.constraints;
  e.end_points = j.end_points;
}

Json evaluation_record(const std::vector<double>& x, const JournaledEvaluation& e, bool per_start) {
  std::vector<double> values;
  Json holds = Json::array();
  for (const ConstraintValue& c : e.constraints) {
    values.insert(values.end(), {c.value, c.margin, c.residual});
    holds.push_back(c.holds);
  }
  Json record{{"kind", "evaluation"},
              {"x", doubles_to_hex(x)},
              {"valid", e.valid},
              {"error", e.error},
              {"objective", doubles_to_hex({e.objective})},
              {"feasible", e.feasible},
              {"constraints", doubles_to_hex(values)},
              {"holds", std::move(holds)},
              {"simulations", e.simulations}};
  if (per_start) {
    record["start"] = e.start;
    record["warm_end"] = warm_end_json(e.end_points);
  }
  return record;
}

std::optional<std::pair<std::vector<double>, JournaledEvaluation>> evaluation_from_record(const Json& record,
                                                                                          std::size_t dimension,
                                                                                          std::size_t constraints) {
  auto x = hex_field(record, "x", dimension);
  auto e = evaluation_of(record, constraints);
  auto warm_end = warm_end_of(record);
  if (!x || !e || !warm_end) return std::nullopt;
  e->start = record.value("start", 0);
  e->end_points = std::move(*warm_end);
  return std::make_pair(std::move(*x), std::move(*e));
}

std::string optimize_fingerprint(const SceneConfig& baseline, const OptimizeStudyConfig& config) {
  const Json identity{
      {"camdyn_version", CAMDYN_VERSION}, {"baseline", to_json(baseline)}, {"optimize", to_json(config)}};
  return fingerprint(identity.dump(-1, ' ', false, Json::error_handler_t::replace));
}

OptimizeJournal::OptimizeJournal(const std::filesystem::path& dir, const std::string& fingerprint,
                                 std::size_t dimension, std::size_t constraints, bool per_start)
    : journal_(journal_path(dir), "optimize", fingerprint, kMaxRecords),
      dimension_(dimension),
      constraint_count_(constraints),
      per_start_(per_start) {
  for (const auto& [index, record] : journal_.done()) {
    next_index_ = index + 1;
    if (record.value("kind", std::string()) != "evaluation") continue;
    auto evaluation = evaluation_from_record(record, dimension_, constraint_count_);
    if (!evaluation) {
      std::cerr << "camdyn: warning: " << path().string() << ": record " << index
                << " is not an evaluation of this study; the design is evaluated again\n";
      continue;
    }
    Key k = key(evaluation->first, evaluation->second.start);
    if (evaluations_.emplace(std::move(k), std::move(evaluation->second)).second) ++resumed_;
  }
}

OptimizeJournal::Key OptimizeJournal::key(const std::vector<double>& x, int start) const {
  Key k = double_bits(x);
  if (per_start_) k.insert(k.begin(), static_cast<std::uint64_t>(start));
  return k;
}

const JournaledEvaluation* OptimizeJournal::find(const std::vector<double>& x, int start) const {
  const auto hit = evaluations_.find(key(x, start));
  return hit == evaluations_.end() ? nullptr : &hit->second;
}

void OptimizeJournal::add(const std::vector<double>& x, const JournaledEvaluation& e) {
  if (x.size() != dimension_ || e.constraints.size() != constraint_count_) return;  // not of this study
  Key k = key(x, e.start);
  if (evaluations_.contains(k)) return;
  Json record{{"index", next_index_++}};
  record.update(evaluation_record(x, e, per_start_));
  journal_.append(record);
  evaluations_.emplace(std::move(k), e);
}

}  // namespace camdyn::optim
