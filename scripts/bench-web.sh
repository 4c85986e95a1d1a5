#!/usr/bin/env bash
# Runs the benchmark of wheeltec-web, the live view (issue #14), and prints its figures:
# wheeltec-emu, wheeltecd and wheeltec-web on vcan0 in one scripts/vcan-run session (User-Mode
# Linux on hosts without SocketCAN), measured by bench/web/web_bench.cjs:
#   1. 0x103 frame (kernel timestamp) -> the record at 8 Foxglove clients, p50/p99, next to a
#      direct subscriber of wheeltecd in the same run;
#   2. wheeltec-web's CPU per record with those 8 viewers (10 ms ticks), its system calls per
#      record (strace -c, exact), and its RSS; what it adds over the daemon's subscriber;
#   3. wheeltec-web against a Python aiohttp Foxglove server (bench/web/aiohttp_foxglove.py, issue
#      #44: at most 0.8x its p50): the same clients at each, 5 alternating rounds of 2 s (--quick:
#      0.5 s) at each server, only one server's clients subscribed at a time; the medians of the
#      rounds' p50 and p99, and their ratio. Needs Debian's python3-aiohttp (/usr/bin/python3);
#   4. the same latency at the page in headless Chromium, next to the daemon's subscriber.
#   (--no-browser leaves 4 out.)
# Telemetry at 50 Hz for 20 s per run; --quick: 5 s, to check that it works.
#
#   scripts/bench-web.sh [--quick] [--no-browser] [--viewers N] [--serial]
#
# --viewers N: N Foxglove clients instead of 8 (1: what one viewer sees, with no other
# viewer's send before its own). --serial: the emulator and the daemon on a pseudo-terminal,
# natively, without scripts/vcan-run (the figures of this host without User-Mode Linux).
#
# BUILD_DIR (default build/) must hold wheeltec-emu, wheeltecd and wheeltec-web; npm's
# Foxglove client is installed into BUILD_DIR/tests/web/node from tests/web/package-lock.json
# when it is not there yet. Writes $BENCH_OUT (default $BUILD_DIR/bench-results)/web-table.md.
set -euo pipefail

REPO_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD_DIR=${BUILD_DIR:-$REPO_ROOT/build}
BENCH_OUT=${BENCH_OUT:-$BUILD_DIR/bench-results}
seconds=20
browser=
viewers=8
link=
while (($#)); do
  case $1 in
    --quick) seconds=5 ;;
    --no-browser) browser=--no-browser ;;  # the Foxglove rounds only (Chromium in a loaded VM takes minutes)
    --serial) link=--serial ;;
    --viewers)
      [[ ${2:-} =~ ^[1-9][0-9]*$ ]] || { echo "bench-web.sh: --viewers needs a number of 1 or more" >&2; exit 2; }
      viewers=$2
      shift ;;
    -h|--help) sed -n '2,25p' "$0"; exit 0 ;;
    *) echo "bench-web.sh: unknown argument $1" >&2; exit 2 ;;
  esac
  shift
done

for program in emulator/wheeltec-emu daemon/wheeltecd web/wheeltec-web; do
  [[ -x $BUILD_DIR/$program ]] || { echo "bench-web.sh: $BUILD_DIR/$program is not built" >&2; exit 1; }
done
/usr/bin/python3 -c 'import aiohttp' 2>/dev/null ||
  { echo "bench-web.sh: /usr/bin/python3 cannot import aiohttp (the comparison's server): install python3-aiohttp" >&2; exit 1; }
node_dir=$BUILD_DIR/tests/web/node
if [[ ! -d $node_dir/node_modules/@foxglove/ws-protocol ]]; then
  mkdir -p "$node_dir"
  cp "$REPO_ROOT/tests/web/package.json" "$REPO_ROOT/tests/web/package-lock.json" "$node_dir/"
  (cd "$node_dir" && npm ci --no-audit --no-fund >/dev/null)
fi
mkdir -p "$BENCH_OUT"

started=$SECONDS
status=0
runner=("$REPO_ROOT/scripts/vcan-run" --)
where="including the virtual machine's boot"
if [[ -n $link ]]; then
  runner=()
  where=natively
fi
"${runner[@]}" "$REPO_ROOT/bench/web/session.sh" "$BUILD_DIR" "$node_dir/node_modules" 50 "$seconds" "$viewers" $browser $link \
  >"$BENCH_OUT/web-run.txt" || status=$?
{
  echo "Run $(date -u '+%Y-%m-%d %H:%M UTC'), $(uname -m), $(nproc) CPUs, load average $(cut -d' ' -f1-3 /proc/loadavg), $((SECONDS - started)) s $where; telemetry at 50 Hz, ${seconds} s per run, $viewers Foxglove clients, ${link:-on vcan0 through scripts/vcan-run}."
  echo
  grep -v '^{' "$BENCH_OUT/web-run.txt" || true
} >"$BENCH_OUT/web-table.md"
grep '^{' "$BENCH_OUT/web-run.txt" | tail -n 1 >"$BENCH_OUT/web.json" || true
echo
cat "$BENCH_OUT/web-table.md"
echo
echo "bench-web.sh: figures in $BENCH_OUT (web-table.md, web.json)"
exit "$status"
