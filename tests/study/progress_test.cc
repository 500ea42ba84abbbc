#include "study/progress.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace {

TEST(Progress, Durations) {
  EXPECT_EQ(camdyn::format_duration(0.0), "00:00");
  EXPECT_EQ(camdyn::format_duration(31.4), "00:31");
  EXPECT_EQ(camdyn::format_duration(72.0), "01:12");
  EXPECT_EQ(camdyn::format_duration(3725.0), "1:02:05");
  EXPECT_EQ(camdyn::format_duration(-1.0), "--:--");
  EXPECT_EQ(camdyn::format_duration(std::numeric_limits<double>::infinity()), "--:--");
}

TEST(Progress, Line) {
  EXPECT_EQ(camdyn::progress_line("compare", 12, 40, 1, 31.0, 72.0),
            "compare: 12/40 runs, 1 failed, 00:31 elapsed, ~01:12 left");
  EXPECT_EQ(camdyn::progress_line("compare", 0, 40, 0, 1.0, -1.0),
            "compare: 0/40 runs, 0 failed, 00:01 elapsed, ~--:-- left");
  EXPECT_EQ(camdyn::progress_line("compare", 40, 40, 2, 100.0, 0.0),
            "compare: 40/40 runs, 2 failed, 01:40 elapsed, done");
}

}  // namespace
