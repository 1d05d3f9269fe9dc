#!/usr/bin/env bash
# Paper-reproduction tessellation experiments (Balazs, Guthe and Klein 2004: Tables 2, 3, 4)
# with OpenCASCADE's BRepMesh at equal measured deviation, in the same run: CSV, PNG and a summary on
# stdout. Benchmarks, not tests (never in CI). Builds only nurbsgl, the generated models and the OCCT
# peer, in a build with the peer enabled (BUILD_DIR, default build-bench, configured here if new; the
# base packages come from scripts/setup.sh). Exits 2 naming the apt-get line when the peer's packages
# or matplotlib are missing.
# Usage: scripts/tessellation_experiments.sh [OUT_DIR] [experiments/tessellation_tables.py options,
#   e.g. --check-samples 24, --models bearing sphere]
#   OUT_DIR defaults to BUILD_DIR/experiments/tessellation; the summary is also OUT_DIR/summary.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib_experiments.sh
experiments_setup "tessellation experiments" nurbsgl generated_models peer_occt_mesh
out=${1:-$build/experiments/tessellation}
shift || true
start=$(date +%s)
mkdir -p "$out"
"$python" experiments/tessellation_tables.py --build "$build" --out "$out" "$@"
echo "tessellation experiments: $(($(date +%s) - start)) s"
