#!/usr/bin/env bash
# The pictures of the README and viewer/README.md (viewer/doc/*.png), taken by the viewer's scripted
# runs under xvfb: the clearance of the paper's pair, a tessellated part and its thickness map. The
# part is the shared bearing (../shared/models/iges/occt_bearing.iges) when present, else the
# generated torus. Needs the build (scripts/setup.sh) and xvfb-run.
# Usage: scripts/pictures.sh [BUILD_DIR] [OUT_DIR]   (defaults: build, viewer/doc)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
out=${2:-viewer/doc}
viewer=$build/viewer/nurbsgl-viewer
models=$build/models
part=../shared/models/iges/occt_bearing.iges
[ -f "$part" ] || part=$models/torus.igs
mkdir -p "$out"
shot() {  # shot NAME WIDTH HEIGHT VIEWER-ARGS...
  local name=$1 width=$2 height=$3
  shift 3
  xvfb-run -a -s "-screen 0 ${width}x${height}x24" "$viewer" "$@" --width "$width" --height "$height" \
    --screenshot "$out/$name.png" >/dev/null
  echo "pictures: $out/$name.png"
}
shot clearance 1100 640 "$models/paper-199x33.igs" "$models/paper-100x105.igs" --move-b 40,-60,30 \
  --rotate-b 0,0,1,10 --frames 60
shot tessellation 960 560 "$part" --mode tessellation --eps 2e-3 --frames 3
shot thickness 960 560 "$part" --mode thickness --frames 3
