#!/usr/bin/env bash
# CLI: uwscan vo synth / vo / evaluate on a small rendered dataset, bad
# frames (black, wrong size, missing) and usage errors.
set -u
bin="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$bin" vo synth --out "$dir/seq" --frames 60 --width 320 --length 1.5 2>/dev/null \
  || fail "vo synth"
for f in rig.yaml frames.csv groundtruth.tum frames/000059.png; do
  [ -f "$dir/seq/$f" ] || fail "vo synth did not write $f"
done

# Clean run with the laser masked: every frame after initialisation posed.
"$bin" vo --dataset "$dir/seq" --out "$dir/t.tum" --mask-laser --status "$dir/status.csv" \
  2>"$dir/log" || fail "vo: $(cat "$dir/log")"
poses=$(grep -vc '^#' "$dir/t.tum")
[ "$poses" -ge 54 ] || fail "only $poses poses"
grep -q "^59,.*,tracked," "$dir/status.csv" || fail "last frame not tracked"
! grep -q "mosaic" "$dir/log" || fail "mono frames taken for a mosaic: $(cat "$dir/log")"
"$bin" evaluate --dataset "$dir/seq" --trajectory "$dir/t.tum" >"$dir/eval" || fail "evaluate"
ate=$(sed -n 's/^ATE (after alignment): rmse \([0-9.]*\) m.*/\1/p' "$dir/eval")
drift=$(sed -n 's/^drift (KITTI.*): \([0-9.]*\) % translation.*/\1/p' "$dir/eval")
awk -v a="$ate" 'BEGIN { exit !(a < 0.004) }' || fail "ATE $ate m too large"
awk -v d="$drift" 'BEGIN { exit !(d < 1.0) }' || fail "drift $drift % too large"
grep -q "RPE per frame" "$dir/eval" || fail "no RPE"
# The motion of what the camera looks at: not without a scene (vo synth
# writes none) unless its distance is given; a negative one is a usage error.
! grep -q "ahead on the optical axis" "$dir/eval" || fail "viewed point without a scene"
"$bin" evaluate --dataset "$dir/seq" --trajectory "$dir/t.tum" --viewed-depth 2 >"$dir/veval" \
  || fail "evaluate --viewed-depth"
grep -q "^the point 2.000 m ahead on the optical axis (the scene): moved [0-9.]* of the truth; [0-9]* % of the camera's translation error is a turn about it$" \
  "$dir/veval" || fail "no viewed-point line: $(cat "$dir/veval")"
"$bin" evaluate --dataset "$dir/seq" --trajectory "$dir/t.tum" --viewed-depth -1 2>"$dir/err" >/dev/null
[ $? -eq 2 ] || fail "--viewed-depth -1: want exit 2"
grep -q -- "--viewed-depth must be" "$dir/err" || fail "--viewed-depth error does not say why"
# A KLT window our tracker does not have: a usage error, no output.
"$bin" vo --dataset "$dir/seq" --out "$dir/w.tum" --klt-window 65 2>"$dir/err" >/dev/null
[ $? -eq 2 ] || fail "--klt-window 65: want exit 2"
grep -q -- "--klt-window must be odd, 5 to 63, got 65" "$dir/err" || fail "--klt-window error: $(cat "$dir/err")"
[ ! -e "$dir/w.tum" ] || fail "--klt-window 65 left a trajectory"
# The other figures' options: usage errors (exit 2) naming the option and what it got.
for option in "--lengths -1" "--lengths nan" "--rpe-step 0" "--max-dt -1" "--max-dt nan" \
  "--rpe-from nan" "--rpe-from 5 --rpe-to 1"; do
  "$bin" evaluate --dataset "$dir/seq" --trajectory "$dir/t.tum" $option 2>"$dir/err" >/dev/null
  [ $? -eq 2 ] || fail "evaluate $option: want exit 2"
  grep -q -- "usage error: ${option%% *} " "$dir/err" || fail "evaluate $option: $(cat "$dir/err")"
done
# RPE over no pair (a step longer than the sequence) is said, not printed as 0, and null in JSON.
"$bin" evaluate --dataset "$dir/seq" --trajectory "$dir/t.tum" --rpe-step 1000 \
  --json "$dir/no_rpe.json" >"$dir/no_rpe" || fail "evaluate --rpe-step 1000"
grep -q "^RPE per 1000 frames: no pair of poses" "$dir/no_rpe" || fail "RPE over no pair: $(cat "$dir/no_rpe")"
python3 -c "import json,sys; r=json.load(open(sys.argv[1]))['trajectory']['rpe']; \
assert r['pairs'] == 0 and r['translation_rmse_m'] is None, r" "$dir/no_rpe.json" ||
  fail "RPE over no pair in the JSON"
# A trajectory on another clock: the error gives both time spans.
awk -v CONVFMT=%.9f '/^#/ { next } { $1 += 1000; print }' "$dir/t.tum" >"$dir/later.tum"
"$bin" evaluate --dataset "$dir/seq" --trajectory "$dir/later.tum" 2>"$dir/err" >/dev/null
[ $? -eq 1 ] || fail "evaluate on another clock: want exit 1"
grep -q "later.tum against .*: only 0 poses associate .*the estimate's times 10[0-9.]* to \
10[0-9.]* s, the ground truth's [0-9.]* to [0-9.]* s)" "$dir/err" || fail "clocks: $(cat "$dir/err")"
# ... and one in milliseconds is named as such.
awk -v CONVFMT=%.9f '/^#/ { next } { $1 *= 1000; print }' "$dir/t.tum" >"$dir/ms.tum"
"$bin" evaluate --dataset "$dir/seq" --trajectory "$dir/ms.tum" 2>"$dir/err" >/dev/null
[ $? -eq 1 ] || fail "evaluate in milliseconds: want exit 1"
grep -q "ms.tum against .*: only [0-2] poses associate .*: the estimate's times in milliseconds?)" \
  "$dir/err" || fail "milliseconds: $(cat "$dir/err")"
# --json with a trajectory alone: the trajectory's figures; an unwritable
# place is an error that names it.
"$bin" evaluate --dataset "$dir/seq" --trajectory "$dir/t.tum" --json "$dir/e.json" >/dev/null \
  || fail "evaluate --json"
grep -q '"trajectory": {' "$dir/e.json" || fail "no trajectory in the JSON"
grep -q '"translation_ratio": [0-9.]' "$dir/e.json" || fail "no motion ratio in the JSON"
"$bin" evaluate --dataset "$dir/seq" --trajectory "$dir/t.tum" --json "$dir/no/such/e.json" \
  >/dev/null 2>"$dir/err"
[ $? -eq 1 ] || fail "--json into a missing folder: want exit 1"
grep -q "$dir/no/such/e.json" "$dir/err" || fail "--json error does not name the file: $(cat "$dir/err")"
# A trajectory of two poses: too few to compare, and both files are named.
grep -v "^#" "$dir/t.tum" | head -2 >"$dir/two.tum"
"$bin" evaluate --dataset "$dir/seq" --trajectory "$dir/two.tum" >/dev/null 2>"$dir/err"
[ $? -eq 1 ] || fail "two poses: want exit 1"
grep -q "$dir/two.tum against $dir/seq/groundtruth.tum: .*only 2 poses" "$dir/err" \
  || fail "too few poses: $(cat "$dir/err")"

# The summary says how many windowed BA solves the time limit stopped.
grep -q "^windowed BA: [0-9]* solves, [0-9]* stopped by the 0.20 s time limit" "$dir/log" \
  || fail "no BA time-limit count in the summary"

# Tracked at half resolution (camera and mask scaled along): still on track.
"$bin" vo synth --out "$dir/wide" --frames 60 --width 640 --length 1.5 2>/dev/null \
  || fail "vo synth 640"
"$bin" vo --dataset "$dir/wide" --out "$dir/h.tum" --mask-laser --max-tracking-width 320 \
  2>"$dir/hlog" || fail "vo at half resolution: $(cat "$dir/hlog")"
grep -q "^tracked: passive colour, 320x240" "$dir/hlog" || fail "not tracked at 320x240"
"$bin" evaluate --dataset "$dir/wide" --trajectory "$dir/h.tum" >"$dir/heval" || fail "evaluate half"
hate=$(sed -n 's/^ATE (after alignment): rmse \([0-9.]*\) m.*/\1/p' "$dir/heval")
awk -v a="$hate" 'BEGIN { exit !(a < 0.004) }' || fail "half-resolution ATE $hate m too large"
"$bin" vo --dataset "$dir/seq" --out "$dir/x.tum" --max-tracking-width -1 2>/dev/null
[ $? -eq 2 ] || fail "--max-tracking-width -1: want exit 2"
"$bin" vo --dataset "$dir/seq" --out "$dir/x.tum" --initial-depth 2000 2>"$dir/err"
[ $? -eq 2 ] || fail "--initial-depth 2000: want exit 2"
grep -q -- "--initial-depth is the distance (m) from the camera to what it looks at" "$dir/err" ||
  fail "--initial-depth 2000: $(cat "$dir/err")"

# Pinhole model runs too (bias is measured in the unit tests and BENCHMARKS.md).
"$bin" vo --dataset "$dir/seq" --out "$dir/p.tum" --model pinhole --quiet || fail "pinhole run"

# Bad frames: black (20), wrong size (30), missing file (40), dropped frames (45-47).
cp -r "$dir/seq" "$dir/bad"
python3 - "$dir/bad" <<'PY' || fail "write bad frames"
import sys
d = sys.argv[1]
with open(f"{d}/frames/black.pgm", "wb") as f:
    f.write(b"P5\n320 240\n255\n" + bytes(320 * 240))
with open(f"{d}/frames/small.pgm", "wb") as f:
    f.write(b"P5\n160 120\n255\n" + bytes([100]) * (160 * 120))
lines = open(f"{d}/frames.csv").read().splitlines()
out = [lines[0]]
for line in lines[1:]:
    i, t, name = line.split(",")
    if i in ("45", "46", "47"):
        continue
    name = {"20": "frames/black.pgm", "30": "frames/small.pgm", "40": "frames/gone.png"}.get(i, name)
    out.append(",".join([i, t, name]))
open(f"{d}/frames.csv", "w").write("\n".join(out) + "\n")
PY
"$bin" vo --dataset "$dir/bad" --out "$dir/b.tum" --status "$dir/bstatus.csv" 2>"$dir/blog" \
  || fail "vo on bad frames: $(cat "$dir/blog")"
grep -q "warning: frame 20: lost" "$dir/blog" || fail "no warning for the black frame"
grep -q "warning: frame 30: invalid: image is 160x120" "$dir/blog" || fail "no wrong-size warning"
grep -q "warning: frame 40: cannot read" "$dir/blog" || fail "no missing-file warning"
grep -q "^# gap " "$dir/b.tum" || fail "gap not marked"
grep -q ",reinitialized," "$dir/bstatus.csv" || fail "no re-initialisation"
grep -q "^59,.*,tracked," "$dir/bstatus.csv" || fail "not tracking at the end"
! grep -q "^20,.*,tracked," "$dir/bstatus.csv" || fail "pose for the black frame"

# Errors.
"$bin" vo synth --out "$dir/seq" --frames 3 2>"$dir/err"
[ $? -eq 1 ] || fail "vo synth into a dataset: want exit 1"
grep -q "seq: output folder exists and is not empty" "$dir/err" || fail "vo synth over: $(cat "$dir/err")"
"$bin" vo synth --out "$dir/synth_inf" --frames 3 --rate inf 2>"$dir/err"
[ $? -eq 2 ] || fail "vo synth --rate inf: want exit 2"
grep -q "usage error: --rate must be in (0, 10000\] Hz, got inf" "$dir/err" || fail "--rate inf: $(cat "$dir/err")"
# Stopped half-way: nothing under the name, no temporary left.
"$bin" vo synth --out "$dir/stopped" --frames 2000 --width 640 2>/dev/null &
sleep 1
kill -TERM $!
wait $!
[ $? -eq 143 ] || fail "vo synth stopped: want exit 143"
[ -z "$(ls "$dir" | grep stopped)" ] || fail "vo synth stopped: left $(ls "$dir" | grep stopped)"
"$bin" vo --dataset "$dir/seq" 2>/dev/null; [ $? -eq 2 ] || fail "missing --out: want exit 2"
"$bin" vo --dataset "$dir/seq" --out "$dir/x.tum" --model fisheye 2>/dev/null
[ $? -eq 2 ] || fail "bad --model: want exit 2"
"$bin" vo --dataset "$dir/none" --out "$dir/x.tum" 2>"$dir/err"; [ $? -eq 1 ] || fail "no dataset: want 1"
grep -q "^uwscan: error: .*none" "$dir/err" || fail "error does not name the folder"
"$bin" vo --dataset "$dir/seq" --out "$dir/x.tum" --ba-time-limit 0 2>"$dir/err"
[ $? -eq 2 ] || fail "--ba-time-limit 0: want 2"
grep -q "usage error: --ba-time-limit" "$dir/err" || fail "error does not name --ba-time-limit"
"$bin" vo --dataset "$dir/seq" --out "$dir/x.tum" --window 2 2>"$dir/err"
[ $? -eq 2 ] || fail "--window 2: want 2"
grep -q "usage error: --window must be at least 3" "$dir/err" || fail "error does not name --window"
"$bin" vo --dataset "$dir/seq" --out "$dir/x.tum" --ba-history -1 2>"$dir/err"
[ $? -eq 2 ] || fail "--ba-history -1: want 2"
grep -q "usage error: --ba-history must be >= 0" "$dir/err" || fail "error does not name --ba-history"
"$bin" vo --dataset "$dir/seq" --out "$dir/x.tum" --mask-laser --mask-margin -1 2>"$dir/err"
[ $? -eq 2 ] || fail "--mask-margin -1: want 2"
grep -q "usage error: --mask-margin must be a number of pixels >= 0, got -1" "$dir/err" ||
  fail "error does not name --mask-margin"
# Numbers that are not finite are refused as usage errors that say what they got.
for option in "--mask-laser --mask-margin nan" "--model pinhole --pinhole-fit-depth inf" \
  "--initial-depth inf" "--ba-time-limit inf"; do
  "$bin" vo --dataset "$dir/seq" --out "$dir/x.tum" $option 2>"$dir/err"
  [ $? -eq 2 ] || fail "$option: want 2"
  name=${option% *}
  grep -q -- "usage error: ${name##* } .*got ${option##* }$" "$dir/err" ||
    fail "$option: $(cat "$dir/err")"
done
"$bin" vo --dataset "$dir/seq" --out "$dir/x.tum" --per-cell 0 2>"$dir/err"
[ $? -eq 2 ] || fail "--per-cell 0: want 2"
grep -q "usage error: --per-cell must be >= 1" "$dir/err" || fail "error does not name --per-cell"
"$bin" vo --dataset "$dir/seq" --out "$dir/x.tum" --contrast-scale 0.8 2>"$dir/err"
[ $? -eq 2 ] || fail "--contrast-scale 0.8: want 2"
grep -q "usage error: --contrast-scale must be in \[0, 0.5\].*got 0.8" "$dir/err" ||
  fail "error does not name --contrast-scale"
[ ! -e "$dir/x.tum" ] || fail "a trajectory written after a bad option"
rm "$dir/bad/groundtruth.tum"
"$bin" evaluate --dataset "$dir/bad" --trajectory "$dir/b.tum" 2>"$dir/err"
[ $? -eq 1 ] || fail "evaluate without ground truth: want 1"
grep -q "groundtruth.tum" "$dir/err" || fail "evaluate error does not name groundtruth.tum"
# A black scan (an exposure far too short; a lens cap, the lights off): the
# first warning of vo, and the first reason reconstruct gives, name the
# first frame as black (they said only that the odometry never started, or
# that no laser line was found).
"$bin" simulate tank-target --out "$dir/black" --frames 6 --width 320 --height 240 \
  --exposure-ms 0.001 --quiet >/dev/null 2>&1 || fail "simulate a black scan"
"$bin" vo --dataset "$dir/black" --out "$dir/black.tum" >/dev/null 2>"$dir/err"
head -n 1 "$dir/err" | grep -q "^uwscan: warning: $dir/black/frames/000000.png: a black frame: 0 % of its samples" ||
  fail "vo on a black scan: $(cat "$dir/err")"
"$bin" reconstruct --dataset "$dir/black" --out "$dir/black_out" >/dev/null 2>"$dir/err"
[ $? -eq 1 ] || fail "reconstruct on a black scan: want 1"
sed -n 2p "$dir/err" | grep -q "^  $dir/black/frames/000000.png: a black frame" ||
  fail "reconstruct on a black scan: $(cat "$dir/err")"
echo "vo CLI tests passed"
