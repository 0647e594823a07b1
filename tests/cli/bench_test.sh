#!/usr/bin/env bash
# CLI: the speed and accuracy benchmarks whose figures docs/BENCHMARKS.md
# records (bench projection, bench laser, bench laser-accuracy, vo bench),
# each on a tiny input: they run, say what they measured, and what they
# measure against the truth holds.
set -u
bin="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
json() { python3 -c "import json, sys; d = json.load(open(sys.argv[1])); print($2)" "$1"; }

# Projection: the exact flat-port projection is its own reference, the
# Taylor series converges to it with iterations, the pinhole is far off.
"$bin" bench projection --points 2000 --repetitions 1 >"$dir/proj.json" 2>"$dir/err" \
  || fail "bench projection: $(cat "$dir/err")"
error() { json "$dir/proj.json" "[r['max_error_vs_exact_px'] for r in d['results'] if r['camera'] == 'Flat1' and r['method'] == '$1'][0]"; }
awk -v e="$(error exact)" 'BEGIN { exit !(e < 1e-6) }' || fail "exact vs exact: $(error exact) px"
awk -v t1="$(error taylor1)" -v t3="$(error taylor3)" -v p="$(error pinhole)" \
  'BEGIN { exit !(t3 < 0.01 && t3 < t1 && t1 < p) }' \
  || fail "Taylor 1/3 iterations $(error taylor1) / $(error taylor3) px, pinhole $(error pinhole) px"
"$bin" bench projection --markdown --points 2000 --repetitions 1 >"$dir/proj.md" \
  || fail "bench projection --markdown"
grep -q "^|.*Flat1" "$dir/proj.md" || fail "bench projection --markdown: no table"

# Laser detection speed on synthetic frames: every method finds the line
# on every row.
"$bin" bench laser --width 320 --height 240 --frames 3 --repetitions 1 >"$dir/laser.json" \
  2>"$dir/err" || fail "bench laser: $(cat "$dir/err")"
[ "$(json "$dir/laser.json" "sorted(r['method'] for r in d['results'])")" = "['argmax', 'cog', 'thesis']" ] \
  || fail "bench laser: methods $(cat "$dir/laser.json")"
[ "$(json "$dir/laser.json" "min(r['mean_points_per_frame'] for r in d['results'])")" = "240.0" ] \
  || fail "bench laser: not a point per row"
"$bin" bench laser --dataset "$dir/none" >/dev/null 2>"$dir/err"
[ $? -eq 1 ] || fail "bench laser --dataset none: want exit 1"
grep -q "$dir/none" "$dir/err" || fail "bench laser --dataset none: does not name it"
# Options out of range are usage errors (exit 2), as elsewhere.
for bad in "laser --frames 0" "pipeline --dataset $dir/none --frames 5" "projection --points 10" \
  "tracks --dataset $dir/none --anchor-every 0" "laser-accuracy --frames 0"; do
  "$bin" bench $bad >/dev/null 2>"$dir/err"
  [ $? -eq 2 ] || fail "bench $bad: want exit 2, got: $(cat "$dir/err")"
  grep -q "must be" "$dir/err" || fail "bench $bad: unclear error: $(cat "$dir/err")"
done

# Laser accuracy against the simulator's true line: the thesis detector is
# sub-pixel in clear water, and an RMS over no detections is "-", not 0.
"$bin" bench laser-accuracy --width 320 --height 240 --frames 2 --turbidity clear turbid \
  >"$dir/acc.md" 2>"$dir/err" || fail "bench laser-accuracy: $(cat "$dir/err")"
rms=$(awk -F' *[|] *' '$2 == "clear" && $3 == "off" && $4 == "thesis" { print $5 }' "$dir/acc.md")
awk -v r="$rms" 'BEGIN { exit !(r != "" && r > 0 && r < 0.3) }' || fail "clear-water RMS '$rms' px"
awk -F' *[|] *' '$2 == "turbid" && $4 == "thesis" && $8 == 0 && $5 != "-" { bad = 1 } END { exit bad }' \
  "$dir/acc.md" || fail "an RMS over no detections is printed as a number: $(cat "$dir/acc.md")"
grep -q '^| turbid | off | thesis | - | 0.0 % |' "$dir/acc.md" || fail "no turbid row: $(cat "$dir/acc.md")"

# VO speed on a small rendered sequence.
"$bin" vo bench --frames 30 --width 320 >"$dir/vo.txt" 2>&1 || fail "vo bench: $(cat "$dir/vo.txt")"
grep -q "^vo bench 320x240, 30 frames: [0-9]* tracked, 0 lost" "$dir/vo.txt" \
  || fail "vo bench: $(cat "$dir/vo.txt")"
grep -q "full VO [0-9.]* frames/s" "$dir/vo.txt" || fail "vo bench: no rate"
exit 0
