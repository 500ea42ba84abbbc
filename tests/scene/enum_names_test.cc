// The scene's enums and their config words (scene/enum_names.h): every value a
// config can name has exactly one word, the words read back to the value, and
// a word that names nothing is refused with the list of words.
#include <gtest/gtest.h>

#include <set>
#include <stdexcept>
#include <string>

#include "scene/scene.h"

namespace camdyn {
namespace {

template <NamedEnum E>
void expect_words_round_trip(std::size_t expected_words) {
  std::set<std::string> seen;
  for (const EnumName<E>& entry : enum_names(E{})) {
    if (entry.name.empty()) continue;  // a value no config can name (e.g. SegmentLaw::none)
    EXPECT_TRUE(seen.insert(std::string(entry.name)).second) << "word twice: " << entry.name;
    ASSERT_TRUE(enum_from_name<E>(entry.name).has_value()) << entry.name;
    EXPECT_EQ(*enum_from_name<E>(entry.name), entry.value) << entry.name;
    EXPECT_EQ(enum_name(entry.value), entry.name);
  }
  EXPECT_EQ(seen.size(), expected_words);
  EXPECT_EQ(enum_name_list<E>().size(), expected_words);
}

TEST(EnumNames, EveryWordReadsBackToItsValue) {
  expect_words_round_trip<SegmentType>(3);
  expect_words_round_trip<SegmentLaw>(7);
  expect_words_round_trip<Motor>(2);
  expect_words_round_trip<Drive>(2);
  expect_words_round_trip<RotationDirection>(2);
  expect_words_round_trip<FollowerShape>(3);
  expect_words_round_trip<FollowerMotion>(2);
  expect_words_round_trip<FrictionRegularization>(2);
  expect_words_round_trip<ContactModel>(5);
  expect_words_round_trip<Tracking>(2);
  expect_words_round_trip<PairFormChoice>(2);
  expect_words_round_trip<IntegrationMethod>(6);
  expect_words_round_trip<JacobianSource>(2);
  expect_words_round_trip<ErrorEstimateMethod>(2);
}

TEST(EnumNames, TheWordsAreThoseOfTheInterface) {
  EXPECT_EQ(to_string(SegmentType::return_), "return");
  EXPECT_EQ(to_string(PairFormChoice::automatic), "auto");
  EXPECT_EQ(to_string(ContactModel::lankarani_nikravesh), "lankarani_nikravesh");
  EXPECT_EQ(enum_name(SegmentLaw::none), "");
  EXPECT_EQ(enum_name(SegmentType::unset), "");
}

TEST(EnumNames, AWordThatNamesNothingIsRefusedWithTheWords) {
  EXPECT_FALSE(enum_from_name<Tracking>("newtonian").has_value());
  EXPECT_FALSE(enum_from_name<SegmentLaw>("").has_value());  // "no law" cannot be asked for
  try {
    parse_enum<Tracking>("newtonian");
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "'newtonian' is not one of 'differential', 'newton'");
  }
  EXPECT_EQ(parse_enum<IntegrationMethod>("rk4"), IntegrationMethod::rk4);
}

TEST(EnumNames, DefaultsThatAConfigMustReplaceHaveNoWord) {
  // A segment's type and law have no default a config could mean: the loader
  // reports them missing (io/json_archive.h), the geometry refuses them.
  EXPECT_EQ(SegmentConfig{}.type, SegmentType::unset);
  EXPECT_EQ(SegmentConfig{}.law, SegmentLaw::none);
}

}  // namespace
}  // namespace camdyn
