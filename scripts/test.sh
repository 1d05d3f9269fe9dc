#!/usr/bin/env bash
# Every test on a fresh Debian 12 machine: set up, build, run ctest (GL tests once per backend:
# EGL, OSMesa, GLFW under xvfb), then the CPU tests again under ASan + UBSan.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build
(cd build && ctest --output-on-failure -j2)
scripts/setup.sh build-asan -DNURBSGL_SANITIZE=ON -DNURBSGL_CPU_ONLY=ON
(cd build-asan && ctest --output-on-failure -j2 -L cpu)
