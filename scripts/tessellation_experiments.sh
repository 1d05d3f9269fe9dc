#!/usr/bin/env bash
# Paper-reproduction tessellation experiments of issue 9 (Balazs, Guthe and Klein 2004: Tables 2, 3, 4)
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
build=${BUILD_DIR:-build-bench}
out=${1:-$build/experiments/tessellation}
shift || true
needed=(python3-matplotlib libocct-modeling-data-dev libocct-modeling-algorithms-dev libocct-data-exchange-dev
  libtbb-dev)
missing=()
for p in "${needed[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "tessellation experiments: missing packages; install them with" >&2
  echo "  apt-get install --no-install-recommends ${missing[*]}" >&2
  exit 2
fi
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNURBSGL_PEER_BENCH=ON >/dev/null
cmake --build "$build" -j"${JOBS:-$(nproc)}" --target nurbsgl generated_models peer_occt_mesh
# Debian's python3 carries python3-matplotlib; another python3 first on PATH may not.
python=/usr/bin/python3
[ -x "$python" ] || python=python3
start=$(date +%s)
mkdir -p "$out"
"$python" experiments/tessellation_tables.py --build "$build" --out "$out" "$@"
echo "tessellation experiments: $(($(date +%s) - start)) s"
