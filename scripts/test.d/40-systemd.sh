#!/usr/bin/env bash
# The shipped systemd units: `systemd-analyze verify` passes on each, and the service's
# `systemd-analyze security` exposure is 2.0 or lower. Both work offline, without a
# running systemd. The unit's ExecStart= is pointed at the freshly built binary so that
# verify can check it is executable; everything else is verified as shipped.
set -euo pipefail
: "${REPO_ROOT:?}" "${BUILD_DIR:?}"
source "$REPO_ROOT/scripts/lib/setup.sh"
install_packages systemd

work=$(mktemp -d)
trap 'rm -rf -- "$work"' EXIT

status=0
# Every unit first, so that one that Requires= another (wheeltec-web: wheeltecd) finds it.
for unit in "$REPO_ROOT"/systemd/*.service; do
  name=$(basename "$unit")
  sed -e "s|^ExecStart=/usr/bin/wheeltecd|ExecStart=$BUILD_DIR/daemon/wheeltecd|" \
      -e "s|^ExecStart=/usr/bin/wheeltec-mqtt|ExecStart=$BUILD_DIR/mqtt/wheeltec-mqtt|" \
      -e "s|^ExecStart=/usr/bin/wheeltec-web|ExecStart=$BUILD_DIR/web/wheeltec-web|" \
      -e "s|^ExecStart=/usr/bin/wheeltec-ros2|ExecStart=$BUILD_DIR/ros2/wheeltec-ros2|" \
      -e "s|^ExecStart=/usr/bin/wheeltec-record|ExecStart=$BUILD_DIR/record/wheeltec-record|" "$unit" >"$work/$name"
done
for unit in "$REPO_ROOT"/systemd/*.service; do
  name=$(basename "$unit")
  if output=$(systemd-analyze verify --man=no "$work/$name" 2>&1) && [[ -z $output ]]; then
    echo "verify $name: OK"
  else
    echo "verify $name: FAILED"; echo "$output"; status=1
  fi
  # --threshold is on the 0-100 scale of the report's 0.0-10.0 figure.
  report=$(systemd-analyze security --offline=true --threshold=20 "$unit" 2>&1) || {
    echo "$report"; echo "security $name: exposure above 2.0"; status=1
  }
  echo "security $name: $(grep -o 'Overall exposure level.*' <<<"$report")"
done
exit "$status"
