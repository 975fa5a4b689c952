# Shared by the scripts/ jobs (sourced, not run).

# plc_configure DIR [cmake options...]: configures DIR with Ninja; uses
# ccache when it is installed (developers' machines), never needs it (CI).
# Without ccache the build uses precompiled headers instead
# (cmake/precompiled_headers.cmake). PLC_CCACHE=0 builds as CI does on a
# machine that has ccache.
plc_configure() {
  local dir="$1"
  shift
  local launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=)
  if [ "${PLC_CCACHE:-1}" != 0 ] && command -v ccache >/dev/null; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  fi
  cmake -S . -B "$dir" -G Ninja "${launcher[@]}" "$@" >/dev/null
}

# plc_jobs: parallel build and test jobs (PLC_JOBS, default: all cores).
plc_jobs() { echo "${PLC_JOBS:-$(nproc)}"; }

# plc_configure_asan: the AddressSanitizer + UndefinedBehaviorSanitizer build
# in build-asan/, shared by scripts/test-asan (the whole suite) and
# scripts/fuzz (the fuzz targets): clang, everything also instrumented for
# libFuzzer (fuzzer-no-link), tests/fuzz/ targets as libFuzzer executables.
# -O1 without NDEBUG (asserts stay on); any sanitizer report is fatal.
# The gtest executables' own files at -O0 without libFuzzer's coverage
# (PLC_GTEST_COMPILE_OPTIONS in CMakeLists.txt: CI's build time).
plc_configure_asan() {
  plc_configure build-asan -DCMAKE_CXX_COMPILER="${PLC_ASAN_CXX:-clang++}" -DPLC_EXCLUDE="" -DPLC_BENCHES=OFF \
    -DPLC_GTEST_COMPILE_OPTIONS="-O0;-fno-sanitize=fuzzer-no-link" \
    -DPLC_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
    -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
}
