// Row-parallel loops on a few threads. Work is split by rows only, and
// every row's random stream is seeded from its index, so results do not
// depend on the number of threads.
#pragma once

#include <algorithm>
#include <functional>
#include <thread>
#include <vector>

namespace uwscan::sim {

// Runs fn(y) for every row on `threads` threads (interleaved blocks of rows).
inline void ParallelRows(int rows, int threads, const std::function<void(int)>& fn) {
  constexpr int kBlock = 8;
  if (threads <= 1 || rows < 2 * kBlock) {
    for (int y = 0; y < rows; ++y) fn(y);
    return;
  }
  std::vector<std::thread> workers;
  for (int t = 0; t < threads; ++t) {
    workers.emplace_back([&, t] {
      for (int start = t * kBlock; start < rows; start += threads * kBlock) {
        for (int y = start; y < std::min(rows, start + kBlock); ++y) fn(y);
      }
    });
  }
  for (auto& worker : workers) worker.join();
}

}  // namespace uwscan::sim
