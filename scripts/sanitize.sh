#!/bin/bash
# Builds the tests with AddressSanitizer and UndefinedBehaviorSanitizer in
# build-sanitize/ (or $1) and runs them: `make sanitize`. Takes about 20 min
# to build and 25 min to run on 2 cores (the pipeline tests run 5-10x
# slower), so it is not part of `make test`.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${1:-build-sanitize}
jobs=${JOBS:-$(nproc)}
# Eigen allocates with its own alignment offset under AddressSanitizer
# (Memory.h: no EIGEN_MALLOC_ALREADY_ALIGNED with __SANITIZE_ADDRESS__),
# while the Debian Ceres library was built to allocate with plain malloc:
# a matrix allocated in Ceres and freed here would be reported as a heap
# overflow. glibc's and the sanitizer's malloc both align to 16 bytes, all
# that Eigen needs without AVX, so keep Ceres's convention.
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
flags+=" -DEIGEN_MALLOC_ALREADY_ALIGNED=1"
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined"
cmake --build "$build_dir" -j "$jobs"
export ASAN_OPTIONS=detect_leaks=1:halt_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
cd "$build_dir" && ctest --output-on-failure -j "$jobs" --timeout 1800
