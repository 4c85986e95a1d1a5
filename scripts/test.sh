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

# ctest leaves much of the processor idle (the suites wait on the emulated chassis, on
# timers and on User-Mode Linux), so the stages' own builds (those that call
# end_of_stage_build) run meanwhile, at the idle scheduling class: they get only the time
# the tests do not want, and the tests run as on a quiet machine. A stage whose build
# failed here builds again when it runs, and reports the error then.
for stage in "$REPO_ROOT"/scripts/test.d/*.sh; do
  if grep -q '^end_of_stage_install' "$stage"; then
    STAGE_INSTALL_ONLY=1 bash "$stage"
  fi
done
stage_builds() {
  chrt --idle -p 0 "$BASHPID" >/dev/null 2>&1 || renice -n 19 -p "$BASHPID" >/dev/null
  local stage
  for stage in "$REPO_ROOT"/scripts/test.d/*.sh; do
    grep -q '^end_of_stage_build' "$stage" || continue
    STAGE_BUILD_ONLY=1 bash "$stage" >"$stage_logs/$(basename "$stage" .sh).build.log" 2>&1 || true
  done
}
stage_builds_started=$SECONDS
set -m  # the builds in a process group of their own, to be stopped as one if ctest fails
stage_builds &
stage_builds_pid=$!
set +m
ctest_status=0
(cd "$BUILD_DIR" && ctest --output-on-failure "$@") || ctest_status=$?
echo "== ctest done in $SECONDS s"
if ((ctest_status != 0)); then
  kill -TERM -- "-$stage_builds_pid" 2>/dev/null || true
  wait "$stage_builds_pid" || true
  exit "$ctest_status"
fi
wait "$stage_builds_pid"
echo "== the stages' builds done in $((SECONDS - stage_builds_started)) s (beside ctest)"
passed=0 failed_stages=()
for stage in "$REPO_ROOT"/scripts/test.d/*.sh; do
  [[ -e $stage ]] || continue
  name=$(basename "$stage" .sh)
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
((${#failed_stages[@]} == 0))
