// The one worker pool of camdyn: a parallel for over independent jobs (the
// runs of a study, the plots of a report, the simulations of a design
// evaluation). Worker threads take the next index from a shared counter, so
// long and short runs balance themselves. The first exception a job throws
// stops the hand-out of new jobs and is rethrown on the calling thread once
// every worker is done. Threads live for one call: a caller that keeps a
// workspace per thread indexes it by the worker number parallel_for_workers
// passes.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace camdyn {

/// Runs job(worker, i) for i in [0, count) on min(threads, count) threads, the
/// calling thread included (worker 0); `worker` in [0, max(threads, 1)) is the
/// number of the thread running the job, e.g. to pick its workspace.
template <class Job>
void parallel_for_workers(std::size_t count, int threads, Job&& job) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto worker = [&](int w) {
    for (std::size_t i = next++; i < count; i = next++) {
      try {
        job(w, i);
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
  for (int k = 0; k < extra; ++k) pool.emplace_back(worker, k + 1);
  worker(0);
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

/// Runs job(i) for i in [0, count) on `threads` threads (the calling thread included).
template <class Job>
void parallel_for(std::size_t count, int threads, Job&& job) {
  parallel_for_workers(count, threads, [&job](int /*worker*/, std::size_t i) { job(i); });
}

}  // namespace camdyn
