#!/usr/bin/env bash
# Test stage: the tests again under AddressSanitizer + LeakSanitizer +
# UndefinedBehaviorSanitizer, in one build:
#   - the unit tests always (they need no CAN interface and run on the host);
#   - the serial suites and the daemon's events suites always (ctest -L serial, ctest -R
#     '^record\.Events': wheeltecd and wheeltec-emu on pseudo-terminals, which need no CAN
#     interface either);
#   - where scripts/vcan-run runs natively (a host with the vcan module), also the
#     integration suites that need no CAN interface and every vcan suite (ctest -L vcan).
#   - Inside User-Mode Linux (a kernel without SocketCAN) the vcan suites are not run
#     here: ASan and LSan cannot run there (their shadow memory and allocator need
#     address ranges that UML's processes do not have; the runtime aborts at start-up).
#     There the programs' memory is checked by 25-memcheck.sh (valgrind, every vcan
#     suite), and the parsers by the fuzz stage (30-fuzz.sh, ASan + UBSan).
# Any sanitizer report fails the stage: reports make the process fail (halt_on_error,
# abort_on_error), and UBSan reports are also written to files that are checked at the end.
#   SANITIZER_BUILD_DIR  the build directory (default $BUILD_DIR-sanitizers)
set -euo pipefail

REPO_ROOT=${REPO_ROOT:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}
BUILD_DIR=${BUILD_DIR:-$REPO_ROOT/build}
# shellcheck source=scripts/lib/setup.sh
source "$REPO_ROOT/scripts/lib/setup.sh"
install_packages "${WHEELTEC_CLANG_PACKAGES[@]}"
prefix=${SANITIZER_BUILD_DIR:-$BUILD_DIR-sanitizers}
jobs=${BUILD_JOBS:-2}
reports=$prefix-reports
rm -rf -- "$reports"
mkdir -p "$reports"

# clang, -O1 -g1 (line tables only): the build is the stage's longest part, clang builds
# this code under the sanitizers in two thirds of g++'s time, and a report needs no more
# than function names and lines.
configure_and_build_with() {
  local dir=$1 flags=$2
  shift 2
  cmake -S "$REPO_ROOT" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE= -DCMAKE_CXX_COMPILER=clang++-14 \
    "${WHEELTEC_FRESH_TREE_OPTIONS[@]}" \
    -DCMAKE_CXX_FLAGS="$flags -O1 -g1 -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
    -DCMAKE_EXE_LINKER_FLAGS="$flags" -DWHEELTEC_BUILD_BENCHMARKS=OFF -DWHEELTEC_BUILD_FUZZERS=OFF >/dev/null
  cmake --build "$dir" -j "$jobs" --target "$@"
}

export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:log_path=$reports/ubsan"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1"

failed=0
build=$prefix
targets=(unit_tests serial_tests record_tests)
# The unit tests of the optional parts, where the main build has them.
unit_programs=(tests/unit/unit_tests)
for program in tests/mqtt/mqtt_unit_tests tests/web/web_unit_tests tests/ros2/unit/ros2_unit_tests \
    tests/mcap/mcap_unit_tests tests/record/unit/record_unit_tests tests/record/unit/black_box_tests; do
  if [[ -f $BUILD_DIR/$program ]]; then
    unit_programs+=("$program")
    targets+=("$(basename "$program")")
  fi
done
if [[ $("$REPO_ROOT/scripts/vcan-run" --where 2>/dev/null) == native ]]; then
  vcan=native
  targets+=(integration_tests)
else
  vcan=uml
fi
echo "sanitizers: ASan, LSan and UBSan build of ${targets[*]} in $build"
configure_and_build_with "$build" "-fsanitize=address,undefined" "${targets[@]}"
[[ -z ${WHEELTEC_STAGE_BUILD_ONLY:-} ]] || exit 0  # scripts/test.sh builds this beside ctest
echo "sanitizers: unit tests"
for program in "${unit_programs[@]}"; do
  "$build/$program" --gtest_color=no --gtest_brief=1 || failed=1
done
echo "sanitizers: serial suites"
# As many at once as in the test command's own ctest run (scripts/test.sh).
ctest_jobs=${CTEST_PARALLEL_LEVEL:-1}
(cd "$build" && ctest -j "$ctest_jobs" -L serial --output-on-failure) || failed=1
echo "sanitizers: the daemon's events suites"
(cd "$build" && ctest -j "$ctest_jobs" -R '^record\.Events' --output-on-failure) || failed=1
if [[ $vcan == native ]]; then
  echo "sanitizers: command-line integration tests"
  "$build/tests/integration/integration_tests" --gtest_filter='CommandLine.*:EmulatorCommandLine.*' --gtest_color=no \
    --gtest_brief=1 || failed=1
  echo "sanitizers: vcan integration tests"
  (cd "$build" && ctest -L vcan -LE soak --output-on-failure) || failed=1
else
  echo "sanitizers: vcan0 is in User-Mode Linux here, where ASan cannot run: the vcan suites run under valgrind (25-memcheck.sh)"
fi

if compgen -G "$reports/ubsan*" >/dev/null; then
  echo "sanitizers: UndefinedBehaviorSanitizer reports:" >&2
  cat "$reports"/ubsan* >&2
  failed=1
fi
exit "$failed"
