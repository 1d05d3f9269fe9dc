#!/usr/bin/env bash
# Paper-reproduction distance experiments (Krishnamurthy et al.: Tables 1, 2, 3, 5, Figs. 12
# and 16, batched points), each beside OpenCASCADE in the same run: CSV, PNG and a summary on stdout.
# Benchmarks, not tests (never in CI). Builds only nurbsgl and the OCCT peer (BUILD_DIR, default
# build-bench, configured here; the base packages come from scripts/setup.sh).
# Without OpenCASCADE's packages (or with NURBSGL_PEER_BENCH=OFF) the peer is not built and its columns
# stay empty; without matplotlib the plots are skipped; one line says what was left out and the
# apt-get line that adds it. Each run rewrites its section of docs/benchmarks.md and REPRODUCTION.md.
# Usage: scripts/experiments.sh [OUT_DIR] [experiments/distance_tables.py options, e.g. --quick, tables]
#   (OUT_DIR may be left out when the first argument is an option)
#   OUT_DIR defaults to BUILD_DIR/experiments; the summary is also written to OUT_DIR/summary.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib_experiments.sh
experiments_setup "experiments" nurbsgl peer_occt_distance
experiments_command+=" $*"
out=$build/experiments
if [[ $# -gt 0 && $1 != -* ]]; then
  out=$1
  shift
fi
start=$(date +%s)
mkdir -p "$out"
"$python" experiments/distance_tables.py --build "$build" --out "$out" "${peer_args[@]}" \
  --command "$experiments_command" "$@" | tee "$out/summary.txt"
echo "experiments: $(($(date +%s) - start)) s"
