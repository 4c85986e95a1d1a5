#!/usr/bin/env bash
# The test command: installs what is missing (Debian 12), configures a fresh build
# directory (build/, or $BUILD_DIR), builds, and runs every unit and vcan
# integration test with ctest. The integration tests run where vcan0 exists:
# natively when possible, else inside User-Mode Linux (see scripts/vcan-run).
set -euo pipefail

REPO_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# shellcheck source=scripts/lib/setup.sh
source "$REPO_ROOT/scripts/lib/setup.sh"

install_dependencies tests
configure_and_build
echo "== build done in $SECONDS s"

# Further stages that need builds of their own (sanitizers, fuzzing, packaging, cross
# builds): each is a script in scripts/test.d/, run in name order with BUILD_DIR set.
export BUILD_DIR REPO_ROOT
# Each stage's output is also kept in $BUILD_DIR-stages/, so that the end of the log can
# repeat why a stage failed: a CI report often shows no more than the log's last lines.
stage_logs=$BUILD_DIR-stages
rm -rf -- "$stage_logs"
mkdir -p "$stage_logs"
export STAGE_LOGS=$stage_logs

# Programs freshly built start slowly the first time inside User-Mode Linux on a busy host
# (their pages come in through hostfs): the harnesses allow this much more for a start.
export WHEELTEC_TEST_START_ALLOWANCE_S=${WHEELTEC_TEST_START_ALLOWANCE_S:-5}
# While ctest runs, the stages that build trees of their own (the sanitizer, fuzzing and
# arm64 builds) build them beside it in the idle scheduling class: they get only the
# processor time the tests leave, and a test's process that wakes takes its core back at
# once. Run afterwards, each stage finds its tree built. WHEELTEC_STAGE_BUILD_ONLY=1 stops
# a stage after its build. The fuzzing stage, which judges no timing, then runs whole
# beside ctest too, one target at a time (about one core is left over beside the timed
# suite): its result and output are reported in its turn below.
builds_beside=() stages_beside=()
for name in 20-sanitizers 30-fuzz 60-arm64; do
  if [[ -e $REPO_ROOT/scripts/test.d/$name.sh ]]; then builds_beside+=("$name"); fi
done
if [[ -e $REPO_ROOT/scripts/test.d/30-fuzz.sh ]]; then stages_beside+=(30-fuzz); fi
beside_pid=
stop_builds_beside() {
  [[ -n $beside_pid ]] && kill -- "-$beside_pid" 2>/dev/null
  return 0
}
trap stop_builds_beside EXIT
# setsid: a session of their own, so that an early exit (an interrupt) ends them all.
# Where the idle class cannot be had, the lowest nice value.
STAGES_BESIDE="${stages_beside[*]}" setsid bash -c '
  chrt --idle -p 0 $$ 2>/dev/null || renice -n 19 -p $$ >/dev/null 2>&1 || true
  ionice -c 3 -p $$ 2>/dev/null || true
  for name; do
    started=$SECONDS
    if WHEELTEC_STAGE_BUILD_ONLY=1 bash "$REPO_ROOT/scripts/test.d/$name.sh" >"$STAGE_LOGS/$name.build.log" 2>&1; then
      echo "== stage $name.sh built beside ctest in $((SECONDS - started)) s"
    else
      echo "== stage $name.sh: its build beside ctest failed, the stage builds again ($STAGE_LOGS/$name.build.log)"
    fi
  done
  for name in $STAGES_BESIDE; do
    started=$SECONDS result=passed
    FUZZ_JOBS=1 bash "$REPO_ROOT/scripts/test.d/$name.sh" >"$STAGE_LOGS/$name.log" 2>&1 || result=FAILED
    echo "$result $((SECONDS - started))" >"$STAGE_LOGS/$name.beside"
    echo "== stage $name.sh $result beside ctest in $((SECONDS - started)) s"
  done' _ "${builds_beside[@]}" &
beside_pid=$!
# Two tests at a time by default (CTEST_PARALLEL_LEVEL=N runs N): the suites that time the
# programs take turns, and beside one of them run only the unit tests and the systemd
# session (tests/CMakeLists.txt, WHEELTEC_TAKES_TURNS).
# A failed test does not end the command: the stages still run, so that one report shows
# every failure and every stage's time; the command fails at the end.
ctest_result=passed
if ! (cd "$BUILD_DIR" && ctest --output-on-failure -j "${CTEST_PARALLEL_LEVEL:-2}" "$@"); then
  ctest_result=FAILED
fi
echo "== ctest $ctest_result, done in $SECONDS s"
wait "$beside_pid" || true
beside_pid=
echo "== the work beside ctest done in $SECONDS s"
passed=0 failed_stages=()
for stage in "$REPO_ROOT"/scripts/test.d/*.sh; do
  [[ -e $stage ]] || continue
  name=$(basename "$stage" .sh)
  if [[ -f $stage_logs/$name.beside ]]; then
    read -r result took <"$stage_logs/$name.beside"
    echo "== stage $name.sh (it ran beside ctest)"
    cat -- "$stage_logs/$name.log"
    if [[ $result == passed ]]; then passed=$((passed + 1)); else failed_stages+=("$name"); fi
    echo "== stage $name.sh $result in $took s, beside ctest"
    continue
  fi
  echo "== stage $name.sh"
  started=$SECONDS
  if bash "$stage" 2>&1 | tee "$stage_logs/$name.log"; then
    result=passed passed=$((passed + 1))
  else
    result=FAILED failed_stages+=("$name")
  fi
  echo "== stage $name.sh $result in $((SECONDS - started)) s"
done
for name in "${failed_stages[@]}"; do
  echo "== FAILED stage $name.sh, its last 60 lines (all of it: $stage_logs/$name.log):"
  tail -n 60 "$stage_logs/$name.log"
done
if ((passed + ${#failed_stages[@]} > 0)); then
  echo "stages: $passed passed, ${#failed_stages[@]} failed${failed_stages[*]:+: ${failed_stages[*]}}"
fi
if [[ $ctest_result == FAILED ]]; then
  echo "== FAILED ctest: these tests failed (their output is in ctest's part of the log):"
  cat -- "$BUILD_DIR/Testing/Temporary/LastTestsFailed.log" 2>/dev/null || true
fi
[[ $ctest_result == passed ]] && ((${#failed_stages[@]} == 0))
