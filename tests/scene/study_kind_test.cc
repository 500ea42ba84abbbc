// The study registry (scene/study_kind.h): every study a config in studies/
// names is registered, and every registered study has its word, its main
// output, its help line and an example config that exists. That each has a
// runner is the compiler's check (the exhaustive switch in cli/run_study.cc);
// tests/cli/cli_test.cc runs each example through `camdyn validate` and checks
// that `camdyn run --help` lists it.
#include "scene/study_kind.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

namespace camdyn {
namespace {

namespace fs = std::filesystem;
const fs::path kSourceDir = CAMDYN_SOURCE_DIR;

TEST(StudyRegistry, EveryEntryHasItsWordOutputHelpAndAnExampleThatExists) {
  std::set<std::string> names, outputs;
  for (const StudyInfo& study : kStudies) {
    EXPECT_TRUE(names.insert(std::string(study.name)).second) << "registered twice: " << study.name;
    EXPECT_TRUE(outputs.insert(std::string(study.main_output)).second) << "main output shared: " << study.main_output;
    EXPECT_EQ(enum_name(study.kind), study.name);
    EXPECT_EQ(&study_info(study.kind), &study);
    EXPECT_FALSE(study.help.empty()) << study.name;
    EXPECT_TRUE(fs::is_regular_file(kSourceDir / study.example)) << study.name << ": " << study.example;
  }
  EXPECT_EQ(enum_name_list<StudyKind>().size(), kStudies.size());
}

TEST(StudyRegistry, EveryStudyNamedInStudiesIsRegistered) {
  std::set<std::string> used;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(kSourceDir / "studies")) {
    if (entry.path().extension() != ".json") continue;
    std::ifstream in(entry.path());
    const nlohmann::json doc = nlohmann::json::parse(in, nullptr, false);
    ASSERT_FALSE(doc.is_discarded()) << entry.path();
    if (!doc.is_object() || !doc.contains("study")) continue;
    ASSERT_TRUE(doc["study"].is_string()) << entry.path();
    const std::string study = doc["study"].get<std::string>();
    EXPECT_TRUE(enum_from_name<StudyKind>(study).has_value()) << entry.path() << ": study '" << study << "'";
    used.insert(study);
  }
  EXPECT_TRUE(used.contains("simulate")) << "the walk found no study configs";
}

}  // namespace
}  // namespace camdyn
