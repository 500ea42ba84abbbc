// The files camdyn was not given (docs/outputs-and-resume.md, "What may be in
// the output folder"; docs/config.md, "Data files"): links planted in the
// output folder are refused, not followed; data paths that are devices, FIFOs,
// /proc or too large are refused before they are read and without hanging;
// text from the inputs reaches the terminal escaped; export refuses a tool
// radius that is not a sane number and leaves no scratch file. Each run is
// bounded by timeout(1): a hang shows as exit 124, not a stuck test.
#include <gtest/gtest.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_run.h"
#include "output/output_folder.h"
#include "study_paths.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

const std::string kTableStudy = kSource + "/studies/peers/long_flight.json";
const std::string kPeriodic = kSource + "/studies/periodic/bouncing_ball.json";
const std::string kShortRun = "--set simulation.cycles=2 --set simulation.discard_cycles=1";
constexpr const char* kPathTimeLimitS = "30";

test::Outcome run_path(const std::string& args, const fs::path& dir) {
  std::vector<std::string> argv = {"timeout", kPathTimeLimitS, CAMDYN_BINARY};
  for (const std::string& a : test::split_args(args)) argv.push_back(a);
  return test::run_process(argv, dir, "camdyn");
}

fs::path victim_in(const fs::path& dir) {
  const fs::path victim = dir / "victim.txt";
  std::ofstream(victim) << "precious\n";
  return victim;
}

TEST(UntrustedPathsCli, LockFileThatIsASymbolicLinkExitsTwoAndTheVictimIsUnchanged) {
  const fs::path dir = test::scratch_dir("untrusted_paths_cli", "lock");
  const fs::path victim = victim_in(dir);
  fs::create_directories(dir / "out");
  fs::create_symlink(victim, dir / "out" / kLockFile);
  const test::Outcome o =
      run_path("run " + kQuickstart + " --quiet " + kShortRun + " --out " + (dir / "out").string(), dir);
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_NE(o.err.find((dir / "out" / kLockFile).string() + ": is a symbolic link"), std::string::npos) << o.err;
  EXPECT_EQ(test::read_text(victim), "precious\n");
  EXPECT_FALSE(fs::exists(dir / "out" / "summary.json"));
}

TEST(UntrustedPathsCli, OutputThatIsASymbolicLinkExitsTwoAndTheVictimIsUnchanged) {
  const fs::path dir = test::scratch_dir("untrusted_paths_cli", "summary");
  const fs::path victim = victim_in(dir);
  fs::create_directories(dir / "out");
  fs::create_symlink(victim, dir / "out" / "summary.json");
  const test::Outcome o =
      run_path("run " + kQuickstart + " --quiet " + kShortRun + " --out " + (dir / "out").string(), dir);
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_NE(o.err.find("summary.json: is a symbolic link"), std::string::npos) << o.err;
  EXPECT_EQ(test::read_text(victim), "precious\n");
  EXPECT_TRUE(fs::is_symlink(dir / "out" / "summary.json"));
}

TEST(UntrustedPathsCli, OutputSubfolderThatIsASymbolicLinkIsRefused) {
  const fs::path dir = test::scratch_dir("untrusted_paths_cli", "orbit");
  fs::create_directories(dir / "elsewhere");
  fs::create_directories(dir / "out");
  fs::create_directory_symlink(dir / "elsewhere", dir / "out" / "orbit");
  const test::Outcome o = run_path("run " + kPeriodic + " --quiet --out " + (dir / "out").string(), dir);
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_NE(o.err.find("orbit: is a symbolic link"), std::string::npos) << o.err;
  EXPECT_TRUE(fs::is_empty(dir / "elsewhere"));
}

TEST(UntrustedPathsCli, LiftTableAtADeviceOrAFifoExitsTwoWithoutHanging) {
  const fs::path dir = test::scratch_dir("untrusted_paths_cli", "table");
  const fs::path fifo = dir / "table.csv";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& file : {std::string("/dev/zero"), fifo.string()}) {
    const test::Outcome o =
        run_path("validate " + kTableStudy + " --set mechanism.cam.motion_law.table.file=" + file, dir);
    EXPECT_EQ(o.code, 2) << file << ": " << o.err;
    EXPECT_NE(o.err.find("mechanism.cam.motion_law.table.file"), std::string::npos) << o.err;
    EXPECT_NE(o.err.find("regular file"), std::string::npos) << o.err;
  }
}

TEST(UntrustedPathsCli, OversizedSparseTableIsRefusedBeforeItIsRead) {
  const fs::path dir = test::scratch_dir("untrusted_paths_cli", "oversized");
  const fs::path big = dir / "big.csv";
  std::ofstream(big) << "angle_deg,lift_m";  // no newline: a reader by lines would hold it whole
  fs::resize_file(big, std::uintmax_t{1} << 30);
  const test::Outcome o = run_path(
      "validate " + kTableStudy + " --max-memory 64 --set mechanism.cam.motion_law.table.file=" + big.string(), dir);
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_NE(o.err.find("1024.0 MB, more than the memory budget of 64 MB"), std::string::npos) << o.err;
}

TEST(UntrustedPathsCli, ExtendsOfProcOrAFifoAndACaseConfigAtADeviceExitTwo) {
  const fs::path dir = test::scratch_dir("untrusted_paths_cli", "extends");
  ASSERT_EQ(::mkfifo((dir / "fifo.json").c_str(), 0600), 0);
  for (const std::string& parent : {std::string("/proc/self/mem"), (dir / "fifo.json").string()}) {
    std::ofstream(dir / "child.json") << R"({"extends": ")" << parent << R"("})";
    const test::Outcome o = run_path("validate " + (dir / "child.json").string(), dir);
    EXPECT_EQ(o.code, 2) << parent << ": " << o.err;
    EXPECT_NE(o.err.find("child.json: extends: cannot read"), std::string::npos) << o.err;
  }
  std::ofstream(dir / "compare.json") << R"({"extends": ")" << kQuickstart
                                      << R"(", "study": "compare", "cases": [{"name": "z", "config": "/dev/zero"}]})";
  const test::Outcome o = run_path("validate " + (dir / "compare.json").string(), dir);
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_NE(o.err.find("cases[0].config"), std::string::npos) << o.err;
}

TEST(UntrustedPathsCli, EscapeSequencesInAKeyOrACsvHeaderArePrintedEscaped) {
  const fs::path dir = test::scratch_dir("untrusted_paths_cli", "escape");
  std::ofstream(dir / "key.json") << R"({"extends": ")" << kQuickstart << R"(", "mechan\u001b[2Jism": 1})";
  const test::Outcome key = run_path("validate " + (dir / "key.json").string(), dir);
  EXPECT_EQ(key.code, 2) << key.err;
  EXPECT_NE(key.err.find("mechan\\x1b[2Jism"), std::string::npos) << key.err;
  EXPECT_EQ(key.err.find('\x1b'), std::string::npos) << key.err;
  std::ofstream(dir / "t.csv") << "angle_deg,\x1b]0;pwned\x07lift_m\n0,0\n";
  const test::Outcome header = run_path(
      "validate " + kTableStudy + " --set mechanism.cam.motion_law.table.file=" + (dir / "t.csv").string(), dir);
  EXPECT_EQ(header.code, 2) << header.err;
  EXPECT_NE(header.err.find("\\x1b]0;pwned\\x07lift_m"), std::string::npos) << header.err;
  EXPECT_EQ(header.err.find('\x1b'), std::string::npos) << header.err;
}

TEST(UntrustedPathsCli, ExportWithAHugeOrNanCutterRadiusExitsTwoLeavingNoScratchFile) {
  const fs::path dir = test::scratch_dir("untrusted_paths_cli", "cutter");
  fs::create_directories(dir / "tmp");
  ::setenv("TMPDIR", (dir / "tmp").c_str(), 1);  // where dxflib's scratch folder would go
  for (const std::string radius : {"1e300", "nan", "inf"}) {
    const fs::path out = dir / ("out-" + radius);
    const test::Outcome o =
        run_path("export " + kQuickstart + " --format dxf --cutter-radius " + radius + " --out " + out.string(), dir);
    EXPECT_EQ(o.code, 2) << radius << ": " << o.err;
    EXPECT_NE(o.err.find("--cutter-radius"), std::string::npos) << o.err;
    EXPECT_TRUE(!fs::exists(out) || fs::is_empty(out)) << radius;
  }
  // The same from the config's field.
  const fs::path out = dir / "out-config";
  const test::Outcome o = run_path("run " + kQuickstart + " --quiet " + kShortRun +
                                       " --set outputs.profile.cutter_radius_mm=1e300 --out " + out.string(),
                                   dir);
  EXPECT_EQ(o.code, 2) << o.err;
  EXPECT_NE(o.err.find("outputs.profile.cutter_radius_mm"), std::string::npos) << o.err;
  EXPECT_TRUE(fs::is_empty(dir / "tmp"));
  ::unsetenv("TMPDIR");
}

TEST(UntrustedPathsCli, ExportDxfWithASaneCutterLeavesOnlyItsFiles) {
  const fs::path dir = test::scratch_dir("untrusted_paths_cli", "dxf");
  const fs::path out = dir / "out";
  const test::Outcome o =
      run_path("export " + kQuickstart + " --format dxf --cutter-radius 4 --out " + out.string(), dir);
  ASSERT_EQ(o.code, 0) << o.err;
  for (const auto& entry : fs::directory_iterator(out))
    EXPECT_EQ(entry.path().filename().string().find(".dxflib."), std::string::npos) << entry.path();
}

}  // namespace
}  // namespace camdyn
