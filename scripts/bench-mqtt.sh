#!/usr/bin/env bash
# Runs the benchmark of wheeltec-mqtt, the fleet bridge (issue #15), and prints its figures:
# one real mosquitto on 127.0.0.1, and per robot wheeltec-emu, wheeltecd and wheeltec-mqtt on
# their own vcan interface, all in one scripts/vcan-run session (User-Mode Linux on hosts
# without SocketCAN), measured by wheeltec-bench-mqtt (bench/mqtt/):
#   1. drive published on the broker -> first 0x121 frame with its velocity, p50/p99, next to
#      the same drive written on wheeltecd's socket;
#   1b. the same drives through a minimal Python bridge on paho-mqtt (bench/mqtt/paho_bridge.py,
#      Debian's python3-paho-mqtt, on the same daemon and broker, alternating blocks), and what
#      each bridge adds over the daemon's socket;
#   1c. broker loss -> zero frame: the broker SIGKILLed while a bridge drives, to the first
#      0x121 frame with zero velocity, for each bridge, several rounds;
#   1c2. broker connection cut -> zero frame: a second wheeltec-mqtt and paho bridge on r1's
#      daemon, each behind a TCP relay (bench/mqtt/connection_relay.hpp) that cuts its broker
#      connection while it drives: the bridges' own part of a broker loss, the broker running;
#   1d. the fleet's emergency stop: one empty message on wheeltec/all/cmd/estop while r1 drives,
#      to its first zero frame (then `release` on the daemon's socket), as many rounds;
#   2. 0x103 frame on the bus (kernel timestamp) -> the record at an MQTT subscriber,
#      p50/p99, next to a direct subscriber of the daemon;
#   3. the bridge's CPU per record (utime+stime over the run / records published), and its
#      and the broker's system calls per record (strace -c);
#   4. N robots against one broker (1, 2, 4, 8, 16, until records are lost): records/s at
#      one subscriber of wheeltec/+/telemetry, records lost, the bridges' telemetry_dropped.
# With --serial it runs natively instead (no vcan, no User-Mode Linux): one robot, whose chassis
# is a pseudo-terminal that the benchmark itself plays (records at 20 Hz, command frames timed
# when read), and only 1, 1b, 1c and 1d; 2-4 need the bus and are skipped. About 2 minutes, 20 s
# with --quick.
# Writes $BENCH_OUT (default: $BUILD_DIR/bench-results) /mqtt.json and mqtt-table.md.
# Takes about 3 minutes; --quick (short runs, 1 and 2 robots, to check that it works) well
# under a minute.
#
#   scripts/bench-mqtt.sh [--quick] [--serial] [-- MORE ARGUMENTS OF wheeltec-bench-mqtt]
#
# BUILD_DIR (default /tmp/build-bench) is configured and built if needed. MQTT_BENCH_ROBOTS
# (e.g. "1,2,4,8,16,24") replaces the list of robot counts.
set -euo pipefail

REPO_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# shellcheck source=bench-common.sh
source "$REPO_ROOT/scripts/bench-common.sh"
bench_arguments '2,30p' --serial "$@"

# shellcheck source=lib/setup.sh
source "$REPO_ROOT/scripts/lib/setup.sh"
# python3-paho-mqtt: the Python bridge (bench/mqtt/paho_bridge.py) measured next to wheeltec-mqtt.
install_packages libmosquitto-dev mosquitto strace python3-paho-mqtt "${WHEELTEC_VCAN_PACKAGES[@]}"

if [[ ! -f $BUILD_DIR/build.ninja ]]; then
  cmake -S "$REPO_ROOT" -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWHEELTEC_BUILD_BENCHMARKS=ON >/dev/null
elif ! grep -q '^WHEELTEC_BUILD_BENCHMARKS:BOOL=ON' "$BUILD_DIR/CMakeCache.txt"; then
  cmake -S "$REPO_ROOT" -B "$BUILD_DIR" -DWHEELTEC_BUILD_BENCHMARKS=ON >/dev/null
fi
cmake --build "$BUILD_DIR" --target wheeltec-bench-mqtt wheeltecd wheeltec-emu wheeltec-mqtt -j"${BUILD_JOBS:-2}"
mkdir -p "$BENCH_OUT"

programs=(--wheeltecd "$BUILD_DIR/daemon/wheeltecd" --bridge "$BUILD_DIR/mqtt/wheeltec-mqtt"
  --paho-bridge "$REPO_ROOT/bench/mqtt/paho_bridge.py"
  --mosquitto "$(command -v mosquitto || echo /usr/sbin/mosquitto)")

if ((SERIAL)); then
  quick=()
  ((QUICK)) && quick=(--quick)
  echo "== wheeltec-mqtt: 1 robot on a serial line (a pseudo-terminal played by the benchmark), against one mosquitto, natively"
  started=$SECONDS
  status=0
  "$BUILD_DIR/bench/wheeltec-bench-mqtt" "${programs[@]}" --serial --json "$BENCH_OUT/mqtt.json" "${quick[@]}" \
    "${extra[@]}" >"$BENCH_OUT/mqtt-table.body.md" || status=$?
  bench_report mqtt ", natively, the chassis on a pseudo-terminal"
fi

args=()
# strace counts the system calls of the bridge and the broker per record exactly (the CPU
# time that User-Mode Linux reports is sampled in 10 ms ticks).
strace=$(command -v strace || true)
[[ -n $strace ]] && args+=(--strace "$strace")
if ((QUICK)); then
  robots=${MQTT_BENCH_ROBOTS:-1,2}
  args+=(--quick)
else
  robots=${MQTT_BENCH_ROBOTS:-1,2,4,8,16}
fi
most=$(tr ',' '\n' <<<"$robots" | sort -n | tail -n 1)
interfaces=$(for ((i = 0; i < most; i++)); do printf 'vcan%d ' "$i"; done)

echo "== wheeltec-mqtt: 1 robot, then $robots robots against one mosquitto (through scripts/vcan-run)"
started=$SECONDS
status=0
VCAN_INTERFACES=${interfaces% } "$REPO_ROOT/scripts/vcan-run" -- "$BUILD_DIR/bench/wheeltec-bench-mqtt" \
  "${programs[@]}" --emulator "$BUILD_DIR/emulator/wheeltec-emu" \
  --robots "$robots" --json "$BENCH_OUT/mqtt.json" "${args[@]}" "${extra[@]}" >"$BENCH_OUT/mqtt-table.body.md" ||
  status=$?
bench_report mqtt " including the virtual machine's boot"
