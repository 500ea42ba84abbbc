// The output folder across processes (docs/outputs-and-resume.md): a run into
// a folder another process holds exits 2 naming that process and leaves the
// folder alone; a finished run writes complete.json, a failed one does not
// and removes the previous run's. The kill -9 loop is tests/cli/kill_loop.py.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "cli_run.h"
#include "output/output_folder.h"
#include "study_paths.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

const std::string kShort = "--set simulation.cycles=2 --set simulation.discard_cycles=1";

test::Outcome run_locked(const std::string& args, const fs::path& dir) {
  return test::run_camdyn(test::split_args(args), dir);
}

TEST(OutputLockCli, RunIntoAFolderAnotherProcessHoldsExitsTwoNamingIt) {
  const fs::path dir = test::scratch_dir("output_lock_cli", "held");
  const fs::path out = dir / "out";
  {
    const OutputLock held(out);  // this test process is "the other run"
    const test::Outcome o = run_locked("run " + kQuickstart + " --quiet " + kShort + " --out " + out.string(), dir);
    EXPECT_EQ(o.code, 2) << o.err;
    EXPECT_NE(o.err.find("in use by camdyn process " + std::to_string(::getpid())), std::string::npos) << o.err;
    EXPECT_NE(o.err.find(out.string()), std::string::npos) << o.err;
    EXPECT_FALSE(fs::exists(out / "summary.json"));  // it wrote nothing
  }
  const test::Outcome o = run_locked("run " + kQuickstart + " --quiet " + kShort + " --out " + out.string(), dir);
  EXPECT_EQ(o.code, 0) << o.err;
  EXPECT_TRUE(fs::exists(out / kCompleteFile));
  EXPECT_FALSE(fs::exists(out / kLockFile));
}

TEST(OutputLockCli, CompletionMarkerOnlyAfterAFinishedRun) {
  const fs::path dir = test::scratch_dir("output_lock_cli", "marker");
  const fs::path out = dir / "out";
  EXPECT_EQ(run_locked("run " + kQuickstart + " --quiet " + kShort + " --out " + out.string(), dir).code, 0);
  ASSERT_TRUE(fs::exists(out / kCompleteFile));
  // A run that fails (here on its input) leaves the folder unfinished: the
  // marker of the run before is gone, whatever else is left.
  const test::Outcome failed = run_locked(
      "run " + kQuickstart + " --quiet " + kShort + " --set mechanism.cam.rpm=-1 --out " + out.string(), dir);
  EXPECT_EQ(failed.code, 2) << failed.err;
  EXPECT_FALSE(fs::exists(out / kCompleteFile));
  EXPECT_FALSE(fs::exists(out / kLockFile));
}

}  // namespace
}  // namespace camdyn
