#!/usr/bin/env bash
# CLI: uwscan demo (the README's first command) on a short, small scan, its
# figures against `uwscan evaluate --result` and the simulator's truth, and
# its usage errors.
set -u
bin="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# 60 frames at 320x240: seconds, not the default's minute. At this size
# each pixel of the simulated sensor gathers 16 times the light it does at
# the thesis camera's 1280x960; the demo sets the camera's gain to its
# lowest, 1, and the red LED's colour no longer clips (at the default gain 4
# it did on half the image, and the odometry failed).
"$bin" demo --frames 60 --width 320 --height 240 --quiet --out "$dir/demo" >"$dir/out" 2>"$dir/err" \
  || fail "demo: $(cat "$dir/err")"
for f in dataset/groundtruth.tum dataset/scene.yaml result/cloud.ply result/cloud_uncompensated.ply \
  result/trajectory.tum result/report.json; do
  [ -s "$dir/demo/$f" ] || fail "demo did not write $f"
done
grep -q "^1\. simulated 60 frames in [0-9.]* s -> $dir/demo/dataset$" "$dir/out" \
  || fail "no simulation line: $(cat "$dir/out")"
grep -q "^2\. reconstructed [0-9]* points from 60 frames (0 without pose) in [0-9.]* s, poses from self-referenced visual odometry$" \
  "$dir/out" || fail "no reconstruction line: $(cat "$dir/out")"
grep -q "^laser on a servo and a red LED (thesis §6.4), 60 frames at 320x240, 144 Hz, gain 1\.$" \
  "$dir/out" || fail "no gain in the demo's header: $(cat "$dir/out")"
grep -q "at full scale" "$dir/out" && fail "the demo's images clip: $(cat "$dir/out")"
grep -q "^cloud: $dir/demo/result/cloud.ply (open with CloudCompare, MeshLab or Open3D)$" "$dir/out" \
  || fail "does not say where the cloud is"

# The demo's point errors are evaluate's, and the compensated cloud is
# within millimetres of the true scene where the uncompensated one is not.
read -r demo_comp demo_unc < <(sed -n 's/^   point error (all surfaces) \([0-9.]*\) mm vs \([0-9.]*\) mm$/\1 \2/p' "$dir/out")
[ -n "${demo_comp:-}" ] || fail "no point error line: $(cat "$dir/out")"
"$bin" evaluate --dataset "$dir/demo/dataset" --result "$dir/demo/result" --json "$dir/e.json" \
  >"$dir/eval" || fail "evaluate --result"
grep -q "^compensated      floor " "$dir/eval" || fail "evaluate: no floor row: $(cat "$dir/eval")"
grep -q "^uncompensated    (all) " "$dir/eval" || fail "evaluate: no uncompensated row"
grep -q "Sim(3) scale" "$dir/eval" || fail "evaluate: no trajectory figures"
comp=$(python3 -c "import json; print(json.load(open('$dir/e.json'))['compensated']['point_error_rms_mm'])")
unc=$(python3 -c "import json; print(json.load(open('$dir/e.json'))['uncompensated']['point_error_rms_mm'])")
awk -v d="$demo_comp" -v e="$comp" 'BEGIN { exit !(d - e < 0.051 && e - d < 0.051) }' \
  || fail "demo says $demo_comp mm, evaluate $comp mm"
awk -v d="$demo_unc" -v e="$unc" 'BEGIN { exit !(d - e < 0.051 && e - d < 0.051) }' \
  || fail "demo says $demo_unc mm uncompensated, evaluate $unc mm"
awk -v c="$comp" -v u="$unc" 'BEGIN { exit !(c < 5 && 3 * c < u) }' \
  || fail "compensated $comp mm against uncompensated $unc mm"

# The clouds saved again as CloudCompare does (ascii, the frame as scalar_frame, normals) give
# evaluate the same figures.
mkdir -p "$dir/resaved"
cp "$dir/demo/result/trajectory.tum" "$dir/resaved/"
for cloud in cloud cloud_uncompensated; do
  python3 - "$dir/demo/result/$cloud.ply" "$dir/resaved/$cloud.ply" <<'PY' || fail "resave $cloud"
import struct, sys
data = open(sys.argv[1], "rb").read()
end = data.index(b"end_header\n") + len(b"end_header\n")
props = [l.split()[1:] for l in data[:end].decode().splitlines() if l.startswith("property")]
codes = {"double": "d", "float": "f", "uchar": "B", "int": "i"}
fmt = "<" + "".join(codes[t] for t, _ in props)
rows = list(struct.iter_unpack(fmt, data[end:]))
names = [n if n != "frame" else "scalar_frame" for _, n in props] + ["nx", "ny", "nz"]
with open(sys.argv[2], "w") as out:
    out.write("ply\nformat ascii 1.0\nelement vertex %d\n" % len(rows))
    out.write("".join("property %s %s\n" % (t, n) for (t, _), n in zip(props, names)))
    out.write("property float nx\nproperty float ny\nproperty float nz\nend_header\n")
    out.write("".join(" ".join(repr(v) for v in row) + " 0 0 1\n" for row in rows))
PY
done
"$bin" evaluate --dataset "$dir/demo/dataset" --result "$dir/resaved" --json "$dir/resaved.json" \
  >/dev/null || fail "evaluate on the resaved clouds"
python3 -c "import json,sys; a, b = (json.load(open(f)) for f in sys.argv[1:]); \
assert a['compensated'] == b['compensated'] and a['uncompensated'] == b['uncompensated']" \
  "$dir/e.json" "$dir/resaved.json" || fail "resaved clouds evaluate differently"

# Again into the same folder: the dataset is replaced, not refused.
"$bin" demo --frames 20 --width 320 --height 240 --quiet --out "$dir/demo" >"$dir/out2" 2>"$dir/err" \
  || fail "demo into its own folder again: $(cat "$dir/err")"
grep -q "^1\. simulated 20 frames" "$dir/out2" || fail "second demo did not simulate again"
[ "$(grep -vc '^#' "$dir/demo/dataset/groundtruth.tum")" -eq 20 ] || fail "dataset not replaced"
grep -q "^   plane std [0-9.]* mm compensated vs [0-9.]* mm uncompensated$" "$dir/out2" \
  || fail "20 frames: the sweep crosses the target, but no plane std: $(cat "$dir/out2")"

# The demo passes on every warning of the reconstruction, as report.json has them (seed 77's
# scan has one: line candidates that stayed put while the laser swept).
"$bin" demo --frames 40 --width 320 --height 240 --seed 77 --quiet --out "$dir/short" \
  >"$dir/out3" 2>"$dir/err" || fail "demo --seed 77: $(cat "$dir/err")"
sed -n 's/^   warning: //p' "$dir/out3" >"$dir/shown"
python3 -c "import json, sys; [print(w) for w in json.load(open(sys.argv[1]))['warnings']]" \
  "$dir/short/result/report.json" >"$dir/reported" || fail "report.json's warnings"
cmp -s "$dir/shown" "$dir/reported" \
  || fail "demo shows $(wc -l <"$dir/shown") warning(s), report.json has $(wc -l <"$dir/reported")"

# Usage errors: exit 2, nothing written; an output that cannot be a folder:
# exit 1, named.
"$bin" demo --frames 5 --out "$dir/few" >/dev/null 2>"$dir/err"
[ $? -eq 2 ] || fail "--frames 5: want exit 2"
grep -q -- "--frames must be >= 20" "$dir/err" || fail "--frames 5: unclear error"
[ ! -e "$dir/few" ] || fail "--frames 5 wrote output"
"$bin" demo --width 160 --height 120 --out "$dir/tiny" >/dev/null 2>"$dir/err"
[ $? -eq 2 ] || fail "--width 160: want exit 2"
grep -q -- "--width/--height must be at least 320x240 (got 160x120)" "$dir/err" \
  || fail "--width 160: unclear error: $(cat "$dir/err")"
[ ! -e "$dir/tiny" ] || fail "--width 160 wrote output"
# A folder `dataset` under --out that the demo did not make is the user's: kept, exit 1 (it was
# removed with all it held).
mkdir -p "$dir/mine/dataset" && echo data >"$dir/mine/dataset/survey.txt"
"$bin" demo --frames 20 --width 320 --height 240 --quiet --out "$dir/mine" >/dev/null 2>"$dir/err"
[ $? -eq 1 ] || fail "--out over a user's dataset folder: want exit 1"
grep -q "$dir/mine/dataset: exists and is not a simulated dataset" "$dir/err" ||
  fail "--out over a user's dataset folder: $(cat "$dir/err")"
[ -f "$dir/mine/dataset/survey.txt" ] || fail "the demo removed a user's dataset folder"
touch "$dir/file"
"$bin" demo --frames 20 --width 320 --height 240 --quiet --out "$dir/file" >/dev/null 2>"$dir/err"
[ $? -eq 1 ] || fail "--out a file: want exit 1"
grep -q "$dir/file: cannot create the output folder" "$dir/err" || fail "--out a file: unclear error"
"$bin" evaluate --dataset "$dir/demo/dataset" --result "$dir/none" >/dev/null 2>"$dir/err"
[ $? -eq 1 ] || fail "evaluate --result on no folder: want exit 1"
grep -q "$dir/none: no such folder" "$dir/err" || fail "evaluate --result on no folder: $(cat "$dir/err")"
# A result without one of its clouds: named before anything is printed; a dataset that is not
# simulated (no scene.yaml): the trajectory alone, and a line that says so.
cp -r "$dir/demo/result" "$dir/partial"
rm "$dir/partial/cloud_uncompensated.ply"
"$bin" evaluate --dataset "$dir/demo/dataset" --result "$dir/partial" >"$dir/out" 2>"$dir/err"
[ $? -eq 1 ] || fail "evaluate --result without a cloud: want exit 1"
grep -q "$dir/partial/cloud_uncompensated.ply: missing" "$dir/err" || fail "partial: $(cat "$dir/err")"
[ ! -s "$dir/out" ] || fail "partial: figures printed before the error"
cp -r "$dir/demo/dataset" "$dir/real"
rm "$dir/real/scene.yaml"
"$bin" evaluate --dataset "$dir/real" --result "$dir/demo/result" >"$dir/out" 2>"$dir/err" ||
  fail "evaluate --result on a dataset without a scene: $(cat "$dir/err")"
grep -q "^ATE" "$dir/out" && grep -q "^clouds: not evaluated ($dir/real has no scene.yaml" "$dir/out" ||
  fail "no scene: $(cat "$dir/out")"
grep -q "warning" "$dir/err" && fail "a copy of the dataset taken for another: $(cat "$dir/err")"
# A result evaluated against another scan (simulated scans share their
# timestamps, so nothing else tells): its report.json names the dataset it
# was made from, and the two ground truths differ.
"$bin" simulate tank-target --out "$dir/other" --frames 5 --width 320 --height 240 --seed 7 \
  >/dev/null 2>&1 || fail "simulate another scan"
"$bin" evaluate --dataset "$dir/other" --result "$dir/demo/result" >/dev/null 2>"$dir/err"
grep -q "^uwscan: warning: $dir/demo/result was reconstructed from $dir/demo/dataset (its report.json), whose ground truth is not $dir/other's" \
  "$dir/err" || fail "a result evaluated against another scan: $(cat "$dir/err")"
exit 0
