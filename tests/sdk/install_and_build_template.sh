#!/usr/bin/env bash
# The SDK as a user meets it: install this build into a temporary prefix,
# write the cell template with the installed plcrun, configure and build it
# out of tree against the prefix (find_package(softplc)), run its test, and
# run the cell with the installed plcrun (it loads build/libmycell.so).
#   install_and_build_template.sh BUILD_DIR WORK_DIR [CXX [CXXFLAGS]]
# CXX and CXXFLAGS are the installed build's (a sanitizer build's libraries
# need the same instrumentation in the project that links them).
set -euo pipefail
build=$1
work=$2
compiler=()
[ -n "${3:-}" ] && compiler=(-DCMAKE_CXX_COMPILER="$3")
[ -n "${4:-}" ] && compiler+=(-DCMAKE_CXX_FLAGS="$4")
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" >"$work/install.log"
"$work/prefix/bin/plcrun" --new-cell "$work/cell"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S "$work/cell" -B "$work/cell/build" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" \
  "${launcher[@]}" "${compiler[@]}" >"$work/configure.log"
cmake --build "$work/cell/build" -j 2
ctest --test-dir "$work/cell/build" --output-on-failure
out=$("$work/prefix/bin/plcrun" "$work/cell/cell.yaml" --for 10s -q --print-vars Main.blinks)
echo "$out"
# 0.5 s to the first blink, then one each 1.02 s (on 0.5 s, off 0.5 s, and
# one scan each to restart a timer).
grep -qx "  Main.blinks = 10" <<<"$out"
