// Row-parallel loops on a few threads. Work is split by rows only, and
// every row's random stream is seeded from its index, so results do not
// depend on the number of threads or on which thread renders a row.
#pragma once

#include <functional>

#include "uwscan/util/parallel.h"

namespace uwscan::sim {

// Runs fn(y) for every row on `threads` threads, in blocks of 8 rows
// (ParallelFor): a thread slowed by costly rows (a laser line's sub-rays)
// does not hold the others up.
inline void ParallelRows(int rows, int threads, const std::function<void(int)>& fn) {
  ParallelFor(rows, threads, 8, fn);
}

}  // namespace uwscan::sim
