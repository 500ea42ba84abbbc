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

// Runs at 2 s each on 2 workers: 6 left take 3 rounds of 2 s.
TEST(Progress, RemainingRunsIsMeanDurationTimesRemainingOverWorkers) {
  EXPECT_DOUBLE_EQ(camdyn::remaining_runs_s(8.0, 4, 6, 2), 6.0);
  EXPECT_DOUBLE_EQ(camdyn::remaining_runs_s(8.0, 4, 6, 1), 12.0);
  // Fewer runs left than workers: they run side by side, one duration.
  EXPECT_DOUBLE_EQ(camdyn::remaining_runs_s(8.0, 4, 1, 8), 2.0);
  EXPECT_DOUBLE_EQ(camdyn::remaining_runs_s(8.0, 4, 0, 2), 0.0);
  EXPECT_DOUBLE_EQ(camdyn::remaining_runs_s(0.0, 0, 6, 2), -1.0);  // nothing finished: unknown
  EXPECT_DOUBLE_EQ(camdyn::remaining_runs_s(8.0, 4, 6, 0), 12.0);  // no worker count: one
}

// Ten runs of 1 s and one that ran into its 60 s wall-time budget: the
// budget run counts at its 60 s, once, so 11 more such runs on one worker
// are expected to take 11 × 70/11 s = 70 s, not the budget each.
TEST(Progress, RemainingRunsCountsABudgetHitRunAtItsBudget) {
  const double finished_s = 10 * 1.0 + 60.0;
  EXPECT_DOUBLE_EQ(camdyn::remaining_runs_s(finished_s, 11, 11, 1), 70.0);
  // A run that failed at once adds its (near-zero) time, not the elapsed time.
  EXPECT_NEAR(camdyn::remaining_runs_s(finished_s + 1e-3, 12, 12, 1), 12 * 70.001 / 12, 1e-12);
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

// The session's throughput: 3 of 12 units in 30 s leave 9 units, 90 s;
// whatever the workers, the rate over all of them is what was measured.
TEST(Progress, RemainingWorkIsElapsedTimesWorkLeftOverWorkDone) {
  EXPECT_DOUBLE_EQ(camdyn::remaining_work_s(30.0, 3.0, 12.0), 90.0);
  EXPECT_DOUBLE_EQ(camdyn::remaining_work_s(30.0, 12.0, 12.0), 0.0);
  EXPECT_DOUBLE_EQ(camdyn::remaining_work_s(30.0, 0.0, 12.0), -1.0);  // nothing done: unknown
  // Below kMinWorkForEstimate of the work, no estimate: one run says too little.
  EXPECT_DOUBLE_EQ(camdyn::remaining_work_s(30.0, 0.04, 1.0), -1.0);
  EXPECT_DOUBLE_EQ(camdyn::remaining_work_s(30.0, 0.05, 1.0), 30.0 * 0.95 / 0.05);
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
