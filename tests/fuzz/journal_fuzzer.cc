// libFuzzer target: resuming a study from its journal (study/journal.h,
// study/journaled_runs.h). A small compare study (kOverrides on
// studies/compare_laws.json: 2 cases × 2 speeds, one overlay) is resumed
// from a journal whose records are the input: the journal's header (the
// study's own, unless the input begins with a header of its own) and then
// the input's lines, each record that carries a "checksum" given the right
// one, so that fuzzed records pass the integrity check and reach the code
// that trusts them (the budget check, the outcomes, comparison.csv/json, the
// overlays, the report). The study runs on a study budget already used up
// (kStudyBudgetS), so runs the journal lacks stop at once (exit 3) and a
// complete journal writes the outputs from the records alone. It must
// recompute, refuse (exit 2) or stop (exit 3), never crash (fuzz_support.h).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "cli/run_study.h"
#include "fuzz_support.h"
#include "io/config.h"
#include "study/journal.h"

namespace {

constexpr double kStudyBudgetS = 1e-3;  // [s] used up before the first run starts
constexpr double kMemoryBudgetMb = 256.0;

// The study the journal belongs to; tests/fuzz/make_corpus.py runs the same
// one (with a budget) to write the seeds, corpus/journal/.
const std::vector<std::string> kOverrides = {
    R"(grid={"mechanism.cam.rpm":[600,1200]})",
    R"(cases=[{"name":"cycloidal"},)"
    R"({"name":"polynomial_345","set":["mechanism.cam.motion_law.segments[0].law=polynomial_345"]}])",
    R"(overlays=[{"mechanism.cam.rpm":1200}])",
    "simulation.cycles=2",
    "simulation.discard_cycles=1",
    "simulation.output_step_deg=5"};

std::string& journal_header() {
  static std::string header;
  return header;
}

std::string& journal_hash() {
  static std::string hash;
  return hash;
}

camdyn::StudyRequest compare_request(const std::filesystem::path& out_dir) {
  camdyn::StudyRequest request;
  request.config_file = std::string(CAMDYN_SOURCE_DIR) + "/studies/compare_laws.json";
  request.overrides = kOverrides;
  request.out_dir = out_dir.string();
  request.jobs = 1;
  request.summary = false;
  request.max_study_time_s = kStudyBudgetS;
  request.max_memory_mb = kMemoryBudgetMb;
  return request;
}

// A record line with its checksum recomputed for this study (as Journal::append
// writes it: FNV-1a of the hash and the record's compact text without it);
// other lines unchanged.
std::string with_valid_checksum(const std::string& line) {
  camdyn::Json record = camdyn::Json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (record.is_discarded() || !record.is_object() || !record.contains("checksum")) return line;
  record.erase("checksum");
  const auto text = [](const camdyn::Json& j) {
    return j.dump(-1, ' ', false, camdyn::Json::error_handler_t::replace);
  };
  record = camdyn::Json::parse(text(record), nullptr, false);
  if (record.is_discarded()) return line;
  record["checksum"] = camdyn::fingerprint(journal_hash() + "\n" + text(record));
  return text(record);
}

std::string journal_text(std::string_view input) {
  std::string text = input.starts_with("{\"camdyn_journal\"") ? "" : journal_header() + "\n";
  std::size_t begin = 0;
  while (begin < input.size()) {
    std::size_t end = input.find('\n', begin);
    const bool complete = end != std::string_view::npos;
    if (!complete) end = input.size();
    text += with_valid_checksum(std::string(input.substr(begin, end - begin)));
    if (complete) text += '\n';  // a last line without its newline stays cut, as a kill leaves it
    begin = end + 1;
  }
  return text;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  camdyn::fuzz::silence_streams();
  setenv("CAMDYN_GNUPLOT", "/nonexistent/camdyn-fuzz-gnuplot", 1);
  // A first start writes the journal's header (the study's fingerprint) and stops on the budget.
  const std::filesystem::path out = camdyn::fuzz::Scratch::get().dir() / "header";
  camdyn::fuzz::expect_camdyn_errors_only([&] { camdyn::run_study(compare_request(out)); });
  std::ifstream journal(out / "journal.jsonl");
  std::getline(journal, journal_header());
  const camdyn::Json header = camdyn::Json::parse(journal_header(), nullptr, false);
  if (header.is_discarded() || !header.contains("hash")) std::abort();  // the set-up itself is broken
  journal_hash() = header["hash"].get<std::string>();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const camdyn::fuzz::Scratch& scratch = camdyn::fuzz::Scratch::get();
  scratch.clear();
  const std::filesystem::path out = scratch.dir() / "out";
  std::filesystem::create_directories(out);
  {
    std::ofstream journal(out / "journal.jsonl", std::ios::binary);
    journal << journal_text(std::string_view(reinterpret_cast<const char*>(data), size));
  }
  camdyn::fuzz::expect_camdyn_errors_only([&] { camdyn::run_study(compare_request(out)); });
  return 0;
}
