// Row-parallel loops on a few threads. Work is split by rows only, and
// every row's random stream is seeded from its index, so results do not
// depend on the number of threads or on which thread renders a row.
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace uwscan::sim {

// Runs fn(y) for every row on `threads` threads. Each thread takes the next
// free block of rows until none is left, so a thread slowed by costly rows
// (a laser line's sub-rays) or by the machine does not hold the others up.
// An exception in any row stops the loop at the next block and is rethrown
// here, once every thread has stopped.
inline void ParallelRows(int rows, int threads, const std::function<void(int)>& fn) {
  constexpr int kBlock = 8;
  if (threads <= 1 || rows < 2 * kBlock) {
    for (int y = 0; y < rows; ++y) fn(y);
    return;
  }
  std::atomic<int> next{0};
  std::mutex failed;
  std::exception_ptr error;
  auto work = [&] {
    try {
      for (int start = next.fetch_add(kBlock); start < rows; start = next.fetch_add(kBlock)) {
        for (int y = start; y < std::min(rows, start + kBlock); ++y) fn(y);
      }
    } catch (...) {
      const std::lock_guard<std::mutex> lock(failed);
      if (!error) error = std::current_exception();
      next = rows;
    }
  };
  std::vector<std::thread> workers;
  for (int t = 1; t < threads; ++t) workers.emplace_back(work);
  work();  // the calling thread takes blocks too
  for (auto& worker : workers) worker.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace uwscan::sim
