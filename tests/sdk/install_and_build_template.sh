#!/usr/bin/env bash
# The SDK as a user meets it: install this build into a temporary prefix,
# then run the README's steps ("In your own project (the SDK)") exactly as
# they are written there, read from the README itself: the installed
# plcrun on PATH writes the cell template, `cd mycell`, configure against
# the prefix (find_package(softplc)), build, run the cell's test, and run
# the cell from inside its folder (`plcrun cell.yaml`, which loads
# build/libmycell.so relative to cell.yaml; issue 21).
#   install_and_build_template.sh BUILD_DIR WORK_DIR [CXX [CXXFLAGS]]
# CXX and CXXFLAGS are the installed build's (a sanitizer build's libraries
# need the same instrumentation in the project that links them); they reach
# the project through CMake's own environment variables, so that the
# command lines stay the README's.
set -euo pipefail
build=$1
work=$2
readme="$(cd "$(dirname "$0")/../.." && pwd)/README.md"
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" >"$work/install.log"

# The shell block after the heading, with the README's prefix replaced.
steps=$(awk '/^### In your own project \(the SDK\)/ { in_section = 1 }
             in_section && /^```sh$/ { in_block = 1; next }
             in_block && /^```$/ { exit }
             in_block { print }' "$readme")
if [ -z "$steps" ] || ! grep -q "plcrun cell.yaml" <<<"$steps"; then
  echo "README.md: no SDK steps with 'plcrun cell.yaml' under 'In your own project (the SDK)'" >&2
  exit 1
fi
steps=${steps//\/opt\/softplc/$work/prefix}
printf 'The README steps, run in %s:\n%s\n' "$work" "$steps"

export PATH="$work/prefix/bin:$PATH"
if [ -n "${3:-}" ]; then export CXX="$3"; fi
if [ -n "${4:-}" ]; then export CXXFLAGS="$4"; fi
if command -v ccache >/dev/null; then export CMAKE_CXX_COMPILER_LAUNCHER=ccache; fi
export CMAKE_BUILD_PARALLEL_LEVEL=2
cd "$work"
status=0
out=$(bash -euo pipefail -c "$steps" 2>&1) || status=$?
echo "$out"
if [ "$status" != 0 ]; then
  echo "the README's SDK steps failed with exit code $status" >&2
  exit 1
fi
# 0.5 s to the first blink, then one each 1.02 s (on 0.5 s, off 0.5 s, and
# one scan each to restart a timer).
grep -qx "  Main.blinks = 10" <<<"$out"
