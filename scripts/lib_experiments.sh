# Sourced by the experiment scripts (experiments.sh, tessellation_experiments.sh,
# raycast_experiments.sh): checks the peer's packages and matplotlib, configures the build with the
# OpenCASCADE peer (BUILD_DIR, default build-bench) and builds the given targets.
# experiments_setup NAME TARGET...: sets $build and $python; exits 2 naming the apt-get line when
# packages are missing.
experiments_setup() {
  local name=$1
  shift
  build=${BUILD_DIR:-build-bench}
  local needed=(python3-matplotlib libocct-modeling-data-dev libocct-modeling-algorithms-dev
    libocct-data-exchange-dev libtbb-dev)
  local missing=() p
  for p in "${needed[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if ((${#missing[@]})); then
    echo "$name: missing packages; install them with" >&2
    echo "  apt-get install --no-install-recommends ${missing[*]}" >&2
    exit 2
  fi
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNURBSGL_PEER_BENCH=ON >/dev/null
  cmake --build "$build" -j"${JOBS:-$(nproc)}" --target "$@"
  # Debian's python3 carries python3-matplotlib; another python3 first on PATH may not.
  python=/usr/bin/python3
  [ -x "$python" ] || python=python3
}
