// Parallel loops on a few threads, for work whose items are independent:
// results do not depend on the number of threads or on which thread did an
// item.
#pragma once

#include <algorithm>
#include <atomic>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace uwscan {

// Runs fn(i) for every i in [0, count) on `threads` threads. Each thread
// takes the next free block of `block` items until none is left, so a
// thread slowed by costly items or by the machine does not hold the others
// up. An exception in any item stops the loop at the next block and is
// rethrown here, once every thread has stopped.
inline void ParallelFor(int count, int threads, int block, const std::function<void(int)>& fn) {
  if (threads <= 1 || count < 2 * block) {
    for (int i = 0; i < count; ++i) fn(i);
    return;
  }
  std::atomic<int> next{0};
  std::mutex failed;
  std::exception_ptr error;
  auto work = [&] {
    try {
      for (int start = next.fetch_add(block); start < count; start = next.fetch_add(block)) {
        for (int i = start; i < std::min(count, start + block); ++i) fn(i);
      }
    } catch (...) {
      const std::lock_guard<std::mutex> lock(failed);
      if (!error) error = std::current_exception();
      next = count;
    }
  };
  std::vector<std::thread> workers;
  for (int t = 1; t < threads; ++t) workers.emplace_back(work);
  work();  // the calling thread takes blocks too
  for (auto& worker : workers) worker.join();
  if (error) std::rethrow_exception(error);
}

// The machine's cores (at least 1).
inline int MachineThreads() {
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

}  // namespace uwscan
