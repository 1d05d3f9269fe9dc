#!/usr/bin/env bash
# A face whose name is not UTF-8 (a Latin-1 byte, as writers on Windows code pages give): `info
# --json` still prints one valid JSON object, the byte shown as U+FFFD. Usage: non_utf8_name.sh
# NURBSGL CYLINDER_FACE_STP WORK_DIR
set -euo pipefail
nurbsgl=$1 source=$2 work=$3
mkdir -p "$work"
sed "s/ADVANCED_FACE(''/ADVANCED_FACE('caf\\xe9'/" "$source" > "$work/latin1.stp"
grep -q $'caf\xe9' "$work/latin1.stp" || { echo "the test file lacks the Latin-1 byte"; exit 1; }
out=$("$nurbsgl" info "$work/latin1.stp" --json)
grep -q $'"name": "caf\xef\xbf\xbd"' <<< "$out" || { echo "no U+FFFD name in: $out" | head -c 2000; exit 1; }
echo "ok"
