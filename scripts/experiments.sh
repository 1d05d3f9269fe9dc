#!/usr/bin/env bash
# Paper-reproduction distance experiments (Krishnamurthy et al.: Tables 1, 2, 3, 5, Figs. 12
# and 16, batched points), each beside OpenCASCADE in the same run: CSV, PNG and a summary on stdout.
# Benchmarks, not tests (never in CI). Builds only nurbsgl and the OCCT peer, in a build with the peer
# enabled (BUILD_DIR, default build-bench, configured here if new; the base packages come from
# scripts/setup.sh). Exits 2 naming the apt-get line when the peer's packages or matplotlib are missing.
# Usage: scripts/experiments.sh [OUT_DIR] [experiments/distance_tables.py options, e.g. --quick, tables]
#   OUT_DIR defaults to BUILD_DIR/experiments; the summary is also written to OUT_DIR/summary.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib_experiments.sh
experiments_setup "experiments" nurbsgl peer_occt_distance
out=${1:-$build/experiments}
shift || true
start=$(date +%s)
mkdir -p "$out"
"$python" experiments/distance_tables.py --build "$build" --out "$out" "$@" | tee "$out/summary.txt"
echo "experiments: $(($(date +%s) - start)) s"
