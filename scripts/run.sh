#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: set up, build, then run the GPU self-check (renderer,
# one reduction, one argmin, one stream compaction with timings against the CPU twins).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build
build/cli/nurbsgl gpu-info
build/cli/nurbsgl --profile selftest --size 1024
