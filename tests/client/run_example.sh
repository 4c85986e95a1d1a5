#!/usr/bin/env bash
# Inside scripts/vcan-run: emulator and daemon on vcan0, then the example; checks the corners.
#   run_example.sh BUILD_DIR EXAMPLE WORK_DIR
set -euo pipefail
build=$1 example=$2 work=$3
socket=$work/wheeltecd.sock
cat >"$work/wheeltecd.json" <<JSON
{ "can": { "interface": "vcan0" }, "chassis": { "type": "diff" }, "api": { "socket": "$socket" } }
JSON
"$build/emulator/wheeltec-emu" --interface vcan0 --chassis diff --boot-delay 1 >"$work/emu.log" 2>&1 &
emulator=$!
"$build/daemon/wheeltecd" --config "$work/wheeltecd.json" >"$work/daemon.log" 2>&1 &
daemon=$!
trap 'kill $emulator $daemon 2>/dev/null; wait' EXIT
for _ in $(seq 100); do [[ -S $socket ]] && break; sleep 0.05; done

status=0
output=$(timeout 60 "$example" "$socket") || status=$?
echo "$output"
if ((status != 0)); then
  echo "FAIL: drive_square exited $status"; cat "$work/daemon.log"; exit 1
fi
# Corner 1 after 2 s at 0.2 m/s straight ahead; corner 2 after a quarter turn left and 2 s
# more; corner 4, after the fourth side and turn, back where it started (on the emulator
# within a few mm; 0.1 m leaves room for a loaded machine's timing).
awk '
  /^corner 1:/ { x1 = $4 }
  /^corner 2:/ { y2 = $7 }
  /^corner 4:/ { seen = 1; d4 = sqrt($4 * $4 + $7 * $7) }
  END {
    ok = seen && x1 > 0.3 && x1 < 0.5 && y2 > 0.25 && y2 < 0.55 && d4 < 0.1
    printf "corner 1 x %.3f m (0.3 to 0.5), corner 2 y %.3f m (0.25 to 0.55), corner 4 %.3f m from the start (below 0.1): %s\n",
           x1, y2, d4, ok ? "ok" : "FAIL"
    exit ok ? 0 : 1
  }' <<<"$output"
