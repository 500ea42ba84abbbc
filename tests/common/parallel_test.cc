// The worker pool (common/parallel.h): every index runs exactly once, each on
// a worker numbered below the thread count, and the first exception of a job
// reaches the caller after every worker is done.
#include "common/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace camdyn {
namespace {

TEST(ParallelFor, EveryIndexRunsOnceForAnyThreadCount) {
  for (const int threads : {0, 1, 2, 5, 64}) {
    std::vector<std::atomic<int>> runs(37);
    parallel_for(runs.size(), threads, [&](std::size_t i) { ++runs[i]; });
    for (std::size_t i = 0; i < runs.size(); ++i) EXPECT_EQ(runs[i].load(), 1) << "threads " << threads << ", i " << i;
  }
  parallel_for(0, 4, [](std::size_t) { FAIL() << "no job for count 0"; });
}

TEST(ParallelForWorkers, WorkerNumbersAreBelowTheThreadCountAndDistinctPerThread) {
  constexpr int kThreads = 3;
  std::mutex mutex;
  std::set<int> workers;
  std::vector<int> worker_of(200, -1);
  parallel_for_workers(worker_of.size(), kThreads, [&](int worker, std::size_t i) {
    worker_of[i] = worker;
    const std::lock_guard<std::mutex> lock(mutex);
    workers.insert(worker);
  });
  for (const int w : worker_of) {
    EXPECT_GE(w, 0);
    EXPECT_LT(w, kThreads);
  }
  EXPECT_FALSE(workers.empty());
  // With one thread the calling thread runs everything as worker 0.
  parallel_for_workers(5, 1, [](int worker, std::size_t) { EXPECT_EQ(worker, 0); });
}

TEST(ParallelFor, FirstExceptionIsRethrownAndStopsTheHandOut) {
  std::atomic<int> started{0};
  EXPECT_THROW(parallel_for(1000, 2,
                            [&](std::size_t i) {
                              ++started;
                              if (i == 3) throw std::runtime_error("job 3");
                              std::this_thread::sleep_for(std::chrono::milliseconds(1));
                            }),
               std::runtime_error);
  EXPECT_LT(started.load(), 1000);
}

}  // namespace
}  // namespace camdyn
