#!/usr/bin/env bash
# Runs the benchmark of wheeltec-ros2, the ROS 2 bridge (issue #22 item 8, measured as issue
# #23 asks of every bridge), and prints its figures: wheeltec-emu, wheeltecd and wheeltec-ros2
# (--localhost-only) on vcan0 and 127.0.0.1, and an independent ROS 2 side (Fast DDS 2.9, set
# up as rmw_fastrtps) in the benchmark, all in one scripts/vcan-run session (User-Mode Linux on
# hosts without SocketCAN), measured by wheeltec-bench-ros2 (bench/ros2/):
#   1. cmd_vel published by a RELIABLE Fast DDS writer -> first 0x121 frame with its velocity,
#      p50/p99, next to the same drive written on wheeltecd's socket;
#   2. 0x103 frame on the bus (kernel timestamp) -> the odom sample with that stamp at a Fast
#      DDS reader, p50/p99, next to a direct subscriber of the daemon;
#   3. the bridge's CPU per record (utime+stime over the run / records published), its system
#      calls per record (strace -c) and its memory (VmRSS, VmHWM).
# Writes $BENCH_OUT (default: $BUILD_DIR/bench-results) /ros2.json and ros2-table.md.
# Takes about 2 minutes; --quick (short runs, to check that it works) well under a minute.
#
#   scripts/bench-ros2.sh [--quick] [-- MORE ARGUMENTS OF wheeltec-bench-ros2]
#
# BUILD_DIR (default /tmp/build-bench) is configured and built if needed, with the tests on:
# the benchmark's DDS side is the ros2 suite's library (tests/ros2/ros2_side).
set -euo pipefail

REPO_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# shellcheck source=bench-common.sh
source "$REPO_ROOT/scripts/bench-common.sh"
bench_arguments '2,19p' '' "$@"

# shellcheck source=lib/setup.sh
source "$REPO_ROOT/scripts/lib/setup.sh"
install_packages cyclonedds-dev cyclonedds-tools libfastrtps-dev fastddsgen libgtest-dev strace \
  "${WHEELTEC_VCAN_PACKAGES[@]}"

# Configured when new, when the benchmarks or the tests are off, or when the benchmark's target
# is missing (a build directory configured before Cyclone DDS or Fast DDS was installed).
if [[ ! -f $BUILD_DIR/build.ninja ]]; then
  cmake -S "$REPO_ROOT" -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWHEELTEC_BUILD_BENCHMARKS=ON \
    -DWHEELTEC_BUILD_TESTS=ON >/dev/null
elif ! grep -q '^WHEELTEC_BUILD_BENCHMARKS:BOOL=ON' "$BUILD_DIR/CMakeCache.txt" ||
     ! grep -q '^WHEELTEC_BUILD_TESTS:BOOL=ON' "$BUILD_DIR/CMakeCache.txt" ||
     ! grep -q 'wheeltec-bench-ros2' "$BUILD_DIR/build.ninja"; then
  cmake -S "$REPO_ROOT" -B "$BUILD_DIR" -DWHEELTEC_BUILD_BENCHMARKS=ON -DWHEELTEC_BUILD_TESTS=ON >/dev/null
fi
if ! grep -q 'wheeltec-bench-ros2' "$BUILD_DIR/build.ninja"; then
  echo "bench-ros2.sh: $BUILD_DIR has no target wheeltec-bench-ros2 (it needs wheeltec-ros2 and tests/ros2's" \
    "Fast DDS side; see cmake's messages)" >&2
  exit 1
fi
cmake --build "$BUILD_DIR" --target wheeltec-bench-ros2 wheeltecd wheeltec-emu wheeltec-ros2 -j"${BUILD_JOBS:-2}"
mkdir -p "$BENCH_OUT"

args=()
# strace counts the bridge's system calls per record exactly (the CPU time that User-Mode
# Linux reports is sampled in 10 ms ticks).
strace=$(command -v strace || true)
[[ -n $strace ]] && args+=(--strace "$strace")
((QUICK)) && args+=(--quick)

echo "== wheeltec-ros2: cmd_vel and odom against a Fast DDS peer (through scripts/vcan-run)"
started=$SECONDS
status=0
"$REPO_ROOT/scripts/vcan-run" -- "$BUILD_DIR/bench/wheeltec-bench-ros2" \
  --wheeltecd "$BUILD_DIR/daemon/wheeltecd" --emulator "$BUILD_DIR/emulator/wheeltec-emu" \
  --bridge "$BUILD_DIR/ros2/wheeltec-ros2" --json "$BENCH_OUT/ros2.json" "${args[@]}" "${extra[@]}" \
  >"$BENCH_OUT/ros2-table.body.md" || status=$?
bench_report ros2 " including the virtual machine's boot"
