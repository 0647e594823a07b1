#!/bin/bash
# Builds the command-line tool with ThreadSanitizer in build-tsan/ (or $1)
# and runs the commands that use threads on small simulated scans: the
# simulator's render threads and PNG writer, the reconstruction's reading
# thread and windowed BA thread, a live replay that drops frames, two
# cameras with two passes, and an external trajectory with the BA on the
# tracking thread: `make tsan`. Takes about 5 min on 2 cores. Stops at
# the first command whose run ThreadSanitizer reports on (exit status 66).
#
# The board detection of `calibrate` is left out: OpenCV runs it on its TBB
# threads, whose synchronisation ThreadSanitizer cannot see (the Debian
# libraries are not instrumented), so it reports races on every image
# between memory OpenCV allocates on one of them and frees on ours.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${1:-build-tsan}
jobs=${JOBS:-$(nproc)}
cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DUWSCAN_BUILD_TESTS=OFF -DUWSCAN_BUILD_BENCH=OFF \
  -DCMAKE_CXX_FLAGS="-fsanitize=thread -fno-omit-frame-pointer" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread"
cmake --build "$build_dir" -j "$jobs" --target uwscan
uwscan=$(realpath "$build_dir/bin/uwscan")
suppressions=$(realpath scripts/tsan.supp)
export TSAN_OPTIONS="halt_on_error=1 exitcode=66 suppressions=$suppressions"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
run() {
  echo "tsan: uwscan $*"
  "$uwscan" "$@" --quiet > /dev/null
}
# Simulates, reconstructs with and without motion compensation, evaluates.
run demo --width 320 --height 240 --frames 60 --out demo
run reconstruct --dataset demo/dataset --out live --live --live-max-lag 0.02
run reconstruct --dataset demo/dataset --out ins --poses demo/dataset/ins.tum --no-async-ba
run simulate hull --out hull --width 320 --height 240 --frames 40 --pods 2 --gain 1 --exposure-ms 2
run reconstruct --dataset hull --out hull_result --passes 2
echo "tsan: no data race reported"
