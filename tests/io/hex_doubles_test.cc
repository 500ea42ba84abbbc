// Doubles as hex text (io/hex_doubles.h): every double comes back to the bit.
#include "io/hex_doubles.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace camdyn {
namespace {

TEST(HexDoubles, EveryKindOfDoubleRoundTripsToTheBit) {
  using L = std::numeric_limits<double>;
  const std::vector<double> values = {
      0.0,         -0.0,          1.0 / 3.0,      -2.5e-300,      L::denorm_min(),         L::max(),
      L::lowest(), L::infinity(), -L::infinity(), L::quiet_NaN(), std::nextafter(1.0, 2.0)};
  const std::string text = doubles_to_hex(values);
  EXPECT_EQ(text.size(), 16 * values.size());
  EXPECT_EQ(text.substr(16, 16), "8000000000000000");  // -0.0: the sign bit only
  const auto back = doubles_from_hex(text, values.size());
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(double_bits(*back), double_bits(values));
}

TEST(HexDoubles, MalformedTextIsNothing) {
  EXPECT_FALSE(doubles_from_hex("3ff000000000000", 1).has_value());   // 15 digits
  EXPECT_FALSE(doubles_from_hex("3ff000000000000g", 1).has_value());  // not hex
  EXPECT_FALSE(doubles_from_hex("3FF0000000000000", 1).has_value());  // upper case is not what is written
  EXPECT_FALSE(doubles_from_hex("3ff0000000000000", 2).has_value());  // one double, two wanted
  EXPECT_EQ(doubles_from_hex("", 0)->size(), 0u);
}

}  // namespace
}  // namespace camdyn
