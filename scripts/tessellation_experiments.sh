#!/usr/bin/env bash
# Paper-reproduction tessellation experiments (Balazs, Guthe and Klein 2004: Tables 2, 3, 4)
# with OpenCASCADE's BRepMesh at equal measured deviation, in the same run: CSV, PNG and a summary on
# stdout. Benchmarks, not tests (never in CI). Builds only nurbsgl, the generated models and the OCCT
# peer (BUILD_DIR, default build-bench, configured here; the base packages come from scripts/setup.sh).
# Without OpenCASCADE's packages (or with NURBSGL_PEER_BENCH=OFF) the peer is not built and its columns
# stay empty; without matplotlib the plots are skipped; one line says what was left out and the
# apt-get line that adds it. Each run rewrites its section of docs/benchmarks.md and REPRODUCTION.md.
# Usage: scripts/tessellation_experiments.sh [OUT_DIR] [experiments/tessellation_tables.py options,
#   e.g. --check-samples 24, --models bearing sphere]
#   OUT_DIR defaults to BUILD_DIR/experiments/tessellation; the summary is also OUT_DIR/summary.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib_experiments.sh
experiments_setup "tessellation experiments" nurbsgl generated_models peer_occt_mesh
experiments_command+=" $*"
out=$build/experiments/tessellation
if [[ $# -gt 0 && $1 != -* ]]; then
  out=$1
  shift
fi
start=$(date +%s)
mkdir -p "$out"
"$python" experiments/tessellation_tables.py --build "$build" --out "$out" "${peer_args[@]}" \
  --command "$experiments_command" "$@"
echo "tessellation experiments: $(($(date +%s) - start)) s"
