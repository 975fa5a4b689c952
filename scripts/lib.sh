# Shared by the scripts/ jobs (sourced, not run).

# plc_configure DIR [cmake options...]: configures DIR with Ninja; uses
# ccache when it is installed (developers' machines), never needs it (CI).
plc_configure() {
  local dir="$1"
  shift
  local launcher=()
  if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
  cmake -S . -B "$dir" -G Ninja "${launcher[@]}" "$@" >/dev/null
}

# plc_jobs: parallel build and test jobs (PLC_JOBS, default: all cores).
plc_jobs() { echo "${PLC_JOBS:-$(nproc)}"; }
