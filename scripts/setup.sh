#!/usr/bin/env bash
# Installs the Debian 12 packages ddtscale needs, where they are missing.
# Run as root (CI and a fresh machine are); prints what it installs.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev
  libopenimageio-dev openimageio-tools libopenexr-dev
  libeigen3-dev doctest-dev libtbb-dev libcli11-dev
  libteem-dev
  libpng-dev zlib1g-dev libisal-dev
  libcsv-dev
  liblcms2-dev
  libopencv-dev libvips-dev libvips-tools
  ffmpeg
  pybind11-dev python3-dev python3-numpy python3-pytest python3-dask python3-distributed
  clang libclang-rt-14-dev
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all packages present"
  exit 0
fi
echo "setup: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
