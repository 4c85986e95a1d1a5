#!/usr/bin/env bash
# systemd.rights: who may connect, read and drive, decided from the kernel's credentials
# of the socket's peer (SO_PEERCRED, SO_PEERGROUPS) under the installed unit, which
# hides other users' /proc entries from the daemon (ProtectProc=invisible). Real users
# and groups, made as an admin makes them; commands run as them with runuser.
# shellcheck source=tests/systemd/lib.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

note "the installed unit with the shipped configuration"
systemctl start "$UNIT"
check "systemctl start $UNIT" is_active
check "the unit hides /proc of other users (ProtectProc=invisible)" \
  test "$(systemctl show -P ProtectProc "$UNIT")" = invisible
check "the socket is the group wheeltec's, mode 0660" \
  test "$(stat -c '%G %a' "$WHEELTEC_SOCKET")" = "wheeltec 660"

useradd --create-home --shell /bin/bash alice
note "root"
expect_ok root drive 0.1 0 0 --for 0
note "alice before she joins: outside the socket's group"
expect_unreachable alice status

note "the one command of docs/deploy.md: $(drive_permission_command)"
check "docs/deploy.md names the command" test -n "$(drive_permission_command)"
run_doc_command_for alice "$(drive_permission_command)"
check "alice's primary group is still alice; wheeltec is a supplementary group" \
  test "$(id -gn alice)" = alice -a -n "$(id -nG alice | tr ' ' '\n' | grep -x wheeltec)"
expect_ok alice status
expect_ok alice drive 0.2 0 0 --for 0
check "alice's drive was accepted as sent" result_is '.vx == 0.2'
expect_ok alice disable
expect_ok alice enable

note "a viewers' group for the socket: api.group = wheeltec-view, api.control_users = [bob]"
groupadd wheeltec-view
for user in bob carol dave; do useradd --create-home --shell /bin/bash "$user"; done
# The daemon's user must be in api.group to give the socket that group (docs/deploy.md).
for user in wheeltec alice bob carol; do usermod -aG wheeltec-view "$user"; done
set_config '.api.group = "wheeltec-view" | .api.control_users = ["bob"]'
systemctl restart "$UNIT"
check "restarted with the new api.group" is_active
check "the socket is the group wheeltec-view's, mode 0660" \
  test "$(stat -c '%G %a' "$WHEELTEC_SOCKET")" = "wheeltec-view 660"

note "root, alice (control_groups via a supplementary group), bob (control_users) drive"
expect_ok root drive 0.1 0 0 --for 0
expect_ok alice drive 0.1 0 0 --for 0
expect_ok bob drive 0.1 0 0 --for 0
expect_ok bob disable
expect_ok bob enable

note "carol: in the socket's group only: reads and stops, may not drive"
expect_ok carol status
rpc_as carol telemetry
check "carol reaches the daemon for telemetry (a record or -32004, no chassis here)" test "$RPC_RC" -eq 0 -o "$(grep -c "code -32004" <<<"$RPC_ERR")" -eq 1
expect_ok carol stats
expect_ok carol stop
expect_code -32005 carol drive 0.1 0 0 --for 0
expect_code -32005 carol enable
expect_code -32005 carol disable
check "control is still enabled after carol's refused disable" \
  json_is '.control.enabled == true' <<<"$(wheeltecctl --json status)"

note "dave: outside the socket's group"
expect_unreachable dave status
expect_unreachable dave stop

finish
