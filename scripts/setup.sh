#!/usr/bin/env bash
# Installs the Debian 12 packages nurbsgl needs (only those missing), then configures and builds.
# Idempotent: a second run installs nothing and rebuilds only what changed.
# Usage: scripts/setup.sh [BUILD_DIR] [extra cmake args...]
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir=${1:-build}
shift || true

packages=(
  build-essential cmake pkg-config           # toolchain
  libegl-dev libegl1-mesa-dev libgl1-mesa-dri libgl-dev libgles-dev  # EGL + Mesa (llvmpipe)
  libosmesa6-dev                             # OSMesa backend
  libepoxy-dev                               # EGL extension entry points
  libglfw3-dev xvfb xauth                    # windowed backend, viewer; xvfb for headless CI
  libglm-dev                                 # vector math
  libopenexr-dev                             # EXR dumps of float textures
  doctest-dev                                # tests
  libcli11-dev nlohmann-json3-dev libfmt-dev # command line, JSON output, formatting
  libeigen3-dev                              # SVD of the trim-curve lifting (tessellation §4)
  libimgui-dev libstb-dev                    # viewer panels (GLFW + OpenGL 3 backends); PNG screenshots
  python3-dev pybind11-dev python3-numpy     # the Python module nurbsgl (python/)
  libembree-dev                              # BVH of the certified meshes (queries/distance/mesh_distance.h)
  python3-pytest python3-distributed         # its tests; scale-out on Dask (nurbsgl.dask)
  python3-matplotlib                         # the deviation histogram (PNG)
  libjs-three                                # the inspection report's 3D view (three.js, inlined)
  chromium                                   # its test in a real browser (headless)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

if [ ! -f "$build_dir/CMakeCache.txt" ]; then
  # Debian's python3, whose packages apt installed above (another python3 first on PATH lacks them).
  cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPython3_EXECUTABLE=/usr/bin/python3 "$@" >/dev/null
fi
cmake --build "$build_dir" -j"$(nproc)"
