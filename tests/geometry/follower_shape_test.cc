// The follower shapes' description (scene/follower_shape.h): every shape a
// config can name is described, with a label and the contact element, rolling
// and config fields of docs/model.md §1 and §4; its word round-trips; and
// FollowerGeometry answers from the same description.
#include "scene/follower_shape.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "geometry/follower_geometry.h"

namespace camdyn {
namespace {

// The description is usable at compile time.
static_assert(follower_shape_traits(FollowerShape::roller).rolls);
static_assert(!follower_shape_traits(FollowerShape::flat).circle());

TEST(FollowerShape, EveryShapeHasAWordALabelAndOneContactField) {
  std::set<std::string> labels;
  for (const EnumName<FollowerShape>& entry : enum_names(FollowerShape{})) {
    ASSERT_FALSE(entry.name.empty());
    EXPECT_EQ(parse_enum<FollowerShape>(entry.name), entry.value);
    EXPECT_EQ(to_string(entry.value), entry.name);
    const FollowerShapeTraits shape = follower_shape_traits(entry.value);
    EXPECT_FALSE(shape.label.empty()) << entry.name;
    EXPECT_TRUE(labels.insert(std::string(shape.label)).second) << "label twice: " << shape.label;
    // Exactly one of radius and face_width sizes the contact element.
    EXPECT_NE(shape.takes_radius(), shape.takes_face_width()) << entry.name;
    EXPECT_EQ(shape.takes_radius(), shape.circle()) << entry.name;
    // Only a circle can spin on an axle.
    EXPECT_TRUE(!shape.rolls || shape.circle()) << entry.name;
    EXPECT_EQ(shape.takes_inertia(), shape.rolls) << entry.name;
  }
  EXPECT_EQ(labels.size(), enum_name_list<FollowerShape>().size());
}

struct ShapeCase {
  const char* word;
  FollowerContact contact;
  bool rolls;
  const char* label;
};

class FollowerShapeTraitsTest : public ::testing::TestWithParam<ShapeCase> {};

TEST_P(FollowerShapeTraitsTest, AreThoseOfPhysics) {
  const ShapeCase& c = GetParam();
  const FollowerShape value = parse_enum<FollowerShape>(c.word);
  const FollowerShapeTraits shape = follower_shape_traits(value);
  EXPECT_EQ(shape.contact, c.contact);
  EXPECT_EQ(shape.rolls, c.rolls);
  EXPECT_EQ(shape.label, c.label);

  FollowerGeometry g;
  g.shape = value;
  EXPECT_EQ(g.circle(), c.contact == FollowerContact::circle);
  EXPECT_EQ(g.rolls(), c.rolls);
  EXPECT_EQ(g.traits().label, c.label);
}

INSTANTIATE_TEST_SUITE_P(Shapes, FollowerShapeTraitsTest,
                         ::testing::Values(ShapeCase{"roller", FollowerContact::circle, true, "roller"},
                                           ShapeCase{"flat", FollowerContact::line, false, "flat face"},
                                           ShapeCase{"mushroom", FollowerContact::circle, false, "mushroom"}),
                         [](const ::testing::TestParamInfo<ShapeCase>& p) { return std::string(p.param.word); });

}  // namespace
}  // namespace camdyn
