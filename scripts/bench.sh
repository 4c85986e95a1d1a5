#!/usr/bin/env bash
# Runs every benchmark of issue #6 and prints the figures:
#   1. the Google Benchmark microbenchmarks (bench/), natively;
#   2. the native fan-out benchmark: wheeltecd's telemetry path from the frame read to 64
#      subscriber sockets, fed through a SOCK_SEQPACKET socket instead of CAN, against the
#      relay floor fed the same way (the throughput target, measured without UML's costs);
#   3. the end-to-end benchmark (wheeltecd against the raw-socket floors) on vcan0
#      through scripts/vcan-run (User-Mode Linux on hosts without SocketCAN);
#   4. the serial link natively on a pseudo-terminal (wheeltec-bench-serial): drive -> command
#      frame and record -> notification, set beside the same two figures on vcan from 3.
# Writes $BENCH_OUT (default: $BUILD_DIR/bench-results) /microbench.json, fanout.json,
# e2e.json, serial.json and table.md. Takes a few minutes; the 30 s idle measurement is the
# longest part.
#
#   scripts/bench.sh [--quick]      --quick: short runs, to check that everything works
#
# BUILD_DIR (default /tmp/build-bench) is configured and built if needed.
set -euo pipefail

REPO_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD_DIR=${BUILD_DIR:-/tmp/build-bench}
BENCH_OUT=${BENCH_OUT:-$BUILD_DIR/bench-results}
QUICK=0
case "${1:-}" in
  --quick) QUICK=1 ;;
  "") ;;
  -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
  *) echo "bench.sh: unknown argument $1" >&2; exit 2 ;;
esac

# shellcheck source=lib/setup.sh
source "$REPO_ROOT/scripts/lib/setup.sh"
install_packages libbenchmark-dev can-utils strace valgrind

if [[ ! -f $BUILD_DIR/build.ninja ]]; then
  cmake -S "$REPO_ROOT" -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DWHEELTEC_BUILD_BENCHMARKS=ON >/dev/null
fi
cmake --build "$BUILD_DIR" --target wheeltec-microbench wheeltec-bench-fanout wheeltec-bench-e2e wheeltec-bench-floor \
  wheeltec-bench-serial wheeltecd -j2
mkdir -p "$BENCH_OUT"

min_time=0.5
e2e_args=()
fanout_args=()
serial_args=()
if ((QUICK)); then
  min_time=0.05
  e2e_args=(--commands 200 --idle-seconds 2 --flood-seconds 2)
  fanout_args=(--step-s 0.3 --max-rate 2000)
  serial_args=(--quick)
fi

echo "== microbenchmarks (native, $(nproc) CPUs) =="
"$BUILD_DIR/bench/wheeltec-microbench" --benchmark_min_time="$min_time" \
  --benchmark_out="$BENCH_OUT/microbench.json" --benchmark_out_format=json

micro_table=$(python3 - "$BENCH_OUT/microbench.json" <<'PY'
import json, sys
targets = {"BM_ReassembleAndDecodeRecord": 20e6, "BM_TelemetryNotificationJson": 1e6}
print("| microbenchmark | ns/op (CPU) | items/s | target | |")
print("|---|---|---|---|---|")
for b in json.load(open(sys.argv[1]))["benchmarks"]:
    rate = b.get("items_per_second", 0)
    target = targets.get(b["name"])
    verdict = "" if target is None else ("met" if rate >= target else "**missed**")
    target_text = "" if target is None else f">= {target/1e6:g} M/s"
    print(f"| {b['name']} | {b['cpu_time']:.1f} | {rate/1e6:.2f} M/s | {target_text} | {verdict} |")
PY
)

echo "== fan-out (native: wheeltecd's telemetry path, a frame socket in place of CAN) =="
"$BUILD_DIR/bench/wheeltec-bench-fanout" --floor "$BUILD_DIR/bench/wheeltec-bench-floor" \
  --json "$BENCH_OUT/fanout.json" "${fanout_args[@]}"

fanout_table=$(python3 - "$BENCH_OUT/fanout.json" <<'PY'
import json, sys
f = json.load(open(sys.argv[1]))
def at(name, rate, key):
    step = next((s for s in f[name]["steps"] if s["rate_hz"] == rate), None)
    return f"{step[key]:.0f}" if step else "-"
d, r = f["wheeltecd"]["max_no_loss_rate_hz"], f["floor"]["max_no_loss_rate_hz"]
print(f"| native fan-out to {f['subscribers']} subscribers (frame socket in place of CAN) | wheeltecd | relay floor | target | |")
print("|---|---|---|---|---|")
print(f"| highest rate with no loss, records/s (steps x2 from 500) | {d:.0f} | {r:.0f} | >= 2000 | {'met' if d >= 2000 else '**missed**'} |")
for rate in (2000.0, 8000.0):
    print(f"| CPU per record at {rate:.0f}/s, us (exact: thread CPU clock, schedstat) | {at('wheeltecd', rate, 'gateway_cpu_us_per_record')} | {at('floor', rate, 'gateway_cpu_us_per_record')} | | |")
PY
)

echo "== end-to-end (vcan0 through scripts/vcan-run) =="
cangen=$(command -v cangen || true)
# strace and callgrind count the daemon's system calls and instructions exactly (the CPU time
# that UML reports is sampled in 10 ms ticks); each adds a separate measurement of idle_s.
profilers=(--strace "$(command -v strace)" --valgrind "$(command -v valgrind)"
           --callgrind-control "$(command -v callgrind_control)")
# Where vcan cannot be had (no vcan0 and no User-Mode Linux) the serial run below still runs,
# and bench.sh fails at the end.
rm -f "$BENCH_OUT/e2e.json"
e2e_failed=0
"$REPO_ROOT/scripts/vcan-run" -- "$BUILD_DIR/bench/wheeltec-bench-e2e" \
  --wheeltecd "$BUILD_DIR/daemon/wheeltecd" --floor "$BUILD_DIR/bench/wheeltec-bench-floor" \
  ${cangen:+--cangen "$cangen"} "${profilers[@]}" --json "$BENCH_OUT/e2e.json" "${e2e_args[@]}" \
  >"$BENCH_OUT/e2e-table.md" || e2e_failed=1

# Idle CPU from the exact counts, priced at this host's native per-call costs (microbenchmarks).
idle_table="(no end-to-end figures: the run on vcan failed)"
[[ -f $BENCH_OUT/e2e.json ]] && idle_table=$(python3 - "$BENCH_OUT/microbench.json" "$BENCH_OUT/e2e.json" <<'PY'
import json, re, sys
micro = {b["name"].split("/")[0]: b for b in json.load(open(sys.argv[1]))["benchmarks"]}
e2e = json.load(open(sys.argv[2]))
ns = lambda name: 1e9 / micro[name]["items_per_second"]
syscall_ns = max(ns("BM_SyscallClockGettime"), ns("BM_SyscallEpollWaitNoWait"), ns("BM_SyscallUnixSocketWriteAndRead"))
wakeup_ns = ns("BM_WakeupFromBlockingRead")
mhz = max(float(m) for m in re.findall(r"cpu MHz\s*:\s*([\d.]+)", open("/proc/cpuinfo").read()))
def column(idle, counted, instructions):
    seconds = counted["seconds"]
    syscalls = counted["syscalls"]["total"] / seconds
    wakeups = idle["voluntary_switches_per_s"]  # from the run without strace (each ptrace stop is a switch)
    ips = instructions["instructions_per_s"]
    us = (syscalls * syscall_ns + wakeups * wakeup_ns + ips / (mhz * 1e6) * 1e9) / 1e3
    return syscalls, wakeups, ips, us
try:
    d = column(e2e["wheeltecd"]["idle"], e2e["wheeltecd"]["idle_counted"], e2e["wheeltecd"]["idle_instructions"])
    r = column(e2e["floor"]["relay_idle"], e2e["floor"]["relay_idle_counted"], e2e["floor"]["relay_idle_instructions"])
except (KeyError, TypeError) as missing:
    print(f"(idle counts not available: {missing!r} missing; see the end-to-end run's messages)")
    sys.exit(0)
print("| idle, 1 subscriber at 20 Hz: counted in UML, priced natively | wheeltecd | relay floor | target | |")
print("|---|---|---|---|---|")
print(f"| system calls/s (strace -c -f -p, {e2e['wheeltecd']['idle_counted']['seconds']:.0f} s) | {d[0]:.1f} | {r[0]:.1f} | | |")
print(f"| wakeups/s (voluntary context switches, /proc, the idle run without strace) | {d[1]:.1f} | {r[1]:.1f} | | |")
print(f"| user-space instructions/s (callgrind, {e2e['wheeltecd']['idle_instructions']['seconds']:.0f} s) | {d[2]:.0f} | {r[2]:.0f} | | |")
print(f"| priced at {syscall_ns:.0f} ns per system call, {wakeup_ns:.0f} ns per wakeup, 1 instruction per cycle at {mhz:.0f} MHz: CPU us/s | {d[3]:.0f} | {r[3]:.0f} | | |")
print(f"| estimated idle CPU on this host natively (% of a core) | {d[3]/1e4:.3f} | {r[3]/1e4:.3f} | < 0.2 | {'met' if d[3]/1e4 < 0.2 else '**missed**'} |")
spec = e2e["floor"].get("spec_floor_idle_instructions")
if spec:
    ips = spec["instructions_per_s"]
    print(f"| user-space instructions/s of the spec floor (the relay plus the spec's work per record and control period, callgrind) | wheeltecd {d[2] / ips:.2f}x it | {ips:.0f}, {ips / r[2]:.2f}x the relay | | |")
print(f"| user-space instructions: wheeltecd against the relay | {d[2] / r[2]:.2f}x | | | |")
PY
)

echo "== serial link (native, a pseudo-terminal) =="
"$BUILD_DIR/bench/wheeltec-bench-serial" --wheeltecd "$BUILD_DIR/daemon/wheeltecd" --json "$BENCH_OUT/serial.json" \
  "${serial_args[@]}" | tee "$BENCH_OUT/serial-table.md"

# The serial figures beside the same two on vcan from the end-to-end run above.
serial_table=$(python3 - "$BENCH_OUT/serial.json" "$BENCH_OUT/e2e.json" <<'PY'
import json, sys
serial = json.load(open(sys.argv[1]))["wheeltecd"]
try:
    vcan = json.load(open(sys.argv[2]))["wheeltecd"]
except (OSError, ValueError, KeyError):
    vcan = None  # the end-to-end run wrote no figures
def cell(source, key, field):
    return f"{source[key][field]:.0f}" if source and key in source else "-"
print("| wheeltecd, serial against CAN (us) | serial: pty, native | CAN: vcan0, end-to-end run above |")
print("|---|---|---|")
for key, what in (("command_latency", "drive -> command frame read by the benchmark"),
                  ("telemetry_latency_1", "record's last byte (CAN: 0x103) written -> notification, 1 subscriber")):
    n = f"n={serial[key]['count']}" + (f" / {vcan[key]['count']}" if vcan and key in vcan else "")
    for field in ("p50_us", "p99_us"):
        print(f"| {what}, {field[:3]} ({n}) | {cell(serial, key, field)} | {cell(vcan, key, field)} |")
PY
)

{
  echo "Run $(date -u '+%Y-%m-%d %H:%M UTC'), $(uname -m), $(nproc) CPUs ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)), load average $(cut -d' ' -f1-3 /proc/loadavg)."
  echo
  echo "$micro_table"
  echo
  echo "$fanout_table"
  echo
  cat "$BENCH_OUT/e2e-table.md"
  echo
  echo "$idle_table"
  echo
  cat "$BENCH_OUT/serial-table.md"
  echo
  echo "$serial_table"
} >"$BENCH_OUT/table.md"
echo
cat "$BENCH_OUT/table.md"
echo
echo "bench.sh: figures in $BENCH_OUT (table.md, microbench.json, fanout.json, e2e.json, serial.json)"
if ((e2e_failed)); then
  echo "bench.sh: the end-to-end run on vcan failed (its messages are above); the serial figures stand alone" >&2
  exit 1
fi
