#!/usr/bin/env bash
# Paper-reproduction distance experiments of issue 8 (Krishnamurthy et al.: Tables 1, 2, 3, 5, Figs. 12
# and 16, batched points), each beside OpenCASCADE in the same run: CSV, PNG and a summary on stdout.
# Benchmarks, not tests (never in CI). Builds only nurbsgl and the OCCT peer, in a build with the peer
# enabled (BUILD_DIR, default build-bench, configured here if new; the base packages come from
# scripts/setup.sh). Exits 2 naming the apt-get line when the peer's packages or matplotlib are missing.
# Usage: scripts/experiments.sh [OUT_DIR] [experiments/distance_tables.py options, e.g. --quick, tables]
#   OUT_DIR defaults to BUILD_DIR/experiments; the summary is also written to OUT_DIR/summary.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${BUILD_DIR:-build-bench}
out=${1:-$build/experiments}
shift || true
needed=(python3-matplotlib libocct-modeling-data-dev libocct-modeling-algorithms-dev libocct-data-exchange-dev
  libtbb-dev)
missing=()
for p in "${needed[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "experiments: missing packages; install them with" >&2
  echo "  apt-get install --no-install-recommends ${missing[*]}" >&2
  exit 2
fi
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNURBSGL_PEER_BENCH=ON >/dev/null
cmake --build "$build" -j"$(nproc)" --target nurbsgl peer_occt_distance
# Debian's python3 carries python3-matplotlib; another python3 first on PATH may not.
python=/usr/bin/python3
[ -x "$python" ] || python=python3
start=$(date +%s)
mkdir -p "$out"
"$python" experiments/distance_tables.py --build "$build" --out "$out" "$@" | tee "$out/summary.txt"
echo "experiments: $(($(date +%s) - start)) s"
