#!/usr/bin/env bash
# Scattered-data gridding, ddtscale grid against gdal_grid -a linear (GDAL's
# Delaunay piecewise-linear interpolation), on random samples of analytic
# fields (bench/grid_fields.cpp): a fault-like step, a tent ridge and a
# smooth field (Franke's function). Prints a markdown table: RMSE and
# maximum error against the true field at the pixel centres, and the wall
# time of each command (best of RUNS runs; reading the points, gridding and
# writing the file included).
#
# Usage: scripts/compare_gdal.sh [build_dir] [work_dir]
#   build_dir  holds ddtscale (default: build)
#   work_dir   keeps the points and grids (default: a temporary directory)
# Environment: SIZES (default "1000 10000 100000"), GRID (default 512),
#   RUNS (default 3), SEED (default 1), COSTS (default "sederberg variance").
# Installs Debian's gdal-bin when gdal_grid is missing (apt-get, as root).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
bin="$build/ddtscale"
[ -x "$bin" ] || { echo "compare_gdal: no $bin; build first (cmake -S . -B $build && cmake --build $build)" >&2; exit 1; }
if ! command -v gdal_grid >/dev/null; then
  echo "compare_gdal: installing gdal-bin" >&2
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends gdal-bin >/dev/null
fi
if [ -n "${2:-}" ]; then
  work="$2"
  mkdir -p "$work"
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
sizes=${SIZES:-"1000 10000 100000"}
grid=${GRID:-512}
runs=${RUNS:-3}
seed=${SEED:-1}
costs=${COSTS:-"sederberg variance"}

tool="$work/grid_fields"
g++ -O2 -std=c++20 bench/grid_fields.cpp -o "$tool" -lOpenImageIO -lOpenImageIO_Util

# Best wall time of $runs runs of a command, in seconds.
best_time() {
  local best="" t0 t1 t
  for _ in $(seq "$runs"); do
    t0=$EPOCHREALTIME
    "$@" >/dev/null 2>&1 || { echo "compare_gdal: failed: $*" >&2; exit 1; }
    t1=$EPOCHREALTIME
    t=$(echo "$t1 - $t0" | bc -l)
    if [ -z "$best" ] || [ "$(echo "$t < $best" | bc -l)" -eq 1 ]; then best=$t; fi
  done
  printf '%.3f' "$best"
}

echo "gdal: $(gdal_grid --version)"
echo "ddtscale: $bin; grid ${grid}x${grid} over [0,1]^2; best of $runs runs; $(nproc) cores"
echo "start-up alone: ddtscale --help $(best_time "$bin" --help) s, gdal_grid --version $(best_time gdal_grid --version) s"
echo
echo "| field | points | method | RMSE | max error | seconds |"
echo "|---|---:|---|---:|---:|---:|"
for field in fault ridge smooth; do
  for n in $sizes; do
    pts="$work/${field}_$n.csv"
    "$tool" points "$field" "$n" "$seed" "$pts"
    cat >"$work/${field}_$n.vrt" <<EOF
<OGRVRTDataSource>
  <OGRVRTLayer name="${field}_$n">
    <SrcDataSource>$pts</SrcDataSource>
    <GeometryType>wkbPoint</GeometryType>
    <GeometryField encoding="PointFromColumns" x="x" y="y" z="z"/>
  </OGRVRTLayer>
</OGRVRTDataSource>
EOF
    row() {  # method label, output file, command...
      local label="$1" out="$2"
      shift 2
      local seconds score
      seconds=$(best_time "$@")
      score=$("$tool" rmse "$field" "$out")
      # score: rmse R max M scored S nodata N
      set -- $score
      [ "$8" -eq 0 ] || echo "compare_gdal: $label left $8 no-data pixels on $field" >&2
      echo "| $field | $((n + 4)) | $label | $2 | $4 | $seconds |"
    }
    row "gdal_grid -a linear" "$work/gdal.tif" \
      gdal_grid -q -a linear -zfield z -txe 0 1 -tye 0 1 -outsize "$grid" "$grid" -ot Float32 -of GTiff \
      "$work/${field}_$n.vrt" "$work/gdal.tif"
    row "ddtscale --no-optimize" "$work/delaunay.exr" \
      "$bin" grid "$pts" "$work/delaunay.exr" --size "${grid}x${grid}" --bounds 0,0,1,1 --no-optimize -q
    for cost in $costs; do
      row "ddtscale --cost $cost" "$work/ddt_$cost.exr" \
        "$bin" grid "$pts" "$work/ddt_$cost.exr" --size "${grid}x${grid}" --bounds 0,0,1,1 --cost "$cost" -q
    done
  done
done
