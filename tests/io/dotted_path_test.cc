// Dotted paths: parsing into key and index steps (with the cam/follower/contact
// short form), finding a field with the reason a step is missing, setting a
// field with the `--set` error messages.
#include "io/dotted_path.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/errors.h"

namespace camdyn {
namespace {

const std::string kHint =
    " (expected a dotted path like mechanism.cam.rpm or mechanism.cam.motion_law.segments[0].lift)";

InputError parse_error(const std::string& path) {
  try {
    parse_dotted_path(path);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for " << path;
  return InputError("", "", "");
}

InputError set_error(Json& document, const std::string& path) {
  try {
    set_dotted_field(document, path, 1);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError for " << path;
  return InputError("", "", "");
}

Json scene() {
  return Json::parse(R"({ "mechanism": { "cam": { "rpm": 900,
      "motion_law": { "segments": [ { "lift": 0.02 }, { "lift": 0.0 } ] } } }, "name": "s" })");
}

TEST(DottedPath, ParsesKeysAndIndices) {
  const std::vector<PathStep> steps = parse_dotted_path("a.b[2][10].c_1");
  ASSERT_EQ(steps.size(), 5u);
  EXPECT_EQ(steps[0].key, "a");
  EXPECT_EQ(steps[1].key, "b");
  EXPECT_TRUE(steps[2].is_index());
  EXPECT_EQ(steps[2].index, 2u);
  EXPECT_EQ(steps[3].index, 10u);
  EXPECT_EQ(steps[4].key, "c_1");
}

TEST(DottedPath, ShortFormGetsMechanismInFront) {
  for (const std::string head : {"cam", "follower", "contact"}) {
    const std::vector<PathStep> steps = parse_dotted_path(head + ".x");
    ASSERT_EQ(steps.size(), 3u);
    EXPECT_EQ(steps[0].key, "mechanism");
    EXPECT_EQ(full_dotted_path(head + ".x"), "mechanism." + head + ".x");
    EXPECT_EQ(full_dotted_path(head + "[0]"), "mechanism." + head + "[0]");
  }
  EXPECT_EQ(parse_dotted_path("camshaft.x").front().key, "camshaft");
  EXPECT_EQ(full_dotted_path("camshaft.x"), "camshaft.x");
  EXPECT_EQ(full_dotted_path("mechanism.cam.rpm"), "mechanism.cam.rpm");
}

TEST(DottedPath, BadSyntaxNamesTheReasonAndThePath) {
  const std::vector<std::pair<std::string, std::string>> cases = {{"a..b", "empty key"},
                                                                  {"", "empty key"},
                                                                  {"a.b.", "empty key"},
                                                                  {"a[x]", "bad array index"},
                                                                  {"a[0", "bad array index"},
                                                                  {"a[1234567890]", "bad array index"},
                                                                  {"mech anism", "unexpected character ' '"},
                                                                  {"a[0]b", "unexpected character after ']'"}};
  for (const auto& [path, reason] : cases) {
    const InputError e = parse_error(path);
    EXPECT_EQ(e.file(), "--set") << path;
    EXPECT_EQ(e.path(), path);
    EXPECT_EQ(e.reason(), reason + kHint) << path;
  }
}

TEST(DottedPath, FindsFieldsOrSaysWhichStepIsMissing) {
  const Json doc = scene();
  std::string why;
  const Json* lift = find_dotted_field(doc, "cam.motion_law.segments[0].lift", why);
  ASSERT_NE(lift, nullptr) << why;
  EXPECT_EQ(*lift, 0.02);
  EXPECT_EQ(find_dotted_field(doc, "mechanism.cam.rpmm", why), nullptr);
  EXPECT_EQ(why, "'rpmm' is not a field of 'mechanism.cam' (did you mean 'rpm'?)");
  EXPECT_EQ(find_dotted_field(doc, "nam", why), nullptr);
  EXPECT_EQ(why, "'nam' is not a field of the scene (did you mean 'name'?)");
  EXPECT_EQ(find_dotted_field(doc, "mechanism.cam.motion_law.segments[2].lift", why), nullptr);
  EXPECT_EQ(why, "'mechanism.cam.motion_law.segments' has no element 2");
  EXPECT_EQ(find_dotted_field(doc, "mechanism.cam.rpm[0]", why), nullptr);
  EXPECT_EQ(why, "'mechanism.cam.rpm' has no element 0");
  EXPECT_EQ(find_dotted_field(doc, "name.x", why), nullptr);
  EXPECT_EQ(why, "'x' is not a field of 'name'");
  EXPECT_EQ(find_dotted_field(doc, "a[x]", why), nullptr);
  EXPECT_EQ(why, "bad array index" + kHint);
}

TEST(DottedPath, SetCreatesMissingObjectsAndReplacesValues) {
  Json doc = scene();
  set_dotted_field(doc, "cam.rpm", 1200);
  set_dotted_field(doc, "mechanism.cam.motion_law.segments[1].lift", 0.01);
  set_dotted_field(doc, "integrator.max_step", 1e-5);
  set_dotted_field(doc, "mechanism.follower.initial.position", nullptr);
  set_dotted_field(doc, "mechanism.follower.initial.position.x", 2);  // a null on the way becomes an object
  EXPECT_EQ(doc["mechanism"]["cam"]["rpm"], 1200);
  EXPECT_EQ(doc["mechanism"]["cam"]["motion_law"]["segments"][1]["lift"], 0.01);
  EXPECT_EQ(doc["integrator"]["max_step"], 1e-5);
  EXPECT_EQ(doc["mechanism"]["follower"]["initial"]["position"]["x"], 2);
}

TEST(DottedPath, SetRejectsStepsIntoTheWrongKindOfValue) {
  Json doc = scene();
  InputError e = set_error(doc, "mechanism.cam.rpm.value");
  EXPECT_EQ(e.file(), "--set");
  EXPECT_EQ(e.path(), "mechanism.cam.rpm.value");
  EXPECT_EQ(e.reason(), "'mechanism.cam.rpm' is 900, not an object");
  EXPECT_EQ(set_error(doc, "cam[0]").reason(), "'mechanism.cam' is an object, not an array");
  EXPECT_EQ(set_error(doc, "cam.motion_law.segments[5].lift").reason(),
            "index 5 is out of range: 'mechanism.cam.motion_law.segments' has 2 elements");
  EXPECT_EQ(doc, scene());  // nothing changed by a failed set
}

}  // namespace
}  // namespace camdyn
