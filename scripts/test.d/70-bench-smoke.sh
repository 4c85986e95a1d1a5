#!/usr/bin/env bash
# Test stage: the benchmarks still build and run. Each microbenchmark runs for a few
# milliseconds and must not report an error, the serial-link benchmark and the Python client's
# run once in their quick modes (natively, on pseudo-terminals), and the wheeltec-mqtt, wheeltec-ros2 and wheeltec-web
# benchmarks run once in their quick modes (inside scripts/vcan-run; wheeltec-mqtt's also once
# natively on a pseudo-terminal); each must report its
# figures. Nothing is timed or compared here (the figures come from scripts/bench.sh,
# scripts/bench-mqtt.sh, scripts/bench-ros2.sh and scripts/bench-web.sh, see docs/performance.md).
set -euo pipefail

REPO_ROOT=${REPO_ROOT:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}
BUILD_DIR=${BUILD_DIR:-$REPO_ROOT/build}
# shellcheck source=../lib/setup.sh
source "$REPO_ROOT/scripts/lib/setup.sh"
install_packages libbenchmark-dev

# The main build may have been configured before Google Benchmark was installed.
cmake -S "$REPO_ROOT" -B "$BUILD_DIR" -DWHEELTEC_BUILD_BENCHMARKS=ON >/dev/null
cmake --build "$BUILD_DIR" --target wheeltec-microbench wheeltec-bench-fanout wheeltec-bench-e2e wheeltec-bench-floor \
  wheeltec-bench-serial wheeltecd -j"${BUILD_JOBS:-2}"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out=$work/microbench.json fanout=$work/fanout.json serial=$work/serial.json
# Runs a benchmark script's quick mode, its figures in $work/NAME; on failure shows its output and fails.
run_quick() {
  local name=$1
  shift
  mkdir -p "$work/$name"
  if ! BUILD_DIR=$BUILD_DIR BENCH_OUT=$work/$name "$@" >"$work/$name/output.txt" 2>&1; then
    cat "$work/$name/output.txt" >&2
    echo "bench smoke: ${*#"$REPO_ROOT/"} failed" >&2
    exit 1
  fi
}
"$BUILD_DIR/bench/wheeltec-microbench" --benchmark_min_time=0.01 --benchmark_format=json >"$out"
python3 - "$out" <<'PY'
import json, sys
runs = json.load(open(sys.argv[1]))["benchmarks"]
expected = {"BM_ControlFrameEncode", "BM_ReassembleAndDecodeRecord", "BM_TelemetryNotificationJson",
            "BM_DriveRequestToFrameAndResponse", "BM_StatusRequestThroughRpcHandler",
            "BM_SyscallClockGettime", "BM_SyscallEpollWaitNoWait", "BM_SyscallUnixSocketWriteAndRead",
            "BM_WakeupFromBlockingRead"}
names = {r["name"].split("/")[0] for r in runs}
errors = [f"{r['name']}: {r.get('error_message')}" for r in runs if r.get("error_occurred")]
missing = expected - names
if errors or missing:
    sys.exit("bench smoke: " + "; ".join(errors + [f"{m} did not run" for m in sorted(missing)]))
print(f"bench smoke: {len(runs)} microbenchmarks ran")
PY
"$BUILD_DIR/bench/wheeltec-bench-e2e" --help >/dev/null

# The fan-out benchmark's shortest run: both gateways deliver telemetry to their subscribers.
"$BUILD_DIR/bench/wheeltec-bench-fanout" --step-s 0.2 --max-rate 500 --floor "$BUILD_DIR/bench/wheeltec-bench-floor" \
  --json "$fanout" >/dev/null
python3 - "$fanout" <<'PY'
import json, sys
f = json.load(open(sys.argv[1]))
for name in ("wheeltecd", "floor"):
    step = f[name]["steps"][0]
    if step["notifications_received"] == 0:
        sys.exit(f"bench smoke: the fan-out benchmark's {name} delivered no notification: {step}")
print("bench smoke: fan-out benchmark ran (wheeltecd and relay floor delivered telemetry)")
PY

# The relay floor's --spec-work (the spec floor of the end-to-end benchmark's instruction
# count): fed one record on a socket pair, it must publish that record's real notification
# and send zero-velocity control frames, which the plain relay does not.
python3 - "$BUILD_DIR/bench/wheeltec-bench-floor" <<'PY'
import json, os, socket, struct, subprocess, sys, tempfile
ours, theirs = socket.socketpair(socket.AF_UNIX, socket.SOCK_SEQPACKET)
path = os.path.join(tempfile.mkdtemp(), "spec-floor.sock")
floor = subprocess.Popen([sys.argv[1], "--frame-fd", str(theirs.fileno()), "--socket", path, "--spec-work"],
                         pass_fds=[theirs.fileno()])
theirs.close()
try:
    sub = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    for attempt in range(500):
        try:
            sub.connect(path)
            break
        except OSError:
            if floor.poll() is not None or attempt == 499:
                sys.exit("bench smoke: the spec floor did not open its socket")
            subprocess.run(["sleep", "0.01"])
    sub.sendall(b'{"jsonrpc":"2.0","method":"subscribe","params":{"topics":["telemetry"]},"id":1}\n')
    sub.settimeout(5)
    sub.recv(4096)
    # vx 123 mm/s, accel z 16400 (about 1 g), battery 11900 mV; then the XOR check byte and the tail.
    body = bytes([0x7B, 0]) + struct.pack(">10h", 123, 0, 0, 0, 0, 16400, 0, 0, 0, 11900)
    check = 0
    for byte in body:
        check ^= byte
    record = body + bytes([check, 0x7D])
    for i in range(3):
        ours.send(struct.pack("=IB3x8s", 0x101 + i, 8, record[8 * i:8 * i + 8]))
    line = b""
    while not line.endswith(b"\n"):
        line += sub.recv(4096)
    params = json.loads(line)["params"]
    if params["velocity"]["vx"] != 0.123 or params["battery"]["voltage"] != 11.9 or "orientation" not in params:
        sys.exit(f"bench smoke: the spec floor's notification is not the record's: {params}")
    ours.settimeout(5)
    while True:
        can_id, dlc, data = struct.unpack("=IB3x8s", ours.recv(16))
        if can_id == 0x121:
            break
    if data != bytes(8):
        sys.exit(f"bench smoke: the spec floor's control frame is not zero velocity: {data.hex()}")
    print("bench smoke: spec floor ran (the record's notification, a zero-velocity control frame)")
finally:
    floor.terminate()
    floor.wait()
PY

# The serial-link benchmark's quick mode (a few seconds, natively on a pseudo-terminal): both
# latencies and the emergency stop's must have samples.
"$BUILD_DIR/bench/wheeltec-bench-serial" --quick --wheeltecd "$BUILD_DIR/daemon/wheeltecd" --json "$serial" >/dev/null
python3 - "$serial" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))["wheeltecd"]
drives, records = d["command_latency"]["count"], d["telemetry_latency_1"]["count"]
estops = d["estop_latency"]["count"]
if not (drives and records and estops):
    sys.exit(f"bench smoke: the serial benchmark timed {drives} drives, {records} records and {estops} estops")
print(f"bench smoke: serial benchmark ran ({drives} drives, {estops} estops and {records} records timed, "
      f"{d['telemetry_latency_1']['lost']} records lost)")
PY

# The Python client's benchmark, quick mode (a few seconds, natively on pseudo-terminals):
# status() round trips on a bare socket and through the package, and a subscription's records.
/usr/bin/python3 "$REPO_ROOT/bench/python/python_bench.py" --quick --wheeltecd "$BUILD_DIR/daemon/wheeltecd" \
  --emu "$BUILD_DIR/emulator/wheeltec-emu" --json "$work/python.json" >/dev/null
python3 - "$work/python.json" <<'PY'
import json, sys
p = json.load(open(sys.argv[1]))
rt, sub, top = p["status_round_trip"], p["subscription_1000hz"], p["subscription_ceiling"]
if not (rt["package"]["median_us"] > 0 and sub["records"] and top["records"]):
    sys.exit(f"bench smoke: the Python benchmark has no figures: {p}")
print(f"bench smoke: Python benchmark ran (status() {rt['ratio_median']:.2f}x the bare call, "
      f"{sub['records_per_s']:.0f} records/s through wheeltecd)")
PY

# The wheeltec-mqtt benchmark's quick mode (about 30 s): one robot's latencies and CPU per
# record, next to the paho-mqtt bridge's drives and broker losses, then 1 and 2 robots against one
# broker. Every figure must be there; none is compared.
run_quick mqtt "$REPO_ROOT/scripts/bench-mqtt.sh" --quick
python3 - "$work/mqtt/mqtt.json" <<'PY'
import json, sys
try:
    m = json.load(open(sys.argv[1]))
except (OSError, ValueError) as problem:
    sys.exit(f"bench smoke: the wheeltec-mqtt benchmark wrote no figures: {problem}")
problems = list(m.get("errors", []))
figures = {
    "drives over MQTT": m["drives"]["via_mqtt"]["count"],
    "drives on the daemon's socket": m["drives"]["direct_wheeltecd"]["count"],
    "drives through the paho bridge": m["drives"]["via_paho_bridge"]["count"],
    "broker hops timed (the broker's part of both bridges' drives)": m["drives"]["broker_hop"]["count"],
    "broker losses timed for wheeltec-mqtt": len(m["broker_loss"]["wheeltec_mqtt"]["rounds_ms"]),
    "broker losses timed for the paho bridge": len(m["broker_loss"]["paho_bridge"]["rounds_ms"]),
    "connection cuts timed for wheeltec-mqtt": len(m["connection_cut"]["wheeltec_mqtt"]["rounds_ms"]),
    "connection cuts timed for the paho bridge": len(m["connection_cut"]["paho_bridge"]["rounds_ms"]),
    "telemetry records matched at the MQTT subscriber": m["telemetry"]["via_mqtt"]["count"],
    "telemetry records matched at the direct subscriber": m["telemetry"]["direct_wheeltecd_subscriber"]["count"],
    "records published in the CPU window": m["cpu_per_record"]["records_published"],
    "scaling steps": len(m["scaling"]),
}
problems += [f"no {name}" for name, value in figures.items() if not value]
problems += [f"{s['robots']} robots: nothing delivered" for s in m["scaling"] if not s["delivered"]]
problems += [f"no {k} in drives" for k in ("added_p50_us", "cpu_us_per_drive") if k not in m["drives"]]
if problems:
    sys.exit("bench smoke: wheeltec-mqtt benchmark: " + "; ".join(problems))
print(f"bench smoke: wheeltec-mqtt benchmark ran ({m['elapsed_s']:.0f} s inside the VM; "
      f"{len(m['scaling'])} scaling steps)")
PY

# Its serial mode (about 20 s, natively: the benchmark plays the chassis on a pseudo-terminal):
# the drives of both bridges and on the daemon's socket, the broker's hop and the broker losses.
run_quick mqtt-serial "$REPO_ROOT/scripts/bench-mqtt.sh" --serial --quick
python3 - "$work/mqtt-serial/mqtt.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
problems = list(m.get("errors", []))
figures = {
    "drives over MQTT": m["drives"]["via_mqtt"]["count"],
    "drives on the daemon's socket": m["drives"]["direct_wheeltecd"]["count"],
    "drives through the paho bridge": m["drives"]["via_paho_bridge"]["count"],
    "broker hops timed": m["drives"]["broker_hop"]["count"],
    "broker losses timed for wheeltec-mqtt": len(m["broker_loss"]["wheeltec_mqtt"]["rounds_ms"]),
    "broker losses timed for the paho bridge": len(m["broker_loss"]["paho_bridge"]["rounds_ms"]),
    "connection cuts timed for wheeltec-mqtt": len(m["connection_cut"]["wheeltec_mqtt"]["rounds_ms"]),
    "connection cuts timed for the paho bridge": len(m["connection_cut"]["paho_bridge"]["rounds_ms"]),
}
problems += [f"no {name}" for name, value in figures.items() if not value]
if problems:
    sys.exit("bench smoke: wheeltec-mqtt benchmark on the serial line: " + "; ".join(problems))
print("bench smoke: wheeltec-mqtt benchmark ran on the serial line (natively)")
PY

# The wheeltec-ros2 benchmark's quick mode (about 45 s): cmd_vel and odom latencies against a
# Fast DDS peer, next to the daemon's own, and the bridge's CPU per record and memory. Every
# figure must be there; none is compared.
run_quick ros2 "$REPO_ROOT/scripts/bench-ros2.sh" --quick
python3 - "$work/ros2/ros2.json" <<'PY'
import json, sys
try:
    r = json.load(open(sys.argv[1]))
except (OSError, ValueError) as problem:
    sys.exit(f"bench smoke: the wheeltec-ros2 benchmark wrote no figures: {problem}")
problems = list(r.get("errors", []))
figures = {
    "cmd_vel timed to the bus": r["drives"]["via_ros2"]["count"],
    "drives on the daemon's socket": r["drives"]["direct_wheeltecd"]["count"],
    "odom samples matched at the Fast DDS reader": r["telemetry"]["via_ros2"]["count"],
    "telemetry records matched at the direct subscriber": r["telemetry"]["direct_wheeltecd_subscriber"]["count"],
    "records published in the CPU window": r["cpu_per_record"]["records_published"],
    "VmRSS of wheeltec-ros2": r["memory"]["wheeltec_ros2"]["rss_kib"],
    "VmHWM of wheeltec-ros2": r["memory"]["wheeltec_ros2"]["hwm_kib"],
}
problems += [f"no {name}" for name, value in figures.items() if not value]
if "bridge_us_per_record" not in r["cpu_per_record"]:
    problems.append("no CPU per record of wheeltec-ros2")
if problems:
    sys.exit("bench smoke: wheeltec-ros2 benchmark: " + "; ".join(problems))
print(f"bench smoke: wheeltec-ros2 benchmark ran ({r['elapsed_s']:.0f} s inside the VM; "
      f"{r['drives']['via_ros2']['count']} cmd_vel and {r['telemetry']['via_ros2']['count']} odom samples timed)")
PY

# The wheeltec-web benchmark's quick mode (about a minute): 8 Foxglove clients and the page in
# headless Chromium, and 8 over wss://, must each have received records, and the CPU and memory figures be there;
# so must the clients of wheeltec-web and of the aiohttp server in the 5 rounds of their comparison (not compared here).
if [[ -x $BUILD_DIR/web/wheeltec-web ]]; then
  run_quick web "$REPO_ROOT/scripts/bench-web.sh" --quick
  python3 - "$work/web/web.json" <<'PY'
import json, sys
w = json.load(open(sys.argv[1]))
figures = {"Foxglove messages": w["foxglove"]["viewers"]["n"], "daemon messages": w["foxglove"]["daemon"]["n"],
           "page messages": w["browser"]["page"]["n"], "records in the CPU window": w["cpu"]["records"],
           "wss:// Foxglove messages": w["tls"]["viewers"]["n"],
           "messages through the relay (the floor of one process)": (w["foxglove"].get("relayed") or {}).get("n"),
           "RSS": w["memory"]["rss_kib"]}
comparison = w.get("aiohttp") or {}
rounds = comparison.get("rounds") or []
figures["rounds against aiohttp"] = len(rounds)
figures["wheeltec-web messages in the aiohttp comparison"] = (comparison.get("wheeltec_web") or {}).get("n")
figures["aiohttp messages in the aiohttp comparison"] = (comparison.get("aiohttp") or {}).get("n")
missing = [name for name, value in figures.items() if not value]
if missing:
    sys.exit("bench smoke: wheeltec-web benchmark: no " + ", no ".join(missing))
print(f"bench smoke: wheeltec-web benchmark ran ({w['foxglove']['viewers']['n']} Foxglove, "
      f"{w['tls']['viewers']['n']} wss:// Foxglove and "
      f"{w['browser']['page']['n']} page messages timed; "
      f"{comparison['aiohttp']['n']} aiohttp messages in {len(rounds)} rounds)")
PY
fi
