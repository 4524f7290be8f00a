#!/bin/sh
# ctest entry for the Blender add-on test: exit 77 (ctest SKIP_RETURN_CODE) when blender is not installed.
# Usage: run_addon_test.sh CLOTHSIM_BIN SCRATCH_DIR
here=$(dirname "$0")
blender=${BLENDER:-blender}
if ! command -v "$blender" >/dev/null 2>&1; then
  echo "SKIPPED: blender is not installed; 'tools/setup blender' installs Debian's blender to run this test"
  exit 77
fi
exec "$blender" -b --factory-startup --python-exit-code 1 --python "$here/test_addon.py" -- "$1" "$2"
