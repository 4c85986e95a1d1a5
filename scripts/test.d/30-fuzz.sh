#!/usr/bin/env bash
# Test stage: builds the libFuzzer targets (fuzz/) with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer (LeakSanitizer included), and runs each for a bounded time
# from its seed corpus in fuzz/corpus/<target>/. Fails on any crash, leak, timeout or
# sanitizer report; the reproducer is left in the build directory's fuzz-artifacts/.
#   FUZZ_SECONDS   time per target (default 20)
#   FUZZ_JOBS      targets run at once (default: the number of cores)
#   FUZZ_BUILD_DIR build directory (default $BUILD_DIR-fuzz)
set -euo pipefail

REPO_ROOT=${REPO_ROOT:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)}
BUILD_DIR=${BUILD_DIR:-$REPO_ROOT/build}
# shellcheck source=scripts/lib/setup.sh
source "$REPO_ROOT/scripts/lib/setup.sh"
install_packages "${WHEELTEC_CLANG_PACKAGES[@]}"

seconds=${FUZZ_SECONDS:-20}
build=${FUZZ_BUILD_DIR:-$BUILD_DIR-fuzz}
jobs=${BUILD_JOBS:-2}
targets=(rpc_line telemetry_frames link_messages candump_log config serial_frames fixed_decimal control mqtt_command web_foxglove
  mcap_reader)

cmake -S "$REPO_ROOT" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "${WHEELTEC_FRESH_TREE_OPTIONS[@]}" \
  -DCMAKE_CXX_COMPILER=clang++-14 \
  -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer" \
  -DWHEELTEC_BUILD_FUZZERS=ON -DWHEELTEC_BUILD_TESTS=OFF -DWHEELTEC_BUILD_BENCHMARKS=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target "${targets[@]/#/fuzz_}"
[[ -z ${WHEELTEC_STAGE_BUILD_ONLY:-} ]] || exit 0  # scripts/test.sh builds this beside ctest

artifacts=$build/fuzz-artifacts
mkdir -p "$artifacts"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# One libFuzzer process is one thread: the targets run FUZZ_JOBS at a time (default: a core each).
parallel=${FUZZ_JOBS:-$(nproc 2>/dev/null || echo 2)}
run_target() {
  local target=$1 corpus=$build/fuzz-corpus/$1 status=0
  # New inputs go to a scratch corpus; the repository's seeds stay as they are.
  rm -rf -- "$corpus"
  mkdir -p "$corpus"
  "$build/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len=8192 -print_final_stats=1 -artifact_prefix="$artifacts/$target-" \
    "$corpus" "$REPO_ROOT/fuzz/corpus/$target" >"$build/fuzz-$target.log" 2>&1 || status=$?
  echo "$status" >"$build/fuzz-$target.status"
}
echo "fuzz: ${#targets[@]} targets for ${seconds} s each, $parallel at a time"
for target in "${targets[@]}"; do
  while (($(jobs -rp | wc -l) >= parallel)); do wait -n || true; done
  run_target "$target" &
done
wait
failed=0
for target in "${targets[@]}"; do
  if [[ $(<"$build/fuzz-$target.status") == 0 ]]; then
    grep -E '^stat::number_of_executed_units|^stat::peak_rss_mb' "$build/fuzz-$target.log" | sed "s/^/fuzz: $target /"
  else
    echo "fuzz: $target FAILED; last lines of $build/fuzz-$target.log:" >&2
    tail -n 40 "$build/fuzz-$target.log" >&2
    failed=1
  fi
done
exit "$failed"
