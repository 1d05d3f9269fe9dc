# Sourced by the experiment scripts (experiments.sh, tessellation_experiments.sh,
# raycast_experiments.sh): finds what is optional (the OpenCASCADE peer's packages, matplotlib),
# configures the build (BUILD_DIR, default build-bench) with the peer when its packages are there and
# builds the given targets (the peer's, named peer_*, only then).
# experiments_setup NAME TARGET...: sets $build, $python, $peer_args (the Python options that leave the
# peer out, or none) and $experiments_command (the command line, for docs/benchmarks.md); prints one
# line naming what is left out and the apt-get line that adds it.
# NURBSGL_PEER_BENCH=OFF leaves the peer out even when its packages are installed; PYTHON picks the
# interpreter (default /usr/bin/python3: Debian's carries python3-matplotlib, another may not).
experiments_setup() {
  local name=$1
  shift
  build=${BUILD_DIR:-build-bench}
  python=${PYTHON:-/usr/bin/python3}
  [ -x "$python" ] || command -v "$python" >/dev/null || python=python3
  local occt=(libocct-modeling-data-dev libocct-modeling-algorithms-dev libocct-data-exchange-dev libtbb-dev)
  local missing=() left=() p
  for p in "${occt[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  local peer=${NURBSGL_PEER_BENCH:-ON}
  ((${#missing[@]})) && peer=OFF
  [ "$peer" = ON ] || left+=("the OpenCASCADE peer columns")
  if ! "$python" -c "import matplotlib" 2>/dev/null; then
    left+=("the plots")
    missing+=(python3-matplotlib)
  fi
  if ((${#left[@]})); then
    local what add=()
    what=$(IFS=,; echo "${left[*]}" | sed 's/,/ and /g')
    ((${#missing[@]})) && add+=("apt-get install --no-install-recommends ${missing[*]}")
    [ "${NURBSGL_PEER_BENCH:-ON}" = ON ] || add+=("NURBSGL_PEER_BENCH=ON")
    echo "$name: left out $what; add them with: $(IFS=,; echo "${add[*]}" | sed 's/,/ and /g')"
  fi
  experiments_command="scripts/$(basename "$0")"
  local v
  for v in BUILD_DIR NURBSGL_PEER_BENCH PYTHON; do
    [ -z "${!v:-}" ] || experiments_command="$v=${!v} $experiments_command"
  done
  local targets=() t
  for t in "$@"; do
    [ "$peer" = ON ] || [[ $t != peer_* ]] && targets+=("$t")
  done
  peer_args=()
  [ "$peer" = ON ] || peer_args=(--peer "")
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNURBSGL_PEER_BENCH="$peer" >/dev/null
  cmake --build "$build" -j"${JOBS:-$(nproc)}" --target "${targets[@]}"
}
