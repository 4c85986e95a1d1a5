#!/usr/bin/env bash
# Test stage: every vcan integration suite again, with wheeltecd and wheeltec-emu
# running under Valgrind's memcheck.
# AddressSanitizer cannot run where the vcan suites run on this kind of host: inside
# User-Mode Linux a process has a 39-bit address space and its stack lies where ASan
# wants its shadow memory, so the ASan runtime aborts at start-up (see 20-sanitizers.sh,
# which runs ASan natively on everything that needs no CAN interface). memcheck finds
# the same kinds of errors (invalid reads and writes, use after free, uninitialised
# values, leaks) in the programs as they drive the CAN paths.
#
# The verdict is memcheck's: the stage fails when any program reports an error, is
# killed by a signal it did not expect, or when the tests cannot run at all. Test
# assertions that fail only because memcheck makes the programs 20-50 times slower
# (latency bounds, control periods) are listed but do not fail this stage: the plain
# ctest run, before the stages, is where the tests' own verdict counts.
#   MEMCHECK_DIR   where the wrappers and logs go (default $BUILD_DIR-memcheck)
#   MEMCHECK_JOBS  suites run at once (default 3)
set -euo pipefail

REPO_ROOT=${REPO_ROOT:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}
BUILD_DIR=${BUILD_DIR:-$REPO_ROOT/build}
# shellcheck source=scripts/lib/setup.sh
source "$REPO_ROOT/scripts/lib/setup.sh"
install_packages valgrind

work=${MEMCHECK_DIR:-$BUILD_DIR-memcheck}
rm -rf -- "$work"
mkdir -p "$work/bin" "$work/logs"

declare -A programs=(
  [wheeltecd]=$BUILD_DIR/daemon/wheeltecd
  [wheeltec-emu]=$BUILD_DIR/emulator/wheeltec-emu
)
# wheeltecctl is left out: it touches no CAN socket, its logic runs under ASan in the unit tests (20-sanitizers.sh),
# and valgrind's start-up in UML (~3 s) would add minutes to the Wheeltecctl suite.
ln -s "$BUILD_DIR/cli/wheeltecctl" "$work/bin/wheeltecctl"
# --vgdb=no: no gdbserver pipes. Their names in /tmp hold the process id, and two suites
# run at once in two User-Mode Linux sessions that share the host's /tmp and repeat process
# ids: one valgrind removed the other's pipes, which then wrote "could not unlink
# /tmp/vgdb-pipe-..." into its log, a line that is not a report but failed the stage.
for name in "${!programs[@]}"; do
  [[ -x ${programs[$name]} ]] || { echo "memcheck: ${programs[$name]} is not built" >&2; exit 1; }
  cat >"$work/bin/$name" <<EOF
#!/bin/sh
exec valgrind --quiet --vgdb=no --error-exitcode=99 --leak-check=full --show-leak-kinds=definite,indirect \\
  --errors-for-leak-kinds=definite,indirect --log-file=$work/logs/$name.\${MEMCHECK_SUITE:-all}.%p.log ${programs[$name]} "\$@"
EOF
  chmod +x "$work/bin/$name"
done

echo "memcheck: vcan integration suites with the programs under valgrind (logs in $work/logs)"
# Valgrind needs 2-5 s to start a program inside UML.
export WHEELTEC_BIN_DIR=$work/bin WHEELTEC_TEST_START_ALLOWANCE_S=20
# EmulatorFidelity is left out: three minutes under valgrind for the emulator's physics,
# which the unit tests and the other emulator suites cover.
suites=$(cd "$BUILD_DIR" && ctest -N -L vcan -LE soak | sed -n 's/^ *Test *#[0-9]*: integration\.\(.*\)$/\1/p' |
  grep -vx EmulatorFidelity)
[[ -n $suites ]] || { echo "memcheck: no vcan suites found in $BUILD_DIR" >&2; exit 1; }
# Three suites at a time, each in its own vcan-run session: under valgrind a suite spends
# most of its time waiting, and timing failures do not count here. Process ids repeat
# across sessions, so each log is named after its suite too.
parallel=${MEMCHECK_JOBS:-3}
run_suite() {
  local suite=$1 status=0
  MEMCHECK_SUITE=$suite timeout 900 "$REPO_ROOT/scripts/vcan-run" -- "$BUILD_DIR/tests/integration/integration_tests" \
    --gtest_filter="$suite.*" --gtest_color=no --gtest_brief=1 >"$work/$suite.out" 2>&1 || status=$?
  echo "$status" >"$work/$suite.status"
}
for suite in $suites; do
  while (($(jobs -rp | wc -l) >= parallel)); do wait -n || true; done
  run_suite "$suite" &
done
wait

failed=0
for suite in $suites; do
  output=$work/$suite.out
  status=$(<"$work/$suite.status")
  slow=$(grep '^\[  FAILED  \] .*(' "$output" | sed 's/^\[  FAILED  \] \([^ ]*\).*/\1/' | tr '\n' ' ' || true)
  summary=$(grep -m1 '^\[==========\] .* ran\.' "$output" || true)
  if [[ -z $summary ]]; then
    echo "memcheck: $suite did not run to the end (exit $status):" >&2
    tail -n 30 "$output" >&2
    failed=1
    continue
  fi
  echo "memcheck: $suite: $summary${slow:+; tests that failed under memcheck (timing; not counted here): $slow}"
done

reports=0
for log in "$work"/logs/*.log; do
  [[ -e $log ]] || continue
  # With --quiet a log holds nothing but the reports (lines "==PID== ...").
  if grep -qv '^==[0-9]*== *$' "$log"; then
    echo "memcheck: report in $(basename "$log"):" >&2
    cat "$log" >&2
    reports=$((reports + 1))
  fi
done
count=$(find "$work/logs" -name '*.log' | wc -l)
echo "memcheck: $count program runs checked, $reports with reports"
((count > 0)) || { echo "memcheck: no program ran under valgrind" >&2; failed=1; }
((reports == 0)) || failed=1
exit "$failed"
