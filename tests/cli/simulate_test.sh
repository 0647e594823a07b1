#!/usr/bin/env bash
# CLI contract of `uwscan simulate`: a small dataset is written completely,
# bad options exit 2, bad output folders exit 1, and nothing partial is left.
set -u
uwscan="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

expect_status() {  # expected_status description command...
  local expected=$1 description=$2
  shift 2
  "$@" >"$work/out" 2>"$work/err"
  local status=$?
  [ "$status" -eq "$expected" ] || fail "$description: exit $status, expected $expected ($(cat "$work/err"))"
  if [ "$expected" -ne 0 ]; then
    grep -q "^uwscan: \(usage \)\?error: \|^\(Run with\|The following\|.*: \)" "$work/err" ||
      fail "$description: no error message"
  fi
}

# A small, fast dataset.
expect_status 0 "tank-target" "$uwscan" simulate tank-target --out "$work/ds" --frames 3 \
  --width 160 --height 120 --seed 7 --quiet
for f in rig.yaml scene.yaml frames.csv groundtruth.tum laser_gt.csv frames/000000.png frames/000002.png; do
  [ -s "$work/ds/$f" ] || fail "missing $f"
done
[ "$(head -1 "$work/ds/frames.csv")" = "index,timestamp_s,file,laser_angle_rad" ] || fail "frames.csv header"
[ "$(grep -vc '^#' "$work/ds/groundtruth.tum")" -eq 3 ] || fail "groundtruth.tum rows"
[ "$(head -1 "$work/ds/laser_gt.csv")" = "frame,laser,u,v,x,y,z" ] || fail "laser_gt.csv header"
[ "$(wc -l < "$work/ds/laser_gt.csv")" -gt 100 ] || fail "laser_gt.csv too short"
[ -z "$(cat "$work/out")" ] || fail "--quiet printed to stdout"

# bench tracks on it: JSON with the flow gain; a dataset without its scene
# (not simulated) or no dataset at all is named in the error.
expect_status 0 "bench tracks" "$uwscan" bench tracks --dataset "$work/ds"
grep -q '"flow_gain_minus_1"' "$work/out" || fail "bench tracks: no flow gain"
mkdir -p "$work/real" && cp "$work/ds/rig.yaml" "$work/ds/frames.csv" "$work/real/"
expect_status 1 "bench tracks, no scene" "$uwscan" bench tracks --dataset "$work/real"
grep -q "real/scene.yaml: missing" "$work/err" || fail "bench tracks: unclear error without scene.yaml"
expect_status 1 "bench tracks, no dataset" "$uwscan" bench tracks --dataset "$work/none"
grep -q "none: no such dataset folder" "$work/err" || fail "bench tracks: unclear error without dataset"

# bench pipeline on a tank it simulates (too few frames above for a
# start): JSON with the speed, the memory and the CPU time it took (cores
# kept busy: more than none, no more than the machine has); a missing
# dataset is named in the error.
expect_status 0 "bench pipeline" "$uwscan" bench pipeline --frames 20 --width 320 --height 240
for key in real_time_factor peak_memory_mb cpu_s cores_busy load_average_before \
  images_in_page_cache_before images_mb images_read_mb_per_s images_mb_per_s_for_real_time; do
  grep -q "\"$key\": [0-9]" "$work/out" || fail "bench pipeline: no $key"
done
grep -q '"images_read_before_timing": true' "$work/out" || fail "bench pipeline: images not read first"
# Its smaller tank is exposed as the 1280x960 one was lit for (gain 1, not 4): nothing clips.
grep -q '"frames_with_clipped_features": 0,' "$work/out" || fail "bench pipeline: the features clip"
# The images just simulated are all in the page cache.
grep -q '"images_in_page_cache_before": 1\.0' "$work/out" || fail "bench pipeline: page cache share"
awk -v cores="$(nproc)" '/"cores_busy":/ { sub(",", "", $2); ok = $2 > 0 && $2 <= cores + 0.5 }
  END { exit !ok }' "$work/out" || fail "bench pipeline: cores_busy out of range"
expect_status 1 "bench pipeline, no dataset" "$uwscan" bench pipeline --dataset "$work/none"
grep -q "none: no such dataset folder" "$work/err" || fail "bench pipeline: unclear error without dataset"

# Deterministic for a seed: the same command gives identical files.
expect_status 0 "tank-target again" "$uwscan" simulate tank-target --out "$work/ds2" --frames 3 \
  --width 160 --height 120 --seed 7 --quiet
for f in frames/000001.png laser_gt.csv groundtruth.tum scene.yaml; do
  cmp -s "$work/ds/$f" "$work/ds2/$f" || fail "not deterministic: $f"
done

# Other scenarios and options.
expect_status 0 "hull rgb turbid" "$uwscan" simulate hull --out "$work/hull" --frames 2 --width 96 \
  --height 72 --turbidity turbid --output rgb --bits 16 --laser-power 0.1 --motion-amplitude 0.05 \
  --gain 2 --exposure-ms 12.5 --quiet
grep -q "  exposure_s: 0.0125$" "$work/hull/scene.yaml" || fail "exposure not in scene.yaml"
grep -q "  gain: 2$" "$work/hull/scene.yaml" || fail "gain not in scene.yaml"
expect_status 0 "snow and motion blur" "$uwscan" simulate tank-target --out "$work/snow" --frames 2 \
  --width 96 --height 72 --marine-snow 200 --motion-blur 3 --supersample 2 --quiet
grep -q "per_m3: 200" "$work/snow/scene.yaml" || fail "snow not in scene.yaml"
grep -q "  supersample: 2" "$work/snow/scene.yaml" || fail "supersample not in scene.yaml"
expect_status 0 "seabed numeric turbidity" "$uwscan" simulate seabed-transect --out "$work/sea" \
  --frames 2 --width 96 --height 72 --turbidity 0.5 --output mono --quiet

expect_status 0 "aquarium" "$uwscan" simulate aquarium --out "$work/aq" --frames 1 --width 96 \
  --height 72 --port-gap-mm 10 --port-tilt-deg 4 --quiet
for f in calib/air/rig.yaml calib/air/frames/000000.png calib/water/groundtruth.tum frames.csv; do
  [ -s "$work/aq/$f" ] || fail "aquarium: missing $f"
done
grep -q "model: pinhole" "$work/aq/calib/air/rig.yaml" || fail "aquarium: air rig is not pinhole"
expect_status 0 "laser-tilt" "$uwscan" simulate laser-tilt --out "$work/lt" --frames 1 --width 96 \
  --height 72 --laser-tilt-deg 8 --quiet
[ -s "$work/lt/calib/laser/frames/000005.png" ] || fail "laser-tilt: calib/laser"

# Two pods: cam1's images in a dataset of its own, its rig listing it first;
# reconstruct takes both cameras (or the first only).
expect_status 0 "two pods" "$uwscan" simulate tank-target --out "$work/pods" --pods 2 --frames 3 \
  --width 160 --height 120 --quiet
for f in cam1/rig.yaml cam1/frames.csv cam1/frames/000002.png cam1/groundtruth.tum cam1/laser_gt.csv; do
  [ -s "$work/pods/$f" ] || fail "two pods: missing $f"
done
[ "$(sed -n 2p "$work/pods/cam1/frames.csv" | cut -d, -f1)" = "3" ] || fail "two pods: cam1 frame indices"
grep -A1 "^cameras:" "$work/pods/cam1/rig.yaml" | grep -q "name: cam1" || fail "two pods: cam1 not first"
expect_status 0 "two pods reconstruct" "$uwscan" reconstruct --dataset "$work/pods" --out "$work/pods.out" \
  --poses "$work/pods/groundtruth.tum"
grep -q "camera cam1 with laser1: 3 frames" "$work/err" || fail "two pods: no cam1 summary"
[ -s "$work/pods.out/trajectory_cam1.tum" ] || fail "two pods: trajectory_cam1.tum"
expect_status 0 "two pods, first camera" "$uwscan" reconstruct --dataset "$work/pods" \
  --out "$work/pods.first" --poses "$work/pods/groundtruth.tum" --main-camera-only --quiet
[ ! -e "$work/pods.first/trajectory_cam1.tum" ] || fail "--main-camera-only wrote cam1"
expect_status 1 "two pods, cam1 on the top folder" "$uwscan" reconstruct --dataset "$work/pods" \
  --out "$work/pods.cam1" --poses "$work/pods/groundtruth.tum" --camera cam1 --quiet
grep -q "pods/cam1" "$work/err" || fail "two pods: --camera cam1 error does not say where"
# One colour frame among raw Bayer ones (another export's): named, exit 1, no output. It used to
# be read as raw samples of a mosaic, or end the odometry with "frame 1: a colour image".
expect_status 0 "an rgb frame" "$uwscan" simulate tank-target --out "$work/rgb1" --frames 1 \
  --width 160 --height 120 --seed 7 --output rgb --quiet
cp -r "$work/ds" "$work/mixed" && cp "$work/rgb1/frames/000000.png" "$work/mixed/frames/000001.png"
expect_status 1 "reconstruct, a colour frame among raw ones" "$uwscan" reconstruct \
  --dataset "$work/mixed" --out "$work/mixed.out" --poses "$work/mixed/groundtruth.tum" --quiet
grep -q "mixed/frames/000001.png: a 3-channel 8-bit image, but the frames before are 1-channel 8-bit (.*mixed/frames/000000.png)" \
  "$work/err" || fail "a colour frame among raw ones: $(cat "$work/err")"
[ ! -e "$work/mixed.out" ] || fail "a colour frame among raw ones: output left"
# Colour frames exported as RGBA (an alpha channel): read as the colour frames they are, the same
# cloud byte for byte; they used to fail with "images must have 1 or 3 channels, not 4", unnamed.
expect_status 0 "rgb frames" "$uwscan" simulate tank-target --out "$work/rgb3" --frames 3 \
  --width 160 --height 120 --seed 7 --output rgb --quiet
cp -r "$work/rgb3" "$work/rgba3"
python3 - "$work/rgba3/frames" <<'PY' || fail "write RGBA frames"
import os, struct, sys, zlib
def chunks(data):
    pos = 8
    while pos < len(data):
        n, = struct.unpack(">I", data[pos:pos + 4])
        yield data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
        pos += 12 + n
def unfilter(raw, width, bpp):
    rows, prev, stride, pos = [], bytearray(width * bpp), width * bpp, 0
    while pos < len(raw):
        kind, line = raw[pos], bytearray(raw[pos + 1:pos + 1 + stride])
        pos += 1 + stride
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], prev[i - bpp] if i >= bpp else 0
            if kind == 1: line[i] = (line[i] + a) & 255
            elif kind == 2: line[i] = (line[i] + b) & 255
            elif kind == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return rows
def chunk(kind, body):
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
for name in os.listdir(sys.argv[1]):
    path = os.path.join(sys.argv[1], name)
    data = open(path, "rb").read()
    parts = list(chunks(data))
    width, height, depth, colour = struct.unpack(">IIBB", parts[0][1][:10])
    assert depth == 8 and colour == 2, (depth, colour)
    rows = unfilter(zlib.decompress(b"".join(b for k, b in parts if k == b"IDAT")), width, 3)
    rgba = b"".join(b"\0" + bytes(v for i in range(width) for v in (*row[3 * i:3 * i + 3], 255))
                    for row in rows)
    header = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    open(path, "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) +
                           chunk(b"IDAT", zlib.compress(rgba)) + chunk(b"IEND", b""))
PY
expect_status 0 "reconstruct rgb frames" "$uwscan" reconstruct --dataset "$work/rgb3" \
  --out "$work/rgb3.out" --poses "$work/rgb3/groundtruth.tum" --quiet
expect_status 0 "reconstruct rgba frames" "$uwscan" reconstruct --dataset "$work/rgba3" \
  --out "$work/rgba3.out" --poses "$work/rgba3/groundtruth.tum" --quiet
cmp -s "$work/rgb3.out/cloud.ply" "$work/rgba3.out/cloud.ply" || fail "rgba frames: another cloud"
expect_status 0 "laser detect rgba frames" "$uwscan" laser detect --dataset "$work/rgba3" \
  --out "$work/rgba3.csv" --quiet

# A --poses trajectory with a gap (as `uwscan vo` marks lost tracking): the frame inside it gets no
# pose (it was interpolated across); one in nanoseconds is refused with the unit it looks like.
awk 'NR == 1 { print; print "# gap 0.003 0.010 lost"; next } !/^#/ && $1 > 0.003 && $1 < 0.010 { next }
  { print }' "$work/ds/groundtruth.tum" >"$work/gap.tum"
expect_status 0 "reconstruct --poses with a gap" "$uwscan" reconstruct --dataset "$work/ds" \
  --out "$work/gap.out" --poses "$work/gap.tum" --quiet
grep -q '"frames_without_pose": 1,' "$work/gap.out/report.json" ||
  fail "a pose inside the trajectory's gap: $(grep frames_without_pose "$work/gap.out/report.json")"
awk '!/^#/ { $1 = sprintf("%.0f", $1 * 1e9) } { print }' "$work/ds/groundtruth.tum" >"$work/ns.tum"
expect_status 1 "reconstruct --poses in nanoseconds" "$uwscan" reconstruct --dataset "$work/ds" \
  --out "$work/ns.out" --poses "$work/ns.tum" --quiet
grep -q "ns.tum: timestamps step by .* these look like nanoseconds (divide by 1e9)" "$work/err" ||
  fail "--poses in nanoseconds: $(cat "$work/err")"
# One in milliseconds covers the frames' times, its steps read as seconds: the scan runs, placing
# every profile with a pose interpolated over seconds, and says so.
awk '!/^#/ { $1 = sprintf("%.6f", $1 * 1e3) } { print }' "$work/ds/groundtruth.tum" >"$work/ms.tum"
expect_status 0 "reconstruct --poses in milliseconds" "$uwscan" reconstruct --dataset "$work/ds" \
  --out "$work/ms.out" --poses "$work/ms.tum"
grep -q "warning: .*ms.tum's poses are 6.94 s apart (median), and the frames' 0.0208 s hold 1 of them.*in milliseconds? divide them by 1000" \
  "$work/err" || fail "--poses in milliseconds: $(cat "$work/err")"
grep -q '"external_pose_step_s": 6.94' "$work/ms.out/report.json" || fail "ms: report.json"

# Replayed live (--live), the run waits for the camera's frames: its summary gives the cloud's lag
# behind the camera and does not blame a disk for the wait. (The clock slowed 100x: 1.4 s.)
mkdir "$work/slow" && cp -r "$work/ds/." "$work/slow/"
awk -F, -v OFS=, 'NR > 1 { $2 = $2 * 100 } { print }' "$work/ds/frames.csv" >"$work/slow/frames.csv"
awk '!/^#/ { $1 = $1 * 100 } { print }' "$work/ds/groundtruth.tum" >"$work/slow/groundtruth.tum"
expect_status 0 "reconstruct --live" "$uwscan" reconstruct --dataset "$work/slow" \
  --out "$work/slow.out" --poses "$work/slow/groundtruth.tum" --live
grep -q "^reconstruct: live, the cloud [0-9.]* s behind the camera at the end" "$work/err" ||
  fail "--live: no lag in the summary: $(cat "$work/err")"
! grep -q "disk" "$work/err" || fail "--live: the camera's pace blamed on a disk: $(cat "$work/err")"

# Outputs onto the dataset's own files are usage errors, the files untouched.
truth_sum=$(cksum <"$work/ds/groundtruth.tum")
expect_status 2 "vo --out onto the ground truth" "$uwscan" vo --dataset "$work/ds" \
  --out "$work/ds/groundtruth.tum" --quiet
grep -q -- "--out $work/ds/groundtruth.tum is an input" "$work/err" || fail "vo --out: $(cat "$work/err")"
expect_status 2 "evaluate --json onto the ground truth" "$uwscan" evaluate --dataset "$work/ds" \
  --trajectory "$work/ds/groundtruth.tum" --json "$work/ds/groundtruth.tum"
[ "$(cksum <"$work/ds/groundtruth.tum")" = "$truth_sum" ] || fail "the ground truth was overwritten"
mkdir -p "$work/again" && cp "$work/ds/groundtruth.tum" "$work/again/trajectory.tum"
expect_status 2 "reconstruct --out holding its --poses" "$uwscan" reconstruct --dataset "$work/ds" \
  --out "$work/again" --poses "$work/again/trajectory.tum" --quiet
[ "$(cksum <"$work/again/trajectory.tum")" = "$truth_sum" ] || fail "--poses replaced by the output"

# The small dataset's raw RGGB frames with another pattern in rig.yaml, reconstructed on the true
# poses: reconstruct_as NAME PATTERN (into $work/NAME.out).
reconstruct_as() {
  cp -r "$work/ds" "$work/$1" && sed -i "s/bayer: rggb/bayer: $2/" "$work/$1/rig.yaml"
  expect_status 0 "reconstruct rggb frames as $2" "$uwscan" reconstruct --dataset "$work/$1" \
    --out "$work/$1.out" --poses "$work/$1/groundtruth.tum" --quiet
}
# Raw Bayer frames with a rig that says bayer: none (a mono camera): a warning names the first
# frame and says what to set; report.json has the phases' ratio (null for the right rig).
reconstruct_as asmono none
grep -q "warning: $work/asmono/frames/000000.png: a single-channel frame whose 2x2 pixel phases differ in mean by a factor of [0-9.]*: it looks like a raw Bayer mosaic.*; set the camera's bayer (rggb, bggr, grbg or gbrg) in rig.yaml$" \
  "$work/err" || fail "raw frames as mono: no warning: $(cat "$work/err")"
grep -q '"mosaic_phase_ratio": [0-9]' "$work/asmono.out/report.json" || fail "raw frames as mono: ratio"
expect_status 0 "vo on raw frames as mono" "$uwscan" vo --dataset "$work/asmono" --out "$work/asmono.tum"
grep -q "warning: $work/asmono/frames/000000.png: a single-channel frame whose 2x2 pixel phases" \
  "$work/err" || fail "vo on raw frames as mono: no warning: $(cat "$work/err")"
# ... and with a pattern whose greens are on the other diagonal (grbg for rggb frames): named.
reconstruct_as grbg grbg
grep -q "warning: $work/grbg/frames/000000.png: rig.yaml says bayer grbg, but this raw frame's green samples are on the other diagonal.*the pattern is rggb or bggr" \
  "$work/err" || fail "rggb frames as grbg: no warning: $(cat "$work/err")"
grep -q '"bayer_doubt": "rggb or bggr"' "$work/grbg.out/report.json" || fail "rggb as grbg: report"
expect_status 0 "reconstruct raw frames" "$uwscan" reconstruct --dataset "$work/ds" \
  --out "$work/ds.out" --poses "$work/ds/groundtruth.tum" --quiet
grep -q '"mosaic_phase_ratio": null' "$work/ds.out/report.json" || fail "raw frames: a ratio"
grep -q '"bayer_doubt": null' "$work/ds.out/report.json" || fail "raw frames: a doubt on the pattern"
! grep -q "other diagonal" "$work/err" || fail "raw frames: a pattern warning: $(cat "$work/err")"
! grep -q "mosaic" "$work/err" || fail "raw frames: a mosaic warning: $(cat "$work/err")"
for cmd in "reconstruct --out $work/sb.out" "vo --out $work/sb.tum" "laser detect --out $work/sb.csv"; do
  # shellcheck disable=SC2086
  expect_status 2 "$cmd --sample-bits 8" "$uwscan" $cmd --dataset "$work/ds" --sample-bits 8
  grep -q -- "--sample-bits must be 9-16 (16: as stored), got 8" "$work/err" ||
    fail "$cmd --sample-bits 8: $(cat "$work/err")"
done
[ ! -e "$work/sb.out" ] && [ ! -e "$work/sb.tum" ] && [ ! -e "$work/sb.csv" ] ||
  fail "--sample-bits 8 wrote output"
expect_status 2 "reconstruct --track-every 0" "$uwscan" reconstruct --dataset "$work/pods" \
  --out "$work/pods.every0" --track-every 0 --quiet
grep -q "track-every must be auto or a count >= 1, got '0'" "$work/err" || fail "--track-every 0: unclear error"
[ ! -e "$work/pods.every0" ] || fail "--track-every 0 created its output folder"
expect_status 2 "reconstruct --track-every 2x" "$uwscan" reconstruct --dataset "$work/pods" \
  --out "$work/pods.every2x" --track-every 2x --quiet
grep -q "track-every must be auto or a count >= 1, got '2x'" "$work/err" || fail "--track-every 2x: unclear error"
for passes in 0 7 2x; do
  expect_status 2 "reconstruct --passes $passes" "$uwscan" reconstruct --dataset "$work/pods" \
    --out "$work/pods.passes" --passes "$passes" --quiet
  grep -q "passes must be auto or 1 to 6, got '$passes'" "$work/err" || fail "--passes $passes: unclear error"
  [ ! -e "$work/pods.passes" ] || fail "--passes $passes created its output folder"
done
expect_status 2 "reconstruct --oracle-depths --poses" "$uwscan" reconstruct --dataset "$work/pods" \
  --out "$work/pods.oracle" --oracle-depths --poses "$work/pods/groundtruth.tum" --quiet
grep -q "oracle-depths and --poses exclude each other" "$work/err" || fail "--oracle-depths --poses: unclear error"
expect_status 2 "reconstruct --oracle-tracks --poses" "$uwscan" reconstruct --dataset "$work/pods" \
  --out "$work/pods.oracle" --oracle-tracks --poses "$work/pods/groundtruth.tum" --quiet
grep -q "oracle-tracks and --poses exclude each other" "$work/err" || fail "--oracle-tracks --poses: unclear error"
cp -al "$work/pods" "$work/pods_noscene" && rm "$work/pods_noscene/scene.yaml"
expect_status 1 "reconstruct --oracle-tracks without scene.yaml" "$uwscan" reconstruct \
  --dataset "$work/pods_noscene" --out "$work/pods.oracle" --oracle-tracks --quiet
grep -q "scene.yaml: missing: --oracle-tracks needs a simulated dataset" "$work/err" ||
  fail "--oracle-tracks without scene.yaml: unclear error"
[ ! -e "$work/pods.oracle/cloud.ply" ] || fail "--oracle-tracks without scene.yaml wrote a cloud"
expect_status 2 "reconstruct --max-init-refinements below --init-refinements" "$uwscan" reconstruct \
  --dataset "$work/pods" --out "$work/pods.refine" --init-refinements 3 --max-init-refinements 2 --quiet
grep -q "max-init-refinements (2) must be at least --init-refinements (3)" "$work/err" ||
  fail "--max-init-refinements 2 --init-refinements 3: unclear error"
[ ! -e "$work/pods.refine" ] || fail "--max-init-refinements below --init-refinements wrote output"
expect_status 1 "reconstruct, no dataset" "$uwscan" reconstruct --dataset "$work/none" \
  --out "$work/none.out" --quiet
grep -q "none: no such dataset folder" "$work/err" || fail "reconstruct: unclear error without dataset"
[ ! -e "$work/none.out" ] || fail "reconstruct without a dataset wrote output"
expect_status 2 "reconstruct --contrast-scale -1" "$uwscan" reconstruct --dataset "$work/pods" \
  --out "$work/pods.contrast" --contrast-scale -1 --quiet
grep -q "contrast-scale must be in \[0, 0.5\]" "$work/err" || fail "--contrast-scale -1: unclear error"
expect_status 2 "reconstruct --contrast-scale high" "$uwscan" reconstruct --dataset "$work/pods" \
  --out "$work/pods.contrast" --contrast-scale high --quiet
grep -q "contrast-scale must be auto or a fraction in \[0, 0.5\], got 'high'" "$work/err" ||
  fail "--contrast-scale high: unclear error"
[ ! -e "$work/pods.contrast" ] || fail "--contrast-scale created its output folder"
expect_status 2 "reconstruct --async-ba --no-async-ba" "$uwscan" reconstruct --dataset "$work/pods" \
  --out "$work/pods.async" --async-ba --no-async-ba --quiet
grep -q "async-ba excludes --no-async-ba" "$work/err" || fail "--async-ba --no-async-ba: unclear error"
[ ! -e "$work/pods.async" ] || fail "--async-ba --no-async-ba created its output folder"
expect_status 2 "reconstruct --window 2" "$uwscan" reconstruct --dataset "$work/pods" \
  --out "$work/pods.window2" --window 2 --quiet
grep -q "window must be at least 3" "$work/err" || fail "--window 2: unclear error"
[ ! -e "$work/pods.window2" ] || fail "--window 2 created its output folder"
expect_status 2 "reconstruct --smoothing-half-window -1" "$uwscan" reconstruct \
  --dataset "$work/pods" --out "$work/pods.smooth" --smoothing-half-window -1 --quiet
grep -q "smoothing-half-window must be >= 0" "$work/err" || fail "--smoothing-half-window -1: unclear error"
[ ! -e "$work/pods.smooth" ] || fail "--smoothing-half-window -1 created its output folder"
expect_status 2 "reconstruct --max-start-plane-angle 0" "$uwscan" reconstruct \
  --dataset "$work/pods" --out "$work/pods.plane" --max-start-plane-angle 0 --quiet
grep -q "max-start-plane-angle must be in (0, 90\] deg, got 0" "$work/err" ||
  fail "--max-start-plane-angle 0: unclear error"
[ ! -e "$work/pods.plane" ] || fail "--max-start-plane-angle 0 created its output folder"
expect_status 2 "reconstruct --ba-history -1" "$uwscan" reconstruct \
  --dataset "$work/pods" --out "$work/pods.history" --ba-history -1 --quiet
grep -q "ba-history must be >= 0" "$work/err" || fail "--ba-history -1: unclear error"
[ ! -e "$work/pods.history" ] || fail "--ba-history -1 created its output folder"
expect_status 2 "reconstruct --passes 2 --poses" "$uwscan" reconstruct --dataset "$work/pods" \
  --out "$work/pods.passes2" --passes 2 --poses "$work/pods/groundtruth.tum" --quiet
grep -q "passes 2 and --poses exclude each other" "$work/err" || fail "--passes 2 --poses: unclear error"
[ ! -e "$work/pods.passes2" ] || fail "--passes 2 --poses created its output folder"

# A damaged frame or one of the wrong size stops reconstruct with the file
# named (the line is found on the image-reading thread for servo sweeps:
# its errors must come through), and no output is left under its name.
cp -r "$work/pods" "$work/broken"
head -c 2000 "$work/pods/frames/000001.png" > "$work/broken/frames/000001.png"
expect_status 1 "reconstruct, truncated frame" "$uwscan" reconstruct --dataset "$work/broken" \
  --out "$work/broken.out" --quiet
grep -q "frames/000001.png: truncated PNG" "$work/err" || fail "truncated frame: unclear error"
[ ! -e "$work/broken.out" ] || fail "truncated frame: output folder left behind"
"$uwscan" simulate tank-target --out "$work/small" --frames 1 --width 80 --height 60 --quiet ||
  fail "small dataset"
cp "$work/small/frames/000000.png" "$work/broken/frames/000001.png"
expect_status 1 "reconstruct, frame of the wrong size" "$uwscan" reconstruct \
  --dataset "$work/broken" --out "$work/broken.out2" --quiet
grep -q "frames/000001.png: image is 80x60 but camera" "$work/err" || fail "wrong size: unclear error"
[ ! -e "$work/broken.out2" ] || fail "wrong size: output folder left behind"
# A missing image is named before the scan starts.
rm "$work/broken/frames/000002.png"
expect_status 1 "reconstruct, missing frame" "$uwscan" reconstruct \
  --dataset "$work/broken" --out "$work/broken.out3" --quiet
grep -q "frames/000002.png: no such image (frame 2 of frames.csv)" "$work/err" ||
  fail "missing frame: unclear error: $(cat "$work/err")"
[ ! -e "$work/broken.out3" ] || fail "missing frame: output folder left behind"

# Usage errors: exit 2.
expect_status 2 "unknown scenario" "$uwscan" simulate no-such --out "$work/e1"
expect_status 2 "zero frames" "$uwscan" simulate tank-target --out "$work/e2" --frames 0
expect_status 2 "negative turbidity" "$uwscan" simulate tank-target --out "$work/e3" --turbidity=-1
expect_status 2 "unknown turbidity" "$uwscan" simulate tank-target --out "$work/e4" --turbidity murky
expect_status 2 "bad output" "$uwscan" simulate tank-target --out "$work/e5" --output jpeg
expect_status 2 "width without height" "$uwscan" simulate tank-target --out "$work/e6" --width 100
expect_status 2 "missing --out" "$uwscan" simulate tank-target
expect_status 2 "negative snow" "$uwscan" simulate tank-target --out "$work/e8" --marine-snow=-1
expect_status 2 "laser tilt out of range" "$uwscan" simulate laser-tilt --out "$work/e7" --laser-tilt-deg 45
expect_status 2 "three pods" "$uwscan" simulate tank-target --out "$work/e9" --pods 3
expect_status 2 "pods on the transect" "$uwscan" simulate seabed-transect --out "$work/e10" --pods 2
expect_status 2 "exposure beyond the frame period" "$uwscan" simulate tank-target --out "$work/e11" \
  --exposure-ms 8
grep -q "exposure-ms 8 is longer than tank-target's frame period (6.94444 ms at 144 Hz)" "$work/err" ||
  fail "exposure beyond the frame period: $(cat "$work/err")"
expect_status 2 "zero exposure" "$uwscan" simulate hull --out "$work/e12" --exposure-ms 0
for e in e1 e2 e3 e4 e5 e6 e7 e8 e9 e10 e11 e12; do [ ! -e "$work/$e" ] || fail "$e was created"; done
grep -q "unknown scenario 'no-such'" <("$uwscan" simulate no-such --out "$work/e1" 2>&1) ||
  fail "unknown scenario message"

# Runtime errors: exit 1, nothing left under the final name.
expect_status 1 "non-empty output" "$uwscan" simulate tank-target --out "$work/ds" --frames 1 \
  --width 32 --height 24 --quiet
mkdir -p "$work/ro" && chmod 555 "$work/ro"
if [ "$(id -u)" -ne 0 ]; then
  expect_status 1 "unwritable output" "$uwscan" simulate tank-target --out "$work/ro/ds" --frames 1 \
    --width 32 --height 24 --quiet
fi
expect_status 1 "output under a file" "$uwscan" simulate tank-target --out "$work/ds/rig.yaml/x" \
  --frames 1 --width 32 --height 24 --quiet
expect_status 1 "output under /proc" "$uwscan" simulate tank-target --out /proc/uwscan-sim \
  --frames 1 --width 32 --height 24 --quiet
grep -q "^uwscan: error: /proc/uwscan-sim: cannot create the output folder: " "$work/err" ||
  fail "output under /proc: the error names the temporary, not --out: $(cat "$work/err")"
expect_status 2 "empty --out" "$uwscan" simulate tank-target --out "" --frames 1 --quiet
expect_status 2 "reconstruct, empty --out" "$uwscan" reconstruct --dataset "$work/ds" --out ""
[ -z "$(ls "$work" | grep tmp-)" ] || fail "temporary folder left behind"
echo "simulate CLI: all checks passed"
