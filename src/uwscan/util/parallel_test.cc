#include "uwscan/util/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

#include "uwscan/sim/parallel.h"

namespace uwscan {
namespace {

// Every item once, in blocks of one (a folder's images) or eight (the
// simulator's rows), on any number of threads.
TEST(ParallelForTest, EveryItemOnceOnAnyNumberOfThreads) {
  for (int block : {1, 8}) {
    for (int threads : {1, 2, 3, 5}) {
      for (int count : {0, 1, 2, 7, 16, 101}) {
        std::vector<std::atomic<int>> seen(static_cast<size_t>(count));
        ParallelFor(count, threads, block, [&](int i) { ++seen[static_cast<size_t>(i)]; });
        for (int i = 0; i < count; ++i)
          EXPECT_EQ(seen[static_cast<size_t>(i)].load(), 1)
              << threads << " threads, block " << block << ", item " << i;
      }
    }
  }
  std::vector<std::atomic<int>> rows(40);
  sim::ParallelRows(40, 2, [&](int y) { ++rows[static_cast<size_t>(y)]; });
  for (const auto& row : rows) EXPECT_EQ(row.load(), 1);
}

TEST(ParallelForTest, AnErrorInAnItemReachesTheCaller) {
  for (int block : {1, 8}) {
    for (int threads : {1, 2, 3}) {
      std::atomic<int> done{0};
      EXPECT_THROW(ParallelFor(200, threads, block,
                               [&](int i) {
                                 if (i == 150) throw std::runtime_error("item 150");
                                 ++done;
                               }),
                   std::runtime_error);
      EXPECT_LT(done.load(), 200);
    }
  }
}

}  // namespace
}  // namespace uwscan
