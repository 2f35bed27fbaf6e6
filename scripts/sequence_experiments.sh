#!/usr/bin/env bash
# Reproduces the figures of docs/sequences.md:
#   1. frame-rate upsampling x4 of the moving scenes against the truth
#      (128x128, 17 kept frames -> 65): docs/sequences/experiments.md and
#      the pictures docs/sequences/*-frames.png, *-xt.png;
#   2. the same at other speeds (motion x0.25 .. x2), the photographs'
#      pan and zoom too: docs/sequences/speeds.md;
#      and a frame-rate conversion by 5/2 (24 to 60 frames a second):
#      docs/sequences/ratio.md;
#   3. the benchmark: a 256x256 x 64-frame RGB sequence (FFmpeg's testsrc2)
#      at time x4, time and peak memory: docs/sequences/benchmark.md.
# Needs ffmpeg (minterpolate and the benchmark's frames) and the Set14
# photograph for pan and zoom (../shared/datasets, or DDTSCALE_DATASETS).
# Usage: scripts/sequence_experiments.sh [BUILD_DIR] [experiments|speeds|ratio|benchmark|all]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
what=${2:-all}
bin="$build/ddtscale"
if [ ! -x "$bin" ]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
  cmake --build "$build" -j"$(nproc)" --target ddtscale
fi
datasets=${DDTSCALE_DATASETS:-../shared/datasets}
photo="$datasets/Set14/baboon.png"
[ -f "$photo" ] || { echo "no photograph at $photo: pan and zoom are skipped" >&2; photo=""; }
mkdir -p docs/sequences

if [ "$what" = all ] || [ "$what" = experiments ]; then
  "$bin" sequence-eval --methods blend,minterpolate,ddt-unsmoothed,ddt,ddt-cubic ${photo:+--photo "$photo"} \
    --pictures docs/sequences --table docs/sequences/experiments.md
fi

if [ "$what" = all ] || [ "$what" = speeds ]; then
  {
    echo "| speed | scene | blend | minterpolate | ddt |"
    echo "|---|---|---|---|---|"
    for speed in 0.25 0.5 1 2; do
      "$bin" sequence-eval --scenes "disk,bar,strokes${photo:+,pan,zoom}" --methods blend,minterpolate,ddt \
        --speed "$speed" ${photo:+--photo "$photo"} -q |
        awk -F'|' -v s="$speed" 'NR > 2 { gsub(/ /, "", $2); gsub(/ /, "", $3); v[$2, $3] = $4; sc[$2] = 1 }
          END { n = split("disk bar strokes pan zoom", order, " ");
                for (i = 1; i <= n; ++i) { k = order[i]; if (k in sc)
                  printf "| %s | %s |%s|%s|%s|\n", s, k, v[k, "blend"], v[k, "minterpolate"], v[k, "ddt"] } }'
    done
  } >docs/sequences/speeds.md
  cat docs/sequences/speeds.md
fi

if [ "$what" = all ] || [ "$what" = ratio ]; then
  "$bin" sequence-eval --time-scale 5/2 --methods blend,minterpolate,ddt ${photo:+--photo "$photo"} \
    --table docs/sequences/ratio.md
fi

if [ "$what" = all ] || [ "$what" = benchmark ]; then
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  ffmpeg -loglevel error -f lavfi -i testsrc2=size=256x256:rate=8 -frames:v 64 -start_number 1 "$tmp/in_%04d.png"
  {
    echo "| run | frames in -> out | tiles | tetrahedralize (s) | optimize (s) | render (s) | write (s) | wall (s) | peak memory (MB) |"
    echo "|---|---|---|---|---|---|---|---|---|"
    for run in 1 2 3; do
      rm -rf "$tmp/out"; mkdir "$tmp/out"
      /usr/bin/time -f "%e %M" -o "$tmp/time" "$bin" "$tmp/in_%04d.png" "$tmp/out/o_%04d.png" --time-scale 4 -v \
        2>"$tmp/log"
      read -r wall kb <"$tmp/time"
      sed -n 's/^done: \([0-9]*\) tiles, .* tetrahedralize \([0-9.]*\) s, optimize \([0-9.]*\) s, render \([0-9.]*\) s, write \([0-9.]*\) s.*/\1 \2 \3 \4 \5/p' "$tmp/log" |
        { read -r tiles tet opt ren wri; echo "| $run | 64 -> 253 | $tiles | $tet | $opt | $ren | $wri | $wall | $((kb / 1024)) |"; }
    done
  } >docs/sequences/benchmark.md
  cat docs/sequences/benchmark.md
fi
