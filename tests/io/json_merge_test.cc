// Deep merge of config documents: objects merge key by key, the patch wins,
// arrays and scalars are replaced, and the paths named "replaced whole" (the
// motion law for configs) are replaced even when both sides are objects.
#include "io/json_merge.h"

#include <gtest/gtest.h>

namespace camdyn {
namespace {

TEST(JsonMerge, ObjectsMergeKeyByKeyPatchWins) {
  Json base = Json::parse(R"({ "a": { "x": 1, "y": 2 }, "b": 3 })");
  deep_merge(base, Json::parse(R"({ "a": { "y": 20, "z": 30 }, "c": 4 })"));
  EXPECT_EQ(base, Json::parse(R"({ "a": { "x": 1, "y": 20, "z": 30 }, "b": 3, "c": 4 })"));
}

TEST(JsonMerge, ArraysScalarsAndNullAreReplaced) {
  Json base = Json::parse(R"({ "list": [1, 2, 3], "n": 1, "o": { "k": 1 }, "s": "x" })");
  deep_merge(base, Json::parse(R"({ "list": [9], "n": null, "o": 5, "s": { "k": 2 } })"));
  EXPECT_EQ(base, Json::parse(R"({ "list": [9], "n": null, "o": 5, "s": { "k": 2 } })"));
}

TEST(JsonMerge, KeepsTheBaseKeyOrderAndAppendsNewKeys) {
  Json base = Json::parse(R"({ "b": 1, "a": 2 })");
  deep_merge(base, Json::parse(R"({ "c": 3, "a": 4 })"));
  EXPECT_EQ(base.dump(), R"({"b":1,"a":4,"c":3})");
}

TEST(JsonMerge, ReplacedWholePathIsNotMergedInto) {
  Json base = Json::parse(R"({ "p": { "q": { "x": 1 }, "r": { "x": 1 } } })");
  deep_merge(base, Json::parse(R"({ "p": { "q": { "y": 2 }, "r": { "y": 2 } } })"), {"p.q"});
  EXPECT_EQ(base, Json::parse(R"({ "p": { "q": { "y": 2 }, "r": { "x": 1, "y": 2 } } })"));
}

TEST(JsonMerge, ConfigMergeReplacesTheMotionLawWhole) {
  Json base = Json::parse(R"({ "mechanism": { "cam": { "rpm": 600,
      "motion_law": { "segments": [ { "type": "dwell", "end_deg": 360 } ] } } } })");
  merge_config(base,
               Json::parse(R"({ "mechanism": { "cam": { "motion_law": { "table": { "file": "lift.csv" } } } } })"));
  EXPECT_EQ(base["mechanism"]["cam"]["rpm"], 600);
  EXPECT_EQ(base["mechanism"]["cam"]["motion_law"], Json::parse(R"({ "table": { "file": "lift.csv" } })"));
}

}  // namespace
}  // namespace camdyn
