#!/usr/bin/env bash
# Many files at once (cli/batch.hpp): files, directories and globs into
# --outdir, names from --suffix/--format, skip or --overwrite, one line per
# failed file without stopping the others, a summary, the exit status; each
# output equals the single-file command's.
# Usage: cli_batch_test.sh path/to/ddtscale
set -u
bin=$(realpath "$1")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0
failed=0
ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL: $*"; }
same_pixels() { oiiotool "$1" "$2" --diff >/dev/null 2>&1; }

cd "$work"
# The batch's temporary logs go to a folder of this test's own, so that
# other tests' batches running beside it (ctest -j) do not count as leftovers.
mkdir -p tmp
export TMPDIR="$work/tmp"
mkdir -p scans more
oiiotool --pattern checker:width=4:height=4:color1=0.1,0.2,0.3:color2=0.9,0.8,0.7 24x16 3 -o a.png
oiiotool --pattern fill:top=0:bottom=1 20x10 1 -d uint16 -o scans/grey16.png
oiiotool --pattern noise:type=uniform:seed=3 16x12 3 -d uint8 -o scans/noise.jpg
oiiotool --pattern constant:color=0.5 6x6 3 -o more/m1.tif
oiiotool --pattern constant:color=0.2 6x6 3 -o more/m2.tif
printf 'not an image' >scans/corrupt.png
printf 'notes' >scans/readme.txt

# Files, a directory (images only: not readme.txt), a glob the shell did not expand, a missing file.
"$bin" a.png scans/ 'more/*.tif' missing.png --outdir out --suffix _x2 --scale 2 >stdout.txt 2>err.txt
code=$?
[ "$code" -eq 1 ] && ok || bad "a failed file must give exit status 1, got $code"
for f in a_x2.png grey16_x2.png noise_x2.jpg m1_x2.tif m2_x2.tif; do
  [ -s "out/$f" ] && ok || bad "out/$f not written ($(cat err.txt))"
done
[ "$(ls out | wc -l)" -eq 5 ] && ok || bad "unexpected outputs: $(ls out)"
[ "$(grep -c '^ddtscale: .*corrupt.png: ' err.txt)" -eq 1 ] && ok || bad "no single line for corrupt.png: $(cat err.txt)"
[ "$(grep -c '^ddtscale: missing.png: ' err.txt)" -eq 1 ] && ok || bad "no single line for missing.png: $(cat err.txt)"
grep -q "5 done, 0 skipped, 2 failed" err.txt && ok || bad "summary: $(tail -1 err.txt)"
[ "$(wc -l <err.txt)" -eq 3 ] && ok || bad "expected two failure lines and a summary: $(cat err.txt)"

# Each output is the single-file command's, bit depth kept.
"$bin" scans/grey16.png single16.png --scale 2 -q
same_pixels out/grey16_x2.png single16.png && ok || bad "batch output differs from the single-file output"
oiiotool --info -v out/grey16_x2.png | grep -q uint16 && ok || bad "16-bit input did not stay 16-bit"

# Existing outputs are skipped, or replaced with --overwrite; options reach every file.
"$bin" a.png more --outdir out --suffix _x2 --scale 2 2>err.txt && ok || bad "rerun failed: $(cat err.txt)"
grep -q "0 done, 3 skipped, 0 failed" err.txt && ok || bad "rerun summary: $(cat err.txt)"
"$bin" a.png --outdir out --suffix _x2 --scale 3 --model point --cost variance --overwrite --jobs 1 2>err.txt
grep -q "1 done, 0 skipped, 0 failed" err.txt && ok || bad "overwrite summary: $(cat err.txt)"
"$bin" a.png single_point.png --scale 3 --model point --cost variance -q
same_pixels out/a_x2.png single_point.png && ok || bad "options were not forwarded to the file's run"

# --format picks the output type; two inputs with one output name: the second fails, the first runs.
mkdir -p twin && cp a.png twin/a.png
"$bin" a.png twin/a.png --outdir exr --format exr --scale 2 --quiet 2>err.txt
[ $? -eq 1 ] && ok || bad "a clash of output names must fail"
grep -q "also the output of" err.txt && ok || bad "clash not reported: $(cat err.txt)"
[ "$(wc -l <err.txt)" -eq 1 ] && ok || bad "--quiet prints only failures: $(cat err.txt)"
oiiotool --info -v exr/a.exr | grep -q openexr && ok || bad "--format exr did not write an EXR"

# Bad batch arguments: one line, no work.
"$bin" a.png --outdir out2 --scale 2 --jobs -1 2>err.txt
[ $? -eq 2 ] && [ "$(wc -l <err.txt)" -eq 1 ] && ok || bad "bad --jobs: $(cat err.txt)"
"$bin" 'nothing/*.png' --outdir out3 --scale 2 2>err.txt
[ $? -eq 1 ] && grep -q "no file matches" err.txt && ok || bad "empty glob: $(cat err.txt)"
ls -a "$TMPDIR" | grep -q "ddtscale-batch-" && bad "temporary logs left behind" || ok

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
