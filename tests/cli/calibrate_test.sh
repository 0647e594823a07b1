#!/usr/bin/env bash
# CLI tests of `uwscan calibrate`: a real run on OpenCV's sample images
# (Debian opencv-doc) and the bad-input paths (exit status, one clear error
# line, no rig written).
set -u
UWSCAN=${1:?usage: calibrate_test.sh path/to/uwscan}
DATA=/usr/share/doc/opencv-doc/examples/data
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# expect STATUS PATTERN -- command...: exit status and a stderr pattern.
expect() {
  local status=$1 pattern=$2
  shift 3
  "$@" >"$TMP/stdout" 2>"$TMP/stderr"
  local got=$?
  [[ $got == "$status" ]] || fail "exit $got (want $status): $* :: $(cat "$TMP/stderr")"
  grep -q -- "$pattern" "$TMP/stderr" || fail "stderr lacks '$pattern': $* :: $(cat "$TMP/stderr")"
}

if [[ -f $DATA/left01.jpg ]]; then
  mkdir -p "$TMP/left" "$TMP/few" "$TMP/five" "$TMP/mixed" "$TMP/out"
  cp "$DATA"/left[0-9][0-9].jpg "$TMP/left/"
  cp "$DATA"/left01.jpg "$DATA"/left02.jpg "$TMP/few/"
  cp "$DATA"/left0[1-5].jpg "$TMP/five/"  # small sets keep the test quick
  "$UWSCAN" calibrate camera --images "$TMP/left" --board 9x6:0.025 --out "$TMP/out/rig.yaml" \
    --report "$TMP/out/report" >"$TMP/stdout" 2>"$TMP/stderr" || fail "real images: $(cat "$TMP/stderr")"
  grep -q "model: pinhole" "$TMP/out/rig.yaml" || fail "rig.yaml lacks the pinhole camera"
  grep -q '"dropped_reason"' "$TMP/out/report/calibration.json" || fail "report lacks views"
  [[ -s $TMP/out/report/calibration_residuals.png ]] || fail "no residual PNG"
  # --rig keeps the lasers of an existing rig and replaces the named camera.
  { cat "$TMP/out/rig.yaml"; printf 'lasers:\n  - name: laser0\n    camera_from_laser: {q: [1, 0, 0, 0], t: [0.3, 0, 0]}\n    p1: 0.0\n    wavelength_nm: 532\n'; } >"$TMP/with_laser.yaml"
  "$UWSCAN" calibrate camera --images "$TMP/five" --board 9x6:0.025 --rig "$TMP/with_laser.yaml" \
    --out "$TMP/out/rig2.yaml" --quiet >/dev/null 2>"$TMP/stderr" || fail "--rig: $(cat "$TMP/stderr")"
  grep -q "laser0" "$TMP/out/rig2.yaml" || fail "--rig dropped the laser"
  [[ $(grep -c "name: cam0" "$TMP/out/rig2.yaml") == 1 ]] || fail "--rig duplicated the camera"

  # A report that cannot be written fails before the calibration runs, and writes no rig; a
  # calibration that fails leaves no report folder.
  expect 1 "out/rig.yaml: cannot create the output folder" -- "$UWSCAN" calibrate camera \
    --images "$TMP/five" --board 9x6:0.025 --out "$TMP/unreported.yaml" --report "$TMP/out/rig.yaml"
  [ ! -e "$TMP/unreported.yaml" ] || fail "a rig written though its report could not be"
  expect 1 "check --board" -- "$UWSCAN" calibrate camera --images "$TMP/five" \
    --board 7x5:0.025 --out "$TMP/bad.yaml" --report "$TMP/failed/report"
  [ ! -e "$TMP/failed" ] || fail "a failed calibration left its report folder"
  # A report among the board images would put its PNG there, read as a board next time.
  expect 2 "is the --images folder: its PNG would be read as a board image" -- "$UWSCAN" \
    calibrate camera --images "$TMP/five" --board 9x6:0.025 --out "$TMP/r.yaml" --report "$TMP/five/"
  [ ! -e "$TMP/five/calibration.json" ] && [ ! -e "$TMP/r.yaml" ] || fail "a report among the images"
  # Wrong board size: no board anywhere.
  expect 1 "check --board" -- "$UWSCAN" calibrate camera --images "$TMP/five" \
    --board 7x5:0.025 --out "$TMP/bad.yaml"
  # No board in any image.
  mkdir -p "$TMP/noboard"
  cp "$DATA/box.png" "$TMP/noboard/" 2>/dev/null || true
  if ls "$TMP/noboard"/*.png >/dev/null 2>&1; then
    expect 1 "no 9x6 board found in any" -- "$UWSCAN" calibrate camera --images "$TMP/noboard" \
      --board 9x6:0.025 --out "$TMP/bad.yaml"
  fi
  # Boards found but rejected by a threshold: said so (not "check --board"), with the first
  # one's measure and the option.
  expect 1 "board was found in 5 of 5 image(s) but none was kept (left01.jpg: low contrast: \
[0-9.]* grey levels < 1000 (--min-contrast))" -- "$UWSCAN" calibrate camera \
    --images "$TMP/five" --board 9x6:0.025 --min-contrast 1000 --out "$TMP/bad.yaml"
  expect 1 "blurred: edge width [0-9.]* px > 0.5 px (--max-edge-width)" -- "$UWSCAN" calibrate \
    camera --images "$TMP/five" --board 9x6:0.025 --max-edge-width 0.5 --out "$TMP/bad.yaml"
  # Too few views.
  expect 1 "need at least 3" -- "$UWSCAN" calibrate camera --images "$TMP/few" \
    --board 9x6:0.025 --out "$TMP/bad.yaml"
  # Images of different sizes.
  cp "$DATA/left01.jpg" "$TMP/mixed/"
  cp "$DATA/lena.jpg" "$TMP/mixed/z.jpg" 2>/dev/null || cp "$DATA/box.png" "$TMP/mixed/z.png"
  expect 1 "same size" -- "$UWSCAN" calibrate camera --images "$TMP/mixed" --board 9x6:0.025 \
    --out "$TMP/bad.yaml"
  # A rig without the named camera.
  expect 1 "nope" -- "$UWSCAN" calibrate laser --rig "$TMP/out/rig.yaml" --camera nope \
    --images "$TMP/left" --board 9x6:0.025 --out "$TMP/bad.yaml"
  # Servo options: both or neither; a bad angle file names the line.
  expect 2 "go together" -- "$UWSCAN" calibrate laser --rig "$TMP/out/rig.yaml" \
    --images "$TMP/left" --board 9x6:0.025 --servo-axis 0,0,0,0,1,0 --out "$TMP/bad.yaml"
  for axis in 0,0,0,0,0,0 0,0,0,nan,1,0 0,0,0,0,1; do
    expect 2 "servo-axis must be .*got '$axis'" -- "$UWSCAN" calibrate laser \
      --rig "$TMP/out/rig.yaml" --images "$TMP/left" --board 9x6:0.025 --servo-axis "$axis" \
      --servo-angles "$TMP/angles.csv" --out "$TMP/bad.yaml"
  done
  printf 'file,angle_deg\nleft01.jpg,zero\n' >"$TMP/angles.csv"
  expect 1 "angles.csv:2" -- "$UWSCAN" calibrate laser --rig "$TMP/out/rig.yaml" \
    --images "$TMP/few" --board 9x6:0.025 --servo-axis 0,0,0,0,1,0 \
    --servo-angles "$TMP/angles.csv" --out "$TMP/bad.yaml"
  # Flat port without the glass.
  expect 2 "glass" -- "$UWSCAN" calibrate camera --images "$TMP/left" --board 9x6:0.025 \
    --model flatport --out "$TMP/bad.yaml"
fi
# Laser calibration on the simulator's laser-tilt scenario (§6.2), against the
# rig the simulator wrote: a laser behind the window at 0 and 6 deg tilt,
# the camera rig given without the laser (no nominal pose to lean on).
for tilt in 0 6; do
  "$UWSCAN" simulate laser-tilt --out "$TMP/lt$tilt" --frames 1 --width 640 --height 480 \
    --laser-tilt-deg $tilt --seed 5 --quiet || fail "simulate laser-tilt $tilt"
  sed '/^lasers:/,$d' "$TMP/lt$tilt/rig.yaml" >"$TMP/lt$tilt/camera.yaml"
  "$UWSCAN" calibrate laser --rig "$TMP/lt$tilt/camera.yaml" --images "$TMP/lt$tilt/calib/laser/frames" \
    --board 11x7:0.025 --target-margin 0.05 --max-edge-width 8 --min-contrast 10 \
    --out "$TMP/lt$tilt/laser.yaml" >"$TMP/stdout" 2>"$TMP/stderr" || fail "laser-tilt $tilt: $(cat "$TMP/stderr")"
  truth_p1=$(awk '/p1:/ {print $2}' "$TMP/lt$tilt/rig.yaml")
  awk -v tilt=$tilt -v truth_p1="$truth_p1" '/^laser laser0/ {
      for (i = 1; i <= NF; ++i) { if ($i == "baseline") b = $(i + 1); if ($i == "x") a = $(i + 1); if ($i == "p1") p = $(i + 1) }
      bad = 0
      if (tilt == 0 && (b < 99.5 || b > 100.5 || a > 0.05 || p < -0.003 || p > 0.003)) bad = 1
      d = (p < 0 ? -p : p) - (truth_p1 < 0 ? -truth_p1 : truth_p1)
      if (tilt > 0 && (d < -0.15 * (truth_p1 < 0 ? -truth_p1 : truth_p1) || d > 0.15 * (truth_p1 < 0 ? -truth_p1 : truth_p1))) bad = 1
      if (bad) { print "laser-tilt " tilt ": baseline " b " mm, angle " a " deg, p1 " p " (truth " truth_p1 ")"; exit 1 }
    }' "$TMP/stdout" || fail "$(awk '/^laser laser0/' "$TMP/stdout") truth p1 $truth_p1"
done

# --air-without-port without water images.
expect 2 "air-without-port needs" -- "$UWSCAN" calibrate camera --images "$TMP" --board 9x6:0.025 \
  --model flatport --glass 1.5,0.01 --air-without-port --out "$TMP/bad.yaml"
# No such folder; bad board text.
expect 1 "not a folder" -- "$UWSCAN" calibrate camera --images "$TMP/none" --board 9x6:0.025 \
  --out "$TMP/bad.yaml"
expect 2 "COLSxROWS" -- "$UWSCAN" calibrate camera --images "$TMP" --board 9by6 --out "$TMP/bad.yaml"
# Centimetres given for metres (2.5 for 25 mm) would scale the calibration by 100.
expect 2 "the square size is in metres, in (0, 1\] (0.025 for 25 mm squares), got 2.5" -- \
  "$UWSCAN" calibrate camera --images "$TMP" --board 9x6:2.5 --out "$TMP/bad.yaml"
[[ -e $TMP/bad.yaml ]] && fail "a rig was written on error"
ls "$TMP"/bad.yaml.tmp* >/dev/null 2>&1 && fail "a temporary rig was left behind"
[[ $failures == 0 ]] && echo "calibrate CLI tests passed"
exit $((failures > 0))
