// Wall time since a point, for the timings the commands report.
#pragma once

#include <chrono>

namespace uwscan {

inline double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace uwscan
