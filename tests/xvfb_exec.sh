#!/bin/sh
# xvfb_exec.sh COMMAND [ARGS...]: COMMAND run under `xvfb-run -a`, ending with COMMAND's own exit status.
# xvfb-run replaces that status with its own when it cannot remove its temporary directory after the
# command ended (5), so the status is written to a file of our own and read back. Each run gets its own
# TMPDIR for xvfb-run's directory. XVFB_RUN names xvfb-run when it is not on PATH.
set -u
work=$(mktemp -d "${TMPDIR:-/tmp}/xvfb_exec.XXXXXX") || exit 125
mkdir "$work/tmp"
XVFB_EXEC_STATUS="$work/status" TMPDIR="$work/tmp" "${XVFB_RUN:-xvfb-run}" -a \
  sh -c '"$@"; echo $? > "$XVFB_EXEC_STATUS"' sh "$@"
xvfb_status=$?
if [ -s "$work/status" ]; then
  status=$(cat "$work/status")
else
  echo "xvfb_exec.sh: xvfb-run ended with $xvfb_status before the command did" >&2
  status=$xvfb_status
  [ "$status" -eq 0 ] && status=125
fi
rm -rf "$work"
exit "$status"
