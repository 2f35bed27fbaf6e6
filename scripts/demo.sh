#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine, builds, and runs the main job: enlarge
# images/astronaut_face.png by 10 into an EXR (half floats, from an 8-bit input) and a PNG to look at.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)" --target ddtscale
build/ddtscale images/astronaut_face.png astronaut_face_x10.exr --scale 10 --verbose
build/ddtscale images/astronaut_face.png astronaut_face_x10.png --scale 10
