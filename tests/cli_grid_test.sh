#!/usr/bin/env bash
# End-to-end checks of `ddtscale grid`: good runs (CSV, XYZ, EXR/TIFF/PNG
# outputs, no-data, duplicates) and bad input (one line on stderr, exit 1
# or 2, an existing output left alone, no temporary file left behind).
# Usage: cli_grid_test.sh path/to/ddtscale
set -u
bin="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0
failed=0
ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL: $*"; }

run_ok() {
  local name="$1"; shift
  if "$bin" grid "$@" >"$work/out.txt" 2>"$work/err.txt"; then ok; else bad "$name: exit $? ($(cat "$work/err.txt"))"; fi
}
# A clean failure: exit 1 or 2, exactly one line on stderr, matching $2.
# The cases start in the background (start-up dominates their time) and
# are judged by check_failures once all have ended.
fail_cases=()
run_fail() {
  local id=${#fail_cases[@]}
  fail_cases+=("$1|$2")
  shift 2
  ( "$bin" grid "$@" >/dev/null 2>"$work/fail_$id.err"; echo $? >"$work/fail_$id.code" ) &
}
check_failures() {
  wait
  local id name pattern code lines
  for id in "${!fail_cases[@]}"; do
    name=${fail_cases[$id]%%|*}
    pattern=${fail_cases[$id]#*|}
    code=$(cat "$work/fail_$id.code")
    lines=$(wc -l <"$work/fail_$id.err")
    if [ "$code" -ne 1 ] && [ "$code" -ne 2 ]; then bad "$name: exit code $code"; continue; fi
    if [ "$lines" -ne 1 ]; then bad "$name: $lines lines on stderr: $(cat "$work/fail_$id.err")"; continue; fi
    grep -q -- "$pattern" "$work/fail_$id.err" && ok || bad "$name: '$(cat "$work/fail_$id.err")' does not say '$pattern'"
  done
  rm -f "$work"/fail_*
}

# Points on the triangle x, y >= 0, x + y <= 10 sampling z = x + 2 y, a
# duplicate of (0, 0) with another value, and one of (10, 0) twice.
{
  echo "x,y,z"
  for i in 0 1 2 3 4 5 6 7 8 9 10; do
    for j in 0 1 2 3 4 5 6 7 8 9 10; do
      [ $((i + j)) -le 10 ] && echo "$i,$j,$((i + 2 * j))"
    done
  done
  echo "0,0,2"
  echo "10,0,10"
  echo "10,0,10"
} >"$work/tri.csv"

run_ok "csv to exr" "$work/tri.csv" "$work/tri.exr" --size 20x20
grep -q "3 duplicates merged into 2 positions" "$work/err.txt" && ok || bad "merge not reported: $(cat "$work/err.txt")"
grep -q "x 0..10, y 0..10" "$work/err.txt" && ok || bad "bounds not reported: $(cat "$work/err.txt")"
oiiotool --dumpdata "$work/tri.exr" >"$work/dump.txt"
grep -q "20 x   20, 1 channel, float" "$work/dump.txt" && ok || bad "EXR: $(head -1 "$work/dump.txt")"
# Row 0 is north: its last pixel (9.75, 9.75) is outside the hull, its first (0.25, 9.75) inside.
grep -q "Pixel (19, 0): nan" "$work/dump.txt" && ok || bad "no NaN outside the hull: $(grep 'Pixel (19, 0)' "$work/dump.txt")"
grep -q "Pixel (0, 0): 19.75" "$work/dump.txt" && ok || bad "north-up value: $(grep 'Pixel (0, 0)' "$work/dump.txt")"
# The duplicate at (0, 0) averages 0 and 2: the bottom-left pixel (0.25, 0.25) is no longer 0.75.
grep -q "Pixel (0, 19): 0.75" "$work/dump.txt" && bad "duplicate not averaged" || ok

# ASCII XYZ as gdal_translate -of XYZ writes it (cell centres, north first),
# gridded over its cell edges: reproduced exactly, no no-data.
printf '105 45 0\n115 45 1\n125 45 2\n105 35 3\n115 35 4\n125 35 5\n' >"$work/grid.xyz"
run_ok "xyz to tiff" "$work/grid.xyz" "$work/grid.tif" --size 3x2 --bounds 100,30,130,50
grep -q "0 no-data pixels" "$work/err.txt" && ok || bad "XYZ grid has no-data: $(cat "$work/err.txt")"
oiiotool --dumpdata "$work/grid.tif" >"$work/dump.txt"
grep -q "3 x    2, 2 channel, float tiff" "$work/dump.txt" && ok || bad "TIFF: $(head -1 "$work/dump.txt")"
grep -q "Pixel (2, 1): 5.000000000 1.000000000" "$work/dump.txt" && ok || bad "XYZ not reproduced"

run_ok "png with alpha" "$work/tri.csv" "$work/tri.png" --size 16x16 --columns x,y,z
grep -q "clamped" "$work/err.txt" && ok || bad "PNG clamping not noted"
oiiotool --info "$work/tri.png" | grep -q "2 channel, uint16 png" && ok || bad "PNG: $(oiiotool --info "$work/tri.png")"
run_ok "lookahead" "$work/tri.csv" "$work/la.exr" --size 16x16 --optimizer lookahead
run_ok "anneal" "$work/tri.csv" "$work/an.exr" --size 16x16 --optimizer anneal --seed 4
run_ok "nodata value" "$work/tri.csv" "$work/nd.tif" --size 16x16 --nodata=-9999 --no-optimize
oiiotool --dumpdata "$work/nd.tif" >"$work/dump.txt"
grep -q "1 channel, float tiff" "$work/dump.txt" && ok || bad "--nodata still adds alpha"
grep -q "Pixel (15, 0): -9999" "$work/dump.txt" && ok || bad "--nodata value not written"
run_ok "verbose, costs, negative bounds" "$work/tri.csv" "$work/v.exr" --size 8x4 --cost variance --cost-channel z \
  --bounds -5,-5,15,15 --verbose
grep -q "flips" "$work/err.txt" && grep -q "render" "$work/err.txt" && ok || bad "--verbose reports no stages"
run_ok "help" --help
for opt in --size --bounds --columns --input-nodata --nodata --cost --cost-channel --no-optimize --tolerance \
  --max-pixels --verbose --quiet; do
  grep -q -- "$opt" "$work/out.txt" && ok || bad "--help does not mention $opt"
done
grep -q -- "--cost TEXT=jnd-edge" "$work/out.txt" && ok || bad "--help does not give jnd-edge as the default cost"

# Bad input.
printf 'x,y,z\n0,0,1\n1,zero,2\n0,1,3\n' >"$work/malformed.csv"
printf '0 0 1\n1 0 nan\n0 1 3\n' >"$work/nan.xyz"
printf '0,0,1\n1,1,2\n2,2,3\n' >"$work/line.csv"
printf 'precious' >"$work/keep.exr"
run_fail "malformed line, keeps existing output" "line 3: field 2 (y) 'zero' is not a number" \
  "$work/malformed.csv" "$work/keep.exr" --size 8x8
run_fail "nan value" "line 2: field 3 'nan' is not a finite number" "$work/nan.xyz" "$work/o.exr" --size 8x8
run_fail "collinear" "span no area" "$work/line.csv" "$work/o.exr" --size 8x8
run_fail "missing input" "no such file" "$work/nope.csv" "$work/o.exr" --size 8x8
run_fail "no size" "size" "$work/tri.csv" "$work/o.exr"
run_fail "bad size" "--size" "$work/tri.csv" "$work/o.exr" --size 0x5
run_fail "inverted bounds" "xmin < xmax" "$work/tri.csv" "$work/o.exr" --size 8x8 --bounds 5,0,1,1
run_fail "too many pixels" "max-pixels" "$work/tri.csv" "$work/o.exr" --size 100x100 --max-pixels 1000
run_fail "jpeg output" ".exr, .tif" "$work/tri.csv" "$work/o.jpg" --size 8x8
run_fail "missing directory" "does not exist" "$work/tri.csv" "$work/nodir/o.exr" --size 8x8
run_fail "unknown column" "no column named 'h'" "$work/tri.csv" "$work/o.exr" --size 8x8 --columns x,y,h
run_fail "unknown optimizer" "--optimizer" "$work/tri.csv" "$work/o.exr" --size 8x8 --optimizer genetic
run_fail "cooling of 1" "strictly between 0 and 1" "$work/tri.csv" "$work/o.exr" --size 8x8 --optimizer anneal --anneal-cooling 1
run_fail "cost channel" "--cost-channel 5" "$work/tri.csv" "$work/o.exr" --size 8x8 --cost-channel 5
printf 'x,y,a,b\n0,0,1,2\n1,0,1,2\n0,1,1,2\n' >"$work/two.csv"
run_fail "png with two channels" "PNG holds 1 or 3" "$work/two.csv" "$work/o.png" --size 8x8

check_failures

# A failing run leaves an existing output alone, and no temporary file.
[ "$(cat "$work/keep.exr")" = "precious" ] && ok || bad "existing output was overwritten"
ls -a "$work" | grep -q '\.tmp' && bad "temporary file left behind" || ok

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
