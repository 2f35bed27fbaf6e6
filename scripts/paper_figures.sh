#!/usr/bin/env bash
# Reproduces the 2D experiments of Tóth et al., "N-dimensional
# Data-Dependent Reconstruction Using Topological Changes", as reported in
# docs/paper-experiments.md:
#   figure 1   bicubic beside DDT at 10x      -> docs/paper-fig1-bicubic-vs-ddt-x10.png
#   figure 8   Lawson above annealing at 6x,  -> docs/paper-fig8-lawson-vs-anneal-x6.png
#              each with its mesh
#   where the flips land (smooth vs busy regions), Lawson against annealing
#   (and the look-ahead optimizer)
#   the Set5 table for every cost and optimizer (ddtscale eval)
# Tables go to stdout and to build-paper/results/. Input: crops of
# images/astronaut_face.png (public domain, see images/README.md).
#   bash scripts/paper_figures.sh            # everything (10-20 minutes on 2 cores)
#   bash scripts/paper_figures.sh --no-eval  # figures and flip statistics only (a few minutes)
# Builds its own tree (build-paper: the library, the CLI and
# tools/paper/paper_experiments); needs what scripts/setup.sh installs.
set -euo pipefail
cd "$(dirname "$0")/.."
run_eval=1
[ "${1:-}" = "--no-eval" ] && run_eval=0
set5="${SET5:-../shared/datasets/Set5}"

cmake -S tools/paper -B build-paper -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build-paper -j"$(nproc)" --target paper_experiments ddtscale
tool=build-paper/paper_experiments
bin=build-paper/ddtscale
out=build-paper/results
mkdir -p "$out" docs
face=images/astronaut_face.png

# Figure 1: the eyes, 40x32 pixels, at 10x; DDT with the paper's Sederberg
# cost, Lawson, piecewise-linear surface.
"$tool" fig1 "$face" --crop 40x32+44+46 --scale 10 --cost sederberg --out docs/paper-fig1-bicubic-vs-ddt-x10.png

# Figure 8: an eye and the cheek below it (the paper's example of a smooth
# region), 40x40 pixels, at 6x; Sederberg's cost; annealing with seed 1 and
# the default schedule. The mesh column shows the framed 20x20 of the cheek.
"$tool" fig8 "$face" --crop 40x40+24+50 --scale 6 --cost sederberg --seed 1 --mesh-roi 2,18,20,20 \
  --out docs/paper-fig8-lawson-vs-anneal-x6.png | tee "$out/fig8.txt"

# Where the flips land: the whole face, three synthetic scenes (two
# piecewise flat, one smooth everywhere), Set5's ground truths.
"$tool" smooth "$face" --cost sederberg,variance,abn,jnd,dlp,dp --seeds 1,2,3 --lookahead | tee "$out/smooth-face.md"
"$tool" smooth "scene:edge_30@64x64" "scene:disk@64x64" "scene:smooth_waves@64x64" \
  --cost sederberg,variance --seeds 1 | tee "$out/smooth-scenes.md"
"$tool" smooth "$set5"/*.png --cost sederberg --seeds 1 --lookahead | tee "$out/smooth-set5.md"
# The schedule: fewer temperature steps end hotter.
for steps in 10 25 50 100; do
  echo "--anneal-steps $steps"
  "$tool" smooth "$face" --cost sederberg --seeds 1 --anneal-steps "$steps"
done | tee "$out/smooth-schedule.md"

[ "$run_eval" = 1 ] || exit 0
# Set5, x2 and x4, every cost, every optimizer. ddt-linear is the paper's
# piecewise-linear surface; ddt (cubic patches on the same mesh) is the
# product's default rendering.
costs=sederberg,sederberg-edge,variance,abn,abn-edge,jnd,jnd-edge,dlp,dlp-edge,dp,dp-edge
"$bin" eval --set "$set5" --scale 2,4 --methods delaunay-linear,ddt-linear,ddt,bicubic --cost "$costs" \
  --optimizer lawson --quiet --csv "$out/set5-lawson.csv" | tee "$out/set5-lawson.txt"
"$bin" eval --set "$set5" --scale 2,4 --methods ddt-linear,ddt --cost "$costs" \
  --optimizer anneal --seed 1 --quiet --csv "$out/set5-anneal.csv" | tee "$out/set5-anneal.txt"
"$bin" eval --set "$set5" --scale 2,4 --methods ddt-linear,ddt --cost "$costs" \
  --optimizer lookahead --quiet --csv "$out/set5-lookahead.csv" | tee "$out/set5-lookahead.txt"
