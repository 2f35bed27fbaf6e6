#!/usr/bin/env bash
# Regenerates the golden outputs of the regression test on purpose:
# every input in images/regression/inputs, every DDT cost with the default
# cubic render, and the paper's costs with the linear render, at x3, to EXR,
# under the point model; and the default box model (the consistent
# reconstruction) with both renders.
# 32-bit float EXR (--float): the default for 8-bit inputs is half, coarser
# than the test's tolerance.
# Run it only when a change of output is intended, look at the new images,
# and say why in the commit. Nothing else writes the goldens.
#   bash scripts/regenerate_goldens.sh [path/to/ddtscale]
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-build/ddtscale}"
[ -x "$bin" ] || { echo "build ddtscale first (cmake --build build)" >&2; exit 1; }
costs=$("$bin" --list-costs)
rm -f images/regression/golden/*.exr
for input in images/regression/inputs/*.png; do
  name=$(basename "$input" .png)
  for cost in $costs; do
    "$bin" "$input" "images/regression/golden/${name}__${cost}__cubic__x3.exr" --scale 3 --cost "$cost" --model point --float --quiet
  done
  for cost in sederberg variance; do
    "$bin" "$input" "images/regression/golden/${name}__${cost}__linear__x3.exr" --scale 3 --cost "$cost" \
      --render linear --model point --float --quiet
  done
  # The default acquisition model's consistent reconstruction.
  for render in cubic linear; do
    "$bin" "$input" "images/regression/golden/${name}__sederberg__${render}__box__x3.exr" --scale 3 --render "$render" \
      --float --quiet
  done
done
ls images/regression/golden | wc -l | xargs echo "goldens written:"
