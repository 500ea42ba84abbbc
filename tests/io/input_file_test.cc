// Data paths are what they claim (io/input_file.h): a regular file within the
// budget is read; a device, a FIFO, /proc, a folder or a file too large is
// refused, naming the file and the field, before anything is read — and
// without blocking.
#include "io/input_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_run.h"
#include "common/errors.h"
#include "common/study_budget.h"
#include "input_error_of.h"
#include "io/csv_reader.h"
#include "io/json_archive.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

constexpr double kMb = 1024.0 * 1024.0;

void write(const fs::path& file, const std::string& text) { std::ofstream(file, std::ios::binary) << text; }

TEST(InputFile, RegularFileAndASymbolicLinkToOneAreReadWhole) {
  const fs::path dir = test::scratch_dir("input_file", "regular");
  write(dir / "a.csv", "x,y\n1,2\n");
  fs::create_symlink(dir / "a.csv", dir / "link.csv");
  EXPECT_EQ(read_input_file((dir / "a.csv").string(), "f"), "x,y\n1,2\n");
  EXPECT_EQ(read_input_file((dir / "link.csv").string(), "f"), "x,y\n1,2\n");
  EXPECT_EQ(check_input_file((dir / "a.csv").string(), "f"), 8u);
}

TEST(InputFile, DevicesAndProcAreRefusedNamingFileAndField) {
  for (const std::string file : {"/dev/zero", "/dev/null", "/proc/self/mem", "/proc/self/status", "/sys/kernel/mm"}) {
    const InputError error =
        test::input_error_of([&] { read_input_file(file, "mechanism.cam.motion_law.table.file"); });
    EXPECT_EQ(error.file(), file);
    EXPECT_EQ(error.path(), "mechanism.cam.motion_law.table.file");
    EXPECT_NE(error.reason().find("regular file"), std::string::npos) << error.what();
  }
}

TEST(InputFile, ASymbolicLinkToADeviceIsRefused) {
  const fs::path dir = test::scratch_dir("input_file", "link_to_device");
  fs::create_symlink("/dev/zero", dir / "zero.csv");
  const InputError error = test::input_error_of([&] { read_input_file((dir / "zero.csv").string(), "f"); });
  EXPECT_NE(error.reason().find("regular file"), std::string::npos) << error.what();
}

TEST(InputFile, AFifoIsRefusedWithoutWaitingForAWriter) {
  const fs::path dir = test::scratch_dir("input_file", "fifo");
  const fs::path fifo = dir / "table.csv";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  const InputError error = test::input_error_of([&] { read_input_file(fifo.string(), "f"); });
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  EXPECT_NE(error.reason().find("FIFO"), std::string::npos) << error.what();
}

TEST(InputFile, AFolderIsRefused) {
  const fs::path dir = test::scratch_dir("input_file", "folder");
  const InputError error = test::input_error_of([&] { read_input_file(dir.string(), "f"); });
  EXPECT_NE(error.reason().find("a directory"), std::string::npos) << error.what();
}

TEST(InputFile, AFileLargerThanTheBudgetIsRefusedBeforeItIsRead) {
  const fs::path dir = test::scratch_dir("input_file", "oversized");
  const fs::path big = dir / "big.csv";
  write(big, "");
  fs::resize_file(big, std::uintmax_t{1} << 30);  // 1 GiB, sparse: reading it would take seconds and the memory
  const auto start = std::chrono::steady_clock::now();
  const InputError error = test::input_error_of([&] { read_input_file(big.string(), "f", 64.0 * kMb); });
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(1));
  EXPECT_NE(error.reason().find("1024.0 MB"), std::string::npos) << error.what();
  // One byte over the limit is refused, the limit itself is read.
  write(big, std::string(1000, 'x'));
  EXPECT_EQ(read_input_file(big.string(), "f", 1000.0).size(), 1000u);
  test::input_error_of([&] { read_input_file(big.string(), "f", 999.0); });
}

TEST(InputFile, TheDefaultLimitIsTheMemoryBudget) {
  const fs::path dir = test::scratch_dir("input_file", "budget");
  const fs::path file = dir / "a.json";
  write(file, "");
  fs::resize_file(file, std::uintmax_t{3} << 20);  // 3 MiB
  const StudyBudgetScope budget(1e9, 2.0);         // 2 MB
  const InputError error = test::input_error_of([&] { read_json_file(file.string()); });
  EXPECT_NE(error.reason().find("--max-memory"), std::string::npos) << error.what();
}

TEST(InputFile, CsvReaderRefusesADeviceNamingTheConfigField) {
  const InputError error = test::input_error_of([] { read_csv("/dev/zero", {"a"}, 1, "runs[0].reference.file"); });
  EXPECT_EQ(error.file(), "/dev/zero");
  EXPECT_EQ(error.path(), "runs[0].reference.file");
}

TEST(InputFile, CsvHeaderControlCharactersReachTheMessageEscaped) {
  const fs::path dir = test::scratch_dir("input_file", "escape");
  write(dir / "t.csv", "angle_deg,\x1b]0;pwned\x07\x1b[2Jlift\n0,0\n");
  const InputError error = test::input_error_of([&] { read_csv((dir / "t.csv").string(), {"lift"}); });
  const std::string what = error.what();
  EXPECT_EQ(what.find('\x1b'), std::string::npos) << what;
  EXPECT_NE(what.find("\\x1b]0;pwned\\x07\\x1b[2Jlift"), std::string::npos) << what;
}

}  // namespace
}  // namespace camdyn
