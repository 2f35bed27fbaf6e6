#!/usr/bin/env bash
# End-to-end checks of image sequences on the ddtscale command: frame-rate
# upsampling (ddtscale in_%04d.png out_%04d.png --time-scale 4), its
# options, sequence-scene and sequence-eval, and bad input (one line on
# stderr, non-zero exit, nothing written or destroyed).
# Usage: cli_sequence_test.sh path/to/ddtscale
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
count() { find "$1" -maxdepth 1 -name "$2" | wc -l; }

# Input: the moving strokes, frames 0..8 of the full rate (every 4th kept below).
mkdir -p "$work/full" "$work/in" "$work/out" "$work/long"
run_ok "sequence-scene" sequence-scene strokes "$work/full/f_%03d.png" --frames 9 --size 40x32
[ "$(count "$work/full" 'f_*.png')" -eq 9 ] && ok || bad "sequence-scene wrote $(count "$work/full" 'f_*.png') frames"
cp "$work/full/f_000.png" "$work/in/in_0001.png"
cp "$work/full/f_004.png" "$work/in/in_0002.png"
cp "$work/full/f_008.png" "$work/in/in_0003.png"

# The main job: 3 frames at time x4 -> 9 frames numbered 1..9, input frames kept.
run_ok "time x4" "$work/in/in_%04d.png" "$work/out/o_%04d.png" --time-scale 4
[ "$(count "$work/out" 'o_*.png')" -eq 9 ] && ok || bad "time x4 wrote $(count "$work/out" 'o_*.png') frames, not 9"
[ -f "$work/out/o_0001.png" ] && [ -f "$work/out/o_0009.png" ] && ok || bad "output numbering is not 1..9"
grep -q "o_0001.png .. .*o_0009.png: 9 frames of 40x32" "$work/err.txt" && ok || bad "summary line: $(cat "$work/err.txt")"
if command -v idiff >/dev/null; then
  idiff -fail 0 "$work/in/in_0002.png" "$work/out/o_0005.png" >/dev/null && ok || bad "input frame 2 is not output frame 5"
fi
# A frame-rate ratio: 3 frames at 5/2 are floor(2 x 2.5) + 1 = 6, frame 6 the instant 2 (the last input frame).
run_ok "time 5/2" "$work/in/in_%04d.png" "$work/out/r_%04d.png" --time-scale 5/2
[ "$(count "$work/out" 'r_*.png')" -eq 6 ] && ok || bad "time 5/2 wrote $(count "$work/out" 'r_*.png') frames, not 6"
if command -v idiff >/dev/null; then
  idiff -fail 0.000001 "$work/in/in_0003.png" "$work/out/r_0006.png" >/dev/null && ok || bad "input frame 3 is not output frame 6 at 5/2"
fi
# Space and time, EXR out, verbose.
run_ok "scale 2, exr" "$work/in/in_%04d.png" "$work/out/big_%02d.exr" --time-scale 2 --scale 2 -v --threads 1
[ "$(count "$work/out" 'big_*.exr')" -eq 5 ] && ok || bad "time x2 wrote $(count "$work/out" 'big_*.exr') frames, not 5"
grep -q "done: 1 tiles" "$work/err.txt" && ok || bad "verbose summary missing: $(tail -1 "$work/err.txt")"
# Tiles over time with --time-tile and --time-margin.
run_ok "tiles" "$work/in/in_%04d.png" "$work/out/t_%04d.png" --time-scale 4 --time-tile 1 --time-margin 1 -v
grep -q "done: 2 tiles" "$work/err.txt" && ok || bad "--time-tile 1 did not make 2 tiles"
# Exact tiles of a sequence this small: one slab of the schedule, so one tile, the untiled frames.
run_ok "exact tiles" "$work/in/in_%04d.png" "$work/out/e_%04d.png" --time-scale 4 --time-tile 1 --exact-tiles -v
grep -q "done: 1 tiles" "$work/err.txt" && ok || bad "--exact-tiles on one slab: $(grep 'done:' "$work/err.txt")"
if command -v idiff >/dev/null; then
  idiff -fail 0 "$work/out/o_0006.png" "$work/out/e_0006.png" >/dev/null && ok || bad "exact tiles changed frame 6"
fi
# Slow texture is tested by default (the verbose log says how many samples
# stay paired along time) and not with --flip-slow-texture.
run_ok "slow texture" "$work/in/in_%04d.png" "$work/out/slow_%04d.png" --time-scale 2 -v
grep -qE "slow texture: [0-9]+ of [0-9]+ samples stay paired along time" "$work/err.txt" && ok ||
  bad "the default run does not test slow texture"
run_ok "--flip-slow-texture" "$work/in/in_%04d.png" "$work/out/flip_%04d.png" --time-scale 2 -v --flip-slow-texture
grep -q "slow texture:" "$work/err.txt" && bad "--flip-slow-texture still tests slow texture" || ok
# The initial mesh sheared along the dominant motion: the strokes move
# (-3, 2) px between the kept frames; --motion off and DX,DY as asked.
run_ok "motion auto" "$work/in/in_%04d.png" "$work/out/m_%04d.png" --time-scale 4 -v
grep -qE "motion: 2 of 2 frame pairs agree on \(-(2\.9|3\.0)[0-9], (1\.9|2\.0)[0-9]\) px a frame: the mesh starts sheared" "$work/err.txt" && ok ||
  bad "the default run does not shear along the strokes' motion: $(grep 'motion:' "$work/err.txt")"
grep -q "presmooth: sigma 0.5 px in space (the mesh starts along the whole-pixel shift)" "$work/err.txt" && ok ||
  bad "the sheared run does not narrow the smoothing: $(grep 'presmooth' "$work/err.txt")"
run_ok "presmooth given" "$work/in/in_%04d.png" "$work/out/m_%04d.png" --time-scale 4 -v --presmooth 1
grep -q "presmooth:" "$work/err.txt" && bad "--presmooth 1 is narrowed along the motion" || ok
run_ok "motion off" "$work/in/in_%04d.png" "$work/out/m_%04d.png" --time-scale 4 -v --motion off
grep -q "motion:" "$work/err.txt" && bad "--motion off still estimates the motion" || ok
grep -q "presmooth:" "$work/err.txt" && bad "--motion off narrows the smoothing" || ok
run_ok "motion given" "$work/in/in_%04d.png" "$work/out/m_%04d.png" --time-scale 4 --motion -3,2
run_fail "no factor" "$work/in/in_%04d.png" "$work/out/nf_%04d.png"
grep -q "give the frame-rate factor" "$work/err.txt" && [ "$(count "$work/out" 'nf_*')" -eq 0 ] && ok ||
  bad "no --time-scale, --scale or --size: $(cat "$work/err.txt")"
run_fail "motion bad" "$work/in/in_%04d.png" "$work/out/mb_%04d.png" --time-scale 4 --motion 3
grep -q "auto, off, DX,DY or DX,DY,ZOOM" "$work/err.txt" && ok || bad "--motion 3: $(cat "$work/err.txt")"
run_fail "motion trailing" "$work/in/in_%04d.png" "$work/out/mt_%04d.png" --time-scale 4 --motion 3,2x
run_ok "motion zoom given" "$work/in/in_%04d.png" "$work/out/mz_%04d.png" --time-scale 4 --motion -3,2,1.02
run_ok "sequence-scene long" sequence-scene strokes "$work/long/l_%03d.png" --frames 12 --size 16x16
run_fail "motion zoom too long" "$work/long/l_%03d.png" "$work/out/mzl_%04d.png" --time-scale 2 --motion 0,0,0.5
grep -q "factor over 1024" "$work/err.txt" && ok || bad "--motion 0,0,0.5: $(cat "$work/err.txt")"
run_fail "motion zoom bad" "$work/in/in_%04d.png" "$work/out/mzb_%04d.png" --time-scale 4 --motion 0,0,3
grep -q "ZOOM the scale a frame about the centre, 0.5 to 2" "$work/err.txt" && ok || bad "--motion 0,0,3: $(cat "$work/err.txt")"
[ -e "$work/out/mzb_0000.png" ] && bad "a refused --motion wrote a frame" || ok
[ "$(count "$work/out" 'mb_*.png')" -eq 0 ] && ok || bad "a refused --motion wrote frames"
run_ok "help" "$work/in/in_%04d.png" x_%04d.png --help
grep -q -- "--time-scale" "$work/out.txt" && ok || bad "--help does not describe --time-scale"

# Bad input: one line, non-zero exit, nothing written.
run_fail "no match" "$work/none_%04d.png" "$work/out/n_%04d.png" --time-scale 2
run_fail "same pattern" "$work/in/in_%04d.png" "$work/in/in_%04d.png" --time-scale 2
run_fail "an input by another spelling" "$work/in/in_%04d.png" "$work/in/../in/in_%04d.png" --time-scale 2
grep -q "is an input frame" "$work/err.txt" && ok || bad "another spelling of the input: $(cat "$work/err.txt")"
run_fail "time scale 0" "$work/in/in_%04d.png" "$work/out/z_%04d.png" --time-scale 0
run_fail "time scale over zero" "$work/in/in_%04d.png" "$work/out/z_%04d.png" --time-scale 5/0
run_fail "time scale not a number" "$work/in/in_%04d.png" "$work/out/z_%04d.png" --time-scale fast
run_fail "time scale with a comma" "$work/in/in_%04d.png" "$work/out/z_%04d.png" --time-scale 2,5
run_fail "time scale half a ratio" "$work/in/in_%04d.png" "$work/out/z_%04d.png" --time-scale 60/
run_fail "two numbers" "$work/in/in_%04d_%d.png" "$work/out/z_%04d.png" --time-scale 2
run_fail "no extension" "$work/in/in_%04d.png" "$work/out/z_%04d" --time-scale 2
cp "$work/in/in_0003.png" "$work/in/in_0005.png"
run_fail "missing frame" "$work/in/in_%04d.png" "$work/out/m_%04d.png" --time-scale 2
grep -q "frame 4" "$work/err.txt" && ok || bad "the missing frame is not named: $(cat "$work/err.txt")"
rm "$work/in/in_0005.png"
"$bin" sequence-scene disk "$work/odd_%d.png" --frames 1 --size 20 2>/dev/null
cp "$work/odd_0.png" "$work/in/in_0004.png"
run_fail "mismatched size" "$work/in/in_%04d.png" "$work/out/s_%04d.png" --time-scale 2
grep -q "all frames must match" "$work/err.txt" && ok || bad "mismatch message: $(cat "$work/err.txt")"
[ "$(count "$work/out" 's_*.png')" -eq 0 ] && ok || bad "a failed run left output frames"
rm "$work/in/in_0004.png"
# An existing output frame survives a failed run.
echo keep >"$work/out/k_0001.png"
run_fail "bad cost" "$work/in/in_%04d.png" "$work/out/k_%04d.png" --time-scale 2 --cost nope
[ "$(cat "$work/out/k_0001.png")" = "keep" ] && ok || bad "a failed run replaced an existing output frame"

# sequence-eval, small: every method but the photograph scenes.
run_ok "sequence-eval" sequence-eval --scenes strokes --methods blend,ddt --size 24 --frames 3 -q
grep -q "| strokes | ddt |" "$work/out.txt" && ok || bad "sequence-eval table: $(cat "$work/out.txt")"
if command -v ffmpeg >/dev/null; then
  run_ok "sequence-eval minterpolate" sequence-eval --scenes bar --methods blend,minterpolate --size 32 --frames 3 -q
  grep -q "| bar | minterpolate |" "$work/out.txt" && ok || bad "minterpolate row missing: $(cat "$work/out.txt")"
else
  echo "cli_sequence_test: no ffmpeg, minterpolate not checked"
fi
run_fail "sequence-eval bad scene" sequence-eval --scenes nope --size 24 --frames 3 -q

# Video files in and out through FFmpeg (setup.sh installs it).
if command -v ffmpeg >/dev/null && command -v ffprobe >/dev/null; then
  probe() { ffprobe -v error -count_packets -select_streams "$2" -show_entries stream="$3" -of csv=p=0 "$1"; }
  mkdir -p "$work/video"
  ffmpeg -v error -f lavfi -i testsrc2=size=48x32:rate=12 -f lavfi -i sine=frequency=440:sample_rate=8000 -t 1 \
    -c:v libx264 -pix_fmt yuv420p -c:a aac -shortest "$work/video/in.mp4"
  run_ok "video x2" "$work/video/in.mp4" "$work/video/out.mp4" --time-scale 2
  [ "$(probe "$work/video/out.mp4" v:0 nb_read_packets,r_frame_rate)" = "24/1,23" ] && ok ||
    bad "video x2: $(probe "$work/video/out.mp4" v:0 nb_read_packets,r_frame_rate), not 23 frames at 24/1"
  [ -n "$(probe "$work/video/out.mp4" a nb_read_packets)" ] && ok || bad "video x2 lost the audio"
  run_ok "video slow motion" "$work/video/in.mp4" "$work/video/slow.mkv" --time-scale 3 --slow-motion --scale 2
  [ "$(probe "$work/video/slow.mkv" v:0 width,r_frame_rate,nb_read_packets)" = "96,12/1,34" ] && ok ||
    bad "slow motion: $(probe "$work/video/slow.mkv" v:0 width,r_frame_rate,nb_read_packets)"
  [ -z "$(probe "$work/video/slow.mkv" a nb_read_packets)" ] && ok || bad "slow motion kept the audio"
  run_ok "video to frames" "$work/video/in.mp4" "$work/video/f_%03d.png" --time-scale 5/2
  [ "$(count "$work/video" 'f_*.png')" -eq 28 ] && ok || bad "video to frames: $(count "$work/video" 'f_*.png'), not 28"
  run_ok "frames to video" "$work/in/in_%04d.png" "$work/video/from_frames.webm" --time-scale 2 --fps 30
  [ "$(probe "$work/video/from_frames.webm" v:0 r_frame_rate,nb_read_packets)" = "60/1,5" ] && ok ||
    bad "frames to video: $(probe "$work/video/from_frames.webm" v:0 r_frame_rate,nb_read_packets)"
  run_ok "video to webm, audio encoded" "$work/video/in.mp4" "$work/video/out.webm" --time-scale 2
  [ -n "$(probe "$work/video/out.webm" a nb_read_packets)" ] && ok || bad "webm lost the audio"
  run_ok "an exact NTSC rate" "$work/in/in_%04d.png" "$work/video/ntsc.mp4" --time-scale 2 --fps 30000/1001
  [ "$(probe "$work/video/ntsc.mp4" v:0 r_frame_rate)" = "60000/1001" ] && ok ||
    bad "30000/1001 x 2: $(probe "$work/video/ntsc.mp4" v:0 r_frame_rate)"
  run_fail "odd size in 4:2:0" "$work/video/in.mp4" "$work/video/x.mp4" --time-scale 2 --size 33x33
  ffmpeg -v error -i "$work/video/in.mp4" -metadata:s:v:0 rotate=90 -c copy "$work/video/turned.mp4"
  run_ok "a video turned a quarter" "$work/video/turned.mp4" "$work/video/upright.mp4" --time-scale 2
  [ "$(probe "$work/video/upright.mp4" v:0 width,height)" = "32,48" ] && ok ||
    bad "turned video: $(probe "$work/video/upright.mp4" v:0 width,height), not 32x48 upright"
  echo "not a video" >"$work/video/fake.mp4"
  run_fail "not a video" "$work/video/fake.mp4" "$work/video/x.mp4" --time-scale 2
  run_fail "video onto itself" "$work/video/in.mp4" "$work/video/in.mp4" --time-scale 2
  run_fail "exact tiles of a video" "$work/video/in.mp4" "$work/video/x.mp4" --time-scale 2 --exact-tiles
  run_fail "bad crf" "$work/video/in.mp4" "$work/video/x.mp4" --time-scale 2 --crf 99
  [ -e "$work/video/x.mp4" ] && bad "a failed run left x.mp4" || ok
  ls -a "$work/video" | grep -q '\.ddtscale-' && bad "a temporary directory left behind" || ok
else
  echo "cli_sequence_test: no ffmpeg, video files not checked"
fi

echo "cli_sequence_test: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
