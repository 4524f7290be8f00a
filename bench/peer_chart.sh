#!/bin/sh
# Runs bench/peer_chart.py (wall time against largest strain on the peer sheet, Blender's qualities and
# clothsim's integrators and steps in one run; docs/accuracy.md "Against a peer"); exits 77 (skipped) where
# blender is not installed.
# Usage: bench/peer_chart.sh CLOTHSIM_BIN SCRATCH_DIR OUT_DIR [peer_chart.py options]
here=$(dirname "$0")
blender=${BLENDER:-blender}
if ! command -v "$blender" >/dev/null 2>&1; then
  echo "SKIPPED: blender is not installed; 'tools/setup blender python3-numpy' installs Debian's blender"
  exit 77
fi
if ! command -v gnuplot >/dev/null 2>&1; then
  echo "SKIPPED: gnuplot is not installed; 'tools/setup' installs it"
  exit 77
fi
exec "$blender" -b --factory-startup --python-exit-code 1 --python "$here/peer_chart.py" -- "$@"
