#!/usr/bin/env bash
# systemd.lifecycle: the package's life cycle on a systemd machine, in the order of
# docs/deploy.md: install (user and group wheeltec, service disabled), configure (check
# the config, the one command that lets a user drive), enable --now with the shipped
# config, upgrade with dpkg -i (a running service is restarted, an edited conffile
# kept), remove (the service stops with a zero frame), purge (the configuration goes).
# Run by scripts/systemd-uml --no-install: this script installs the package itself.
# shellcheck source=tests/systemd/lib.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"
: "${SYSTEMD_UML_DEB:?the package to install}"
package=wheeltec-gateway

note "docs/deploy.md 4. Installing: dpkg -i"
installing=$(now)
DEBIAN_FRONTEND=noninteractive dpkg -i "$SYSTEMD_UML_DEB"
check "dpkg -i succeeded" test $? -eq 0
figure "dpkg -i took $(seconds_since "$installing") s"
version=$(dpkg-query -W -f='${Version}' "$package")
check "installed: $package $version" test "$(dpkg-query -W -f='${db:Status-Status}' "$package")" = installed
check "the system group wheeltec exists" bash -c "getent group wheeltec >/dev/null"
check "the system user wheeltec exists, in group wheeltec, uid < 1000" \
  test "$(id -gn wheeltec)" = wheeltec -a "$(id -u wheeltec)" -lt 1000
check "the service is installed disabled" test "$(systemctl is-enabled "$UNIT")" = disabled
check "and not started" test "$(systemctl is-active "$UNIT")" = inactive
check "the conffile lets the group wheeltec drive" \
  json_is '.api.control_groups == ["wheeltec"]' "$CONFIG"

note "docs/deploy.md 5. Configuring: check the configuration; let a user drive"
check "wheeltecd --check-config accepts the shipped file" \
  wheeltecd --config "$CONFIG" --check-config >/dev/null
useradd --create-home --shell /bin/bash owner
command=$(drive_permission_command)
note "as the docs say, for the user owner: $command"
run_doc_command_for owner "$command"
check "owner is in group wheeltec" bash -c "id -nG owner | tr ' ' '\n' | grep -qx wheeltec"

note "docs/deploy.md 6. Enabling and checking: systemctl enable --now"
systemctl enable --now "$UNIT"
check "systemctl enable --now succeeded" test $? -eq 0
check "enabled" test "$(systemctl is-enabled "$UNIT")" = enabled
check "active" is_active
status_json=$(wheeltecctl --json status)
check "wheeltecctl status: bus can0 up (the shipped config)" \
  json_is '.bus.interface == "can0" and .bus.state == "up"' <<<"$status_json"
systemctl status --no-pager "$UNIT" | sed -n 's/^ *Status: /    systemctl status: Status: /p'
check "journalctl -u $UNIT has the daemon's lines" test -n "$(journalctl -u "$UNIT" -o cat --no-pager | grep -v '^$' | head -n 1)"

note "docs/deploy.md 7. Driving: owner drives"
expect_ok owner drive 0.2 0 0 --for 0.3

note "docs/deploy.md 8. Upgrading: dpkg -i of a newer version"
set_config '.control.limits.vx = 0.5'
unpacked=$work/unpacked
dpkg-deb -R "$SYSTEMD_UML_DEB" "$unpacked"
new_version="$version+1"
sed -i "s/^Version: .*/Version: $new_version/" "$unpacked/DEBIAN/control"
dpkg-deb -b "$unpacked" "$work/newer.deb" >/dev/null
old_pid=$(main_pid)
upgrading=$(now)
DEBIAN_FRONTEND=noninteractive dpkg -i "$work/newer.deb" </dev/null
check "dpkg -i of $new_version succeeded" test $? -eq 0
figure "upgrade took $(seconds_since "$upgrading") s"
check "installed version is $new_version" test "$(dpkg-query -W -f='${Version}' "$package")" = "$new_version"
check "the running service was restarted (MainPID $old_pid -> $(main_pid))" pid_changed_and_active "$old_pid"
check "still enabled" test "$(systemctl is-enabled "$UNIT")" = enabled
check "the edited conffile was kept" json_is '.control.limits.vx == 0.5' "$CONFIG"
check "no conffile left behind as .dpkg-dist or .dpkg-new" \
  bash -c "! ls /etc/wheeltecd/ | grep -q 'dpkg-'"
rpc_as root drive 0.8 0 0 --for 0
check "the restarted daemon uses the edited limit: drive 0.8 comes back 0.5" \
  result_is '.vx == 0.5 and .clamped == true'

note "docs/deploy.md 8. Removing: dpkg -r stops the service with a zero frame"
bus_start
drive_in_background root 0.25
check "a client drives: 121#00FA... on the bus" wait_for 5 frame_seen_after "" 121#00FA000000000000
mark=$(bus_mark)
dpkg -r "$package"
check "dpkg -r succeeded" test $? -eq 0
drive_stop
check "the service is stopped" bash -c "! systemctl is-active --quiet $UNIT"
frames_after "$mark" | awk '$2 ~ /^121#/' | tail -n 3 | sed 's/^/    bus: /'
last_two=$(frames_after "$mark" | awk '$2 ~ /^121#/' | tail -n 2 | awk '{ print $2 }' | tr '\n' ' ')
check "the daemon's last frames: zero control frame, then disable" test "$last_two" = "$ZERO_FRAME $DISABLE_FRAME "
check "the programs are gone" bash -c "! command -v wheeltecd"
check "remove keeps the configuration" test -f "$CONFIG"

note "docs/deploy.md 8. Purging: dpkg -P removes the configuration"
dpkg -P "$package"
check "dpkg -P succeeded" test $? -eq 0
check "/etc/wheeltecd is gone" test ! -e /etc/wheeltecd
check "the enablement symlink is gone" test ! -e /etc/systemd/system/multi-user.target.wants/wheeltecd.service -a ! -L /etc/systemd/system/multi-user.target.wants/wheeltecd.service
if getent passwd wheeltec >/dev/null; then figure "after purge the user wheeltec stays (Debian policy)"
else figure "after purge the user wheeltec is gone"; fi

finish
