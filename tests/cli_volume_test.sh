#!/usr/bin/env bash
# End-to-end checks of the volume side of the ddtscale command: the main
# job (ddtscale in.nrrd out.nrrd --scale 4), its options, volume-field and
# volume-eval, and bad input (one line on stderr, non-zero exit, nothing
# destroyed). Usage: cli_volume_test.sh path/to/ddtscale
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
  if "$bin" "$@" >"$work/out.txt" 2>"$work/err.txt"; then ok; else bad "$name: exit $? ($(cat "$work/err.txt"))"; fi
}
run_fail() {
  local name="$1"; shift
  "$bin" "$@" >"$work/out.txt" 2>"$work/err.txt"
  local code=$?
  local lines
  lines=$(wc -l <"$work/err.txt")
  if [ "$code" -ne 1 ] && [ "$code" -ne 2 ]; then bad "$name: exit code $code"; return; fi
  if [ "$lines" -ne 1 ]; then bad "$name: $lines lines on stderr: $(cat "$work/err.txt")"; return; fi
  ok
}
# header FIELD FILE: the value of a NRRD header field (the header is text up to the first blank line).
header() { sed -n '/^$/q;p' "$2" | sed -n "s/^$1: //p"; }

run_ok "volume-field" volume-field sphere "$work/s.nrrd" --size 10 --type uint8 --encoding gzip --supersample 4
run_ok "volume-field float" volume-field hydrogen "$work/h.nhdr" --size 6x7x8 --supersample 2
[ -f "$work/h.raw" ] && ok || bad "detached data file h.raw missing"

# The main job.
run_ok "main job" "$work/s.nrrd" "$work/out.nrrd" --scale 4
[ "$(header sizes "$work/out.nrrd")" = "40 40 40" ] && ok || bad "main job: sizes $(header sizes "$work/out.nrrd")"
[ "$(header type "$work/out.nrrd")" = "unsigned char" ] && ok || bad "8-bit input did not stay 8-bit"
[ "$(header encoding "$work/out.nrrd")" = "gzip" ] && ok || bad "gzip input did not stay gzip"
run_ok "float, detached, non-integer scale" "$work/h.nhdr" "$work/h2.nhdr" --scale 2.5 --cost sederberg
[ "$(header sizes "$work/h2.nhdr")" = "15 18 20" ] && ok || bad "scale 2.5: sizes $(header sizes "$work/h2.nhdr")"
[ "$(header type "$work/h2.nhdr")" = "float" ] && ok || bad "float input did not stay float"
run_ok "size, type, encoding" "$work/s.nrrd" "$work/sz.nrrd" --size 12x14x16 --type float32 --encoding raw
[ "$(header sizes "$work/sz.nrrd")" = "12 14 16" ] && ok || bad "--size: $(header sizes "$work/sz.nrrd")"
[ "$(header type "$work/sz.nrrd")" = "float" ] && [ "$(header encoding "$work/sz.nrrd")" = "raw" ] && ok ||
  bad "--type/--encoding not applied"
run_ok "verbose, compare, picture" "$work/s.nrrd" "$work/v.nrrd" --scale 3 --verbose --compare trilinear,tricubic \
  --picture "$work/v.png" --iso 100
grep -q "flips 2-3: [0-9]*, 3-2: [0-9]*, 4-4: [0-9]*, 2-2: [0-9]*" "$work/err.txt" && grep -q "cost variance" "$work/err.txt" &&
  grep -q "peak memory" "$work/err.txt" && ok || bad "--verbose does not report flips of each kind, cost and memory"
[ -f "$work/v.trilinear.nrrd" ] && [ -f "$work/v.tricubic.nrrd" ] && ok || bad "--compare did not write the baselines"
oiiotool --info "$work/v.png" >/dev/null 2>&1 && ok || bad "--picture is not a readable image"
run_ok "methods" "$work/s.nrrd" "$work/m.nrrd" --scale 2 --method trilinear
run_ok "single slice" volume-field sphere "$work/flat.nrrd" --size 8x8x1
run_ok "single slice enlarged" "$work/flat.nrrd" "$work/flat4.nrrd" --scale 4
[ "$(header sizes "$work/flat4.nrrd")" = "32 32 4" ] && ok || bad "single slice: $(header sizes "$work/flat4.nrrd")"
# Channels: an RGB volume (a leading axis of kind RGB-color) keeps its
# channel axis, kind and sample type; each channel is reproduced at the
# input samples (x3: output voxel 3i + 1 is input voxel i).
{
  printf 'NRRD0004\ntype: uchar\ndimension: 4\nsizes: 3 4 4 4\nkinds: RGB-color space space space\n'
  printf 'space: right-anterior-superior\nspace directions: none (1,0,0) (0,1,0) (0,0,2)\nspace origin: (0,0,0)\n'
  printf 'encoding: ascii\n\n'
  for i in $(seq 0 63); do printf '%d %d %d\n' $((i * 4 % 256)) $((255 - i * 3)) $(((i * 37) % 200)); done
} >"$work/rgb.nrrd"
run_ok "RGB volume" "$work/rgb.nrrd" "$work/rgb3.nrrd" --scale 3 --encoding ascii --verbose
grep -q "3 channels" "$work/err.txt" && ok || bad "RGB volume: --verbose does not name the channels"
[ "$(header sizes "$work/rgb3.nrrd")" = "3 12 12 12" ] && ok || bad "RGB volume: sizes $(header sizes "$work/rgb3.nrrd")"
[ "$(header kinds "$work/rgb3.nrrd")" = "RGB-color space space space" ] && ok ||
  bad "RGB volume: kinds $(header kinds "$work/rgb3.nrrd")"
[ "$(header type "$work/rgb3.nrrd")" = "unsigned char" ] && ok || bad "RGB volume did not stay 8-bit"
# Input voxel (1, 2, 3) = sample 57 of the ascii list; output voxel (4, 7, 10).
want=$(sed -n '/^$/,$p' "$work/rgb.nrrd" | sed 1d | sed -n "$((1 + 3 * 16 + 2 * 4 + 1))p")
got=$(sed -n '/^$/,$p' "$work/rgb3.nrrd" | sed 1d | tr -s ' \n' '\n\n' | sed '/^$/d' |
  sed -n "$((3 * ((10 * 12 + 7) * 12 + 4) + 1)),$((3 * ((10 * 12 + 7) * 12 + 4) + 3))p" | tr '\n' ' ' | sed 's/ $//')
[ "$got" = "$want" ] && ok || bad "RGB volume: voxel (4, 7, 10) is '$got', input voxel (1, 2, 3) was '$want'"
run_ok "RGB volume, compare and picture" "$work/rgb.nrrd" "$work/rgb2.nrrd" --scale 2 --compare trilinear \
  --picture "$work/rgb.png"
[ "$(header sizes "$work/rgb2.trilinear.nrrd")" = "3 8 8 8" ] && ok || bad "RGB volume: --compare lost the channels"

run_ok "volume-eval" volume-eval --size 5 --scale 2 --methods trilinear,ddt --input-ss 2 --reference-ss 1 --quiet
grep -q "| sphere | ddt |" "$work/out.txt" && ok || bad "volume-eval printed no table"

run_ok "help" "$work/s.nrrd" --help
for opt in --scale --size --method --cost --compare --picture --iso --type --encoding --tolerance --max-voxels --verbose --quiet; do
  grep -q -- "$opt" "$work/out.txt" && ok || bad "--help does not mention $opt"
done

# Bad input.
printf 'not a volume' >"$work/corrupt.nrrd"
# 4 axes of unknown kind are a series now; 6 axes are nothing a volume has.
printf 'NRRD0004\ntype: uchar\ndimension: 6\nsizes: 3 2 2 2 2 2\nencoding: ascii\n\n%s\n' "$(seq -s ' ' 1 96)" >"$work/rgb.nrrd"
run_fail "missing input" "$work/nope.nrrd" "$work/o.nrrd" --scale 2
run_fail "corrupt input" "$work/corrupt.nrrd" "$work/o.nrrd" --scale 2
run_fail "six axes" "$work/rgb.nrrd" "$work/o.nrrd" --scale 2
run_fail "scale zero" "$work/s.nrrd" "$work/o.nrrd" --scale 0
grep -q "^ddtscale: --scale must be a positive number$" "$work/err.txt" && ok || bad "--scale 0: $(cat "$work/err.txt")"
run_fail "scale negative" "$work/s.nrrd" "$work/o.nrrd" --scale -3
run_fail "scale not a number" "$work/s.nrrd" "$work/o.nrrd" --scale abc
run_fail "no scale" "$work/s.nrrd" "$work/o.nrrd"
# In slabs (above 47^3 voxels) the optimizer runs in parallel: the same bits for any --threads.
run_ok "volume-field 48" volume-field hydrogen "$work/h48.nrrd" --size 48 --supersample 1
run_ok "one thread" "$work/h48.nrrd" "$work/h48_1.nrrd" --scale 2 --threads 1
run_ok "two threads" "$work/h48.nrrd" "$work/h48_2.nrrd" --scale 2 --threads 2
cmp -s "$work/h48_1.nrrd" "$work/h48_2.nrrd" && ok || bad "--threads 1 and 2 gave different volumes"
run_fail "zero threads" "$work/s.nrrd" "$work/o.nrrd" --scale 2 --threads 0
# The render: cubic by default, linear on request (the same mesh, another field).
run_ok "render linear" "$work/h48.nrrd" "$work/h48_linear.nrrd" --scale 2 --render linear
run_ok "render cubic" "$work/h48.nrrd" "$work/h48_cubic.nrrd" --scale 2 --render cubic --slopes mc4
cmp -s "$work/h48_1.nrrd" "$work/h48_cubic.nrrd" && ok || bad "the default render is not --render cubic"
cmp -s "$work/h48_1.nrrd" "$work/h48_linear.nrrd" && bad "--render linear gave the cubic volume" || ok
run_fail "unknown render" "$work/s.nrrd" "$work/o.nrrd" --scale 2 --render quintic
run_fail "unknown slopes" "$work/s.nrrd" "$work/o.nrrd" --scale 2 --slopes steep
run_fail "bad size" "$work/s.nrrd" "$work/o.nrrd" --size 4x4
run_fail "too many voxels" "$work/s.nrrd" "$work/o.nrrd" --scale 100 --max-voxels 1000
run_fail "output is input" "$work/s.nrrd" "$work/s.nrrd" --scale 2
run_fail "missing directory" "$work/s.nrrd" "$work/nodir/o.nrrd" --scale 2
run_fail "unknown cost" "$work/s.nrrd" "$work/o.nrrd" --scale 2 --cost nope
run_fail "unknown type" "$work/s.nrrd" "$work/o.nrrd" --scale 2 --type rgb
run_fail "unknown compare" "$work/s.nrrd" "$work/o.nrrd" --scale 2 --compare lanczos
run_fail "image output" "$work/s.nrrd" "$work/o.png" --scale 2
run_fail "unknown field" volume-field torus "$work/t.nrrd"

# Volume series (4 axes x, y, z, t): end to end, time node-centred.
run_ok "series field" volume-field moving-sphere "$work/ms.nrrd" --size 6 --steps 4 --supersample 2
[ "$(header sizes "$work/ms.nrrd")" = "6 6 6 4" ] && [ "$(header kinds "$work/ms.nrrd")" = "domain domain domain time" ] &&
  ok || bad "series field: sizes $(header sizes "$work/ms.nrrd"), kinds $(header kinds "$work/ms.nrrd")"
run_ok "series x2, time x4" "$work/ms.nrrd" "$work/ms2.nrrd" --scale 2 --time-scale 4 --compare quadrilinear,tricubic-linear \
  --picture "$work/ms.png" --iso 0.5 --verbose
[ "$(header sizes "$work/ms2.nrrd")" = "12 12 12 13" ] && ok || bad "series: sizes $(header sizes "$work/ms2.nrrd")"
[ "$(header centerings "$work/ms2.nrrd")" = "cell cell cell node" ] && ok ||
  bad "series: centerings $(header centerings "$work/ms2.nrrd")"
grep -q "triangulate: 864 points, 9000 simplices" "$work/err.txt" && grep -q "optimize: cost variance" "$work/err.txt" &&
  ok || bad "series --verbose: no 4D triangulation and optimization reported"
[ -f "$work/ms2.quadrilinear.nrrd" ] && [ -f "$work/ms2.tricubic-linear.nrrd" ] && ok || bad "series --compare missing"
oiiotool --info "$work/ms.png" >/dev/null 2>&1 && ok || bad "series --picture is not a readable image"
run_ok "series, --scale on every axis" "$work/ms.nrrd" "$work/ms3.nrrd" --scale 2 --method delaunay --render linear
[ "$(header sizes "$work/ms3.nrrd")" = "12 12 12 7" ] && ok || bad "series --scale 2: $(header sizes "$work/ms3.nrrd")"
run_ok "series --time-scale alone" "$work/ms.nrrd" "$work/ms4.nrrd" --time-scale 3 --method quadrilinear
[ "$(header sizes "$work/ms4.nrrd")" = "6 6 6 10" ] && ok || bad "series --time-scale 3: $(header sizes "$work/ms4.nrrd")"
# A fractional time scale: floor((4 - 1) * 2.4) + 1 = 8 steps at the instants g / 2.4, untiled and in
# exact tiles alike.
run_ok "series --time-scale 2.4" "$work/ms.nrrd" "$work/ms6.nrrd" --time-scale 2.4 --compare quadrilinear
[ "$(header sizes "$work/ms6.nrrd")" = "6 6 6 8" ] && [ "$(header sizes "$work/ms6.quadrilinear.nrrd")" = "6 6 6 8" ] &&
  ok || bad "series --time-scale 2.4: $(header sizes "$work/ms6.nrrd")"
run_ok "series --time-scale 2.4 in tiles" "$work/ms.nrrd" "$work/ms7.nrrd" --time-scale 2.4 --tile-slices 2
cmp -s "$work/ms6.nrrd" "$work/ms7.nrrd" && ok || bad "series --time-scale 2.4: tiles differ from the untiled result"
run_ok "series --size XxYxZxT" "$work/ms.nrrd" "$work/ms5.nrrd" --size 8x9x10x5 --method tricubic-linear
[ "$(header sizes "$work/ms5.nrrd")" = "8 9 10 5" ] && ok || bad "series --size: $(header sizes "$work/ms5.nrrd")"
run_ok "series eval" volume-eval --series --size 6 --steps 3 --methods quadrilinear,ddt --quiet
grep -q "| moving-sphere | ddt |" "$work/out.txt" && ok || bad "volume-eval --series printed no ddt row"
run_ok "series eval, another field" volume-eval --series --fields moving-box --size 6 --steps 3 --methods ddt --quiet
grep -q "| moving-box | ddt |" "$work/out.txt" && ok || bad "volume-eval --series --fields moving-box printed no ddt row"
run_fail "series eval, two fields" volume-eval --series --fields moving-box,moving-blob --size 6 --steps 3
run_ok "series field: the blob" volume-field moving-blob "$work/blob.nrrd" --size 6 --steps 3
run_fail "bad --time-scale" "$work/ms.nrrd" "$work/o.nrrd" --scale 2 --time-scale -1
run_fail "zero --time-scale" "$work/ms.nrrd" "$work/o.nrrd" --time-scale 0 --scale 2
run_fail "--time-scale not a number" "$work/ms.nrrd" "$work/o.nrrd" --time-scale fast
run_fail "--time-scale on a 3D volume" "$work/s.nrrd" "$work/o.nrrd" --scale 2 --time-scale 2
run_fail "series method on a 3D volume" "$work/s.nrrd" "$work/o.nrrd" --scale 2 --method quadrilinear
run_fail "3D compare on a series" "$work/ms.nrrd" "$work/o.nrrd" --scale 2 --compare trilinear
run_fail "series too large" "$work/ms.nrrd" "$work/o.nrrd" --scale 4 --time-scale 100 --max-voxels 100000
run_fail "steps twice" "$work/ms.nrrd" "$work/o.nrrd" --size 8x8x8x8 --time-scale 2
"$bin" "$work/ms.nrrd" --help | grep -q -- "--time-scale" && ok || bad "--help does not document --time-scale"
"$bin" volume-eval --help | grep -q -- "--series" && ok || bad "volume-eval --help does not document --series"
[ -f "$work/o.nrrd" ] && bad "a refused series run wrote its output" || ok

# A failing run never destroys an existing output.
printf 'precious' >"$work/keep.nrrd"
run_fail "keeps existing output" "$work/corrupt.nrrd" "$work/keep.nrrd" --scale 2
[ "$(cat "$work/keep.nrrd")" = "precious" ] && ok || bad "existing output was overwritten"
cp "$work/s.nrrd" "$work/s_copy.nrrd"
run_fail "input untouched" "$work/s.nrrd" "$work/s.nrrd" --scale 2
# The graduated optimization: on by default for series, off for 3D volumes, --presmooth either way.
run_ok "series presmooth default" "$work/ms.nrrd" "$work/ps.nrrd" --time-scale 2 -v
grep -q "optimize on the smoothed samples" "$work/err.txt" && ok || bad "series: no graduated optimization by default"
run_ok "series presmooth 0" "$work/ms.nrrd" "$work/ps.nrrd" --time-scale 2 --presmooth 0 -v
grep -q "optimize on the smoothed samples" "$work/err.txt" && bad "--presmooth 0 still smoothed" || ok
run_ok "3D presmooth 1" "$work/s.nrrd" "$work/ps3.nrrd" --scale 2 --presmooth 1 -v
grep -q "optimize on the smoothed samples" "$work/err.txt" && ok || bad "3D --presmooth 1 did not smooth"
# Tiles over time: margins that reach over the whole series give the untiled bits.
run_ok "series whole" "$work/ms.nrrd" "$work/tw.nrrd" --time-scale 2 -q
run_ok "series tiles" "$work/ms.nrrd" "$work/tt.nrrd" --time-scale 2 --time-tile 1 --time-margin 8 -v
grep -q "tiles: 1 of 1 steps" "$work/err.txt" && ok || bad "--time-tile 1 on 4 steps, one slab: $(grep 'tiles:' "$work/err.txt")"
cmp -s "$work/tw.nrrd" "$work/tt.nrrd" && ok || bad "exact tiles of a series of one slab differ from the whole"
# (a margin of 8 is cut to the series' 3 intervals)
run_ok "series loose tiles" "$work/ms.nrrd" "$work/tt.nrrd" --time-scale 2 --time-tile 1 --time-margin 8 --loose-tiles -v
grep -q "tiles: 3 of 1 steps, margin 3 (loose)" "$work/err.txt" && ok || bad "--loose-tiles on 4 steps: $(grep 'tiles:' "$work/err.txt")"
cmp -s "$work/tw.nrrd" "$work/tt.nrrd" && ok || bad "tiles with margins over the whole series differ from the whole"
# Tiles along z of a 3D volume (exact by default: the untiled bits).
run_ok "z tiles" "$work/h48.nrrd" "$work/h48_t.nrrd" --scale 2 --tile-slices 16 -v
grep -q "tiles: 3 of 16 slices, margin [0-9]* (exact; slabs of 19" "$work/err.txt" && ok ||
  bad "--tile-slices 16 on 48 slices: $(grep 'tiles:' "$work/err.txt")"
cmp -s "$work/h48_1.nrrd" "$work/h48_t.nrrd" && ok || bad "exact z tiles differ from the untiled volume"
run_ok "loose z tiles" "$work/h48.nrrd" "$work/h48_l.nrrd" --scale 2 --tile-slices 16 --loose-tiles --tile-margin 2 -v
grep -q "margin 2 (loose)" "$work/err.txt" && ok || bad "--loose-tiles: $(grep 'tiles:' "$work/err.txt")"
run_fail "z tiles, fractional scale" "$work/s.nrrd" "$work/t3.nrrd" --scale 2.5 --tile-slices 2
run_fail "tiles of a classic method" "$work/s.nrrd" "$work/t3.nrrd" --scale 2 --tile-slices 2 --method trilinear
run_fail "presmooth negative" "$work/s.nrrd" "$work/ps3.nrrd" --scale 2 --presmooth -1
cmp -s "$work/s.nrrd" "$work/s_copy.nrrd" && ok || bad "input was modified"
ls -a "$work" | grep -q '\.ddtscale-' && bad "temporary directory left behind" || ok

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
