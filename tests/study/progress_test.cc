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
            "compare: 12/40 runs, 1 failed, 00:31 elapsed, ~01:15 left");
  EXPECT_EQ(camdyn::progress_line("compare", 0, 40, 0, 1.0, -1.0),
            "compare: 0/40 runs, 0 failed, 00:01 elapsed, estimating time left");
  EXPECT_EQ(camdyn::progress_line("compare", 40, 40, 2, 100.0, 0.0),
            "compare: 40/40 runs, 2 failed, 01:40 elapsed, done");
}

// A time left is rounded up to what an estimate can tell: 5 s below a
// minute, 15 s below ten minutes, a minute below an hour, then five minutes.
TEST(Progress, TimeLeftIsRoundedUpAndSaysWhenItIsNotKnown) {
  EXPECT_EQ(camdyn::format_time_left(0.4), "~00:05 left");
  EXPECT_EQ(camdyn::format_time_left(32.0), "~00:35 left");
  EXPECT_EQ(camdyn::format_time_left(60.0), "~01:00 left");
  EXPECT_EQ(camdyn::format_time_left(87.0), "~01:30 left");
  EXPECT_EQ(camdyn::format_time_left(601.0), "~11:00 left");
  EXPECT_EQ(camdyn::format_time_left(3725.0), "~1:05:00 left");
  EXPECT_EQ(camdyn::format_time_left(-1.0), "estimating time left");
  EXPECT_EQ(camdyn::format_time_left(std::numeric_limits<double>::quiet_NaN()), "estimating time left");
}

// Forty runs of 10 s on 2 workers: at 10 s two are done, 38 left take 190 s.
// Three such runs: at 10 s one is left, on one worker: 10 s, not 5 s (the
// pace of two workers). One worker: the rate it measured, 3 of 12 in 30 s.
TEST(Progress, RemainingWorkIsTheRatePerWorkerOnTheWorkersStillBusy) {
  EXPECT_DOUBLE_EQ(camdyn::remaining_work_s(10.0, 2.0, 40.0, 2, 40, 38), 190.0);
  EXPECT_DOUBLE_EQ(camdyn::remaining_work_s(10.0, 2.0, 3.0, 2, 3, 1), 10.0);
  EXPECT_DOUBLE_EQ(camdyn::remaining_work_s(30.0, 3.0, 12.0, 1, 12, 9), 90.0);
  // A jump map of two ranges of 4 speeds on 2 workers: at 10 s one range is
  // done and the other has reported one speed; 3 speeds left on one worker
  // at 5 speeds per 20 worker-seconds: 12 s.
  EXPECT_DOUBLE_EQ(camdyn::remaining_work_s(10.0, 5.0, 8.0, 2, 2, 1), 12.0);
  EXPECT_DOUBLE_EQ(camdyn::remaining_work_s(30.0, 12.0, 12.0, 2, 12, 0), 0.0);
  EXPECT_DOUBLE_EQ(camdyn::remaining_work_s(30.0, 0.0, 12.0, 2, 12, 12), -1.0);  // nothing done: unknown
  // Below kMinWorkForEstimate of the work, no estimate: one run says too little.
  EXPECT_DOUBLE_EQ(camdyn::remaining_work_s(30.0, 0.04, 1.0, 1, 1, 1), -1.0);
  EXPECT_NEAR(camdyn::remaining_work_s(30.0, 0.05, 1.0, 1, 1, 1), 570.0, 1e-9);
  EXPECT_DOUBLE_EQ(camdyn::remaining_work_s(30.0, 3.0, 12.0, 0, 12, 9), 90.0);  // no worker count: one
}

// A jump map's two ranges of unequal cost: the meter counts the speeds each
// range reports as it goes, not only the ranges it finishes, and does not
// count a range's speeds twice when the range finishes.
TEST(Progress, MeterCountsWorkReportedInsideRunsOnce) {
  camdyn::ProgressMeter meter("jump_map", 2, 0, 0, 2, false, 8.0);
  camdyn::report_work_done(1.0);  // this thread's run: one speed
  camdyn::report_work_done(2.0);
  meter.finished(false, 0.0, 4.0);  // its four speeds: one more
  EXPECT_EQ(meter.failed(), 0u);
  EXPECT_DOUBLE_EQ(meter.work_done_so_far(), 4.0);
  meter.finished(true, 0.0, 4.0);  // the other range, reported nothing on the way
  EXPECT_DOUBLE_EQ(meter.work_done_so_far(), 8.0);
  EXPECT_EQ(meter.failed(), 1u);
}

// A bisection that needs fewer steps than its bracket allows ends the line there.
TEST(Progress, MeterTotalShrinksToTheRunsDone) {
  camdyn::ProgressMeter meter("speed_limit", 10, 0, 0, 1, false);
  for (int i = 0; i < 4; ++i) meter.finished(false, 0.0);
  meter.set_total(2);  // never below what is done
  EXPECT_EQ(meter.total(), 4u);
  EXPECT_DOUBLE_EQ(meter.session_work(), 4.0);
}

TEST(Progress, RemainingIterationsIsTheRateTimesWhatIsLeft) {
  EXPECT_DOUBLE_EQ(camdyn::remaining_iterations_s(25, 100, 5.0), 15.0);
  EXPECT_DOUBLE_EQ(camdyn::remaining_iterations_s(100, 100, 20.0), 0.0);
  EXPECT_DOUBLE_EQ(camdyn::remaining_iterations_s(120, 100, 20.0), 0.0);
  EXPECT_DOUBLE_EQ(camdyn::remaining_iterations_s(0, 100, 1.0), -1.0);
}

}  // namespace
