#!/usr/bin/env bash
# examples/drive_square.py, the standard-library Python client quoted in docs/api.md: the
# quote must be the file verbatim, and the file must drive the square on the emulator and
# the daemon on vcan0 and come back near where it started.
#   python_example.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=${1:?usage: python_example.sh BUILD_DIR SOURCE_DIR}
source=${2:?usage: python_example.sh BUILD_DIR SOURCE_DIR}
example=$source/examples/drive_square.py

# The ```python block of docs/api.md against the file.
quoted=$(awk '/^```python$/ { inside = 1; next } inside && /^```$/ { exit } inside' "$source/docs/api.md")
if ! diff -u "$example" - <<<"$quoted"; then
  echo "FAIL: the example quoted in docs/api.md differs from examples/drive_square.py (diff above)"
  exit 1
fi
echo "docs/api.md quotes examples/drive_square.py verbatim"

work=$(mktemp -d /tmp/wheeltec-python-example.XXXXXX)
trap 'rm -rf -- "$work"' EXIT
"$source/scripts/vcan-run" -- bash "$source/tests/client/run_example.sh" "$build" "$example" "$work"
