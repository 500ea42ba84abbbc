// A parallel for over independent jobs (the runs of a study, the plots of a report): worker
// threads take the next index from a shared counter, so long and short runs
// balance themselves. The first exception a job throws stops the hand-out of
// new jobs and is rethrown on the calling thread once every worker is done.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace camdyn {

/// Runs job(i) for i in [0, count) on `threads` threads (the calling thread included).
template <class Job>
void parallel_for(std::size_t count, int threads, Job&& job) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto worker = [&] {
    for (std::size_t i = next++; i < count; i = next++) {
      try {
        job(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
        next = count;
      }
    }
  };
  const int extra = std::max(0, std::min<int>(threads, static_cast<int>(count)) - 1);
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(extra));
  for (int k = 0; k < extra; ++k) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace camdyn
