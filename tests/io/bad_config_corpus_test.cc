// The bad-config corpus (tests/data/bad_configs): every file there breaks one
// rule. expected.json says which stage must reject it and what the error names.
// "config" files must fail load_scene with an InputError whose path contains
// the expected dotted path and whose message names the file; "geometry" files
// must pass the config layer (the CLI tests check that the cam build rejects them).
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "common/errors.h"
#include "io/config.h"
#include "io/json_archive.h"

namespace camdyn {
namespace {

namespace fs = std::filesystem;

const fs::path kCorpusDir = fs::path(CAMDYN_TEST_DATA_DIR) / "bad_configs";

struct CorpusEntry {
  std::string file;     ///< name inside kCorpusDir
  std::string stage;    ///< "config" or "geometry"
  std::string path;     ///< substring of InputError::path()
  std::string message;  ///< substring of what(), may be empty
};

void PrintTo(const CorpusEntry& e, std::ostream* os) { *os << e.file; }

/// Read at test registration; a broken sidecar gives no entries, which
/// BadConfigCorpus.SidecarListsEveryFile reports.
std::vector<CorpusEntry> load_entries() {
  std::vector<CorpusEntry> entries;
  try {
    const Json expected = read_json_file((kCorpusDir / "expected.json").string());
    for (const auto& item : expected.at("files").items()) {
      const Json& e = item.value();
      entries.push_back({item.key(), e.at("stage").get<std::string>(), e.at("path").get<std::string>(),
                         e.value("message", std::string())});
    }
  } catch (const std::exception&) {
    entries.clear();
  }
  return entries;
}

class BadConfigFile : public testing::TestWithParam<CorpusEntry> {};

TEST_P(BadConfigFile, IsRejectedAtItsStageNamingFileAndPath) {
  const CorpusEntry& entry = GetParam();
  const std::string file = (kCorpusDir / entry.file).string();
  ASSERT_TRUE(fs::is_regular_file(file)) << file;
  if (entry.stage == "geometry") {
    // The config layer accepts it; building the cam is what must fail.
    EXPECT_NO_THROW(load_scene(file));
    return;
  }
  ASSERT_EQ(entry.stage, "config");
  try {
    load_scene(file);
    FAIL() << entry.file << " was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(e.path().find(entry.path), std::string::npos)
        << "path '" << e.path() << "' lacks '" << entry.path << "': " << e.what();
    EXPECT_NE(std::string(e.what()).find(entry.file), std::string::npos)
        << "message does not name the file: " << e.what();
    EXPECT_NE(std::string(e.what()).find(entry.message), std::string::npos)
        << "message lacks '" << entry.message << "': " << e.what();
  }
}

std::string entry_name(const testing::TestParamInfo<CorpusEntry>& info) {
  std::string name = fs::path(info.param.file).stem().string();
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

INSTANTIATE_TEST_SUITE_P(BadConfigCorpus, BadConfigFile, testing::ValuesIn(load_entries()), entry_name);

TEST(BadConfigCorpus, SidecarListsEveryFile) {
  const std::vector<CorpusEntry> entries = load_entries();
  EXPECT_GE(entries.size(), 18u);
  std::set<std::string> listed;
  for (const CorpusEntry& e : entries) {
    listed.insert(e.file);
    EXPECT_TRUE(e.stage == "config" || e.stage == "geometry") << e.file;
  }
  for (const auto& item : fs::directory_iterator(kCorpusDir)) {
    const std::string name = item.path().filename().string();
    if (item.path().extension() != ".json" || name == "good_base.json" || name == "expected.json") {
      continue;
    }
    EXPECT_EQ(listed.count(name), 1u) << name << " is not in expected.json";
  }
}

TEST(BadConfigCorpus, GoodBaseIsAccepted) { EXPECT_NO_THROW(load_scene((kCorpusDir / "good_base.json").string())); }

}  // namespace
}  // namespace camdyn
