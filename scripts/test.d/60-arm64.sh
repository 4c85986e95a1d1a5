#!/usr/bin/env bash
# arm64: cross-compiles the three programs and the unit tests for aarch64 with Debian's
# cross compiler and :arm64 multiarch libraries (cmake/toolchain-aarch64.cmake), then
# runs the unit tests under qemu-user. Integration tests need vcan and stay native.
set -euo pipefail
: "${REPO_ROOT:?}" "${BUILD_DIR:?}"
source "$REPO_ROOT/scripts/lib/setup.sh"

add_arm64_architecture
install_packages "${WHEELTEC_ARM64_PACKAGES[@]}"

arm_build=$BUILD_DIR/arm64  # removed with the build directory
# Release: what a robot runs; without RelWithDebInfo's debug information the cross build,
# most of this stage, takes about a quarter less.
cmake -S "$REPO_ROOT" -B "$arm_build" -G Ninja -DCMAKE_BUILD_TYPE=Release "${WHEELTEC_FRESH_TREE_OPTIONS[@]}" \
  -DCMAKE_TOOLCHAIN_FILE="$REPO_ROOT/cmake/toolchain-aarch64.cmake" \
  -DWHEELTEC_BUILD_BENCHMARKS=OFF -DWHEELTEC_BUILD_FUZZERS=OFF
cmake --build "$arm_build" -j "${BUILD_JOBS:-2}" --target wheeltecd wheeltecctl wheeltec-emu unit_tests
[[ -z ${WHEELTEC_STAGE_BUILD_ONLY:-} ]] || exit 0  # scripts/test.sh builds this beside ctest

for program in daemon/wheeltecd cli/wheeltecctl emulator/wheeltec-emu tests/unit/unit_tests; do
  description=$(file -b "$arm_build/$program")
  echo "$program: $description"
  [[ $description == *"ARM aarch64"* ]] || { echo "arm64: $program is not an aarch64 executable"; exit 1; }
done

export QEMU_LD_PREFIX=/usr/aarch64-linux-gnu
qemu-aarch64 "$arm_build/daemon/wheeltecd" --version
# Under qemu-user a process that changes its credentials (setgroups, setgid, setuid, even
# as raw system calls) never returns, so the test that connects as another user runs
# natively only (in ctest). The timeout makes any other hang fail this stage, not the run.
# The stall sentinel's tests fork the sentinel, whose process closes every descriptor it does
# not use, qemu-user's own among them: under qemu it never runs (natively, and under valgrind
# in the memcheck stage, it does).
(cd "$arm_build/tests/unit" && timeout --signal=KILL 900 qemu-aarch64 ./unit_tests --gtest_color=no --gtest_brief=1 \
  --gtest_filter=-PeerCredentials.SupplementaryGroupsComeFromTheKernelAsAtConnect:StallSentinelTest.*)
