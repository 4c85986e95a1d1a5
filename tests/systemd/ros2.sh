#!/usr/bin/env bash
# systemd.ros2: wheeltec-ros2 as the package installs it, next to the installed wheeltecd, as
# docs/ros2.md says (enable --now). The unit is installed disabled and rated 2.0 or less by
# systemd-analyze security; under its hardening the bridge, as the user wheeltec, creates its
# DDS participant (UDP on loopback: the session has no other IP interface), connects to the
# daemon (its journal and the daemon's client count say so) and keeps running; a daemon
# restart does not restart it and it reconnects; systemctl stop ends it cleanly (exit 0) and
# closes its daemon connection; a config file with an unknown key stops it with exit 2, no
# restarts. (The bridge under load and on DDS is the ros2 suite's: tests/ros2.)
# shellcheck source=tests/systemd/lib.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

readonly BRIDGE=wheeltec-ros2
readonly BRIDGE_CONFIG=/etc/wheeltec-ros2/wheeltec-ros2.json

emulator_pid=
cleanup() {
  [[ -n $emulator_pid ]] && kill "$emulator_pid" 2>/dev/null
  if ((failures)); then
    journal_tail "$BRIDGE"
    echo "---- systemctl status $BRIDGE"
    systemctl status --no-pager -n 0 "$BRIDGE" 2>/dev/null
  fi
}

# wait_calmly SECONDS COMMAND...: as wait_for, polling every 0.5 s: a process started in User-Mode
# Linux is slow to start, and journalctl or wheeltecctl every 50 ms would take the CPU from
# the bridge that is starting.
wait_calmly() {
  local deadline
  deadline=$(awk -v s="$1" -v n="$(date +%s.%N)" 'BEGIN { printf "%.3f", n + s }')
  shift
  until "$@"; do
    awk -v d="$deadline" -v n="$(date +%s.%N)" 'BEGIN { exit !(n > d) }' && return 1
    sleep 0.5
  done
}
# section TITLE: a note with the seconds since the suite started.
section() { note "$* (at $(seconds_since "$suite_started") s)"; }
# journal_time REGEX: when the bridge's first journal line matching REGEX was written (epoch s).
journal_time() { journalctl -u "$BRIDGE" -o short-unix --no-pager | grep -m1 -- "$1" | awk '{ print $1 }'; }
bridge_state() { systemctl is-active "$BRIDGE"; }
bridge_active() { [[ $(bridge_state) == active ]]; }
bridge_failed() { [[ $(bridge_state) == failed ]]; }
bridge_pid() { systemctl show -P MainPID "$BRIDGE"; }
bridge_restarts() { systemctl show -P NRestarts "$BRIDGE"; }
# journal_count REGEX: lines of the bridge's journal (this boot) that match.
journal_count() { journalctl -u "$BRIDGE" -o cat --no-pager | grep -c -- "$1"; }
journal_has_at_least() { (($(journal_count "$1") >= $2)); }  # REGEX COUNT
# The daemon's connected clients, this wheeltecctl call included.
daemon_clients() { wheeltecctl --json stats 2>/dev/null | jq -r '.clients // empty'; }
daemon_clients_are() { [[ $(daemon_clients) == "$1" ]]; }
# udp_sockets_of PID: the UDP sockets the process holds (its DDS participant).
udp_sockets_of() { ss -Huanp 2>/dev/null | grep -c "pid=$1,"; }
has_udp_sockets() { (($(udp_sockets_of "$1") > 0)); }

section "installed disabled, hardened"
check "$BRIDGE.service is installed disabled" test "$(systemctl is-enabled "$BRIDGE")" = disabled
check_exposure "$BRIDGE"

section "the daemon and the emulated chassis"
start_ready_chassis
base_clients=$(daemon_clients)
with_bridge=$((base_clients + 1))
figure "the daemon's clients before the bridge (wheeltecctl included): $base_clients"

section "systemctl enable --now $BRIDGE (no config file: the defaults)"
enabling=$(now)
systemctl enable --now "$BRIDGE"
check "systemctl enable --now $BRIDGE" bridge_active
check "the bridge logs that it connected to wheeltecd" wait_calmly 30 journal_has_at_least 'connected to wheeltecd at /run/wheeltecd/wheeltecd.sock' 1
figure "enable --now to connected: $(seconds_since "$enabling") s (polled); started to connected in the journal: $(diff_s "$(journal_time 'Started wheeltec-ros2')" "$(journal_time 'connected to wheeltecd')") s"
check "the daemon counts one more client ($with_bridge)" wait_calmly 5 daemon_clients_are "$with_bridge"
pid=$(bridge_pid)
check "it runs as the user wheeltec" test "$(ps -o user= -p "$pid" | tr -d ' ')" = wheeltec
check "its DDS participant holds UDP sockets under RestrictAddressFamilies=" wait_calmly 5 has_udp_sockets "$pid"
figure "UDP sockets of the bridge: $(ss -Huanp 2>/dev/null | grep "pid=$pid," | awk '{print $4}' | tr '\n' ' ')"
journalctl -u "$BRIDGE" -o cat --no-pager | sed -n '1,3s/^/    journal: /p'
sleep 3
check "3 s later it still runs, same process, no restarts" \
  test "$(bridge_state) $(bridge_pid) $(bridge_restarts)" = "active $pid 0"
check "nothing in its journal at warning or worse" \
  test -z "$(journalctl -u "$BRIDGE" -p warning -o cat --no-pager | grep -v '^$')"

section "systemctl restart wheeltecd: the bridge stays and reconnects"
systemctl restart "$UNIT"
check "wheeltecd is back" wait_calmly 10 socket_answers
check "the bridge logs the lost daemon" wait_calmly 10 journal_has_at_least 'lost wheeltecd' 1
check "and connects again" wait_calmly 15 journal_has_at_least 'connected to wheeltecd' 2
check "the bridge was not restarted" test "$(bridge_state) $(bridge_pid)" = "active $pid"
check "the new daemon counts it ($with_bridge clients)" wait_calmly 5 daemon_clients_are "$with_bridge"

section "systemctl stop: a clean exit, the daemon connection closed"
systemctl stop "$BRIDGE"
check "the unit is inactive" test "$(bridge_state)" = inactive
check "the bridge exited 0" test "$(systemctl show -P ExecMainStatus "$BRIDGE")" = 0
check "its journal says it stopped on SIGTERM" journal_has_at_least 'signal 15: stopping' 1
check "the daemon's client count drops ($base_clients)" wait_calmly 5 daemon_clients_are "$base_clients"

section "a config file with an unknown key: exit 2, no restart loop"
install -d -m 0755 /etc/wheeltec-ros2
printf '{"domain_id": 3, "bogus": true}\n' >"$BRIDGE_CONFIG"
restarts_before=$(bridge_restarts)
systemctl start "$BRIDGE"
check "the unit fails" wait_calmly 20 bridge_failed
check "with exit status 2" test "$(systemctl show -P ExecMainStatus "$BRIDGE")" = 2
# A restart that systemd had scheduled would show as "activating" (auto-restart), not "failed".
check "and no restart (RestartPreventExitStatus=2): failed, restarts still $restarts_before" \
  test "$(bridge_state) $(bridge_restarts)" = "failed $restarts_before"
check "the journal names the key" journal_has_at_least "$BRIDGE_CONFIG: bogus: unknown key" 1
journalctl -u "$BRIDGE" -o cat --no-pager | grep 'unknown key' | sed 's/^/    journal: /'

cleanup
finish
