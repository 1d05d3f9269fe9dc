#!/usr/bin/env bash
# Every numeric option of every command, and every coordinate of the inputs (--point, --move-b,
# --rotate-b; points, rays, motion and mesh files), with hostile values (nan, inf, -inf, 0, -1, 1e-300, 1e300, 2^63): each run exits 2 naming the option,
# or exits 0 (1 for a measured deviation above --eps) with only finite numbers in its output, within
# SWEEP_TIMEOUT seconds (30). Usage: option_sweep.sh NURBSGL MODELS_DIR WORK_DIR
set -u
nurbsgl=$1 models=$2 work=$3
timeout_s=${SWEEP_TIMEOUT:-30}
mkdir -p "$work"
sphere=$models/sphere.igs paper=$models/paper-100x105-trimmed.igs
rays=$work/rays.txt mesh=$work/mesh.obj
printf '0 0 30 0 0 -1\n30 0 0 -1 0 0\n' >"$rays"
printf 'v 10 0 0\nv 0 10 0\nv 0 0 10\nf 1 2 3\n' >"$mesh"
values=(nan inf -inf 0 -1 1e-300 1e300 9223372036854775808)
failures=0 runs=0

# check OPTION CMD...: one run of CMD (the value already in it), judged as the header says.
check() {
  local option=$1
  shift
  local out rc
  out=$(timeout "$timeout_s" "$nurbsgl" "$@" 2>&1)
  rc=$?
  runs=$((runs + 1))
  local why=""
  case $rc in
    2) grep -qF -- "$option" <<<"$out" || why="exit 2 without naming $option" ;;
    0 | 1)
      # Exit 1 only for the check an option sets: a measured deviation above --eps.
      if [ "$rc" = 1 ] && ! grep -qE "FAILED: measured deviation [0-9.e+-]+ exceeds eps" <<<"$out"; then
        why="exit 1, not a deviation above --eps"
      fi
      if grep -qiwE -- '-?(nan|inf|infinity)' <<<"$out"; then why="${why:+$why; }a non-finite number printed"; fi ;;
    124) why="no answer within $timeout_s s" ;;
    *) why="exit $rc" ;;
  esac
  if [ -n "$why" ]; then
    failures=$((failures + 1))
    printf 'FAIL: nurbsgl %s\n  %s\n%s\n' "$*" "$why" "$(head -c 600 <<<"$out" | sed 's/^/    | /')"
  fi
}

# sweep_list OPTION TEMPLATE PREFIX... -- SUFFIX...: OPTION between PREFIX and SUFFIX, its value
# TEMPLATE with X replaced by each value (X,0,0 for --point: each coordinate in turn).
sweep_list() {
  local option=$1 template=$2
  shift 2
  local prefix=()
  while [ "$1" != "--" ]; do prefix+=("$1"); shift; done
  shift
  for v in "${values[@]}"; do check "$option" "${prefix[@]}" "$option" "${template//X/$v}" "$@"; done
}

# sweep OPTION PREFIX... -- SUFFIX...: a plain number.
sweep() {
  local option=$1
  shift
  sweep_list "$option" X "$@"
}

# sweep_file FILE TEMPLATE CMD...: FILE written as TEMPLATE (printf format) with X replaced by each
# value, then CMD (which reads FILE); exit 2 must name FILE.
sweep_file() {
  local file=$1 template=$2
  shift 2
  for v in "${values[@]}"; do
    # shellcheck disable=SC2059
    printf -- "${template//X/$v}" >"$file"
    check "$file" "$@"
  done
}

sweep --gl-threads --gl osmesa info "$sphere" --
for o in --tolerance --grid --max-samples --tile-mb --face; do sweep $o --gl osmesa evaluate "$paper" --; done
sweep --tolerance --gl osmesa info "$paper" --bounds --
for o in --tol --host-cells --max-samples; do sweep $o --gl osmesa distance "$sphere" --point 0,0,20 --; done
sweep_list --point X,0,20 --gl osmesa distance "$sphere" --
sweep_list --point 0,0,X --gl osmesa distance "$sphere" --
for o in --tol --reduce-block --compact-fanout --host-pairs --max-samples; do
  sweep $o --gl osmesa clearance "$sphere" "$sphere" --move-b 30,0,0 --
done
sweep --voxels --gl osmesa clearance "$sphere" "$sphere" --move-b 30,0,0 --first-stage voxels --
sweep_list --move-b X,0,0 --gl osmesa clearance "$sphere" "$sphere" --
sweep_list --rotate-b 0,0,1,X --gl osmesa clearance "$sphere" "$sphere" --move-b 30,0,0 --
sweep_list --rotate-b X,0,0,30 --gl osmesa clearance "$sphere" "$sphere" --move-b 30,0,0 --
for o in --eps --loop-share --face --threads --max-cells; do sweep $o tessellate "$sphere" --; done
sweep --eps tessellate "$sphere" --relative --
sweep --check-samples tessellate "$sphere" --check --
for o in --eps --samples --threads; do sweep $o deviation "$sphere" "$mesh" --; done
for o in --threads --dacrt-patches --dacrt-rays --tolerance; do sweep $o --gl osmesa raycast "$sphere" --rays "$rays" --; done
for o in --samples --spacing --min-wall --tolerance; do sweep $o --gl osmesa thickness "$sphere" --; done
sweep --ball-tolerance --gl osmesa thickness "$sphere" --samples 200 --ball --
for o in --size --density; do sweep $o --gl osmesa selftest --; done
sweep --seed generate random-trimmed -o "$work/random.igs" --

# The same for every coordinate kind of the text inputs.
points=$work/points.txt motion=$work/motion.txt hostile_rays=$work/hostile_rays.txt hostile_mesh=$work/hostile.obj
for t in 'X 0 20\n' '0 0 X\n'; do sweep_file "$points" "$t" --gl osmesa distance "$sphere" --points "$points"; done
sweep_file "$points" '0 0 X\n' --gl osmesa distance "$sphere" --points "$points" --per-point
for t in 'X 0 30 0 0 -1\n' '0 0 30 0 0 X\n' '0 0 30 X 0 -1\n'; do
  sweep_file "$hostile_rays" "$t" --gl osmesa raycast "$sphere" --rays "$hostile_rays"
done
for t in 'X 0 0 0 0 1 0\n' '30 0 0 0 0 1 X\n' '30 0 0 X 0 1 30\n'; do
  sweep_file "$motion" "$t" --gl osmesa clearance "$sphere" "$sphere" --motion "$motion"
done
for t in 'v X 0 0\nv 0 10 0\nv 0 0 10\nf 1 2 3\n' 'v 10 0 0\nv 0 10 0\nv 0 0 10\nf 1 2 3 X\n'; do
  sweep_file "$hostile_mesh" "$t" deviation "$sphere" "$hostile_mesh"
done

echo "option sweep: $runs runs, $failures failures"
[ "$failures" = 0 ]
