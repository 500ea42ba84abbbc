// The journal of a compare study: records survive reopening, a line cut off
// by a kill is dropped (and the next record starts on a line of its own), a
// journal of another study is refused.
#include "study/journal.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

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
  EXPECT_EQ(j.done().size(), 2u);
  EXPECT_TRUE(j.done().count(2));
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

TEST(Fingerprint, IsFnv1a64) {
  EXPECT_EQ(camdyn::fingerprint(""), "cbf29ce484222325");
  EXPECT_EQ(camdyn::fingerprint("a"), "af63dc4c8601ec8c");
  EXPECT_NE(camdyn::fingerprint("ab"), camdyn::fingerprint("ba"));
}

}  // namespace
