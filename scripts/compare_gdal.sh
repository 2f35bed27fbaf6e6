#!/usr/bin/env bash
# Scattered-data gridding, ddtscale grid against gdal_grid -a linear (GDAL's
# Delaunay piecewise-linear interpolation), on random samples of analytic
# fields (bench/grid_fields.cpp): a fault-like step, a tent ridge and a
# smooth field (Franke's function), over a square of EXTENT units (metres,
# say). Prints a markdown table: RMSE and maximum error against the true
# field at the pixel centres, the wall time of each command (best of RUNS
# runs; start-up, reading the points, gridding and writing the file
# included) and, for ddtscale, the time of its triangulate + optimize +
# render stages as --verbose reports them.
#
# Usage: scripts/compare_gdal.sh [build_dir] [work_dir]
#   build_dir  holds ddtscale (default: build)
#   work_dir   keeps the points and grids (default: a temporary directory)
# Environment: SIZES (default "1000 10000 100000"), GRID (default 512),
#   RUNS (default 3), SEED (default 1), EXTENT (default 1000),
#   COSTS (default "jnd-edge sederberg variance"; jnd-edge is grid's default),
#   FIGURE (a .png path: also draw docs/scattered-fault-ridge.png, crops of
#   the truth, gdal_grid, DDT jnd-edge and DDT variance at 1000 points, fault
#   above, ridge below).
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
extent=${EXTENT:-1000}
costs=${COSTS:-"jnd-edge sederberg variance"}

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

# The OGR virtual layer that makes a CSV of x,y,z a point layer for gdal_grid.
write_vrt() {  # layer name, csv, vrt
  cat >"$3" <<EOF
<OGRVRTDataSource>
  <OGRVRTLayer name="$1">
    <SrcDataSource>$2</SrcDataSource>
    <GeometryType>wkbPoint</GeometryType>
    <GeometryField encoding="PointFromColumns" x="x" y="y" z="z"/>
  </OGRVRTLayer>
</OGRVRTDataSource>
EOF
}

echo "gdal: $(gdal_grid --version)"
echo "ddtscale: $bin; grid ${grid}x${grid} over [0,$extent]^2; best of $runs runs; $(nproc) cores;" \
  "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "start-up alone: ddtscale --help $(best_time "$bin" --help) s, gdal_grid --version $(best_time gdal_grid --version) s"
echo
echo "| field | points | method | RMSE | max error | seconds | ddtscale stages (s) |"
echo "|---|---:|---|---:|---:|---:|---:|"
for field in fault ridge smooth; do
  for n in $sizes; do
    pts="$work/${field}_$n.csv"
    "$tool" points "$field" "$n" "$seed" "$pts" "$extent"
    write_vrt "${field}_$n" "$pts" "$work/${field}_$n.vrt"
    row() {  # method label, output file, command...
      local label="$1" out="$2"
      shift 2
      local seconds score stages="-"
      seconds=$(best_time "$@")
      if [ "$1" = "$bin" ]; then
        stages=$("$@" --verbose 2>&1 >/dev/null | grep -E '^(triangulate:|optimize: cost |render:)' |
          sed -E 's/.* ([0-9.]+) s$/\1/' | paste -sd+ | bc -l)
        stages=$(printf '%.3f' "$stages")
      fi
      score=$("$tool" rmse "$field" "$out")
      # score: rmse R max M scored S nodata N
      set -- $score
      [ "$8" -eq 0 ] || echo "compare_gdal: $label left $8 no-data pixels on $field" >&2
      echo "| $field | $((n + 4)) | $label | $2 | $4 | $seconds | $stages |"
    }
    row "gdal_grid -a linear" "$work/gdal.tif" \
      gdal_grid -q -a linear -zfield z -txe 0 "$extent" -tye 0 "$extent" -outsize "$grid" "$grid" -ot Float32 \
      -of GTiff "$work/${field}_$n.vrt" "$work/gdal.tif"
    row "ddtscale --no-optimize" "$work/delaunay.exr" \
      "$bin" grid "$pts" "$work/delaunay.exr" --size "${grid}x${grid}" --bounds "0,0,$extent,$extent" --no-optimize -q
    for cost in $costs; do
      row "ddtscale --cost $cost" "$work/ddt_$cost.exr" \
        "$bin" grid "$pts" "$work/ddt_$cost.exr" --size "${grid}x${grid}" --bounds "0,0,$extent,$extent" \
        --cost "$cost" -q
    done
  done
done

if [ -n "${FIGURE:-}" ]; then
  panels=()
  for field in fault ridge; do
    # The fault spans 0..1.5, the ridge 0..1; crops of 192 x 192 pixels of
    # the 512 x 512 grid across the feature, enlarged 2x (box filter).
    if [ "$field" = fault ]; then gain=0.6667 crop=192x192+160+110; else gain=1 crop=192x192+160+160; fi
    pts="$work/${field}_fig.csv"
    "$tool" points "$field" 1000 "$seed" "$pts" "$extent"
    write_vrt "${field}_fig" "$pts" "$work/${field}_fig.vrt"
    "$tool" truth "$field" "$grid" "$grid" "$work/${field}_truth.exr"
    gdal_grid -q -a linear -zfield z -txe 0 "$extent" -tye 0 "$extent" -outsize "$grid" "$grid" -ot Float32 \
      "$work/${field}_fig.vrt" "$work/${field}_gdal.tif"
    for cost in jnd-edge variance; do
      "$bin" grid "$pts" "$work/${field}_$cost.exr" --size "${grid}x${grid}" --bounds "0,0,$extent,$extent" \
        --cost "$cost" -q
    done
    for m in truth.exr gdal.tif jnd-edge.exr variance.exr; do
      oiiotool "$work/${field}_$m" --ch 0 --mulc "$gain" --cut "$crop" --resize:filter=box 384x384 \
        --colormap viridis -d uint8 -o "$work/${field}_${m%.*}.png"
      panels+=("$work/${field}_${m%.*}.png")
    done
  done
  oiiotool "${panels[@]}" --mosaic:pad=6 4x2 -d uint8 -o "$FIGURE"
  echo "figure: $FIGURE"
fi
