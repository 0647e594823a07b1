// Helpers that let the models run on double and on ceres::Jet alike.
#pragma once

#include <ceres/jet.h>

namespace uwscan {

// The value part of a scalar: itself for double, `.a` (recursively) for Jets.
// Iterative solvers run on these values; one final Newton step in T then
// carries exact first derivatives (implicit function theorem).
inline double ScalarOf(double x) { return x; }
template <typename T, int N>
double ScalarOf(const ceres::Jet<T, N>& x) {
  return ScalarOf(x.a);
}

}  // namespace uwscan
