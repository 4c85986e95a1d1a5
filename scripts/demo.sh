#!/usr/bin/env bash
# The demo: installs what is missing (Debian 12), builds, and then, on vcan0,
# starts the chassis emulator and the daemon, streams telemetry, drives the
# emulated robot for 3 s while its measured velocity shows in the telemetry,
# prints the status, and stops everything cleanly.
set -euo pipefail

REPO_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# shellcheck source=scripts/lib/setup.sh
source "$REPO_ROOT/scripts/lib/setup.sh"

install_dependencies
# The three programs the session runs, nothing else.
WHEELTEC_BUILD_TESTS=OFF WHEELTEC_BUILD_BENCHMARKS=OFF configure_and_build wheeltecd wheeltecctl wheeltec-emu
exec "$REPO_ROOT/scripts/vcan-run" -- "$REPO_ROOT/scripts/lib/demo-session.sh" "$BUILD_DIR"
