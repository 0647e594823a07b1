#!/usr/bin/env bash
# CLI: camera project/backproject round trip, analyze port, error handling.
set -u
bin="$1"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

cat >"$dir/rig.yaml" <<'YAML'
format: uwscan-rig/1
cameras:
  - name: cam0
    width: 1280
    height: 960
    bayer: none
    model: flatport
    fx: 785.0
    fy: 785.0
    cx: 640.0
    cy: 480.0
    distortion: [-0.05, 0.01, 0.0, 0.0, 0.0]
    port:
      normal: [0, 0, 1]
      d_air: 0.005
      d_glass: 0.010
      n_air: 1.0
      n_glass: 1.77
      n_water: 1.337
    rig_from_camera: {q: [1, 0, 0, 0], t: [0, 0, 0]}
YAML
printf 'u,v\n10,20\n640,480\n1200.5,900.25\n' >"$dir/pixels.csv"
"$bin" camera backproject --rig "$dir/rig.yaml" --in "$dir/pixels.csv" --out "$dir/rays.csv" || fail "backproject"
# Points 2 m along each ray, projected back with each method.
python3 - "$dir" <<'PY' || fail "points"
import csv, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(f"{d}/rays.csv")))
with open(f"{d}/points.csv", "w") as out:
    out.write("x,y,z\n")
    for r in rows:
        assert r["valid"] == "1", r
        o = [float(r[k]) for k in ("ox", "oy", "oz")]
        v = [float(r[k]) for k in ("dx", "dy", "dz")]
        out.write(",".join(str(o[i] + 2.0 * v[i]) for i in range(3)) + "\n")
    out.write("0,0,-1\n")  # behind the camera: invalid
PY
for method in exact taylor; do
  "$bin" camera project --rig "$dir/rig.yaml" --method $method --iterations 3 --in "$dir/points.csv" \
    --out "$dir/back_$method.csv" || fail "project $method"
  python3 - "$dir" $method <<'PY' || fail "round trip $method"
import csv, sys
d, method = sys.argv[1], sys.argv[2]
expected = list(csv.DictReader(open(f"{d}/pixels.csv")))
got = list(csv.DictReader(open(f"{d}/back_{method}.csv")))
assert len(got) == 4, got
for e, g in zip(expected, got):
    assert g["valid"] == "1"
    err = max(abs(float(e["u"]) - float(g["u"])), abs(float(e["v"]) - float(g["v"])))
    assert err < (1e-6 if method == "exact" else 1e-4), (method, e, g, err)
assert got[3]["valid"] == "0", got[3]
PY
done

"$bin" analyze port --rig "$dir/rig.yaml" --depth 2 >"$dir/analyze.txt" || fail "analyze port"
grep -q "(fit depth)" "$dir/analyze.txt" || fail "analyze output"
grep -q "image corner" "$dir/analyze.txt" || fail "analyze d_air"
# The water's depth (or millimetres) given for the distance looked at: a usage error.
"$bin" analyze port --rig "$dir/rig.yaml" --depth 2000 >/dev/null 2>"$dir/err"
[ $? -eq 2 ] || fail "--depth 2000 should exit 2"
grep -q -- "--depth is the distance (m) from the camera to what it looks at, at most 100 m" \
  "$dir/err" || fail "--depth 2000: $(cat "$dir/err")"

# Errors: bad input exits 1 with one line naming the file; usage exits 2.
"$bin" camera project --rig "$dir/missing.yaml" --in "$dir/points.csv" --out "$dir/x.csv" 2>"$dir/err"
[ $? -eq 1 ] || fail "missing rig should exit 1"
grep -q "missing.yaml" "$dir/err" || fail "error names the file"
points_sum=$(cksum <"$dir/points.csv")
"$bin" camera project --rig "$dir/rig.yaml" --in "$dir/points.csv" --out "$dir/points.csv" \
  2>"$dir/err"
[ $? -eq 2 ] || fail "--out onto --in should exit 2"
grep -q -- "--out $dir/points.csv is an input" "$dir/err" || fail "--out onto --in: $(cat "$dir/err")"
[ "$(cksum <"$dir/points.csv")" = "$points_sum" ] || fail "--out onto --in replaced the points"
printf 'x,y,z\n1,2\n' >"$dir/bad.csv"
"$bin" camera project --rig "$dir/rig.yaml" --in "$dir/bad.csv" --out "$dir/out.csv" 2>"$dir/err"
[ $? -eq 1 ] || fail "bad csv should exit 1"
grep -q "bad.csv:2" "$dir/err" || fail "error names file and line: $(cat "$dir/err")"
[ ! -e "$dir/out.csv" ] || fail "no output on error"
ls "$dir" | grep -q tmp && fail "temporary left behind"
# Other columns (text too) are skipped, a spreadsheet's byte order mark and CRLF are read; a file
# separated by semicolons is said to be.
printf '\xef\xbb\xbfname,u,v\r\ncentre,640,480\r\n' >"$dir/named.csv"
"$bin" camera backproject --rig "$dir/rig.yaml" --in "$dir/named.csv" --out "$dir/named_rays.csv" \
  2>"$dir/err" || fail "a named pixel: $(cat "$dir/err")"
[ "$(sed -n 2p "$dir/named_rays.csv")" = "$(sed -n 3p "$dir/rays.csv")" ] || fail "named pixel's ray"
printf 'u;v\n640;480\n' >"$dir/semicolons.csv"
"$bin" camera backproject --rig "$dir/rig.yaml" --in "$dir/semicolons.csv" --out "$dir/x.csv" 2>"$dir/err"
[ $? -eq 1 ] || fail "semicolons should exit 1"
grep -q "semicolons.csv: missing column 'u' (header 'u;v'; columns are separated by commas)" \
  "$dir/err" || fail "semicolons: $(cat "$dir/err")"
[ ! -e "$dir/x.csv" ] || fail "no output for a file without the columns"
"$bin" camera project --rig "$dir/rig.yaml" --method fisheye --in "$dir/points.csv" --out "$dir/x.csv" 2>/dev/null
[ $? -eq 2 ] || fail "bad method should exit 2"
"$bin" camera frobnicate 2>/dev/null
[ $? -eq 2 ] || fail "unknown subcommand should exit 2"
sed 's/n_water: 1.337/n_water: 0.5/' "$dir/rig.yaml" >"$dir/bad_rig.yaml"
"$bin" analyze port --rig "$dir/bad_rig.yaml" 2>"$dir/err"
[ $? -eq 1 ] || fail "invalid rig should exit 1"
grep -q "bad_rig.yaml.*n_water" "$dir/err" || fail "rig error names file and key: $(cat "$dir/err")"
# A camera the rig does not have: exit 1, naming the rig's file and the camera.
for cmd in "camera project --in $dir/points.csv --out $dir/x.csv" "analyze port"; do
  "$bin" $cmd --rig "$dir/rig.yaml" --camera nope >/dev/null 2>"$dir/err"
  [ $? -eq 1 ] || fail "$cmd --camera nope should exit 1"
  grep -q "$dir/rig.yaml: the rig has no camera named 'nope'" "$dir/err" \
    || fail "$cmd --camera nope: $(cat "$dir/err")"
done
[ ! -e "$dir/x.csv" ] || fail "no output for a camera the rig does not have"
# An empty value (an unset shell variable) is a usage error naming the option, in every command.
for cmd in "camera project --rig $dir/rig.yaml --in $dir/points.csv --out" \
  "analyze port --rig $dir/rig.yaml --camera" "evaluate --dataset $dir --trajectory x.tum --json" \
  "laser detect --out x.csv --images"; do
  "$bin" $cmd "" >/dev/null 2>"$dir/err"
  [ $? -eq 2 ] || fail "$cmd '': want exit 2"
  grep -q -- "^${cmd##* }: empty value$" "$dir/err" || fail "$cmd '': $(cat "$dir/err")"
done
# A fitting depth that is no distance: a usage error (exit 2) that says what it got.
for depth in 0 -1 nan inf; do
  "$bin" analyze port --rig "$dir/rig.yaml" --depth "$depth" >/dev/null 2>"$dir/err"
  [ $? -eq 2 ] || fail "analyze port --depth $depth should exit 2"
  grep -q "usage error: --depth must be a distance > 0.05 m, got $depth" "$dir/err" \
    || fail "--depth $depth: $(cat "$dir/err")"
done
echo "camera CLI: all checks passed"
