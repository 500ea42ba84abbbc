#include "io/atomic_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "common/errors.h"
#include "input_error_of.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test, removed afterwards.
class AtomicFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ =
        fs::temp_directory_path() / ("camdyn-atomic-" + std::string(info->name()) + "-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  static std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  // Everything in the directory: temporary files must not linger.
  std::size_t entries() const {
    return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }

  fs::path dir_;
};

TEST_F(AtomicFileTest, WriteCreatesParentsAndLeavesNoTempFile) {
  const fs::path path = dir_ / "a" / "b" / "out.txt";
  write_file_atomic(path, "hello\n");
  EXPECT_EQ(read(path), "hello\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(path.parent_path()), fs::directory_iterator()), 1);
}

TEST_F(AtomicFileTest, WriteReplacesExistingFile) {
  const fs::path path = dir_ / "out.txt";
  write_file_atomic(path, "old content that is longer");
  write_file_atomic(path, "new");
  EXPECT_EQ(read(path), "new");
  EXPECT_EQ(entries(), 1u);
}

TEST_F(AtomicFileTest, NothingVisibleUntilCommit) {
  const fs::path path = dir_ / "out.txt";
  AtomicFile file(path);
  file.stream() << "partial";
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::exists(file.temp_path()));
  EXPECT_EQ(file.temp_path().parent_path(), path.parent_path());
  file.commit();
  EXPECT_EQ(read(path), "partial");
  EXPECT_FALSE(fs::exists(file.temp_path()));
}

TEST_F(AtomicFileTest, UncommittedLeavesNeitherFile) {
  const fs::path path = dir_ / "out.txt";
  fs::path temp;
  {
    AtomicFile file(path);
    temp = file.temp_path();
    file.stream() << "abandoned";
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(temp));
  EXPECT_EQ(entries(), 0u);
}

TEST_F(AtomicFileTest, UncommittedKeepsPreviousVersion) {
  const fs::path path = dir_ / "out.txt";
  write_file_atomic(path, "complete");
  {
    AtomicFile file(path);
    file.stream() << "truncated";
  }
  EXPECT_EQ(read(path), "complete");
  EXPECT_EQ(entries(), 1u);
}

TEST_F(AtomicFileTest, UnwritableDirectoryThrowsWithPath) {
  fs::create_directories(dir_);
  const fs::path blocker = dir_ / "file";
  write_file_atomic(blocker, "x");
  // A regular file where a directory is needed.
  try {
    write_file_atomic(blocker / "out.txt", "y");
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(blocker.string()), std::string::npos) << e.what();
  }
}

// kill -9 during a write leaves `<name>.tmp.<pid>`; the next write of that
// file removes it once its process is gone, and leaves a live one alone.
TEST_F(AtomicFileTest, StaleTemporaryOfAKilledRunIsRemovedOnTheNextWrite) {
  fs::create_directories(dir_);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) ::_exit(0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);  // reaped: the pid is gone
  const fs::path path = dir_ / "timeseries.csv";
  const fs::path stale = dir_ / ("timeseries.csv.tmp." + std::to_string(child));
  const fs::path live = dir_ / ("timeseries.csv.tmp." + std::to_string(::getppid()));
  const fs::path other = dir_ / ("summary.json.tmp." + std::to_string(child));
  for (const fs::path& p : {stale, live, other}) std::ofstream(p) << "partial";
  write_file_atomic(path, "t\n");
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));   // its process still runs
  EXPECT_TRUE(fs::exists(other));  // another file's: removed when that file is written
  write_file_atomic(dir_ / "summary.json", "{}");
  EXPECT_FALSE(fs::exists(other));
  EXPECT_EQ(read(path), "t\n");
}

// Outputs cannot be redirected (docs/outputs-and-resume.md): a link, FIFO or
// device planted where camdyn writes is an InputError naming it, and the
// file a link names keeps its bytes.
TEST_F(AtomicFileTest, SymbolicLinkAtTheTemporaryNameIsRefusedAndItsTargetKept) {
  fs::create_directories(dir_);
  const fs::path victim = dir_ / "victim.txt";
  write_file_atomic(victim, "precious\n");
  const fs::path path = dir_ / "summary.json";
  const fs::path planted = dir_ / ("summary.json.tmp." + std::to_string(::getpid()));
  fs::create_symlink(victim, planted);
  const InputError error = test::input_error_of([&] { write_file_atomic(path, "{}"); });
  EXPECT_EQ(error.file(), planted.string());
  EXPECT_NE(error.reason().find("a symbolic link"), std::string::npos) << error.what();
  EXPECT_EQ(read(victim), "precious\n");
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::is_symlink(planted));  // not ours to remove
}

TEST_F(AtomicFileTest, SymbolicLinkFifoOrFolderAtTheFinalNameIsRefused) {
  fs::create_directories(dir_);
  const fs::path victim = dir_ / "victim.txt";
  write_file_atomic(victim, "precious\n");
  fs::create_symlink(victim, dir_ / "link.json");
  ASSERT_EQ(::mkfifo((dir_ / "fifo.json").c_str(), 0600), 0);
  fs::create_directory(dir_ / "folder.json");
  for (const char* name : {"link.json", "fifo.json", "folder.json"}) {
    const InputError error = test::input_error_of([&] { write_file_atomic(dir_ / name, "{}"); });
    EXPECT_EQ(error.file(), (dir_ / name).string());
  }
  EXPECT_EQ(read(victim), "precious\n");
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.json"));
  EXPECT_EQ(entries(), 4u);  // the victim, the three planted: no temporary left
}

TEST_F(AtomicFileTest, StaleRegularFileAtTheTemporaryNameIsReplaced) {
  fs::create_directories(dir_);
  const fs::path path = dir_ / "out.txt";
  std::ofstream(dir_ / ("out.txt.tmp." + std::to_string(::getpid()))) << "left by an earlier writer";
  write_file_atomic(path, "new");
  EXPECT_EQ(read(path), "new");
  EXPECT_EQ(entries(), 1u);
}

TEST_F(AtomicFileTest, SubfolderOfAnOutputFolderThatIsASymbolicLinkIsRefused) {
  const fs::path elsewhere = dir_ / "elsewhere";
  const fs::path out = dir_ / "out";
  fs::create_directories(elsewhere);
  fs::create_directories(out);
  fs::create_directory_symlink(elsewhere, out / "orbit");
  {
    const OutputFolderRoot root(out);
    const InputError error = test::input_error_of([&] { write_file_atomic(out / "orbit" / "summary.json", "{}"); });
    EXPECT_EQ(error.file(), (out / "orbit").string());
    EXPECT_TRUE(fs::is_empty(elsewhere));
  }
  // The output folder itself may be a link (the user named it), and outside a
  // registered output folder nothing is checked above the file.
  fs::create_directory_symlink(out, dir_ / "out-link");
  const OutputFolderRoot root(dir_ / "out-link");
  write_file_atomic(dir_ / "out-link" / "summary.json", "{}");
  EXPECT_EQ(read(out / "summary.json"), "{}");
}

}  // namespace
}  // namespace camdyn
