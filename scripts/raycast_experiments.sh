#!/usr/bin/env bash
# Ray casting and thickness experiments (Lemasson et al.: rays per second of the BVH and
# DACRT methods, tests per ray (Fig. 7), memory (Fig. 11), the accuracy histogram (Fig. 13)) with
# OpenCASCADE's IntCurvesFace_ShapeIntersector on the same rays in the same run: CSV, PNG and a
# summary on stdout. Benchmarks, not tests (never in CI). Needs ../shared/models.
# Usage: scripts/raycast_experiments.sh [OUT_DIR] [experiments/raycast_tables.py options, e.g.
#   --rays 1000000 --peer-rays 2000 --models vase Ventilator]
#   OUT_DIR defaults to BUILD_DIR/experiments/raycast; the summary is also OUT_DIR/summary.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib_experiments.sh
experiments_setup "raycast experiments" nurbsgl peer_occt_distance
out=${1:-$build/experiments/raycast}
shift || true
start=$(date +%s)
mkdir -p "$out"
"$python" experiments/raycast_tables.py --build "$build" --out "$out" "$@"
echo "raycast experiments: $(($(date +%s) - start)) s"
