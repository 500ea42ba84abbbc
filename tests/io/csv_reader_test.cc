// The numeric CSV reader: values, comments, and an InputError naming the file
// and the line or column for each kind of bad input.
#include "io/csv_reader.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "common/errors.h"
#include "common/study_budget.h"

namespace camdyn {
namespace {

class CsvReader : public ::testing::Test {
 protected:
  /// Writes `text` to a fresh file in the test temp dir and returns its path.
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = ::testing::TempDir() + "camdyn_csv_reader_" + name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  /// Reads and expects an InputError with this path and a reason containing `reason_part`.
  void expect_error(const std::string& file, const std::vector<std::string>& columns, const std::string& path,
                    const std::string& reason_part, std::size_t min_rows = 1) {
    try {
      read_csv(file, columns, min_rows);
      ADD_FAILURE() << "no InputError for " << file;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), file) << e.what();
      EXPECT_EQ(e.path(), path) << e.what();
      EXPECT_NE(e.reason().find(reason_part), std::string::npos) << e.what();
    }
  }
};

TEST_F(CsvReader, ReadsRequestedColumnsSkippingCommentsAndOtherColumns) {
  const std::string f = write("good.csv",
                              "\xEF\xBB\xBF# measured drop test\r\n"
                              "time, \"force_N\" ,note\r\n"
                              "0.0, 1.5, start\r\n"
                              "\r\n"
                              "# a comment between rows\r\n"
                              "1e-3,+2.25e1,\r\n"
                              "2e-3,-3,end\r\n");
  const CsvColumns csv = read_csv(f, {"force_N", "time"});
  ASSERT_EQ(csv.rows(), 3u);
  EXPECT_EQ(csv["time"], (std::vector<double>{0.0, 1e-3, 2e-3}));
  EXPECT_EQ(csv["force_N"], (std::vector<double>{1.5, 22.5, -3.0}));
  EXPECT_EQ(csv.lines, (std::vector<int>{3, 6, 7}));
  EXPECT_EQ(csv.names, (std::vector<std::string>{"force_N", "time"}));
  EXPECT_THROW(csv["note"], std::out_of_range);
}

// The rows a file may bring are bounded by the memory budget while it is
// read (common/study_budget.h): refused naming the first line past it.
TEST_F(CsvReader, AFileBeyondTheMemoryBudgetIsRefusedWhileItIsRead) {
  std::string text = "angle,lift\n";
  for (int i = 0; i < 20000; ++i) text += std::to_string(i) + ",0.5\n";
  const std::string f = write("big.csv", text);
  {
    // A row costs 2 (2 × 8 + 4) + 128 = 168 bytes: 1 MB holds 6241 of them.
    const StudyBudgetScope budget(1e9, 1.0);
    expect_error(f, {"angle", "lift"}, "line 6244", "more than the memory budget of 1 MB (--max-memory)");
  }
  EXPECT_EQ(read_csv(f, {"angle", "lift"}).rows(), 20000u);  // the default budget holds them
}

TEST_F(CsvReader, ReadsTheGeometryTestTable) {
  const CsvColumns csv = read_csv(CAMDYN_TEST_DATA_DIR "/geometry/periodic_lift.csv", {"angle_deg", "lift"}, 4);
  ASSERT_EQ(csv.rows(), 13u);
  EXPECT_EQ(csv["angle_deg"].back(), 360.0);
  EXPECT_EQ(csv["lift"][5], 0.0125);
}

TEST_F(CsvReader, MissingColumnNamesTheColumn) {
  const std::string f = write("missing_col.csv", "angle_deg,lift\n0,0\n");
  expect_error(f, {"angle_deg", "lift_m"}, "column lift_m", "not in the header");
}

TEST_F(CsvReader, NanValueNamesTheLine) {
  const std::string f = write("nan.csv", "# c\nangle_deg,lift\n0,0\n10,nan\n");
  expect_error(f, {"angle_deg", "lift"}, "line 4", "NaN");
  const std::string g = write("inf.csv", "angle_deg,lift\n0,-inf\n");
  expect_error(g, {"angle_deg", "lift"}, "line 2", "not finite");
}

TEST_F(CsvReader, NonNumericValueNamesTheLine) {
  const std::string f = write("text.csv", "angle_deg,lift\n0,0\n10,0.001\n20,abc\n");
  expect_error(f, {"angle_deg", "lift"}, "line 4", "'abc' is not a number");
  const std::string g = write("partial.csv", "angle_deg,lift\n0,1.5mm\n");
  expect_error(g, {"angle_deg", "lift"}, "line 2", "'1.5mm'");
  const std::string h = write("empty_field.csv", "angle_deg,lift\n0,\n");
  expect_error(h, {"angle_deg", "lift"}, "line 2", "empty");
}

TEST_F(CsvReader, UnrequestedTextColumnIsIgnoredButFieldCountMustMatch) {
  const std::string f = write("fields.csv", "a,b\n1,x\n2\n");
  expect_error(f, {"a"}, "line 3", "has 1 fields, the header has 2");
}

TEST_F(CsvReader, MissingFileEmptyFileAndTooFewRows) {
  const std::string missing = ::testing::TempDir() + "camdyn_csv_reader_does_not_exist.csv";
  expect_error(missing, {"a"}, "", "cannot open");
  const std::string empty = write("empty.csv", "# only a comment\n");
  expect_error(empty, {"a"}, "", "no header");
  const std::string short_file = write("short.csv", "a\n1\n2\n");
  expect_error(short_file, {"a"}, "", "at least 3", 3);
}

TEST_F(CsvReader, DuplicateHeaderNameIsAmbiguous) {
  const std::string f = write("dup.csv", "a,a\n1,2\n");
  expect_error(f, {"a"}, "column a", "more than once");
}

}  // namespace
}  // namespace camdyn
