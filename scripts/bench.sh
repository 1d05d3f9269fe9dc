#!/usr/bin/env bash
# Benchmarks with figures (not tests): the gpgpu layer per backend, surface evaluation, and the
# peer comparison with OpenCASCADE (installed here from Debian if missing; not a dependency of
# nurbsgl itself).
set -euo pipefail
cd "$(dirname "$0")/.."
peer=(libocct-modeling-data-dev libocct-modeling-algorithms-dev libocct-data-exchange-dev libtbb-dev
      libcgal-dev libembree-dev libfcl-dev)  # the mesh pipeline peer (experiments/peer_mesh_pipeline.cpp)
missing=()
for p in "${peer[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
scripts/setup.sh build-bench -DNURBSGL_PEER_BENCH=ON
for backend in egl osmesa; do build-bench/experiments/bench_gpgpu --gl "$backend"; echo; done
build-bench/experiments/bench_peer_occt --gl egl
echo
# Trim classification vs OpenCASCADE's BRepClass_FaceClassifier on every shared IGES model.
build-bench/experiments/peer_occt_classify --csv build-bench/peer_occt_classify.csv
# Points, rays, thickness and clearance against the mesh pipeline (BRepMesh, CGAL, Embree, FCL), OpenCASCADE beside.
if [[ -x build-bench/experiments/peer_mesh_pipeline ]]; then
  /usr/bin/python3 experiments/mesh_pipeline.py --cli build-bench/cli/nurbsgl \
    --peer build-bench/experiments/peer_mesh_pipeline --occt build-bench/experiments/peer_occt_distance \
    --floor build-bench/experiments/bench_ray_floor --out build-bench/experiments/mesh_pipeline
fi
