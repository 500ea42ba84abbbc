// The output folder's lock, completion marker and the sweep of temporaries
// left by killed runs (output/output_folder.h, io/atomic_file.h). The lock
// across processes (a second `camdyn run` into a locked folder exits 2) is
// in tests/cli/output_lock_cli_test.cc; the kill -9 loop in tests/cli/kill_loop.py.
#include "output/output_folder.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_run.h"
#include "common/errors.h"
#include "input_error_of.h"
#include "io/atomic_file.h"
#include "io/config.h"
#include "io/json_archive.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

/// The id of a process that has exited (and been reaped): no process has it
/// now, unless the system reused it in between, which the kernel avoids.
pid_t dead_pid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  return pid;
}

void touch(const fs::path& file) { std::ofstream(file) << "partial"; }

TEST(OutputLock, SecondLockOnTheFolderIsAnInputErrorNamingTheHolder) {
  const fs::path dir = test::scratch_dir("output_folder", "second") / "out";
  const OutputLock first(dir);
  EXPECT_TRUE(fs::exists(dir / kLockFile));
  const InputError e = test::input_error_of([&] { const OutputLock second(dir); });
  EXPECT_EQ(e.file(), dir.string());
  EXPECT_NE(e.reason().find("camdyn process " + std::to_string(::getpid())), std::string::npos) << e.reason();
  EXPECT_NE(e.reason().find("--out"), std::string::npos) << e.reason();
}

TEST(OutputLock, FolderThatIsAFileIsAnInputError) {
  const fs::path dir = test::scratch_dir("output_folder", "file");
  touch(dir / "out");
  const InputError e = test::input_error_of([&] { const OutputLock lock(dir / "out"); });
  EXPECT_EQ(e.file(), (dir / "out").string());
  EXPECT_NE(e.reason().find("cannot create the output folder"), std::string::npos) << e.reason();
}

TEST(OutputLock, ReleasedLockLeavesNoFileAndCanBeTakenAgain) {
  const fs::path dir = test::scratch_dir("output_folder", "again");
  { const OutputLock lock(dir); }
  EXPECT_FALSE(fs::exists(dir / kLockFile));
  EXPECT_TRUE(fs::exists(dir));  // it existed before: kept, even empty
  const OutputLock again(dir);
  EXPECT_TRUE(fs::exists(dir / kLockFile));
}

TEST(OutputLock, LockFileOfAKilledRunDoesNotBlock) {
  // kill -9 leaves the file (with the dead process's id) but not the lock.
  const fs::path dir = test::scratch_dir("output_folder", "killed");
  std::ofstream(dir / kLockFile) << dead_pid() << "\n";
  const OutputLock lock(dir);
  EXPECT_EQ(test::read_text(dir / kLockFile), std::to_string(::getpid()) + "\n");
}

TEST(OutputLock, FolderItCreatedIsRemovedWhenNothingWasWritten) {
  const fs::path base = test::scratch_dir("output_folder", "created");
  { const OutputLock lock(base / "empty"); }
  EXPECT_FALSE(fs::exists(base / "empty"));  // a run that stopped at a bad input leaves nothing
  {
    const OutputLock lock(base / "written");
    touch(base / "written" / "summary.json");
  }
  EXPECT_TRUE(fs::exists(base / "written" / "summary.json"));
  EXPECT_FALSE(fs::exists(base / "written" / kLockFile));
}

TEST(CompletionMarker, IsWrittenAndRemoved) {
  const fs::path dir = test::scratch_dir("output_folder", "marker");
  write_completion_marker(dir, "identify", "identified.json");
  const Json marker = read_json_file((dir / kCompleteFile).string());
  EXPECT_EQ(marker["complete"], true);
  EXPECT_EQ(marker["study"], "identify");
  EXPECT_EQ(marker["main_output"], "identified.json");
  remove_completion_marker(dir);
  EXPECT_FALSE(fs::exists(dir / kCompleteFile));
  remove_completion_marker(dir);  // already gone: fine
}

TEST(StaleTemporaries, ThoseOfDeadProcessesAreRemovedOthersKept) {
  const fs::path dir = test::scratch_dir("output_folder", "stale");
  fs::create_directories(dir / "runs" / "deeper");
  const std::string dead = std::to_string(dead_pid()), alive = std::to_string(::getpid());
  for (const fs::path& f : {dir / ("timeseries.csv.tmp." + dead), dir / ("checkpoint.json.tmp." + dead),
                            dir / "runs" / ("a.csv.tmp." + dead), dir / ("report.html.tmp." + alive),
                            dir / "notes.tmp.txt", dir / "runs" / "deeper" / ("b.csv.tmp." + dead)})
    touch(f);
  remove_stale_temporary_files(dir);
  EXPECT_FALSE(fs::exists(dir / ("timeseries.csv.tmp." + dead)));
  EXPECT_FALSE(fs::exists(dir / ("checkpoint.json.tmp." + dead)));
  EXPECT_FALSE(fs::exists(dir / "runs" / ("a.csv.tmp." + dead)));
  EXPECT_TRUE(fs::exists(dir / ("report.html.tmp." + alive)));               // its process is running
  EXPECT_TRUE(fs::exists(dir / "notes.tmp.txt"));                            // not a temporary of ours
  EXPECT_TRUE(fs::exists(dir / "runs" / "deeper" / ("b.csv.tmp." + dead)));  // deeper than one level
}

// The lock file is never written through a link or a FIFO planted in its
// place (it would be truncated and get a process id): exit 2, naming it.
TEST(OutputLock, SymbolicLinkFifoOrHardLinkAtTheLockFileIsRefusedAndTheVictimKept) {
  const fs::path dir = test::scratch_dir("output_folder", "planted_lock");
  const fs::path victim = dir / "victim.txt";
  std::ofstream(victim) << "precious\n";
  for (const char* kind : {"symlink", "fifo", "hardlink"}) {
    const fs::path out = dir / kind;
    fs::create_directories(out);
    if (std::string(kind) == "symlink") fs::create_symlink(victim, out / kLockFile);
    if (std::string(kind) == "fifo") {
      ASSERT_EQ(::mkfifo((out / kLockFile).c_str(), 0600), 0);
    }
    if (std::string(kind) == "hardlink") fs::create_hard_link(victim, out / kLockFile);
    const InputError error = test::input_error_of([&] { const OutputLock lock(out); });
    EXPECT_EQ(error.file(), (out / kLockFile).string()) << kind << ": " << error.what();
    EXPECT_EQ(test::read_text(victim), "precious\n") << kind;
  }
}

TEST(OutputLock, ItsFolderRefusesSubfoldersThatAreSymbolicLinks) {
  const fs::path dir = test::scratch_dir("output_folder", "subfolder_link");
  fs::create_directories(dir / "elsewhere");
  fs::create_directories(dir / "out");
  fs::create_directory_symlink(dir / "elsewhere", dir / "out" / "orbit");
  {
    const OutputLock lock(dir / "out");
    test::input_error_of([&] { write_file_atomic(dir / "out" / "orbit" / "timeseries.csv", "t\n"); });
  }
  EXPECT_TRUE(fs::is_empty(dir / "elsewhere"));
}

}  // namespace
}  // namespace camdyn
