// The journal of a compare study: records survive reopening, a line cut off
// by a kill is dropped (and the next record starts on a line of its own), a
// journal of another study is refused.
#include "study/journal.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "common/errors.h"

namespace {

namespace fs = std::filesystem;
using camdyn::Journal;
using camdyn::Json;

class JournalTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("camdyn_journal_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    path_ = dir_ / "journal.jsonl";
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string text() const {
    std::ifstream in(path_);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  fs::path dir_, path_;
};

TEST_F(JournalTest, RecordsSurviveReopening) {
  {
    Journal j(path_, "compare", "abc", 3);
    EXPECT_TRUE(j.done().empty());
    j.append(Json{{"index", 2}, {"value", 0.1}});
    j.append(Json{{"index", 0}, {"value", 1e-300}});
  }
  Journal j(path_, "compare", "abc", 3);
  ASSERT_EQ(j.done().size(), 2u);
  EXPECT_EQ(j.done().at(2)["value"].get<double>(), 0.1);  // exact round trip
  EXPECT_EQ(j.done().at(0)["value"].get<double>(), 1e-300);
  EXPECT_FALSE(j.done().count(1));
}

TEST_F(JournalTest, LineCutByAKillIsDropped) {
  { Journal(path_, "compare", "abc", 3).append(Json{{"index", 0}}); }
  std::ofstream(path_, std::ios::app) << R"({"index": 1, "sta)";
  {
    Journal j(path_, "compare", "abc", 3);
    EXPECT_EQ(j.done().size(), 1u);
    j.append(Json{{"index", 1}});
  }
  Journal j(path_, "compare", "abc", 3);
  EXPECT_EQ(j.done().size(), 2u);
  EXPECT_EQ(text().find("sta"), std::string::npos);
}

TEST_F(JournalTest, UnreadableLineIsSkippedAndIndexOutOfRangeIgnored) {
  { Journal(path_, "compare", "abc", 3).append(Json{{"index", 0}}); }
  std::ofstream(path_, std::ios::app) << "garbage\n"
                                      << R"({"index": 7})"
                                      << "\n"
                                      << R"({"index": 2})"
                                      << "\n";
  Journal j(path_, "compare", "abc", 3);
  EXPECT_EQ(j.done().size(), 1u);  // index 2 has no checksum: not trusted either
  EXPECT_TRUE(j.done().count(0));
}

TEST_F(JournalTest, JournalOfAnotherStudyIsRefused) {
  { Journal(path_, "compare", "abc", 3).append(Json{{"index", 0}}); }
  EXPECT_THROW(Journal(path_, "compare", "abd", 3), camdyn::InputError);
  EXPECT_THROW(Journal(path_, "compare", "abc", 4), camdyn::InputError);
  std::ofstream(path_) << "not a journal\n";
  EXPECT_THROW(Journal(path_, "compare", "abc", 3), camdyn::InputError);
}

TEST_F(JournalTest, HeaderCutByAKillStartsAfresh) {
  std::ofstream(path_) << R"({"camdyn_jou)";
  Journal j(path_, "compare", "abc", 3);
  EXPECT_TRUE(j.done().empty());
  EXPECT_EQ(text().find("camdyn_jou\""), std::string::npos);
  EXPECT_NE(text().find(R"("hash":"abc")"), std::string::npos);
}

/// The lines of the journal's text.
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Each record carries the FNV-1a of the study's hash and its compact JSON
// without the checksum (docs/outputs-and-resume.md, "Checksums").
TEST_F(JournalTest, RecordsCarryTheChecksumOfTheirContentAndTheStudy) {
  { Journal(path_, "compare", "abc", 3).append(Json{{"index", 1}, {"value", 0.5}}); }
  const std::vector<std::string> lines = lines_of(text());
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[1], std::string(R"({"index":1,"value":0.5,"checksum":")") +
                          camdyn::fingerprint("abc\n"
                                              R"({"index":1,"value":0.5})") +
                          "\"}");
}

// One changed digit (still valid JSON), a record copied from a journal of
// another study, a record without a checksum (an earlier camdyn): none is
// trusted, each is left to be run again with a warning.
TEST_F(JournalTest, RecordsThatFailTheirChecksumAreNotTrusted) {
  {
    Journal j(path_, "compare", "abc", 3);
    j.append(Json{{"index", 0}, {"value", 1485.25}});
    j.append(Json{{"index", 1}, {"value", 7.0}});
  }
  std::vector<std::string> lines = lines_of(text());
  ASSERT_EQ(lines.size(), 3u);
  const std::size_t digit = lines[1].find("1485");
  ASSERT_NE(digit, std::string::npos);
  lines[1][digit + 1] = '3';  // 1385.25: a value the run never gave
  { Journal(dir_ / "other.jsonl", "compare", "xyz", 3).append(Json{{"index", 2}, {"value", 3.0}}); }
  std::ifstream other(dir_ / "other.jsonl");
  std::string copied;
  std::getline(other, copied);
  std::getline(other, copied);
  std::ofstream(path_, std::ios::trunc) << lines[0] << "\n"
                                        << lines[1] << "\n"
                                        << lines[2] << "\n"
                                        << copied << "\n"
                                        << R"({"index":2,"value":4.0})"
                                        << "\n";
  ::testing::internal::CaptureStderr();
  Journal j(path_, "compare", "abc", 3);
  const std::string warnings = ::testing::internal::GetCapturedStderr();
  ASSERT_EQ(j.done().size(), 1u);
  EXPECT_EQ(j.done().at(1)["value"].get<double>(), 7.0);
  EXPECT_NE(warnings.find("line 2 fails its checksum"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("line 4 fails its checksum"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("line 5 has no checksum"), std::string::npos) << warnings;
}

// A record whose text holds invalid UTF-8 (an error message) still verifies
// after the round trip through the file.
TEST_F(JournalTest, ARecordWithInvalidUtf8StillVerifies) {
  { Journal(path_, "compare", "abc", 3).append(Json{{"index", 0}, {"error", std::string("bad \xff byte")}}); }
  Journal j(path_, "compare", "abc", 3);
  EXPECT_EQ(j.done().size(), 1u);
}

TEST_F(JournalTest, AJournalThatIsNotARegularFileIsRefused) {
  fs::create_directories(path_);
  try {
    Journal j(path_, "compare", "abc", 3);
    ADD_FAILURE() << "a directory was opened as a journal";
  } catch (const camdyn::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a directory, not a regular file"), std::string::npos) << e.what();
  }
  fs::remove(path_);
  ASSERT_EQ(::mkfifo(path_.c_str(), 0644), 0);
  EXPECT_THROW(Journal(path_, "compare", "abc", 3), camdyn::InputError);  // without blocking on the read
}

TEST(Fingerprint, IsFnv1a64) {
  EXPECT_EQ(camdyn::fingerprint(""), "cbf29ce484222325");
  EXPECT_EQ(camdyn::fingerprint("a"), "af63dc4c8601ec8c");
  EXPECT_NE(camdyn::fingerprint("ab"), camdyn::fingerprint("ba"));
}

}  // namespace
