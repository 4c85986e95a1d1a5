#!/usr/bin/env bash
# The Python examples: examples/drive_square_socket.py, the standard-library client quoted in
# docs/api.md (the quote must be the file verbatim), and examples/drive_square.py on the
# wheeltec package (python/); each must drive the square on the emulator and the daemon on
# vcan0 and come back near where it started.
#   python_example.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=${1:?usage: python_example.sh BUILD_DIR SOURCE_DIR}
source=${2:?usage: python_example.sh BUILD_DIR SOURCE_DIR}
socket_example=$source/examples/drive_square_socket.py
package_example=$source/examples/drive_square.py

# The ```python block of docs/api.md against the file.
quoted=$(awk '/^```python$/ { inside = 1; next } inside && /^```$/ { exit } inside' "$source/docs/api.md")
if ! diff -u "$socket_example" - <<<"$quoted"; then
  echo "FAIL: the example quoted in docs/api.md differs from examples/drive_square_socket.py (diff above)"
  exit 1
fi
echo "docs/api.md quotes examples/drive_square_socket.py verbatim"

work=$(mktemp -d /tmp/wheeltec-python-example.XXXXXX)
trap 'rm -rf -- "$work"' EXIT
mkdir "$work/socket" "$work/package"
export PYTHONPATH=$source/python${PYTHONPATH:+:$PYTHONPATH}
"$source/scripts/vcan-run" -- bash -c 'bash "$1" "$2" "$3" "$4" && bash "$1" "$2" "$5" "$6"' _ \
  "$source/tests/client/run_example.sh" "$build" "$socket_example" "$work/socket" "$package_example" "$work/package"
