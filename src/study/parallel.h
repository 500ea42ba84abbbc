// A parallel for over independent jobs (simulation runs of a study): worker
// threads take the next index from a shared counter, so long and short runs
// balance themselves. Exceptions are the caller's to catch inside `job`.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace camdyn {

/// Runs job(i) for i in [0, count) on `threads` threads (the calling thread included).
template <class Job>
void parallel_for(std::size_t count, int threads, Job&& job) {
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t i = next++; i < count; i = next++) job(i);
  };
  const int extra = std::max(0, std::min<int>(threads, static_cast<int>(count)) - 1);
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(extra));
  for (int k = 0; k < extra; ++k) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
}

}  // namespace camdyn
