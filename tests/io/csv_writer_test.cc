#include "io/csv_writer.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/json_writer.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

class CsvTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("camdyn-csv-" + std::string(info->name()) + "-" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  fs::path dir_;
};

TEST_F(CsvTest, WritesHeaderAndRows) {
  const fs::path path = dir_ / "t.csv";
  CsvWriter csv(path, {"time", "gap"});
  csv.row({0.0, 1.5});
  csv.row(std::vector<double>{0.25, -2e-9});
  EXPECT_FALSE(fs::exists(path));  // atomic: only after commit
  csv.commit();
  EXPECT_EQ(read(path), "time,gap\n0,1.5\n0.25,-2e-09\n");
  EXPECT_EQ(csv.rows_written(), 2u);
}

TEST_F(CsvTest, NumbersRoundTrip) {
  const std::vector<double> values = {0.1, 1.0 / 3.0, 6.02214076e23, 5e-324, std::numeric_limits<double>::max(), -0.0};
  // strtod, not std::stod: stod throws on the subnormal 5e-324.
  for (double v : values) EXPECT_EQ(std::strtod(format_double(v).c_str(), nullptr), v) << format_double(v);
}

TEST_F(CsvTest, MixedCellsAreQuotedWhenNeeded) {
  const fs::path path = dir_ / "m.csv";
  CsvWriter csv(path, {"case", "rpm", "value", "error"});
  csv.row({"cyc", 1500, 0.5, "says \"no\", twice"});
  csv.row({std::string("a\nb"), std::size_t{2}, 1.0, ""});
  csv.commit();
  EXPECT_EQ(read(path), "case,rpm,value,error\ncyc,1500,0.5,\"says \"\"no\"\", twice\"\n\"a\nb\",2,1,\n");
}

TEST_F(CsvTest, NaNIsRefusedNamingTheColumn) {
  const fs::path path = dir_ / "n.csv";
  {
    CsvWriter csv(path, {"time", "contact_force"});
    csv.row({0.0, 1.0});
    try {
      csv.row({0.1, std::nan("")});
      FAIL() << "expected std::logic_error";
    } catch (const std::logic_error& e) {
      EXPECT_NE(std::string(e.what()).find("contact_force"), std::string::npos) << e.what();
    }
    EXPECT_THROW(csv.row({"x", std::numeric_limits<double>::infinity()}), std::logic_error);
  }
  // The writer was never committed: nothing is left behind.
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(CsvTest, WrongCellCountIsRefused) {
  CsvWriter csv(dir_ / "c.csv", {"a", "b"});
  EXPECT_THROW(csv.row({1.0}), std::logic_error);
  EXPECT_THROW(csv.row({1.0, 2.0, 3.0}), std::logic_error);
}

// Rows from columns: the same text as row by row, across many flushes of the
// writer's buffer, and every number reads back to the same double.
TEST_F(CsvTest, RowsFromColumnsMatchRowByRowAndRoundTrip) {
  std::vector<double> a, b, c;
  std::uint64_t bits = 0x9e3779b97f4a7c15ULL;
  for (int i = 0; i < 50000; ++i) {  // about 3 MB: several buffers
    bits = bits * 6364136223846793005ULL + 1442695040888963407ULL;
    const double noise = static_cast<double>(bits >> 11) * 0x1.0p-53;  // [0, 1), full 53-bit mantissas
    a.push_back(1e-5 * i);
    b.push_back((noise - 0.5) * std::pow(10.0, i % 40 - 20));
    c.push_back(i % 7 == 0 ? -0.0 : 1.0 / (i + 1));
  }
  const std::vector<const std::vector<double>*> columns = {&a, &b, &c};
  CsvWriter bulk(dir_ / "bulk.csv", {"a", "b", "c"});
  bulk.rows_from_columns(columns);
  EXPECT_EQ(bulk.rows_written(), a.size());
  bulk.commit();
  CsvWriter single(dir_ / "single.csv", {"a", "b", "c"});
  for (std::size_t i = 0; i < a.size(); ++i) single.row({a[i], b[i], c[i]});
  single.commit();
  const std::string text = read(dir_ / "bulk.csv");
  EXPECT_EQ(text, read(dir_ / "single.csv"));

  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "a,b,c");
  std::size_t row = 0;
  while (std::getline(in, line)) {
    ASSERT_LT(row, a.size());
    const std::size_t p = line.find(','), q = line.find(',', p + 1);
    ASSERT_NE(q, std::string::npos) << line;
    EXPECT_EQ(std::strtod(line.substr(0, p).c_str(), nullptr), a[row]);
    EXPECT_EQ(std::strtod(line.substr(p + 1, q - p - 1).c_str(), nullptr), b[row]);
    const double back = std::strtod(line.substr(q + 1).c_str(), nullptr);
    EXPECT_EQ(back, c[row]);
    EXPECT_EQ(std::signbit(back), std::signbit(c[row]));
    ++row;
  }
  EXPECT_EQ(row, a.size());
}

TEST_F(CsvTest, RowsFromColumnsRefuseBadInputLeavingNoPartialRow) {
  const fs::path path = dir_ / "r.csv";
  const std::vector<double> t = {0.0, 0.1, 0.2}, f = {1.0, std::nan(""), 3.0}, short_column = {1.0};
  {
    CsvWriter csv(path, {"time", "contact_force"});
    const std::vector<const std::vector<double>*> one = {&t};
    EXPECT_THROW(csv.rows_from_columns(one), std::logic_error);
    const std::vector<const std::vector<double>*> ragged = {&t, &short_column};
    EXPECT_THROW(csv.rows_from_columns(ragged), std::logic_error);
    const std::vector<const std::vector<double>*> with_nan = {&t, &f};
    try {
      csv.rows_from_columns(with_nan);
      FAIL() << "expected std::logic_error";
    } catch (const std::logic_error& e) {
      EXPECT_NE(std::string(e.what()).find("'contact_force', row 2"), std::string::npos) << e.what();
    }
    EXPECT_EQ(csv.rows_written(), 1u);
    csv.row({0.5, 0.5});
    csv.commit();
  }
  // The row with the NaN left nothing: the next row follows the first.
  EXPECT_EQ(read(path), "time,contact_force\n0,1\n0.5,0.5\n");
}

// The JSON writer shares the fixture: same temporary directory handling.
using JsonTest = CsvTest;

TEST_F(JsonTest, WrittenWithTwoSpaceIndent) {
  const fs::path path = dir_ / "s.json";
  nlohmann::ordered_json doc = {{"name", "x"}, {"metrics", {{"b", 1.5}, {"a", 2}}}};
  write_json_atomic(path, doc);
  EXPECT_EQ(read(path), "{\n  \"name\": \"x\",\n  \"metrics\": {\n    \"b\": 1.5,\n    \"a\": 2\n  }\n}\n");
}

TEST_F(JsonTest, NaNIsRefusedNamingThePointer) {
  const fs::path path = dir_ / "s.json";
  nlohmann::ordered_json doc;
  doc["metrics"]["peak/force"] = 1.0;
  doc["series"] = {1.0, 2.0, std::numeric_limits<double>::infinity()};
  try {
    write_json_atomic(path, doc);
    FAIL() << "expected std::logic_error";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("/series/2"), std::string::npos) << e.what();
  }
  doc["series"] = {1.0};
  doc["metrics"]["peak/force"] = std::nan("");
  try {
    write_json_atomic(path, doc);
    FAIL() << "expected std::logic_error";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("/metrics/peak~1force"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace camdyn
