#!/usr/bin/env bash
# ddtscale against libvips and oiiotool, end to end (issue 18,
# docs/performance.md "Against libvips"). Child processes, interleaved,
# medians of the wall time; peak memory is GNU time's %M (ru_maxrss from
# wait4); output file sizes.
#   bench/vips_compare.sh BUILD_DIR [RUNS] [GROWTH_SIZES] [LARGE]
#   e.g. bench/vips_compare.sh build 5 "256 512 1024 2048 4096" 8192
# The input is the benchmark's 1024x1024 RGB PNG (ddtscale_bench writes it).
set -eu
build=${1:?build directory}
runs=${2:-5}
sizes=${3:-"256 512 1024 2048 4096"}
large=${4:-0}
work=${WORK:-/tmp/ddtscale-vips}
mkdir -p "$work"
# Setup: Debian's libvips command-line tools, installed when missing.
if ! command -v vips >/dev/null; then
  if [ "$(id -u)" -eq 0 ]; then apt-get install -y libvips-tools >/dev/null; else sudo apt-get install -y libvips-tools; fi
fi
ddt="$build/ddtscale"
in="$work/in1024.png"
[ -f "$in" ] || "$build/ddtscale_bench" --only none --large 0 --work "$work" >/dev/null
# one NAME CMD...: runs CMD once, appends "NAME seconds kilobytes" to $work/runs.txt
one() {
  local name="$1"; shift
  /usr/bin/time -f "%e %M" -o "$work/t.txt" "$@" >/dev/null 2>&1 || { echo "FAILED: $*"; return 1; }
  echo "$name $(cat "$work/t.txt")" >>"$work/runs.txt"
}
cp "$work/runs.txt" "$work/runs_prev.txt" 2>/dev/null || true
: >"$work/runs.txt"
echo "load at start: $(cat /proc/loadavg)"
for r in $(seq "$runs"); do
  one vips_png vips resize "$in" "$work/vips.png" 4 --kernel cubic
  one ddt_png "$ddt" "$in" "$work/ddt.png" --scale 4 --quiet
  one ddt_png_point "$ddt" "$in" "$work/ddt_point.png" --scale 4 --quiet --model point
  one oiio_exr oiiotool "$in" --resize:filter=catmull-rom 400% -o "$work/oiio.exr"
  one ddt_exr "$ddt" "$in" "$work/ddt.exr" --scale 4 --quiet
  one ddt_exr_point "$ddt" "$in" "$work/ddt_point.exr" --scale 4 --quiet --model point
done
median() { sort -n | awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }'; }
summary() {  # NAME FILE: median seconds, median peak RSS, file size
  local t m
  t=$(awk -v n="$1" '$1 == n { print $2 }' "$work/runs.txt" | median)
  m=$(awk -v n="$1" '$1 == n { print $3 }' "$work/runs.txt" | median)
  awk -v n="$1" -v t="$t" -v m="$m" -v s="$(stat -c %s "$2")" \
    'BEGIN { printf "| %s | %.2f s | %.0f MB | %.1f MB |\n", n, t, m / 1024, s / 1048576 }'
}
echo "| case | median wall | median peak RSS | file |"
echo "|---|---|---|---|"
summary vips_png "$work/vips.png"
summary ddt_png "$work/ddt.png"
summary ddt_png_point "$work/ddt_point.png"
summary oiio_exr "$work/oiio.exr"
summary ddt_exr "$work/ddt.exr"
summary ddt_exr_point "$work/ddt_point.exr"
# Growth, x4 to PNG, one run each, default and --model point, vips beside.
echo
echo "| input | vips wall | vips RSS | ddtscale wall | ddtscale RSS | --model point wall | --model point RSS |"
echo "|---|---|---|---|---|---|---|"
for n in $sizes; do
  g="$work/g$n.png"
  if [ "$n" -le 1024 ]; then vips crop "$in" "$g" 0 0 "$n" "$n"; else vips replicate "$in" "$work/r.v" $(( (n + 1023) / 1024 )) $(( (n + 1023) / 1024 )) && vips crop "$work/r.v" "$g" 0 0 "$n" "$n"; fi
  : >"$work/runs.txt"
  one v vips resize "$g" "$work/gv.png" 4 --kernel cubic
  one d "$ddt" "$g" "$work/gd.png" --scale 4 --quiet --max-pixels 1000000000
  one p "$ddt" "$g" "$work/gp.png" --scale 4 --quiet --model point --max-pixels 1000000000
  awk -v n="$n" '{ w[$1] = $2; m[$1] = $3 } END { printf "| %d^2 | %.2f s | %.0f MB | %.2f s | %.0f MB | %.2f s | %.0f MB |\n", n, w["v"], m["v"] / 1024, w["d"], m["d"] / 1024, w["p"], m["p"] / 1024 }' "$work/runs.txt"
  rm -f "$g" "$work/gv.png" "$work/gd.png" "$work/gp.png" "$work/r.v"
done
if [ "$large" -gt 0 ]; then
  g="$work/large.png"
  vips replicate "$in" "$work/r.v" $(( large / 1024 )) $(( large / 1024 )) && vips copy "$work/r.v" "$g"
  : >"$work/runs.txt"
  one L "$ddt" "$g" "$work/large.exr" --scale 2 --quiet --max-pixels 1000000000
  echo; echo "large ${large}^2 x2 to EXR: $(cat "$work/runs.txt")"
  rm -f "$g" "$work/r.v" "$work/large.exr"
fi
echo "load at end: $(cat /proc/loadavg)"
