#!/usr/bin/env bash
# Ray casting and thickness experiments (Lemasson et al.: rays per second of the BVH and
# DACRT methods, tests per ray (Fig. 7), memory (Fig. 11), the accuracy histogram (Fig. 13)) with
# OpenCASCADE's IntCurvesFace_ShapeIntersector on the same rays in the same run: CSV, PNG and a
# summary on stdout. Benchmarks, not tests (never in CI). Needs ../shared/models.
# Without OpenCASCADE's packages (or with NURBSGL_PEER_BENCH=OFF) the peer is not built and its columns
# stay empty; without matplotlib the plots are skipped; one line says what was left out and the
# apt-get line that adds it. Each run rewrites its section of docs/benchmarks.md.
# Usage: scripts/raycast_experiments.sh [OUT_DIR] [experiments/raycast_tables.py options, e.g.
#   --rays 1000000 --peer-rays 2000 --models vase Ventilator]
#   OUT_DIR defaults to BUILD_DIR/experiments/raycast; the summary is also OUT_DIR/summary.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib_experiments.sh
experiments_setup "raycast experiments" nurbsgl peer_occt_distance
experiments_command+=" $*"
out=$build/experiments/raycast
if [[ $# -gt 0 && $1 != -* ]]; then
  out=$1
  shift
fi
start=$(date +%s)
mkdir -p "$out"
"$python" experiments/raycast_tables.py --build "$build" --out "$out" "${peer_args[@]}" \
  --command "$experiments_command" "$@"
echo "raycast experiments: $(($(date +%s) - start)) s"
