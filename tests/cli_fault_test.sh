#!/usr/bin/env bash
# Fault tests of the ddtscale command (issue 20, docs/reliability.md): a full
# disk, links planted where outputs are staged, an input's detached data
# file as an output, SIGTERM during a write, devices and FIFOs as input,
# decompression bombs and huge arguments. Each case must end in a clean
# refusal (exit 1 or 2, one line on stderr) within a time limit, so that a
# regression fails instead of hanging, and must leave every existing file as
# it was and no staging directory behind.
# Usage: cli_fault_test.sh path/to/ddtscale
set -u
bin="$1"
work=$(mktemp -d)
mounted=""
cleanup() {
  [ -n "$mounted" ] && umount "$mounted" 2>/dev/null
  rm -rf "$work"
}
trap cleanup EXIT
passed=0
failed=0
ok() { passed=$((passed + 1)); }
bad() { failed=$((failed + 1)); echo "FAIL: $*"; }
limit=20  # seconds a refusal may take; every case below needs well under one

# Expect a clean, quick failure: exit 1 or 2 (not a signal, not the
# timeout's 124), exactly one line on stderr.
run_fail() {
  local name="$1"; shift
  timeout -s KILL "$limit" "$bin" "$@" >"$work/out.txt" 2>"$work/err.txt"
  local code=$?
  local lines
  lines=$(wc -l <"$work/err.txt")
  if [ "$code" -eq 137 ]; then bad "$name: still running after $limit s"; return; fi
  if [ "$code" -ne 1 ] && [ "$code" -ne 2 ]; then bad "$name: exit code $code ($(head -c 300 "$work/err.txt"))"; return; fi
  if [ "$lines" -ne 1 ]; then bad "$name: $lines lines on stderr: $(head -c 300 "$work/err.txt")"; return; fi
  ok
}
# run_fail, and the message must contain PATTERN (grep -E).
run_fail_saying() {
  local name="$1" pattern="$2"; shift 2
  local before=$failed
  run_fail "$name" "$@"
  [ "$failed" -gt "$before" ] && return
  grep -qE "$pattern" "$work/err.txt" || bad "$name: message '$(cat "$work/err.txt")' does not say /$pattern/"
}
run_ok() {
  local name="$1"; shift
  if timeout -s KILL "$limit" "$bin" "$@" >"$work/out.txt" 2>"$work/err.txt"; then ok
  else bad "$name: exit $? ($(head -c 300 "$work/err.txt"))"; fi
}
# No staging directory (.ddtscale-XXXXXX) left in DIR.
no_stage_left() {
  local name="$1" dir="$2"
  if compgen -G "$dir/.ddtscale-*" >/dev/null; then bad "$name: staging directory left: $(ls -a "$dir")"; else ok; fi
}
same_file() {
  local name="$1" a="$2" b="$3"
  cmp -s "$a" "$b" && ok || bad "$name: $b changed"
}

oiiotool --pattern noise:type=uniform:min=0:max=1 256x256 3 -d uint8 -o "$work/noise256.png"
oiiotool --pattern checker:width=4:height=4 16x16 3 -o "$work/small.png"

# --- Full disk: a 2 MB tmpfs (root only; skipped where mounting is not allowed).
disk="$work/disk"
mkdir -p "$disk"
if [ "$(id -u)" -eq 0 ] && mount -t tmpfs -o size=2m tmpfs "$disk" 2>/dev/null; then
  mounted="$disk"
  for ext in png jpg tif exr; do
    "$bin" "$work/small.png" "$disk/keep.$ext" --scale 2 --quiet || bad "full disk: cannot write the first keep.$ext"
    cp "$disk/keep.$ext" "$work/keep.$ext"
    # 2048x2048 noise (1024x1024 float in EXR) does not fit in what is left of 2 MB.
    scale=8
    [ "$ext" = exr ] && scale=4
    # JPEG at its default quality (90) squeezes it into 2 MB: at 100 it does not.
    quality=()
    [ "$ext" = jpg ] && quality=(--quality 100)
    run_fail_saying "full disk, $ext" "space" "$work/noise256.png" "$disk/keep.$ext" --scale "$scale" --model point \
      --no-optimize --render linear "${quality[@]}"
    same_file "full disk, $ext" "$work/keep.$ext" "$disk/keep.$ext"
    no_stage_left "full disk, $ext" "$disk"
    rm -f "$disk/keep.$ext"
  done
  # A TIFF with EXIF is written by path (OpenImageIO's TIFF writer breaks
  # through an IOProxy with EXIF): libtiff's own write error, then the same.
  oiiotool "$work/small.png" --attrib Exif:DateTimeOriginal "2020:01:02 03:04:05" -d uint8 -o "$work/small_exif.tif"
  oiiotool "$work/noise256.png" --attrib Exif:DateTimeOriginal "2020:01:02 03:04:05" -o "$work/noise_exif.tif"
  "$bin" "$work/small_exif.tif" "$disk/keep.tif" --scale 2 --quiet || bad "full disk: cannot write keep.tif with EXIF"
  cp "$disk/keep.tif" "$work/keep.tif"
  run_fail_saying "full disk, tif with EXIF" "space|[Ww]rite error" "$work/noise_exif.tif" "$disk/keep.tif" --scale 8 \
    --model point --no-optimize --render linear
  same_file "full disk, tif with EXIF" "$work/keep.tif" "$disk/keep.tif"
  no_stage_left "full disk, tif with EXIF" "$disk"
  rm -f "$disk/keep.tif"
  "$bin" volume-field sphere "$disk/keep.nhdr" --size 4 --type uint8 >/dev/null 2>&1 || bad "full disk: no keep.nhdr"
  cp "$disk/keep.nhdr" "$work/keep.nhdr" && cp "$disk/keep.raw" "$work/keep.raw"
  run_fail_saying "full disk, nhdr" "space" volume-field sphere "$disk/keep.nhdr" --size 128 --type float32 \
    --supersample 1
  same_file "full disk, nhdr header" "$work/keep.nhdr" "$disk/keep.nhdr"
  same_file "full disk, nhdr data" "$work/keep.raw" "$disk/keep.raw"
  no_stage_left "full disk, nhdr" "$disk"
  umount "$disk" && mounted=""
else
  echo "skipped: full-disk cases (mounting a 2 MB tmpfs needs root and a mount permission)"
fi

# --- Links planted in the output directory: at the temporary names older
# versions chose (.<stem>.tmp<N><ext>) and at staging-directory names. The
# file they point to must not change, the output must be a regular file.
out="$work/planted"
mkdir -p "$out"
printf 'precious\n' >"$work/victim.txt"
cp "$work/victim.txt" "$work/victim.orig"
for n in $(seq 0 199); do
  ln -s "$work/victim.txt" "$out/.o.tmp$n.png"
  ln -s "$work/victim.txt" "$out/.ddtscale-$(printf '%06d' "$n")"
done
run_ok "planted links" "$work/small.png" "$out/o.png" --scale 2 --quiet
same_file "planted links" "$work/victim.orig" "$work/victim.txt"
[ -f "$out/o.png" ] && [ ! -L "$out/o.png" ] && ok || bad "planted links: o.png is not a regular file"
# An output that is a link to a missing file is refused; a link to a file is written through.
ln -s "$work/nowhere.png" "$out/dangling.png"
run_fail "dangling output link" "$work/small.png" "$out/dangling.png" --scale 2
[ ! -e "$work/nowhere.png" ] && ok || bad "dangling output link: its target was created"
cp "$work/small.png" "$work/linked.png"
ln -s "$work/linked.png" "$out/through.png"
run_ok "output link" "$work/noise256.png" "$out/through.png" --scale 0.5 --quiet
[ -L "$out/through.png" ] && ! cmp -s "$work/small.png" "$work/linked.png" && ok || bad "output link not written through"

# --- The input's detached data file as an output's data file.
"$bin" volume-field sphere "$work/a.nhdr" --size 6 --type uint8 >/dev/null 2>&1 || bad "cannot make a.nhdr"
sed -i 's/^data file: .*/data file: b.raw/' "$work/a.nhdr"
mv "$work/a.raw" "$work/b.raw"
cp "$work/b.raw" "$work/b.orig"
run_fail_saying "nhdr data file as output" "refusing" "$work/a.nhdr" "$work/b.nhdr" --scale 2
same_file "nhdr data file as output" "$work/b.orig" "$work/b.raw"
[ ! -e "$work/b.nhdr" ] && ok || bad "nhdr data file as output: b.nhdr written"
ln "$work/b.raw" "$work/hard.raw" 2>/dev/null && {
  run_fail "nhdr data file, hard link" "$work/a.nhdr" "$work/hard.nhdr" --scale 2
  same_file "nhdr data file, hard link" "$work/b.orig" "$work/b.raw"
}

# --- SIGTERM while the output is staged: the old output stays, no staging
# directory is left. The signal is sent as soon as the staging directory
# appears (the write has begun).
sig="$work/sig"
mkdir -p "$sig"
oiiotool --pattern noise 384x384 3 -d uint16 -o "$work/noise384.png"
for attempt in 1 2 3; do
  cp "$work/small.png" "$sig/old.tif"
  "$bin" "$work/noise384.png" "$sig/old.tif" --scale 8 --model point --no-optimize --render linear --quiet \
    2>"$work/sig_err.txt" &
  pid=$!
  for _ in $(seq 1 3000); do
    compgen -G "$sig/.ddtscale-*" >/dev/null && break
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.01
  done
  kill -TERM "$pid" 2>/dev/null
  wait "$pid"
  code=$?
  [ "$code" -ne 0 ] && break
done
if [ "$code" -eq 0 ]; then
  echo "skipped: SIGTERM during the write (the write ended before the signal, 3 times)"
else
  [ "$code" -eq 143 ] || [ "$code" -eq 1 ] && ok || bad "SIGTERM: exit code $code"
  same_file "SIGTERM during the write" "$work/small.png" "$sig/old.tif"
  no_stage_left "SIGTERM during the write" "$sig"
fi

# --- Devices and FIFOs as input: refused before they are opened.
mkfifo "$work/fifo.png" "$work/fifo.csv" "$work/fifo.nrrd" "$work/fifo.raw"
run_fail_saying "/dev/zero as image" "regular file" /dev/zero "$work/o.png" --scale 2
run_fail_saying "/dev/urandom as image" "regular file" /dev/urandom "$work/o.png" --scale 2
run_fail_saying "FIFO as image" "regular file" "$work/fifo.png" "$work/o.png" --scale 2
run_fail_saying "FIFO as points" "regular file" grid "$work/fifo.csv" "$work/o.exr" --size 8
run_fail_saying "FIFO as volume" "regular file" "$work/fifo.nrrd" "$work/o.nrrd" --scale 2
printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\ndata file: fifo.raw\n' >"$work/f.nhdr"
run_fail_saying "FIFO as NRRD data file" "regular file" "$work/f.nhdr" "$work/o.nrrd" --scale 2
printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4 4 4\nencoding: raw\ndata file: /dev/zero\n' >"$work/z.nhdr"
run_fail "/dev/zero as NRRD data file" "$work/z.nhdr" "$work/o.nrrd" --scale 2 --any-data-file

# --- Decompression bombs: headers that claim more than the file holds,
# refused from the header before any decoding.
# tiff W H: a 150-byte little-endian TIFF, 8-bit grey, one strip of 1 byte.
tiff() {
  local w=$1 h=$2
  le32() { printf "\\x$(printf %02x $(($1 & 255)))\\x$(printf %02x $((($1 >> 8) & 255)))\\x$(printf %02x $((($1 >> 16) & 255)))\\x$(printf %02x $((($1 >> 24) & 255)))"; }
  entry() { printf "\\x$(printf %02x $(($1 & 255)))\\x$(printf %02x $(($1 >> 8)))\\x$(printf %02x $2)\\x00"; le32 1; le32 "$3"; }
  printf 'II*\x00'; le32 8
  printf '\x08\x00'                                    # 8 entries
  entry 256 4 "$w"; entry 257 4 "$h"                  # width, length (LONG)
  entry 258 3 8; entry 259 3 1; entry 262 3 1         # 8 bits, no compression, min-is-black
  entry 273 4 110; entry 278 4 "$h"; entry 279 4 1    # strip offset, rows per strip, strip bytes
  le32 0; printf '\x00'
}
tiff 1000000 1000000 >"$work/bomb.tif"
tiff 30000 30000 >"$work/bomb30k.tif"
tiff 16 16 >"$work/tiny.tif"
oiiotool --info "$work/tiny.tif" >/dev/null 2>&1 && ok || bad "the TIFF writer of this test makes no valid TIFF"
run_fail_saying "TIFF bomb, 10^12 pixels" "exceeds" "$work/bomb.tif" "$work/o.png" --scale 0.001
run_fail_saying "TIFF bomb, 30000^2 pixels, limit" "exceeds --max-input-pixels 100000000; give --max-input-pixels 900000000 to allow it" "$work/bomb30k.tif" "$work/o.png" \
  --scale 0.1 --max-input-pixels 100000000
run_fail_saying "TIFF bomb, output from the header" "exceeds --max-pixels [0-9]+; give --max-pixels 3600000000 to allow it" "$work/bomb30k.tif" "$work/o.png" --scale 2 \
  --max-input-pixels 1000000000
# Past the input limit, the memory: 10^10 pixels need 40 GB decoded (on a
# machine with more available, OpenImageIO's 32 GB limit or the decode refuses).
tiff 100000 100000 >"$work/bomb100k.tif"
run_fail_saying "TIFF bomb, memory" "memory|exceeds|cannot read" "$work/bomb100k.tif" "$work/o.png" --scale 0.01 \
  --max-input-pixels 100000000000
printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 4000 4000 4000\nencoding: gzip\ndata file: d.raw.gz\n' >"$work/bomb.nhdr"
printf '' | gzip >"$work/d.raw.gz"
run_fail_saying "NRRD bomb" "exceeds --max-input-voxels" "$work/bomb.nhdr" "$work/o.nrrd" --scale 1
printf 'NRRD0004\ntype: uint8\ndimension: 3\nsizes: 400 400 400\nencoding: raw\ndata file: d.raw.gz\n' >"$work/b400.nhdr"
run_fail_saying "NRRD 400^3, limit" "exceeds --max-input-voxels" "$work/b400.nhdr" "$work/o.nrrd" --scale 1 \
  --max-input-voxels 1000000
run_fail_saying "NRRD 400^3, output" "exceeds --max-voxels" "$work/b400.nhdr" "$work/o.nrrd" --scale 4 \
  --max-input-voxels 100000000
printf 'x,y,v\n0,0,1\n1,0,2\n0,1,3\n1,1,4\n' >"$work/p.csv"
run_fail_saying "points over the limit" "line 5: more than 3 points" grid "$work/p.csv" "$work/o.exr" --size 8 \
  --max-input-points 3

# --- Huge arguments.
run_fail "scale 1e308" "$work/small.png" "$work/o.png" --scale 1e308
run_fail "width 2^40" "$work/small.png" "$work/o.png" --width 1099511627776
run_fail "width 99999 x height 99999" "$work/small.png" "$work/o.png" --width 99999 --height 99999
run_fail "max-pixels 10^30" "$work/small.png" "$work/o.png" --scale 2 --max-pixels 1000000000000000000000000000000
run_fail "threads 99999999" "$work/small.png" "$work/o.png" --scale 2 --threads 99999999
run_fail "tile rows 10^20" "$work/small.png" "$work/o.png" --scale 2 --tile-rows 100000000000000000000
run_fail "mesh roi at INT_MAX" "$work/small.png" "$work/o.png" --scale 2 --mesh "$work/m.svg" \
  --mesh-roi 2147483647,2147483647,2147483647,2147483647
run_fail "volume scale 1e308" "$work/a.nhdr" "$work/o.nrrd" --scale 1e308 --any-data-file
run_fail "grid size 10^6 squared" grid "$work/p.csv" "$work/o.exr" --size 1000000x1000000
run_fail_saying "grid bounds 1e308" "double precision" grid "$work/p.csv" "$work/o.exr" --size 8 \
  --bounds -1e308,-1e308,1e308,1e308
# Points 0..1e308 rendered every pixel 0 with exit 0 (issue 20, item 11); shifted far out they grid as near 0.
printf 'x,y,v\n0,0,1\n1e308,0,2\n0,1e308,3\n1e308,1e308,4\n5e307,4e307,5\n' >"$work/far.csv"
run_fail_saying "grid points 0..1e308" "double precision" grid "$work/far.csv" "$work/o.exr" --size 8 --no-optimize
printf 'x,y,v\n1e300,1e300,1\n1.5e300,1e300,2\n1e300,1.5e300,3\n1.5e300,1.5e300,4\n1.2e300,1.3e300,5\n' >"$work/far.csv"
run_fail_saying "grid flips at a 5e299 span" "flips" grid "$work/far.csv" "$work/o.exr" --size 8
run_ok "grid at 1e300 without flips" grid "$work/far.csv" "$work/far.exr" --size 8 --no-optimize
printf 'x,y,v\n1,1,1\n1.5,1,2\n1,1.5,3\n1.5,1.5,4\n1.2,1.3,5\n' >"$work/near.csv"
run_ok "grid at 1 without flips" grid "$work/near.csv" "$work/near.exr" --size 8 --no-optimize
oiiotool "$work/far.exr" "$work/near.exr" --diff --fail 1e-5 >/dev/null 2>&1 && ok || bad "grid at 1e300 differs from at 1"
long=$(head -c 100000 /dev/zero | tr '\0' 'a')
run_fail "input name of 100000 characters" "$work/$long.png" "$work/o.png" --scale 2
run_fail "output name of 100000 characters" "$work/small.png" "$work/$long.png" --scale 2
run_fail "eval scale 2^40" eval --synthetic --scale 1099511627776 --quiet

echo "cli_fault_test: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
