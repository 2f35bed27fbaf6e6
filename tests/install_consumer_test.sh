#!/usr/bin/env bash
# The install and its package config: `cmake --install` into a temporary
# prefix, then a consumer project (tests/consumer) built against it from
# the C++ example of README.md ("Use from C++"), run on a reference image.
# Usage: install_consumer_test.sh BUILD_DIR SOURCE_DIR
set -eu
build="$1"
source="$2"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake --install "$build" --prefix "$work/prefix" >"$work/install.log" 2>&1 || { cat "$work/install.log"; exit 1; }
# The installed headers are the public folder only.
[ -f "$work/prefix/include/ddtscale/ddtscale.hpp" ] || { echo "FAIL: no ddtscale.hpp installed"; exit 1; }
if find "$work/prefix/include" -name '*.hpp' | grep -v '/include/ddtscale/' | grep -q .; then
  echo "FAIL: headers outside include/ddtscale installed"; exit 1
fi
# The README's example, the block after its marker line.
awk '/ctest install_consumer compiles this block/ {found = 1; next}
     found && /^```cpp/ {inside = 1; next}
     inside && /^```/ {exit}
     inside {print}' "$source/README.md" >"$work/upscale_file.cpp"
[ -s "$work/upscale_file.cpp" ] || { echo "FAIL: no example found in README.md"; exit 1; }
cmake -S "$source/tests/consumer" -B "$work/consumer" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" -DEXAMPLE_SOURCE="$work/upscale_file.cpp" >"$work/configure.log" 2>&1 ||
  { cat "$work/configure.log"; exit 1; }
cmake --build "$work/consumer" >"$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }
out=$("$work/consumer/upscale_file" "$source/images/regression/inputs/strokes.png" "$work/big.exr")
case "$out" in
  "128x128, "*" flips") ;;
  *) echo "FAIL: the example printed '$out'"; exit 1 ;;
esac
[ -s "$work/big.exr" ] || { echo "FAIL: no output written"; exit 1; }
# Errors are one line on stderr and exit status 1.
if "$work/consumer/upscale_file" "$work/missing.png" "$work/x.exr" 2>"$work/err.txt"; then
  echo "FAIL: a missing input succeeded"; exit 1
fi
[ "$(wc -l <"$work/err.txt")" -eq 1 ] || { echo "FAIL: error not one line:"; cat "$work/err.txt"; exit 1; }
# The installed command: the front, and ddtscale-full beside it for what the front hands on.
"$work/prefix/bin/ddtscale" "$source/images/regression/inputs/strokes.png" "$work/cmd.png" --scale 2 -q ||
  { echo "FAIL: the installed ddtscale, PNG to PNG"; exit 1; }
"$work/prefix/bin/ddtscale" "$source/images/regression/inputs/strokes.png" "$work/cmd.exr" --scale 2 -q ||
  { echo "FAIL: the installed ddtscale, PNG to EXR"; exit 1; }
"$work/prefix/bin/ddtscale" "$source/images/regression/inputs/strokes.png" "$work/cmd.tif" --scale 2 -q ||
  { echo "FAIL: the installed ddtscale, handed on to ddtscale-full"; exit 1; }
echo "install and consumer: ok ($out)"
