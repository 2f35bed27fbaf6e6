#!/usr/bin/env bash
# Reproduces the figures of docs/volumes.md:
#   1. the paper's 3D experiments (sphere and hydrogen orbital, 32^3, x4):
#      docs/volumes/experiments.md and the pictures docs/volumes/*.png;
#   1b. the hydrogen orbital as an 8-bit data set (quantized input, as the
#      paper's hydrogen volume): docs/volumes/hydrogen-8bit.md and
#      docs/volumes/hydrogen-x4-q8*.png;
#   1c. the volume-series experiment (4D: the moving sphere, 32^3 x 16 steps,
#      x2 in space, x4 in time): docs/volumes/series-experiments.md and
#      docs/volumes/moving-sphere-x2-t4*.png;
#   1d. the same experiment on the other series fields (a moving box, a
#      turning bar, a smooth moving blob): docs/volumes/series-other.md and
#      docs/volumes/<field>-x2-t4*.png;
#   2. the benchmark (hydrogen orbital at 32^3, 64^3, 128^3, x2 and x4; time
#      of each stage and peak memory): docs/volumes/benchmark.md.
# Usage: scripts/volume_experiments.sh [BUILD_DIR] [experiments|series|series-other|benchmark|all]
# BUILD_DIR defaults to build (configured and built here when missing).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
what=${2:-all}
bin="$build/ddtscale"
if [ ! -x "$bin" ]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release
  cmake --build "$build" -j"$(nproc)" --target ddtscale
fi
mkdir -p docs/volumes

if [ "$what" = all ] || [ "$what" = experiments ]; then
  "$bin" volume-eval --size 32 --scale 4 --pictures docs/volumes --table docs/volumes/experiments.md
  "$bin" volume-eval --size 32 --scale 4 --fields hydrogen --quantize 8 \
    --methods trilinear,tricubic,delaunay,ddt-linear:variance,ddt:variance,ddt:sederberg \
    --picture-methods trilinear,tricubic,ddt-linear:variance,ddt:variance \
    --iso 0.02 --pictures docs/volumes --table docs/volumes/hydrogen-8bit.md
fi

if [ "$what" = all ] || [ "$what" = series ]; then
  "$bin" volume-eval --series --size 32 --steps 16 --scale 2 --time-scale 4 \
    --pictures docs/volumes --table docs/volumes/series-experiments.md
fi

if [ "$what" = all ] || [ "$what" = series-other ]; then
  # One field a run; the tables joined under one header.
  other=$(mktemp)
  for field in moving-box spinning-bar moving-blob; do
    "$bin" volume-eval --series --fields "$field" --size 32 --steps 16 --scale 2 --time-scale 4 \
      --methods quadrilinear,tricubic-linear,ddt --picture-methods quadrilinear,tricubic-linear,ddt \
      --pictures docs/volumes --table "$other.$field" -q
    if [ ! -s "$other" ]; then cat "$other.$field" >"$other"; else tail -n +3 "$other.$field" >>"$other"; fi
    rm -f "$other.$field"
  done
  mv "$other" docs/volumes/series-other.md
fi

if [ "$what" = all ] || [ "$what" = benchmark ]; then
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  # stage NAME LOG: the seconds at the end of the verbose line "NAME: ..., T s".
  stage() { sed -n "s/^$1: .*, \([0-9.]*\) s\$/\1/p" "$2" | tail -1; }
  {
    echo "| input | scale | output | tetrahedra | flips | tetrahedralize (s) | optimize (s) | render (s) | total (s) | peak memory (MB) |"
    echo "|---|---|---|---|---|---|---|---|---|---|"
    for n in 32 64 128; do
      "$bin" volume-field hydrogen "$tmp/h$n.nrrd" --size "$n" --supersample 2
      for s in 2 4; do
        start=$(date +%s.%N)
        "$bin" "$tmp/h$n.nrrd" "$tmp/out.nrrd" --scale "$s" --verbose 2>"$tmp/log"
        end=$(date +%s.%N)
        tets=$(sed -n 's/^tetrahedralize: [0-9]* points, \([0-9]*\) tetrahedra.*/\1/p' "$tmp/log")
        flips=$(sed -n 's/^optimize: cost .*(total \([0-9]*\)).*/\1/p' "$tmp/log")
        memory=$(sed -n 's/^peak memory: \([0-9]*\) MB/\1/p' "$tmp/log")
        printf "| %d^3 | x%d | %d^3 | %s | %s | %s | %s | %s | %.1f | %s |\n" "$n" "$s" $((n * s)) "$tets" "$flips" \
          "$(stage tetrahedralize "$tmp/log")" "$(stage optimize "$tmp/log")" "$(stage render "$tmp/log")" \
          "$(echo "$end - $start" | bc)" "$memory"
        rm -f "$tmp/out.nrrd"
      done
    done
  } | tee docs/volumes/benchmark.md
fi
