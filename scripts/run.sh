#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: set up and build, then on the bundled (generated)
# trimmed 100x105 surface of the paper: describe it with its Filip bounds, evaluate it on the GPU on
# the knot-aligned grid whose Euclidean bound K_e is 1e-4 of the model size on every cell, with its
# trim mask; the clearance of the paper's surface pair and the tessellation of the trimmed surface
# within 1e-3 of its size, checked; then the GPU self-check with timings.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh build
model=build/models/paper-100x105-trimmed.igs
build/cli/nurbsgl gpu-info
build/cli/nurbsgl info "$model" --bounds
build/cli/nurbsgl --profile evaluate "$model" --tolerance 1e-4
build/cli/nurbsgl clearance build/models/paper-199x33.igs build/models/paper-100x105.igs --tol 1e-5
build/cli/nurbsgl tessellate "$model" --eps 1e-3 --relative --check -o build/paper-100x105-trimmed.ply
build/cli/nurbsgl selftest --size 1024
