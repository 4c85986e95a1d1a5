#!/usr/bin/env bash
# The demo's session on vcan0 (run by scripts/demo.sh through scripts/vcan-run):
#   demo-session.sh BUILD_DIR
set -euo pipefail

BUILD_DIR=${1:?usage: demo-session.sh BUILD_DIR}
WHEELTECD=$BUILD_DIR/daemon/wheeltecd
WHEELTECCTL=$BUILD_DIR/cli/wheeltecctl
EMULATOR=$BUILD_DIR/emulator/wheeltec-emu
INTERFACE=${DEMO_INTERFACE:-vcan0}

work=$(mktemp -d /tmp/wheeltec-demo.XXXXXX)
socket=$work/wheeltecd.sock
export WHEELTEC_SOCKET=$socket
emulator_pid=
daemon_pid=
watch_pid=

stop_process() {  # PID NAME: SIGTERM, wait, report how it ended
  local pid=$1 name=$2 status=0
  [[ -n $pid ]] || return 0
  kill -TERM "$pid" 2>/dev/null || true
  wait "$pid" || status=$?
  echo "demo: $name stopped (exit status $status)"
  return "$status"
}

# shellcheck disable=SC2317  # called by the EXIT trap
cleanup() {
  [[ -n $watch_pid ]] && kill -TERM "$watch_pid" 2>/dev/null
  [[ -n $daemon_pid ]] && kill -TERM "$daemon_pid" 2>/dev/null
  [[ -n $emulator_pid ]] && kill -TERM "$emulator_pid" 2>/dev/null
  wait 2>/dev/null
  rm -rf -- "$work"
}
trap cleanup EXIT

cat > "$work/wheeltecd.json" <<JSON
{
  "can":     { "interface": "$INTERFACE", "dialect": "manual" },
  "chassis": { "type": "mecanum" },
  "api":     { "socket": "$socket" },
  "log":     { "level": "info" }
}
JSON

echo "demo: starting the chassis emulator on $INTERFACE (boot delay 2 s)"
"$EMULATOR" --interface "$INTERFACE" --chassis mecanum --boot-delay 2 --battery 22.6 \
  > "$work/emulator.log" 2>&1 &
emulator_pid=$!

echo "demo: starting wheeltecd"
"$WHEELTECD" --config "$work/wheeltecd.json" > "$work/wheeltecd.log" 2>&1 &
daemon_pid=$!
for _ in $(seq 50); do
  [[ -S $socket ]] && "$WHEELTECCTL" version >/dev/null 2>&1 && break
  kill -0 "$daemon_pid" 2>/dev/null || { cat "$work/wheeltecd.log"; echo "demo: wheeltecd failed" >&2; exit 1; }
  sleep 0.1
done
"$WHEELTECCTL" version

echo
echo "demo: \$ wheeltecctl watch -n 10"
"$WHEELTECCTL" watch -n 10

echo
echo "demo: waiting for the emulated chassis to boot and run its self-test (it drives itself"
echo "demo: forward at 0.2 m/s for 2 s, as the real firmware does; drive is refused meanwhile)"
phase=
for _ in $(seq 150); do
  now=$("$WHEELTECCTL" --json status | grep -o '"phase":[a-z"-]*' || true)
  [[ $now != "$phase" ]] && { echo "demo: chassis.phase ${now#\"phase\":}"; phase=$now; }
  [[ $now == '"phase":"ready"' ]] && break
  sleep 0.1
done
echo "demo: \$ wheeltecctl drive 0.3 0 0.5 --for 3   (telemetry below shows the measured velocity)"
"$WHEELTECCTL" watch -n 90 &
watch_pid=$!
"$WHEELTECCTL" drive 0.3 0 0.5 --for 3
wait "$watch_pid"
watch_pid=

echo
echo "demo: \$ wheeltecctl status"
"$WHEELTECCTL" status

echo
status=0
stop_process "$daemon_pid" wheeltecd || status=1
daemon_pid=
stop_process "$emulator_pid" wheeltec-emu || status=1
emulator_pid=
if [[ $status -ne 0 ]]; then
  echo "--- wheeltecd log ---"; cat "$work/wheeltecd.log"
  echo "--- wheeltec-emu log ---"; cat "$work/emulator.log"
fi
echo "demo: done"
exit "$status"
