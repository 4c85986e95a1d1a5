#!/usr/bin/env bash
# Soak test of wheeltecd: builds soak_driver if needed and runs it inside
# scripts/vcan-run (User-Mode Linux when the kernel has no vcan).
#
#   scripts/soak.sh [--build-dir DIR] [--duration SECONDS (60)] [--link-period SECONDS (4)]
#                   [--max-stall-periods N (2)] [--keep]
#                   [--daemon-scheduling unit|default|nice:N|rr:N|fifo:N (unit)]
#                   [--observer-scheduling nice:N|rr:N|fifo:N]
#
# The emulator sends telemetry at 200 Hz with --drop, --corrupt and --reorder, the link
# goes down and up every --link-period seconds, and 16 clients subscribe, drive, stall
# and reconnect; the daemon is scheduled as systemd/wheeltecd.service schedules it.
# Exits non-zero when any check fails (see tests/soak/soak_driver.cpp).
set -euo pipefail

REPO_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${BUILD_DIR:-$REPO_ROOT/build}
driver_args=()
while (($#)); do
  case $1 in
    --build-dir) build_dir=$2; shift 2 ;;
    --duration|--link-period|--max-stall-periods|--daemon-scheduling|--observer-scheduling) driver_args+=("$1" "$2"); shift 2 ;;
    --keep) driver_args+=("$1"); shift ;;
    -h|--help) sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "soak.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done

if [[ ! -f $build_dir/CMakeCache.txt ]]; then
  cmake -S "$REPO_ROOT" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo
fi
cmake --build "$build_dir" -j "${BUILD_JOBS:-2}" --target soak_driver
exec "$REPO_ROOT/scripts/vcan-run" -- "$build_dir/tests/soak/soak_driver" "${driver_args[@]}"
