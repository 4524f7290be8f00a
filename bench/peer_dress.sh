#!/bin/sh
# Runs bench/peer_dress.py (the knife-pleat dress in Blender's cloth modifier against clothsim); exits 77 (skipped)
# where blender or the dress data are not there. Usage: bench/peer_dress.sh CLOTHSIM_BIN SCRATCH_DIR [options]
here=$(dirname "$0")
blender=${BLENDER:-blender}
if ! command -v "$blender" >/dev/null 2>&1; then
  echo "SKIPPED: blender is not installed; 'tools/setup blender python3-numpy' installs Debian's blender"
  exit 77
fi
if [ ! -f "$here/../../shared/data/garments/cipc/dress_knife_drape_with_body.obj" ] && ! echo "$*" | grep -q -- --dress; then
  echo "SKIPPED: ../shared/data/garments/cipc/dress_knife_drape_with_body.obj is not there (or pass --dress PATH)"
  exit 77
fi
exec "$blender" -b --factory-startup --python-exit-code 1 --python "$here/peer_dress.py" -- "$@"
