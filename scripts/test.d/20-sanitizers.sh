#!/usr/bin/env bash
# Test stage: the unit and integration tests again under sanitizers.
#   1. AddressSanitizer + LeakSanitizer + UndefinedBehaviorSanitizer build: the unit tests
#      and the integration suites that need no CAN interface, run natively.
#   2. UndefinedBehaviorSanitizer build: every vcan integration suite (ctest -L vcan),
#      which scripts/vcan-run runs inside User-Mode Linux on a kernel without SocketCAN.
#      ASan and LSan cannot run there: their shadow memory and allocator need address
#      ranges that UML's processes do not have (the runtime aborts at start-up);
#      25-memcheck.sh runs those suites with the programs under valgrind instead. Where
#      vcan-run runs natively, the ASan build runs the vcan suites as well.
# Any sanitizer report fails the stage: reports make the process fail (halt_on_error,
# abort_on_error), and UBSan reports are also written to files that are checked at the end.
#   SANITIZER_BUILD_DIR  prefix of the two build directories (default $BUILD_DIR-sanitizers)
set -euo pipefail

REPO_ROOT=${REPO_ROOT:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}
BUILD_DIR=${BUILD_DIR:-$REPO_ROOT/build}
prefix=${SANITIZER_BUILD_DIR:-$BUILD_DIR-sanitizers}
jobs=${BUILD_JOBS:-2}
reports=$prefix-reports
rm -rf -- "$reports"
mkdir -p "$reports"

configure_and_build_with() {
  local dir=$1 flags=$2
  shift 2
  cmake -S "$REPO_ROOT" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMAKE_CXX_FLAGS="$flags -fno-sanitize-recover=undefined -fno-omit-frame-pointer" \
    -DCMAKE_EXE_LINKER_FLAGS="$flags" -DWHEELTEC_BUILD_BENCHMARKS=OFF -DWHEELTEC_BUILD_FUZZERS=OFF >/dev/null
  cmake --build "$dir" -j "$jobs" --target "$@"
}

export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:log_path=$reports/ubsan"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1:detect_stack_use_after_return=1"

failed=0
asan=$prefix/asan-ubsan
echo "sanitizers: AddressSanitizer + UndefinedBehaviorSanitizer build in $asan"
configure_and_build_with "$asan" "-fsanitize=address,undefined" unit_tests
echo "sanitizers: unit tests (ASan, LSan, UBSan)"
"$asan/tests/unit/unit_tests" --gtest_color=no --gtest_brief=1 || failed=1
cmake --build "$asan" -j "$jobs" --target integration_tests
echo "sanitizers: command-line integration tests (ASan, LSan, UBSan)"
"$asan/tests/integration/integration_tests" --gtest_filter='CommandLine.*' --gtest_color=no --gtest_brief=1 || failed=1

# Where scripts/vcan-run runs natively (a host with the vcan module), ASan and LSan work
# for the vcan suites too.
if "$REPO_ROOT/scripts/vcan-run" -- sh -c 'test -z "${VCAN_RUN_IN_UML:-}"' 2>/dev/null; then
  echo "sanitizers: vcan integration tests natively (ASan, LSan, UBSan)"
  (cd "$asan" && ctest -L vcan -LE soak --output-on-failure) || failed=1
else
  echo "sanitizers: vcan0 is in User-Mode Linux here: the vcan suites run under UBSan only (and memcheck, 25-memcheck.sh)"
fi

ubsan=$prefix/ubsan
echo "sanitizers: UndefinedBehaviorSanitizer build in $ubsan"
configure_and_build_with "$ubsan" "-fsanitize=undefined" integration_tests
echo "sanitizers: vcan integration tests (UBSan)"
(cd "$ubsan" && ctest -L vcan -LE soak --output-on-failure) || failed=1

if compgen -G "$reports/ubsan*" >/dev/null; then
  echo "sanitizers: UndefinedBehaviorSanitizer reports:" >&2
  cat "$reports"/ubsan* >&2
  failed=1
fi
exit "$failed"
