# shellcheck shell=bash disable=SC2034,SC2154
# Sourced by scripts/bench-mqtt.sh and scripts/bench-ros2.sh: their command line and the end of a run
# (their QUICK, SERIAL and `extra`; their `started` and `status`).
# BUILD_DIR (default /tmp/build-bench) and BENCH_OUT (default $BUILD_DIR/bench-results).
BUILD_DIR=${BUILD_DIR:-/tmp/build-bench}
BENCH_OUT=${BENCH_OUT:-$BUILD_DIR/bench-results}

# bench_arguments HELP_LINES ALLOWED "$@": sets QUICK (--quick), SERIAL (--serial, when ALLOWED is
# "--serial") and `extra` (the arguments after --); -h prints the script's lines HELP_LINES.
bench_arguments() {
  local help_lines=$1 allowed=$2
  shift 2
  QUICK=0 SERIAL=0 extra=()
  while (($#)); do
    case "$1" in
      --quick) QUICK=1 ;;
      --) shift; extra=("$@"); break ;;
      -h|--help) sed -n "$help_lines" "$0"; exit 0 ;;
      *) [[ -n $allowed && $1 == "$allowed" ]] || { echo "${0##*/}: unknown argument $1" >&2; exit 2; }; SERIAL=1 ;;
    esac
    shift
  done
}

# bench_report NAME WHERE: the run's line (time taken since $started, WHERE) above the benchmark's
# table $BENCH_OUT/NAME-table.body.md in NAME-table.md, printed; exits with $status.
bench_report() {
  {
    echo "Run $(date -u '+%Y-%m-%d %H:%M UTC'), $(uname -m), $(nproc) CPUs ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)), load average $(cut -d' ' -f1-3 /proc/loadavg), $((SECONDS - started)) s$2."
    echo
    cat "$BENCH_OUT/$1-table.body.md"
  } >"$BENCH_OUT/$1-table.md"
  rm -f "$BENCH_OUT/$1-table.body.md"
  echo
  cat "$BENCH_OUT/$1-table.md"
  echo
  echo "bench-$1.sh: figures in $BENCH_OUT ($1-table.md, $1.json)"
  exit "$status"
}
