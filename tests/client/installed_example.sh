#!/usr/bin/env bash
# examples/drive_square built against the *installed* wheeltec-client, as a program outside
# this tree would build it (CMake's find_package, and pkg-config), then run against the
# emulator and the daemon on vcan0: it must drive the square and print the odometry.
#   installed_example.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=${1:?usage: installed_example.sh BUILD_DIR SOURCE_DIR}
source=${2:?usage: installed_example.sh BUILD_DIR SOURCE_DIR}
work=$(mktemp -d /tmp/wheeltec-client-example.XXXXXX)
trap 'rm -rf -- "$work"' EXIT

cmake --install "$build" --prefix "$work/prefix" --component client >/dev/null
cmake -S "$source/examples" -B "$work/cmake-build" -G Ninja -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/cmake-build"
pc_dir=$(dirname "$(find "$work/prefix" -name wheeltec-client.pc)")
# shellcheck disable=SC2046  # pkg-config's words are separate arguments
c++ -O1 -o "$work/drive_square_pkgconfig" "$source/examples/drive_square.cpp" \
  $(PKG_CONFIG_PATH=$pc_dir pkg-config --cflags --libs wheeltec-client)
echo "built drive_square against the installed library with CMake and with pkg-config"

"$source/scripts/vcan-run" -- bash "$source/tests/client/run_example.sh" "$build" "$work/cmake-build/drive_square" "$work"
