#!/usr/bin/env bash
# CLI: uwscan laser detect on small PGM frames written here, with ground truth.
set -u
bin="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

mkdir -p "$dir/frames" "$dir/empty"
python3 - "$dir/frames" <<'PY' || fail "write frames"
import math, random, sys
d = sys.argv[1]
random.seed(3)
W, H = 160, 120
def frame(name, centre):
    rows = []
    for v in range(H):
        row = bytearray()
        for u in range(W):
            x = 30 + 10 * math.sin(u * 0.3) * math.cos(v * 0.2)  # texture
            if centre is not None:
                c = centre + 0.1 * v
                x += 180 * math.exp(-0.5 * ((u - c) / 1.5) ** 2)
            x += random.gauss(0, 1.5)
            row.append(max(0, min(255, int(round(x)))))
        rows.append(bytes(row))
    with open(f"{d}/{name}", "wb") as f:
        f.write(b"P5\n%d %d\n255\n" % (W, H) + b"".join(rows))
frame("000.pgm", 60.25)
frame("001.pgm", None)
frame("002.pgm", 100.5)
with open(f"{d}/003.png", "wb") as f:
    f.write(b"\x89PNG\r\n\x1a\n truncated")
PY

"$bin" laser detect --images "$dir/frames" --out "$dir/det.csv" --overlay "$dir/overlay" 2>"$dir/err" \
  || fail "detect: $(cat "$dir/err")"
grep -q "003.png: unreadable" "$dir/err" || fail "warning for the truncated frame: $(cat "$dir/err")"
python3 - "$dir/det.csv" <<'PY' || fail "detections wrong"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
by_frame = {}
for r in rows:
    by_frame.setdefault(int(r["frame"]), []).append(r)
assert 1 not in by_frame and 3 not in by_frame, "frames without a line must be empty"
for frame, centre in ((0, 60.25), (2, 100.5)):
    pts = by_frame[frame]
    assert len(pts) >= 110, (frame, len(pts))
    errors = [abs(float(p["u"]) - (centre + 0.1 * float(p["v"]))) for p in pts]
    rms = (sum(e * e for e in errors) / len(errors)) ** 0.5
    assert rms < 0.15, (frame, rms)
PY
[ -f "$dir/overlay/000.png" ] || fail "overlay image"
# A red laser's line looked for in green (the default without a rig): named, with the --channel
# that finds it; looked for in red, no such warning and the line found.
mkdir -p "$dir/red"
python3 - "$dir/red" <<'PY' || fail "write colour frames"
import math, random, sys
random.seed(5)
W, H = 160, 120
pixels = bytearray()
for v in range(H):
    for u in range(W):
        texture = 30 + 10 * math.sin(u * 0.3) * math.cos(v * 0.2)
        red = texture + 180 * math.exp(-0.5 * ((u - 70.5 - 0.1 * v) / 1.5) ** 2)
        for x in (red, texture, texture):
            pixels.append(max(0, min(255, int(round(x + random.gauss(0, 1.5))))))
with open(sys.argv[1] + "/000.ppm", "wb") as f:
    f.write(b"P6\n%d %d\n255\n" % (W, H) + bytes(pixels))
PY
"$bin" laser detect --images "$dir/red" --out "$dir/red.csv" 2>"$dir/err" || fail "red: $(cat "$dir/err")"
grep -q "warning: the laser line shows in red, not in green, the colour looked in: give --channel red" \
  "$dir/err" || fail "red line looked for in green: $(cat "$dir/err")"
"$bin" laser detect --images "$dir/red" --out "$dir/red.csv" --channel red 2>"$dir/err" ||
  fail "red: $(cat "$dir/err")"
! grep -q "shows in" "$dir/err" || fail "red line looked for in red: $(cat "$dir/err")"
[ "$(wc -l <"$dir/red.csv")" -gt 100 ] || fail "red line looked for in red: not found"
# Overlays into the images' own folder would replace the frames with their drawings (they did):
# a usage error, the frames untouched; so is an --out onto an input.
cp -r "$dir/frames" "$dir/own"
sum_before=$(cksum <"$dir/own/000.pgm")
"$bin" laser detect --images "$dir/own" --out "$dir/own.csv" --overlay "$dir/own/" --quiet \
  2>"$dir/err"
[ $? -eq 2 ] || fail "--overlay onto the images: want exit 2"
grep -q -- "--overlay $dir/own/ is the folder of the images" "$dir/err" ||
  fail "--overlay onto the images: $(cat "$dir/err")"
[ "$(cksum <"$dir/own/000.pgm")" = "$sum_before" ] || fail "--overlay overwrote a frame"
[ ! -e "$dir/own/000.png" ] || fail "--overlay wrote beside the frames"
"$bin" laser detect --images "$dir/own" --out "$dir/own/000.pgm" --quiet 2>"$dir/err"
[ $? -eq 2 ] || fail "--out onto a frame: want exit 2"
[ "$(cksum <"$dir/own/000.pgm")" = "$sum_before" ] || fail "--out overwrote a frame"
! grep -q "full scale" "$dir/err" || fail "no clipping on these frames: $(cat "$dir/err")"
! grep -q "mosaic" "$dir/err" || fail "mono frames taken for a mosaic: $(cat "$dir/err")"

# The same frame as a raw Bayer mosaic under a reddish light (R G / G B samples at 1, 0.6, 0.6,
# 0.3 of it), read without a rig (a mono camera): a warning names the frame and says what to do.
mkdir -p "$dir/mosaic"
python3 - "$dir/frames/000.pgm" "$dir/mosaic/000.pgm" <<'PY' || fail "write a mosaic"
import sys
data = open(sys.argv[1], "rb").read()
header, pixels = data[:15], bytearray(data[15:])  # "P5\n160 120\n255\n"
gain = ((1.0, 0.6), (0.6, 0.3))
for i in range(len(pixels)):
    pixels[i] = int(pixels[i] * gain[(i // 160) % 2][i % 2])
open(sys.argv[2], "wb").write(header + bytes(pixels))
PY
"$bin" laser detect --images "$dir/mosaic" --out "$dir/mosaic.csv" --quiet 2>"$dir/err" \
  || fail "detect on a mosaic: $(cat "$dir/err")"
grep -q "^laser detect: warning: $dir/mosaic/000.pgm: a single-channel frame whose 2x2 pixel phases differ in mean by a factor of [0-9.]*: it looks like a raw Bayer mosaic.*; give --rig with the camera's bayer" \
  "$dir/err" || fail "no warning for a mosaic read as mono: $(cat "$dir/err")"

# A scene clipped on a quarter of the image (a mono camera at a colour
# camera's exposure): the line is still found beside it, and a warning says why
# it may be lost there.
mkdir -p "$dir/clipped"
python3 - "$dir/clipped" <<'PY' || fail "write clipped frames"
import math, sys
W, H = 160, 120
for k in range(3):
    rows = []
    for v in range(H):
        row = bytearray()
        for u in range(W):
            x = 255 if u < 40 else 60 + 150 * math.exp(-0.5 * ((u - 100 - k) / 1.5) ** 2)
            row.append(min(255, int(round(x))))
        rows.append(bytes(row))
    with open(f"{sys.argv[1]}/{k:03d}.pgm", "wb") as f:
        f.write(b"P5\n%d %d\n255\n" % (W, H) + b"".join(rows))
PY
"$bin" laser detect --images "$dir/clipped" --out "$dir/clipped.csv" 2>"$dir/err" \
  || fail "detect on clipped frames: $(cat "$dir/err")"
grep -q "warning: in 3 frame(s) the scene itself is at full scale" "$dir/err" \
  || fail "clipping warning: $(cat "$dir/err")"
# 40 of the 135 columns away from the line (100 +- 12 px) are clipped.
grep -q "(29.6 % over all frames)" "$dir/err" || fail "clipped share: $(cat "$dir/err")"
[ "$(wc -l <"$dir/clipped.csv")" -gt 300 ] || fail "the line beside the clipped part"

for method in cog argmax; do
  "$bin" laser detect --images "$dir/frames" --out "$dir/$method.csv" --method $method --quiet 2>/dev/null \
    || fail "method $method"
  [ "$(wc -l <"$dir/$method.csv")" -gt 200 ] || fail "$method found too little"
done

# Errors: empty folder and size mismatch exit 1 without output; bad method exits 2.
"$bin" laser detect --images "$dir/empty" --out "$dir/x.csv" 2>"$dir/err"
[ $? -eq 1 ] || fail "empty folder should exit 1"
grep -q "no images" "$dir/err" || fail "empty folder message"
cat >"$dir/rig.yaml" <<'YAML'
format: uwscan-rig/1
cameras:
  - name: cam0
    width: 320
    height: 240
    bayer: none
    model: pinhole
    fx: 300.0
    fy: 300.0
    cx: 160.0
    cy: 120.0
    distortion: [0, 0, 0, 0, 0]
    rig_from_camera: {q: [1, 0, 0, 0], t: [0, 0, 0]}
YAML
"$bin" laser detect --images "$dir/frames" --rig "$dir/rig.yaml" --out "$dir/y.csv" 2>"$dir/err"
[ $? -eq 1 ] || fail "size mismatch should exit 1"
grep -q "000.pgm: image is 160x120 but camera 'cam0' is 320x240" "$dir/err" || fail "mismatch message: $(cat "$dir/err")"
[ ! -e "$dir/y.csv" ] || fail "no output on error"
# Half the size in both directions (binned): the error gives the
# intrinsics for it, about pixel centres, and a rig with them is taken.
grep -q "0.5 times its size in both directions.*width: 160, height: 120, fx: 150, fy: 150, cx: 79.75, cy: 59.75" \
  "$dir/err" || fail "binned frames: no intrinsics for their size: $(cat "$dir/err")"
sed -e 's/width: 320/width: 160/; s/height: 240/height: 120/; s/fx: 300.0/fx: 150/; s/fy: 300.0/fy: 150/' \
  -e 's/cx: 160.0/cx: 79.75/; s/cy: 120.0/cy: 59.75/' "$dir/rig.yaml" > "$dir/rig_binned.yaml"
"$bin" laser detect --images "$dir/frames" --rig "$dir/rig_binned.yaml" --out "$dir/y.csv" \
  2>"$dir/err" || fail "the rig with the suggested intrinsics: $(cat "$dir/err")"
rm -f "$dir/y.csv"
"$bin" laser detect --images "$dir/frames" --out "$dir/z.csv" --method hough 2>/dev/null
[ $? -eq 2 ] || fail "bad method should exit 2"
for bad in "--sigma 0" "--scan diagonal" "--channel infrared" "--albedo purple"; do
  "$bin" laser detect --images "$dir/frames" --out "$dir/z.csv" $bad 2>"$dir/err"
  [ $? -eq 2 ] || fail "$bad should exit 2"
  grep -q -- "${bad%% *} must be" "$dir/err" || fail "$bad: unclear error: $(cat "$dir/err")"
  [ ! -e "$dir/z.csv" ] || fail "$bad wrote output"
done
# An interleaved scan (frames.csv's laser_on): the frames with the laser off are skipped, not
# searched for a line they cannot have, and the summary counts them.
"$bin" simulate tank-target --out "$dir/interleaved" --frames 6 --width 320 --height 240 \
  --laser-interleave --quiet || fail "simulate an interleaved scan"
"$bin" laser detect --dataset "$dir/interleaved" --out "$dir/il.csv" 2>"$dir/err" ||
  fail "laser detect on an interleaved scan: $(cat "$dir/err")"
grep -q "^laser detect: 6 frames (.*, 3 with the laser off (skipped), " "$dir/err" ||
  fail "interleaved summary: $(cat "$dir/err")"
off=$(awk -F, 'NR > 1 && $1 % 2 == 1' "$dir/il.csv" | wc -l)
on=$(awk -F, 'NR > 1 && $1 % 2 == 0' "$dir/il.csv" | wc -l)
[ "$off" -eq 0 ] && [ "$on" -gt 0 ] || fail "detections with the laser off: $off (on: $on)"
echo "laser CLI: all checks passed"
