#!/usr/bin/env bash
# End-to-end checks of the ddtscale command: the main job, --help, and bad
# input (one line on stderr, non-zero exit, no crash, nothing destroyed).
# Usage: cli_test.sh path/to/ddtscale source_dir
set -u
bin="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0
failed=0
ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL: $*"; }

# Expect success.
run_ok() {
  local name="$1"; shift
  if "$bin" "$@" >"$work/out.txt" 2>"$work/err.txt"; then ok; else bad "$name: exit $? ($(cat "$work/err.txt"))"; fi
}
# Expect a clean failure: exit 1 or 2, exactly one line on stderr.
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
size_of() { oiiotool --info "$1" | sed -E 's/.* ([0-9]+) x +([0-9]+).*/\1x\2/'; }

oiiotool --pattern checker:width=4:height=4:color1=0.1,0.2,0.3:color2=0.9,0.8,0.7 24x16 3 -o "$work/in.png"
oiiotool --pattern fill:top=0:bottom=1 20x10 1 -d uint16 -o "$work/grey16.png"

# The main job.
run_ok "main job" "$work/in.png" "$work/out.exr" --scale 10
[ "$(size_of "$work/out.exr")" = "240x160" ] && ok || bad "main job: size $(size_of "$work/out.exr")"
# An 8-bit input gives a half-float EXR, a 16-bit one a float EXR (--float forces it).
oiiotool --info -v "$work/out.exr" | grep -q "half" && ok || bad "EXR of an 8-bit input is not half"
run_ok "main job, 16 bit" "$work/grey16.png" "$work/out16.exr" --scale 2
oiiotool --info -v "$work/out16.exr" | grep -q "float" && ok || bad "EXR of a 16-bit input is not float"
run_ok "exr --float" "$work/in.png" "$work/f.exr" --scale 2 --float
oiiotool --info -v "$work/f.exr" | grep -q "float" && ok || bad "--float: not a float EXR"
run_fail "float png" "$work/in.png" "$work/o.png" --scale 2 --float
run_fail "half and float" "$work/in.png" "$work/o.exr" --scale 2 --half --float
run_ok "non-integer scale" "$work/in.png" "$work/out25.png" --scale 2.5
[ "$(size_of "$work/out25.png")" = "60x40" ] && ok || bad "scale 2.5: size $(size_of "$work/out25.png")"
run_ok "width only" "$work/in.png" "$work/w.png" --width 48
[ "$(size_of "$work/w.png")" = "48x32" ] && ok || bad "--width: size $(size_of "$work/w.png")"
run_ok "16-bit PNG" "$work/grey16.png" "$work/grey16_x3.png" --scale 3 --cost variance
oiiotool --info -v "$work/grey16_x3.png" | grep -q "uint16" && ok || bad "16-bit input did not give 16-bit PNG"
run_ok "verbose" "$work/in.png" "$work/v.tif" --scale 2 --verbose --cost sederberg-edge --cost-channel luma
grep -q "flips" "$work/err.txt" && grep -q "render" "$work/err.txt" && ok || bad "--verbose reports no stages"
run_ok "no optimize" "$work/in.png" "$work/n.png" --scale 2 --no-optimize
run_ok "linear render" "$work/in.png" "$work/lin.png" --scale 2 --render linear
for model in point box gauss:0.6 bicubic; do
  run_ok "model $model" "$work/in.png" "$work/model.exr" --scale 3 --model "$model"
done
for model in gauss gauss: gauss:-1 gauss:abc Box area ""; do
  run_fail "malformed --model '$model'" "$work/in.png" "$work/o.png" --scale 2 --model "$model"
done
# Straight edges drawn as edges by default; --no-step-edges keeps the smooth reconstruction.
"$bin" scene edge_30 "$work/edge.exr" --size 24x24 >/dev/null 2>&1 && ok || bad "scene edge_30"
run_ok "step edges" "$work/edge.exr" "$work/edge_on.exr" --scale 6 --verbose
grep -Eq " [1-9][0-9]* step-edge footprints" "$work/err.txt" && ok || bad "no step-edge footprints on edge_30"
run_ok "no step edges" "$work/edge.exr" "$work/edge_off.exr" --scale 6 --no-step-edges --verbose
grep -q " 0 step-edge footprints" "$work/err.txt" && ok || bad "--no-step-edges drew step edges"
run_ok "cubic render, mc slopes" "$work/in.png" "$work/cub.png" --scale 2 --render cubic --slopes mc
run_fail "unknown render" "$work/in.png" "$work/o.png" --scale 2 --render spline

# Comparison, mesh view, scenes.
run_ok "compare" "$work/in.png" "$work/side.exr" --scale 3 --compare bicubic
[ "$(size_of "$work/side.exr")" = "146x48" ] && ok || bad "compare: size $(size_of "$work/side.exr")"
run_ok "compare plain" "$work/in.png" "$work/plain.exr" --scale 3
oiiotool "$work/side.exr" --cut 72x48+74+0 -o "$work/right.exr"
oiiotool "$work/right.exr" "$work/plain.exr" --diff >/dev/null 2>&1 && ok || bad "compare: right half differs from plain DDT"
for m in nearest bilinear lanczos; do run_ok "compare $m" "$work/in.png" "$work/side_$m.png" --scale 2 --compare "$m"; done
run_fail "compare unknown" "$work/in.png" "$work/o.png" --scale 2 --compare magic
run_ok "mesh svg" "$work/in.png" "$work/m.png" --scale 2 --mesh "$work/mesh.svg"
grep -q "<svg" "$work/mesh.svg" && grep -q "</svg>" "$work/mesh.svg" && grep -q "data:image/png;base64" "$work/mesh.svg" && ok || bad "mesh.svg malformed"
run_ok "mesh png roi" "$work/in.png" "$work/m.png" --scale 2 --mesh "$work/mesh.png" --mesh-roi 4,4,12,8
[ -s "$work/mesh.png" ] && ok || bad "mesh.png not written"
run_fail "mesh roi outside" "$work/in.png" "$work/m.png" --scale 2 --mesh "$work/mesh2.png" --mesh-roi 20,4,12,8
run_fail "mesh roi malformed" "$work/in.png" "$work/m.png" --scale 2 --mesh "$work/mesh2.png" --mesh-roi 4,4
run_ok "scene" scene edge_30 "$work/scene.png" --size 40x30
[ "$(size_of "$work/scene.png")" = "40x30" ] && ok || bad "scene: size"
run_fail "scene unknown" scene nope "$work/scene.png"
run_ok "list costs" --list-costs
grep -qx "variance" "$work/out.txt" && ok || bad "--list-costs lacks variance"
run_ok "version" -V
grep -Eq "^ddtscale [0-9]+[.][0-9]+[.][0-9]+ [(]OpenImageIO [0-9.]+, CGAL [0-9.]+, TBB [0-9.]+[)]$" "$work/out.txt" && ok || bad "--version: $(cat "$work/out.txt")"
# -V elsewhere may be an option's value: here a suffix, not a request for the version.
run_ok "suffix -V" "$work/in.png" --outdir "$work/vdir" --suffix -V --scale 2 --quiet
[ -f "$work/vdir/in-V.png" ] && ok || bad "--suffix -V wrote no in-V.png"

# Degenerate images.
oiiotool --pattern constant:color=0.5 1x1 3 -o "$work/one.png"
oiiotool --pattern fill:left=0:right=1 9x1 1 -o "$work/row.png"
oiiotool --pattern fill:top=0:bottom=1 1x9 1 -o "$work/col.png"
oiiotool --pattern constant:color=0.3 8x8 1 -o "$work/flat.png"
for f in one row col flat; do run_ok "degenerate $f" "$work/$f.png" "$work/${f}_x4.png" --scale 4; done

# --help documents every option.
run_ok "help" --help
for opt in --scale --width --height --cost --cost-channel --no-optimize --tolerance --max-pixels --render --slopes --model --compare --mesh --mesh-roi --list-costs --version --verbose --quiet; do
  grep -q -- "$opt" "$work/out.txt" && ok || bad "--help does not mention $opt"
done

# Bad input.
printf 'not an image' >"$work/corrupt.png"
run_fail "missing input" "$work/nope.png" "$work/o.png" --scale 2
run_fail "corrupt input" "$work/corrupt.png" "$work/o.png" --scale 2
# Cut files: libpng would add its own line; a cut JPEG decodes "successfully" in grey.
head -c 200 "$work/in.png" >"$work/cut.png"
run_fail "truncated PNG" "$work/cut.png" "$work/o.png" --scale 2
oiiotool --pattern noise:type=uniform:seed=3 64x64 3 -d uint8 -o "$work/noise.jpg"
head -c "$(( $(stat -c %s "$work/noise.jpg") * 3 / 5 ))" "$work/noise.jpg" >"$work/cut.jpg"
run_fail "truncated JPEG" "$work/cut.jpg" "$work/o.png" --scale 2
grep -q "Premature end" "$work/err.txt" && ok || bad "truncated JPEG: $(cat "$work/err.txt")"
run_ok "whole JPEG" "$work/noise.jpg" "$work/noise_x2.png" --scale 2
run_fail "scale zero" "$work/in.png" "$work/o.png" --scale 0
grep -q "positive" "$work/err.txt" && ok || bad "scale zero: the error does not say the scale must be positive"
run_fail "width zero" "$work/in.png" "$work/o.png" --width 0
grep -q "positive" "$work/err.txt" && ok || bad "width zero: the error does not say the size must be positive"
run_fail "scale negative" "$work/in.png" "$work/o.png" --scale -3
run_fail "scale not a number" "$work/in.png" "$work/o.png" --scale abc
run_fail "no scale" "$work/in.png" "$work/o.png"
run_fail "too many pixels" "$work/in.png" "$work/o.png" --scale 100 --max-pixels 1000
run_fail "output is input" "$work/in.png" "$work/in.png" --scale 2
run_fail "missing directory" "$work/in.png" "$work/nodir/o.png" --scale 2
run_fail "unknown cost" "$work/in.png" "$work/o.png" --scale 2 --cost nope
run_fail "unknown extension" "$work/in.png" "$work/o.nosuchformat" --scale 2
run_fail "missing argument" "$work/in.png"
mkdir "$work/ro" && chmod 555 "$work/ro"
if [ "$(id -u)" -ne 0 ]; then run_fail "read-only directory" "$work/in.png" "$work/ro/o.png" --scale 2; fi

# A failing run never destroys an existing output.
printf 'precious' >"$work/keep.png"
run_fail "keeps existing output" "$work/corrupt.png" "$work/keep.png" --scale 2
[ "$(cat "$work/keep.png")" = "precious" ] && ok || bad "existing output was overwritten"
cp "$work/in.png" "$work/in_copy.png"
run_fail "input untouched" "$work/in.png" "$work/in.png" --scale 2
cmp -s "$work/in.png" "$work/in_copy.png" && ok || bad "input was modified"
ls -a "$work" | grep -q '\.tmp' && bad "temporary file left behind" || ok

# Metadata (docs/reliability.md): a portrait JPEG (EXIF orientation 6) stays
# portrait in PNG (applied) and keeps its tag in JPEG (carried); a second TIFF
# page is dropped with a warning.
oiiotool "$work/in.png" --attrib Orientation 6 -o "$work/portrait.jpg"
run_ok "portrait to PNG" "$work/portrait.jpg" "$work/portrait.png" --scale 2
[ "$(size_of "$work/portrait.png")" = "32x48" ] && ok || bad "portrait to PNG: size $(size_of "$work/portrait.png")"
run_ok "portrait to JPEG" "$work/portrait.jpg" "$work/portrait_x2.jpg" --scale 2
oiiotool --info -v "$work/portrait_x2.jpg" | grep -q "Orientation: 6" && ok || bad "portrait to JPEG: orientation lost"
oiiotool "$work/in.png" "$work/in.png" --siappend -o "$work/two.tif"
run_ok "two-page TIFF" "$work/two.tif" "$work/two_x2.png" --scale 2
grep -q "pages or parts; only the first" "$work/err.txt" && ok || bad "two-page TIFF: no warning ($(cat "$work/err.txt"))"

# Encoders (io/encode_options.hpp): a higher PNG level is no larger and
# decodes to the same pixels; --half writes half floats; bad values fail in
# one line.
run_ok "png level 0" "$work/in.png" "$work/l0.png" --scale 3 --compression 0:none
run_ok "png level 9" "$work/in.png" "$work/l9.png" --scale 3 --compression 9:adaptive
[ "$(stat -c %s "$work/l9.png")" -le "$(stat -c %s "$work/l0.png")" ] && ok || bad "png level 9 larger than level 0"
oiiotool "$work/l0.png" "$work/l9.png" --diff >/dev/null && ok || bad "png levels decode differently"
# The default, fast (ISA-L's igzip), and zlib's 1:up:rle: the same pixels,
# in valid PNGs; fast takes a filter; a JPEG's PNG (through OpenImageIO) too.
run_ok "png fast (default)" "$work/in.png" "$work/fast.png" --scale 3
run_ok "png zlib 1:up:rle" "$work/in.png" "$work/zlib1.png" --scale 3 --compression 1:up:rle
oiiotool "$work/fast.png" "$work/zlib1.png" --diff >/dev/null && ok || bad "png fast decodes differently from zlib"
run_ok "png fast:paeth" "$work/in.png" "$work/paeth.png" --scale 3 --compression fast:paeth
oiiotool "$work/fast.png" "$work/paeth.png" --diff >/dev/null && ok || bad "png fast:paeth decodes differently"
run_ok "jpeg to png, default" "$work/portrait.jpg" "$work/portrait_fast.png" --scale 2
run_fail "png fast adaptive" "$work/in.png" "$work/o.png" --scale 2 --compression fast:adaptive
run_ok "exr half" "$work/grey16.png" "$work/h.exr" --scale 2 --half --compression zip
oiiotool --info "$work/h.exr" | grep -q half && ok || bad "--half: not a half EXR ($(oiiotool --info "$work/h.exr"))"
run_ok "tiff lzw" "$work/in.png" "$work/c.tif" --scale 2 --compression lzw
oiiotool --info -v "$work/c.tif" | grep -q 'compression: "lzw"' && ok || bad "tiff lzw not in the file"
run_ok "jpeg quality" "$work/in.png" "$work/q.jpg" --scale 2 --quality 70
run_fail "png level 10" "$work/in.png" "$work/o.png" --scale 2 --compression 10
run_fail "exr method" "$work/in.png" "$work/o.exr" --scale 2 --compression zap
run_fail "half png" "$work/in.png" "$work/o.png" --scale 2 --half
run_fail "quality png" "$work/in.png" "$work/o.png" --scale 2 --quality 50
run_fail "quality range" "$work/in.png" "$work/o.jpg" --scale 2 --quality 101

# Streaming (io/band_writer.hpp): the file written by bands as they are
# rendered is the one written whole, byte for byte (the input carries a
# DateTime, so both outputs carry the same one).
oiiotool "$work/in.png" --attrib DateTime "2026:01:02 03:04:05" -o "$work/dated.png"
for ext in png tif exr; do
  for model in point box; do
    run_ok "stream $ext $model" "$work/dated.png" "$work/s.$ext" --scale 3 --model "$model" --tile-rows 8
    run_ok "whole $ext $model" "$work/dated.png" "$work/w.$ext" --scale 3 --model "$model" --tile-rows 8 --no-stream
    cmp -s "$work/s.$ext" "$work/w.$ext" && ok || bad "streamed $ext ($model) differs from the whole write"
  done
done
run_ok "stream tiled tif" "$work/dated.png" "$work/t.tif" --scale 3 --model point --tile-size 32
run_ok "whole tif point" "$work/dated.png" "$work/wp.tif" --scale 3 --model point --no-stream
oiiotool "$work/t.tif" "$work/wp.tif" --diff >/dev/null && ok || bad "tiled TIFF pixels differ"
run_fail "tile size" "$work/in.png" "$work/o.tif" --scale 2 --tile-size 20
run_fail "tile png" "$work/in.png" "$work/o.png" --scale 2 --tile-size 32

# Read by bands (pipeline/banded_upscale.hpp): --tile-rows on an image with
# the region schedule reads, enlarges and writes it band by band; the file
# is the one enlarged whole, byte for byte, under both models.
oiiotool --pattern fill:top=0.1,0.6,0.9:bottom=0.9,0.4,0.1 512x2048 3 --pattern noise:type=uniform:min=0:max=0.3 512x2048 3 --add -d uint8 -o "$work/tall.png"
for model in box point; do
  run_ok "banded $model" "$work/tall.png" "$work/b.png" --scale 2 --model "$model" --tile-rows 256 --verbose
  grep -q "read by bands of 256 rows" "$work/err.txt" && ok || bad "banded $model: not read by bands ($(head -3 "$work/err.txt"))"
  run_ok "whole $model" "$work/tall.png" "$work/w.png" --scale 2 --model "$model" --tile-rows -1
  cmp -s "$work/b.png" "$work/w.png" && ok || bad "read by bands ($model) differs from the whole image's enlargement"
done
# Meshes made by bands (pipeline/banded_meshes.hpp): the box model's
# wavefront drawing from them writes the bytes of one mesh.
run_ok "mesh bands" "$work/tall.png" "$work/mb.png" --scale 2 --mesh-band-rows 700 --tile-rows -1 --verbose
grep -q "mesh bands: 3 of 700 rows" "$work/err.txt" && ok || bad "mesh bands: not made by bands ($(grep mesh "$work/err.txt" | head -3))"
run_ok "one mesh" "$work/tall.png" "$work/om.png" --scale 2 --mesh-band-rows -1 --tile-rows -1
cmp -s "$work/mb.png" "$work/om.png" && ok || bad "meshes made by bands differ from one mesh"
run_fail "mesh band rows" "$work/tall.png" "$work/mb2.png" --scale 2 --mesh-band-rows -2
# --max-memory: below the smallest band a job is refused in one line with
# the size to give, and nothing is written; at that size it is read by
# bands (the same bytes as whole). The size is read from the refusal, as
# the process's own resident memory (larger under sanitizers) is part of it.
run_fail "max-memory too small" "$work/tall.png" "$work/m2.png" --scale 2 --model point --max-memory 100M
grep -q "give --max-memory [0-9]*M or more" "$work/err.txt" && ok || bad "--max-memory 100M: $(cat "$work/err.txt")"
[ ! -e "$work/m2.png" ] && ok || bad "--max-memory 100M: an output was written"
needed=$(sed -n 's/.*give --max-memory \([0-9]*\)M or more.*/\1/p' "$work/err.txt")
needed="$(( ${needed:-320} + 80 ))M"  # headroom: the resident pages vary from run to run
run_ok "max-memory bands" "$work/tall.png" "$work/m.png" --scale 2 --model point --max-memory "$needed" --verbose
grep -q "read by bands of" "$work/err.txt" && ok || bad "--max-memory $needed: not read by bands ($(head -3 "$work/err.txt"))"
cmp -s "$work/m.png" "$work/w.png" && ok || bad "--max-memory: the bands differ from the whole image's enlargement"
run_fail "max-memory not a size" "$work/tall.png" "$work/m2.png" --scale 2 --max-memory 2Q
run_fail "max-memory zero" "$work/tall.png" "$work/m2.png" --scale 2 --max-memory 0
# A tiled input is read by rows of tiles.
oiiotool "$work/tall.png" --tile 64 64 -o "$work/tall_tiled.tif"
run_ok "banded tiled tif" "$work/tall_tiled.tif" "$work/bt.png" --scale 2 --model point --tile-rows 256  # w.png: point, above
oiiotool "$work/bt.png" "$work/w.png" --diff --fail 0 >/dev/null && ok || bad "a tiled TIFF read by bands differs in its pixels"

# The front: PNG to PNG or EXR without OpenImageIO (cli/front_main.cpp),
# the same file as ddtscale-full's; the rest handed to ddtscale-full.
full="$(dirname "$bin")/ddtscale-full"
if readelf -d "$bin" | grep -q OpenImageIO; then bad "the front links OpenImageIO"; else ok; fi
run_ok "front, PNG to PNG" "$work/in.png" "$work/front.png" --scale 3
"$full" "$work/in.png" "$work/full.png" --scale 3 -q && cmp -s "$work/front.png" "$work/full.png" && ok ||
  bad "the front's PNG differs from ddtscale-full's"
run_ok "front, 16-bit gray PNG" "$work/grey16.png" "$work/front16.png" --scale 2
"$full" "$work/grey16.png" "$work/full16.png" --scale 2 -q && cmp -s "$work/front16.png" "$work/full16.png" && ok ||
  bad "the front's 16-bit PNG differs from ddtscale-full's"
oiiotool --pattern checker:width=3:height=3:color1=0.1,0.2,0.3,0.5:color2=0.9,0.8,0.7,1 21x13 4 -o "$work/rgba.png"
run_ok "front, RGBA PNG" "$work/rgba.png" "$work/front_rgba.png" --scale 2
"$full" "$work/rgba.png" "$work/full_rgba.png" --scale 2 -q && cmp -s "$work/front_rgba.png" "$work/full_rgba.png" && ok ||
  bad "the front's RGBA PNG differs from ddtscale-full's"
# Handed on: another output format, --compare, a subcommand's --help, a bad option.
run_ok "front hands on TIFF" "$work/in.png" "$work/front.tif" --scale 2
run_ok "front hands on a tiled EXR" "$work/in.png" "$work/front_tiled.exr" --scale 2 --tile-size 64
oiiotool --info -v "$work/front_tiled.exr" | grep -q "tile size: 64 x 64" && ok || bad "front: the tiled EXR is not tiled"
run_ok "front hands on --compare" "$work/in.png" "$work/front_cmp.png" --scale 2 --compare bicubic
"$bin" scene --help | grep -q -- "--scene\|scene" && ok || bad "front: scene --help"
run_fail "front hands on a bad option" "$work/in.png" "$work/x.png" --no-such-option
"$bin" --version | grep -q OpenImageIO && ok || bad "front: --version"
# Without ddtscale-full beside it: PNG still works, the rest fails in one line.
mkdir -p "$work/alone" && cp "$bin" "$work/alone/ddtscale"
"$bin" "$work/in.png" "$work/front_2.png" --scale 2 -q && "$work/alone/ddtscale" "$work/in.png" "$work/alone.png" --scale 2 -q &&
  cmp -s "$work/alone.png" "$work/front_2.png" && ok || bad "the front alone: PNG to PNG"
saved_bin="$bin"; bin="$work/alone/ddtscale"
# PNG to EXR through OpenEXR alone (io/exr_file.hpp): half from 8 bits,
# float from 16, the pixels ddtscale-full writes.
run_ok "the front alone, PNG to EXR" "$work/in.png" "$work/alone.exr" --scale 2
oiiotool --info -v "$work/alone.exr" | grep -q "half openexr" && ok || bad "the front alone: EXR not half"
"$full" "$work/in.png" "$work/full_alone.exr" --scale 2 -q
oiiotool "$work/alone.exr" "$work/full_alone.exr" --diff >/dev/null 2>&1 && ok || bad "the front alone: EXR pixels differ"
run_ok "the front alone, 16-bit PNG to EXR" "$work/grey16.png" "$work/alone16.exr" --scale 2 --compression dwaa:80
oiiotool --info -v "$work/alone16.exr" | grep -q "float openexr" && ok || bad "the front alone: 16-bit EXR not float"
run_fail "the front alone, TIFF" "$work/in.png" "$work/alone.tif" --scale 2
grep -q "cannot run .*ddtscale-full" "$work/err.txt" && ok || bad "the front alone: message $(cat "$work/err.txt")"
[ ! -e "$work/alone.tif" ] && ok || bad "the front alone wrote a TIFF"
bin="$saved_bin"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
