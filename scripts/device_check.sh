#!/usr/bin/env bash
# One prepared run that answers, on a machine with a GPU, what a software renderer cannot: the
# renderer each GL backend starts, the self-check, the GL test programs under EGL and the EGL device
# platform, and the queries with the GPU engines beside the CPU ones on the shared models (points,
# rays, thickness, clearance, clash), each answer's certificate included. Builds Release in
# build-device (scripts/setup.sh installs what is missing), writes one report and prints it.
# Under 8 minutes on a 16-core machine; runs (green) under llvmpipe too.
# Usage: scripts/device_check.sh [REPORT]   (default build-device/device_report.txt)
# Exit 0 when every step passed, 1 otherwise (the report names the step).
set -uo pipefail
cd "$(dirname "$0")/.."
build=build-device
report=${1:-$build/device_report.txt}
models=${NURBSGL_SHARED_DIR:-../shared}/models
start=$(date +%s)
mkdir -p "$(dirname "$report")" "$build"
log=$build/device_check.log
: >"$log"
failed=0
rows=()

# step NAME SECONDS_LIMIT command...: runs it (output to the log), records exit and time.
step() {
  local name=$1 limit=$2
  shift 2
  local t0 rc
  t0=$(date +%s.%N)
  echo "=== $name: $*" >>"$log"
  timeout "$limit" "$@" >>"$log" 2>&1
  rc=$?
  local secs
  secs=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  rows+=("$(printf '%-44s exit %3d  %7s s' "$name" "$rc" "$secs")")
  [[ $rc -eq 0 ]] || failed=1
  echo "device_check: $name: exit $rc in $secs s" >&2
  return 0
}

# The figures of one query: `nurbsgl ... --json` into FILE, then the fields a reader needs. The BVH
# method's rays (the GPU pass and its CPU twin) exit 1 by design, their nearest hits not certified
# (a ray grazing a face within the bicubic tolerance may miss it): that exit, with that reason in
# the JSON, passes; the report prints the reason.
query() {
  local name=$1 file=$build/$1.json
  shift
  step "$name" 120 bash -c '"$@" --json > "'"$file"'"; rc=$?
    [[ $rc -eq 1 ]] && grep -q "\"uncertified\": \"the nearest hits are not certified" "'"$file"'" && rc=0
    exit $rc' _ "$@"
}

step "setup and Release build" 420 scripts/setup.sh "$build" -DCMAKE_BUILD_TYPE=Release
ng=$build/cli/nurbsgl
{
  echo "nurbsgl device check, $(date -u +%Y-%m-%dT%H:%MZ), $(uname -srm), $(nproc) cores"
  command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader
  for gl in egl egl-device osmesa; do
    echo "--- gpu-info --gl $gl"
    "$ng" gpu-info --gl "$gl" 2>&1 | head -12
  done
} >"$build/gpu_info.txt" 2>&1
step "gpu-info (every backend)" 60 "$ng" gpu-info --gl egl-device
step "selftest (egl-device)" 120 "$ng" selftest --gl egl-device
step "GL test programs (EGL, EGL device)" 300 bash -c "cd $build && ctest -j\$(nproc) --output-on-failure -R 'gpgpu_tests\\[(egl|egl-device)\\]|queries_tests\\[(egl|egl-device)(,shared)?\\]'"

# Queries on the shared models, GPU engines beside the CPU ones (the same points and rays). The
# Ventilator at 1e-3: its file edges lie up to 2e-4 of its size off their faces, and a bound widened
# by that gap meets only a tolerance of twice it.
if [[ -d $models ]]; then
  vent=$models/step/pythonocc_Ventilator.stp motor=$models/generated/occt_Motor-c.step
  comp8=$models/step/gmsh_component8.step asm=$models/assembly/gmsh_as1-tu-203.stp
  awk 'BEGIN { srand(7); for (i = 0; i < 20000; ++i) printf "%.9f %.9f %.9f\n", -50 + 100*rand(), -50 + 100*rand(), -5 + 30*rand() }' >"$build/points_vent.txt"
  awk 'BEGIN { srand(8); for (i = 0; i < 20000; ++i) printf "%.9f %.9f %.9f\n", -160 + 320*rand(), -160 + 320*rand(), -60 + 400*rand() }' >"$build/points_motor.txt"
  awk 'BEGIN { srand(9); for (i = 0; i < 100000; ++i) { x = -60 + 120*rand(); y = -60 + 120*rand();
       printf "%.6f %.6f 40 %.6f %.6f -1\n", x, y, 0.2*(rand() - 0.5), 0.2*(rand() - 0.5) } }' >"$build/rays_vent.txt"
  for engine in gpu cpu; do
    query "distance_vent_$engine" "$ng" distance "$vent" --points "$build/points_vent.txt" --tol 1e-3 --engine "$engine" --no-cache
    query "distance_motor_$engine" "$ng" distance "$motor" --points "$build/points_motor.txt" --tol 1e-4 --engine "$engine" --no-cache
    query "raycast_vent_$engine" "$ng" raycast "$vent" --rays "$build/rays_vent.txt" --engine "$engine"
    query "thickness_comp8_$engine" "$ng" thickness "$comp8" --engine "$engine"
    query "clearance_comp8_$engine" "$ng" clearance "$comp8" "$comp8" --move-b 70,5,3 --tol 1e-4 --engine "$engine"
  done
  # The certified meshes beside them (points; rays, the default), and the GPU pass's CPU twin.
  query "distance_vent_mesh" "$ng" distance "$vent" --points "$build/points_vent.txt" --tol 1e-3 --path mesh
  query "distance_motor_mesh" "$ng" distance "$motor" --points "$build/points_motor.txt" --tol 1e-4 --path mesh
  query "raycast_vent_bvh_cpu" "$ng" raycast "$vent" --rays "$build/rays_vent.txt" --engine cpu --method bvh
  query "thickness_comp8_ball_gpu" "$ng" thickness "$comp8" --ball --ball-engine gpu
  query "clearance_comp8_paper" "$ng" clearance "$comp8" "$comp8" --move-b 70,5,3 --tol 1e-4 --paper
  query "clash_assembly_gpu" "$ng" clash "$asm" --tol 1e-4 --engine gpu
else
  rows+=("shared models absent ($models): queries skipped")
fi

# The report: the steps, the renderers, and per query its time and certificate.
{
  echo "# nurbsgl device check"
  cat "$build/gpu_info.txt"
  echo
  echo "## steps"
  printf '%s\n' "${rows[@]}"
  echo
  echo "## queries (seconds of the queries themselves; engine used; answers not meeting the tolerance)"
  for f in "$build"/distance_*.json "$build"/raycast_*.json "$build"/thickness_*.json "$build"/clearance_*.json "$build"/clash_*.json; do
    [[ -s $f ]] || continue
    /usr/bin/python3 - "$f" <<'EOF'
import json, sys, os
f = sys.argv[1]
try:
    j = json.load(open(f))
except Exception as e:
    print(f"{os.path.basename(f):32} unreadable: {e}")
    sys.exit(0)
name = os.path.basename(f)[:-5]
engine = j.get("engine")
if isinstance(engine, dict):
    engine = engine.get("used")
if j.get("path") == "mesh" or (j.get("method") in ("mesh", "bvh", "dacrt") and engine == "cpu"):
    engine = j.get("path") if j.get("path") == "mesh" else f"cpu {j.get('method')}"
secs = j.get("seconds")
fig = ""
if "over_tolerance" in j:
    fig = f"{j.get('points')} points, not found {j.get('not_found')}, over tolerance {j.get('over_tolerance')}, uncertified {j.get('uncertified')}"
elif "rays" in j:
    fig = f"{j.get('rays')} rays, cast {j.get('seconds_cast', '')} s, hits {j.get('hits')}"
elif "pairs" in j:
    fig = f"{j.get('pairs')} pairs, computed {j.get('pairs_computed')}, uncertified {j.get('pairs_uncertified')}"
elif "distance" in j:
    fig = f"distance {j.get('distance')}, bound {j.get('bound')}, meets {j.get('meets_tolerance')}"
print(f"{name:32} engine {engine!s:5} seconds {secs!s:22} {fig}")
if j.get("uncertified"):
    print(f"{'':32} not certified: {j['uncertified']}")
EOF
  done
  echo
  echo "total: $(($(date +%s) - start)) s; log: $log"
} >"$report"
cat "$report"
exit $failed
