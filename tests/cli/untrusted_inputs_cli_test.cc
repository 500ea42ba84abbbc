// The cases of issue 36's outside attack that untrusted_paths_cli_test.cc
// does not hold yet (docs/fuzzing.md, "Regression tests of the
// untrusted-input cases"): a compare case config or an identification record
// that is a FIFO, a study journal that is a FIFO or a planted link, and
// journal records whose checksum was recomputed around a field of the wrong
// shape (journal_fuzzer's findings), a train too stiff for double precision
// and a follower radius far larger than the cam (probe_fields.py, run_fuzzer,
// export_fuzzer).
// Each run is bounded by timeout(1): a hang shows as exit 124, not a stuck test.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "io/config.h"
#include "study/journal.h"
#include "study_paths.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

const std::string kIdentifyStudy = std::string(CAMDYN_TEST_DATA_DIR) + "/identify/single.json";
constexpr const char* kInputTimeLimitS = "30";

test::Outcome run_input(const std::string& args, const fs::path& dir) {
  std::vector<std::string> argv = {"timeout", kInputTimeLimitS, CAMDYN_BINARY};
  for (const std::string& a : test::split_args(args)) argv.push_back(a);
  return test::run_process(argv, dir, "camdyn");
}

// A compare study of two short runs of the quickstart cam, the second overlaid in the report.
fs::path small_compare(const fs::path& dir) {
  const fs::path config = dir / "compare.json";
  std::ofstream(config) << R"({"extends": ")" << kQuickstart << R"(", "name": "small", "study": "compare",
    "simulation": {"cycles": 2, "discard_cycles": 1},
    "grid": {"mechanism.cam.rpm": [600, 700]}, "overlays": [{"mechanism.cam.rpm": 700}]})";
  return config;
}

// The journal of `config` (into `out`) holding `records`, each given the
// checksum camdyn would give it (study/journal.h: FNV-1a of the study's
// fingerprint and the record): the header comes from a start on a budget
// already used up, which writes the header only.
void forge_journal(const fs::path& config, const fs::path& out, const std::vector<Json>& records) {
  const test::Outcome first =
      run_input("run " + config.string() + " --quiet --max-study-time 1e-9 --out " + out.string(), out.parent_path());
  ASSERT_EQ(first.code, 3) << first.err;
  const std::string text = test::read_text(out / "journal.jsonl");
  const std::string header_line = text.substr(0, text.find('\n'));
  const std::string hash = Json::parse(header_line)["hash"].get<std::string>();
  std::ofstream journal(out / "journal.jsonl");
  journal << header_line << "\n";
  for (Json record : records) {
    record["checksum"] = fingerprint(hash + "\n" + record.dump());
    journal << record.dump() << "\n";
  }
}

TEST(UntrustedInputsCli, CompareCaseConfigAtAFifoExitsTwoWithoutHanging) {
  const fs::path dir = test::scratch_dir("untrusted_inputs_cli", "case_fifo");
  ASSERT_EQ(::mkfifo((dir / "case.json").c_str(), 0600), 0);
  std::ofstream(dir / "compare.json") << R"({"extends": ")" << kQuickstart
                                      << R"(", "study": "compare", "cases": [{"name": "z", "config": ")"
                                      << (dir / "case.json").string() << R"("}]})";
  const test::Outcome o = run_input("validate " + (dir / "compare.json").string(), dir);
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_NE(o.err.find("cases[0].config"), std::string::npos) << o.err;
}

TEST(UntrustedInputsCli, IdentificationRecordAtAFifoOrADeviceExitsTwoWithoutHanging) {
  const fs::path dir = test::scratch_dir("untrusted_inputs_cli", "record_fifo");
  const fs::path fifo = dir / "record.csv";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& file : {std::string("/dev/zero"), fifo.string()}) {
    const test::Outcome o = run_input("validate " + kIdentifyStudy + " --set reference.file=" + file, dir);
    EXPECT_EQ(o.code, 2) << file << ": " << o.err;
    EXPECT_NE(o.err.find("reference.file"), std::string::npos) << o.err;
    EXPECT_NE(o.err.find("regular file"), std::string::npos) << o.err;
  }
}

TEST(UntrustedInputsCli, JournalThatIsAFifoExitsTwoWithoutHanging) {
  const fs::path dir = test::scratch_dir("untrusted_inputs_cli", "journal_fifo");
  fs::create_directories(dir / "out");
  ASSERT_EQ(::mkfifo((dir / "out" / "journal.jsonl").c_str(), 0600), 0);
  const test::Outcome o =
      run_input("run " + small_compare(dir).string() + " --quiet --out " + (dir / "out").string(), dir);
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_NE(o.err.find("journal.jsonl"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("FIFO"), std::string::npos) << o.err;
}

TEST(UntrustedInputsCli, JournalThatIsASymbolicLinkExitsTwoAndTheVictimIsUnchanged) {
  const fs::path dir = test::scratch_dir("untrusted_inputs_cli", "journal_link");
  const fs::path victim = dir / "victim.txt";
  std::ofstream(victim) << "precious\n";
  fs::create_directories(dir / "out");
  fs::create_symlink(victim, dir / "out" / "journal.jsonl");
  const test::Outcome o =
      run_input("run " + small_compare(dir).string() + " --quiet --out " + (dir / "out").string(), dir);
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_NE(o.err.find("journal.jsonl"), std::string::npos) << o.err;
  EXPECT_EQ(test::read_text(victim), "precious\n");
  EXPECT_TRUE(fs::is_symlink(dir / "out" / "journal.jsonl"));
}

// A journal header edited by hand whose study, hash or run count is of
// another type (journal_fuzzer's finding: read with Json::value, nlohmann's
// type_error 302, exit 1): exit 2 naming the journal, as any other study's.
TEST(UntrustedInputsCli, JournalHeaderWithFieldsOfAnotherTypeExitsTwo) {
  const fs::path dir = test::scratch_dir("untrusted_inputs_cli", "journal_header_types");
  const fs::path config = small_compare(dir);
  for (const std::string& header : {std::string(R"({"camdyn_journal":1,"study":5,"hash":"x","runs":4})"),
                                    std::string(R"({"camdyn_journal":1,"study":"compare","hash":[1],"runs":-4})")}) {
    fs::create_directories(dir / "out");
    std::ofstream(dir / "out" / "journal.jsonl") << header << "\n";
    const test::Outcome o = run_input("run " + config.string() + " --quiet --out " + (dir / "out").string(), dir);
    EXPECT_EQ(o.code, 2) << header << ": " << o.err;
    EXPECT_NE(o.err.find("journal.jsonl"), std::string::npos) << o.err;
    EXPECT_NE(o.err.find("journal of a different compare study"), std::string::npos) << o.err;
  }
}

// A record that passes its checksum but whose "status" is a number (edited,
// then the FNV-1a checksum recomputed: it is no secret) was trusted and then
// read as a string: exit 1. That run is now done again.
TEST(UntrustedInputsCli, JournalRecordWithAValidChecksumButNoStatusTextIsRunAgain) {
  const fs::path dir = test::scratch_dir("untrusted_inputs_cli", "journal_status");
  const fs::path config = small_compare(dir);
  forge_journal(config, dir / "out", {Json{{"index", 0}, {"status", 5}, {"error", ""}, {"metrics", Json::object()}}});
  const test::Outcome o = run_input("run " + config.string() + " --quiet --out " + (dir / "out").string(), dir);
  EXPECT_EQ(o.code, 0) << o.err;
  EXPECT_NE(o.err.find("the record of run 0 has no status; that run is done again"), std::string::npos) << o.err;
  const std::string csv = test::read_text(dir / "out" / "comparison.csv");
  EXPECT_EQ(csv.find("failed"), std::string::npos) << csv;
}

// An overlaid run's record whose overlay lacks a series (journal_fuzzer's
// finding: the report read it with at(), exit 1): the report is written
// without that overlay.
TEST(UntrustedInputsCli, JournalRecordWithAMalformedOverlayStillWritesTheReport) {
  const fs::path dir = test::scratch_dir("untrusted_inputs_cli", "journal_overlay");
  const fs::path config = small_compare(dir);
  const Json overlay = {{"cam_angle_deg", {0.0, 180.0}}, {"follower_position", {0.0, 0.02}}};  // no contact_force
  forge_journal(
      config, dir / "out",
      {Json{{"index", 1}, {"status", "ok"}, {"error", ""}, {"metrics", Json::object()}, {"overlay", overlay}}});
  const test::Outcome o = run_input("run " + config.string() + " --quiet --out " + (dir / "out").string(), dir);
  EXPECT_EQ(o.code, 0) << o.err;
  EXPECT_TRUE(fs::exists(dir / "out" / "report.html")) << o.err;
}

// A follower train whose stiffness matrix loses its rank in floating point
// (probe_fields.py, run_fuzzer): exit 1 "held train: K is singular" as an
// internal error before; now exit 2 naming the train.
TEST(UntrustedInputsCli, TrainWithAnExtremeStiffnessOrRatioExitsTwoNamingTheTrain) {
  const fs::path dir = test::scratch_dir("untrusted_inputs_cli", "train_extreme");
  const std::string rocker = kSource + "/studies/valvetrain/pushrod_rocker.json";
  for (const std::string& set :
       {std::string("mechanism.train[1].link.ratio=2e9"), std::string("mechanism.train[1].link.stiffness=1e300")}) {
    const test::Outcome o = run_input("validate " + rocker + " --set " + set, dir);
    EXPECT_EQ(o.code, 2) << set << ": " << o.err;
    EXPECT_NE(o.err.find("mechanism.train: a stiffness or lever ratio of the train is too extreme"), std::string::npos)
        << o.err;
  }
}

// export_fuzzer's finding: a roller of 1e300 mm read a NaN lift and the CSV
// writer's guard ended the export with exit 1. Now refused before any file
// is written (by the option's own range, and behind it by the export's
// limit of 1000 × the base radius, as for a cutter).
TEST(UntrustedInputsCli, ExportWithAFollowerFarLargerThanTheCamExitsTwoWritingNothing) {
  const fs::path dir = test::scratch_dir("untrusted_inputs_cli", "export_roller");
  const test::Outcome o =
      run_input("export " + kQuickstart + " --out " + (dir / "out").string() + " --follower-radius 1e300", dir);
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_NE(o.err.find("--follower-radius"), std::string::npos) << o.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "follower_lift.csv"));
}

}  // namespace
// A jump map's range record that passes its checksum but whose points are
// not what camdyn writes (the checksum recomputed: it is no secret) was read
// with at() and get(): exit 1. It is an input error naming the journal.
TEST(UntrustedInputsCli, JumpMapRecordWithAValidChecksumButMalformedPointsExitsTwo) {
  const fs::path dir = test::scratch_dir("untrusted_inputs_cli", "jump_map_record");
  const fs::path config = dir / "map.json";
  std::ofstream(config) << R"({"extends": ")" << kQuickstart << R"(", "name": "map", "study": "jump_map",
    "jump_map": {"low_rpm": 1000, "high_rpm": 1100, "speeds": 2, "ranges": 1, "transient_revolutions": 3,
                 "samples": 3}, "periodic": {"max_period": 1, "lyapunov_revolutions": 10}})";
  forge_journal(config, dir / "out", {Json{{"index", 0}, {"status", "ok"}, {"points", {Json{{"rpm", "fast"}}}}}});
  const test::Outcome o = run_input("run " + config.string() + " --quiet --out " + (dir / "out").string(), dir);
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_NE(o.err.find("journal.jsonl"), std::string::npos) << o.err;
  EXPECT_NE(o.err.find("speed range 0"), std::string::npos) << o.err;
}

}  // namespace camdyn
