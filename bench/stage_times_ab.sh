#!/bin/bash
# Interleaved A/B stage times of two ddtscale binaries: for each input, runs
# A B A B ... (RUNS each, default 5) with `--scale 2 --model point --verbose`
# and prints the median optimize and render seconds of each binary.
#   bench/stage_times_ab.sh OLD_BINARY NEW_BINARY INPUT...
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: $0 OLD_BINARY NEW_BINARY INPUT..." >&2; exit 2; }
A=$1 B=$2; shift 2
runs=${RUNS:-5}
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
median() { sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}'; }
for input in "$@"; do
  : > "$work/A"; : > "$work/B"
  for _ in $(seq "$runs"); do
    for side in A B; do
      "${!side}" "$input" "$work/out.exr" --scale 2 --model point --verbose 2>&1 |
        awk '/^optimize: cost/{o=$(NF-1)} /^render:/{r=$(NF-1)} END{print o, r}' >> "$work/$side"
    done
  done
  for side in A B; do
    echo "$(basename "$input") $side optimize $(cut -d' ' -f1 "$work/$side" | median) s," \
      "render $(cut -d' ' -f2 "$work/$side" | median) s (runs: $(cut -d' ' -f1 "$work/$side" | tr '\n' ' '))"
  done
done
