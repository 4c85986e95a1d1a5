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
(cd "$BUILD_DIR" && ctest --output-on-failure "$@")
echo "== ctest done in $SECONDS s"

# Further stages that need builds of their own (sanitizers, fuzzing, packaging, cross
# builds): each is a script in scripts/test.d/, run in name order with BUILD_DIR set.
export BUILD_DIR REPO_ROOT
passed=0 failed=0
for stage in "$REPO_ROOT"/scripts/test.d/*.sh; do
  [[ -e $stage ]] || continue
  echo "== stage $(basename "$stage")"
  started=$SECONDS
  if bash "$stage"; then result=passed passed=$((passed + 1)); else result=FAILED failed=$((failed + 1)); fi
  echo "== stage $(basename "$stage") $result in $((SECONDS - started)) s"
done
if ((passed + failed > 0)); then
  echo "stages: $passed passed, $failed failed"
fi
((failed == 0))
