#!/usr/bin/env bash
# The test command: installs what is missing (Debian 12), configures a fresh build
# directory (build/, or $BUILD_DIR), builds, and runs every unit and vcan
# integration test with ctest. The integration tests run where vcan0 exists:
# natively when possible, else inside User-Mode Linux (see scripts/vcan-run).
set -euo pipefail

REPO_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
# shellcheck source=scripts/lib/setup.sh
source "$REPO_ROOT/scripts/lib/setup.sh"

install_dependencies
configure_and_build
cd "$BUILD_DIR"
ctest --output-on-failure "$@"
