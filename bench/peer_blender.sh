#!/bin/sh
# Runs bench/peer_blender.py (Blender's cloth modifier against clothsim, docs/performance.md "Blender"); exits
# 77 (skipped) where blender is not installed.
# Usage: bench/peer_blender.sh CLOTHSIM_BIN SCRATCH_DIR [peer_blender.py options]
here=$(dirname "$0")
blender=${BLENDER:-blender}
if ! command -v "$blender" >/dev/null 2>&1; then
  echo "SKIPPED: blender is not installed; 'tools/setup blender python3-numpy' installs Debian's blender"
  exit 77
fi
exec "$blender" -b --factory-startup --python-exit-code 1 --python "$here/peer_blender.py" -- "$@"
