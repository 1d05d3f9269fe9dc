#!/usr/bin/env bash
# Runs the libFuzzer target fuzz_TARGET (iges, step, bpt, mesh, motion, query_text or points; fuzz/) for SECONDS
# under ASan + UBSan. Builds it with clang in build-fuzz/ (NURBSGL_FUZZ=ON, NURBSGL_CPU_ONLY=ON) when needed, seeds
# its corpus from the project's own files (the generated models of build/models, tests/data, the
# shared models, fuzz/regressions/TARGET), and writes what it finds (crash-*, timeout-*, slow-unit-*)
# to fuzz/findings/TARGET/. Once fixed, a finding goes into fuzz/regressions/TARGET/, which every build
# replays (ctest -R fuzz.replay).
# Usage: scripts/fuzz.sh TARGET SECONDS [libFuzzer options...]
set -euo pipefail
cd "$(dirname "$0")/.."
target=${1:?usage: scripts/fuzz.sh TARGET SECONDS}
seconds=${2:?usage: scripts/fuzz.sh TARGET SECONDS}
shift 2
case $target in
  iges | step | bpt | mesh | motion | query_text | points) ;;
  *) echo "fuzz.sh: unknown target '$target' (iges, step, bpt, mesh, motion, query_text, points)" >&2; exit 2 ;;
esac
build=${NURBSGL_FUZZ_BUILD:-build-fuzz}
if [ ! -f "$build/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNURBSGL_FUZZ=ON -DNURBSGL_CPU_ONLY=ON >/dev/null
else
  cmake "$build" >/dev/null  # a target added since the last run
fi
cmake --build "$build" -j2 --target "fuzz_$target" >/dev/null

corpus=$build/fuzz/corpus/$target findings=fuzz/findings/$target
mkdir -p "$corpus" "$findings"
# small EXTENSIONS DIR...: the files under 300 KB with one of EXTENSIONS (a regex alternation).
small() {
  local ext=$1
  shift
  find "$@" -maxdepth 3 -type f -size -300k -regextype posix-extended -iregex ".*\.($ext)" 2>/dev/null || true
}
shared=${NURBSGL_SHARED_DIR:-../shared}/models
case $target in
  iges) for f in $(small 'igs|iges' build/models tests/data "$shared/iges" "$shared/generated"); do
          cp "$f" "$corpus/"; done ;;
  step) for f in $(small 'stp|step' tests/data "$shared/step" "$shared/generated" "$shared/assembly"); do
          cp "$f" "$corpus/"; done ;;
  bpt) for f in $(small bpt "$shared/teapot"); do cp "$f" "$corpus/"; done ;;
  mesh) # the first byte picks the format: 0 STL, 1 OBJ, 2 PLY
    k=0
    for f in $(small 'stl|obj|ply' tests/data build/tests/cli); do
      case ${f##*.} in stl) b='\x00' ;; obj) b='\x01' ;; *) b='\x02' ;; esac
      { printf "$b"; cat "$f"; } >"$corpus/seed_$k"; k=$((k + 1))
    done ;;
  query_text) for f in $(small txt tests/data build/tests/cli); do cp "$f" "$corpus/"; done ;;
  points) for f in $(small 'txt|csv|ply|npy|pts|xyz' tests/data build/tests/cli); do cp "$f" "$corpus/"; done ;;
  motion) printf '5 0 0 0 0 1 0\n6,0,0,0,0,1,30\n# comment\n0 0 0 1 1 1 -720\n' >"$corpus/seed_motion" ;;
esac
"$build/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
  -artifact_prefix="$findings/" "$@" "$corpus" "fuzz/regressions/$target"
