#!/bin/bash
# The default (--model box) against --model point, end to end, per output
# format: for each of EXR (default samples), EXR --float and PNG, runs the
# two commands alternately (RUNS each, default 5) and prints the median wall
# times and their ratio (issue 15's 1.5x target).
#   bench/model_ratio.sh [BINARY] [INPUT]
# BINARY defaults to build/ddtscale, INPUT to the benchmark's 1024x1024 PNG
# (/tmp/ddtscale-bench/in1024.png, written by build/ddtscale_bench).
set -euo pipefail
bin=${1:-build/ddtscale}
input=${2:-/tmp/ddtscale-bench/in1024.png}
[ -f "$input" ] || { echo "$0: no input '$input' (run build/ddtscale_bench --only end-to-end --runs 1 first)" >&2; exit 2; }
runs=${RUNS:-5}
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
median() { sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}'; }
cases=("exr:out.exr:" "exr --float:out.exr:--float" "png:out.png:")
for _ in $(seq "$runs"); do
  for i in "${!cases[@]}"; do
    IFS=: read -r _ out extra <<<"${cases[$i]}"
    for model in box point; do
      /usr/bin/time -f "%e" -o "$work/t" "$bin" "$input" "$work/$out" --scale 4 --quiet --model "$model" $extra
      cat "$work/t" >> "$work/$i.$model"
    done
  done
done
printf '| output | default (box) | --model point | ratio |\n|---|---|---|---|\n'
for i in "${!cases[@]}"; do
  IFS=: read -r name _ _ <<<"${cases[$i]}"
  b=$(median < "$work/$i.box"); p=$(median < "$work/$i.point")
  printf '| %s | %.2f s | %.2f s | %.2fx |\n' "$name" "$b" "$p" "$(echo "$b / $p" | bc -l)"
done
