#!/usr/bin/env bash
# Sets up a fresh Debian 12 machine (packages, as root), configures, builds
# and runs the whole test suite with ctest. Extra arguments go to ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
ctest --test-dir build --output-on-failure -j"$(nproc)" "$@"
