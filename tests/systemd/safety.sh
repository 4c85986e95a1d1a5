#!/usr/bin/env bash
# systemd.safety: the robot is stopped when the daemon itself fails under the installed
# unit. SIGKILL: systemd restarts it and its first control frame is zero. A hung daemon
# (SIGSTOP while a client drives): the kernel's deadman (CAN_BCM) puts the zero frame on
# the bus within 1 s, then the watchdog kills and restarts the daemon. The emergency stop's
# latch, with the shipped config (safety.state_file in the unit's StateDirectory), survives
# `systemctl restart`: drives stay refused, only zero frames leave, until root releases it.
# shellcheck source=tests/systemd/lib.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

bus_start
systemctl start "$UNIT"
check "systemctl start $UNIT" is_active

# first_control_frame_since EPOCH: "TIMESTAMP ID#DATA" of the first control frame at or
# after EPOCH.
first_control_frame_since() { frames_since "$1" | control_frames | head -n 1; }
new_daemon_sent_a_control_frame() { [[ -n $(first_control_frame_since "$1") ]]; }

note "SIGKILL while a client drives at 0.25 m/s"
drive_in_background root 0.25
check "the client drives: 121#00FA... on the bus" wait_for 5 frame_seen_after "" 121#00FA000000000000
old_pid=$(main_pid)
killed=$(now)
systemctl kill -s KILL "$UNIT"
check "systemd restarts the daemon (new MainPID, active)" wait_for 10 pid_changed_and_active "$old_pid"
figure "SIGKILL to active again: $(seconds_since "$killed") s (RestartSec=$(systemctl show -P RestartUSec "$UNIT"))"
drive_stop
new_start=$(unit_start_time)
check "the new daemon sends control frames" wait_for 5 new_daemon_sent_a_control_frame "$new_start"
first=$(first_control_frame_since "$new_start")
figure "first control frame of the restarted daemon (pid $(main_pid)): ${first#* }, $(diff_s "$new_start" "${first%% *}") s after its start"
check "the restarted daemon's first control frame is zero" test "${first#* }" = "$ZERO_FRAME"
frames_since "$new_start" | awk 'NR <= 3' | sed 's/^/    bus: /'

note "hung daemon: SIGSTOP while a client drives at 0.25 m/s"
drive_in_background root 0.25
mark=$(bus_mark)
check "the client drives: 121#00FA... on the bus" wait_for 5 frame_seen_after "$mark" 121#00FA000000000000
old_pid=$(main_pid)
restarts_before=$(systemctl show -P NRestarts "$UNIT")
# The window is measured from just before the SIGSTOP (an upper bound); "nothing but zero
# since the hang" from just after it (a frame of the last period may still leave between).
hung=$(now)
kill -STOP "$old_pid"
hung_after=$(now)
zero_after_hang() { frames_since "$hung" | awk -v z="$ZERO_FRAME" '$2 == z { found = 1 } END { exit !found }'; }
wait_for 5 zero_after_hang
zero_ts=$(frames_since "$hung" | awk -v z="$ZERO_FRAME" '$2 == z { print $1; exit }')
if [[ -n $zero_ts ]]; then
  window=$(diff_s "$hung" "$zero_ts")
  figure "hang-to-zero window: $(printf '%.2f' "$window") s"
  check "the zero frame is on the bus within 1 s of the hang ($window s)" at_most "$window" 1.0
else
  fail "no zero frame on the bus within 5 s of the hang"
fi
nonzero_after_zero=$( [[ -n $zero_ts ]] && frames_since "$zero_ts" | nonzero_control_frames | head -n 1)
check "no non-zero control frame after it" test -z "$nonzero_after_zero"

note "the watchdog (WatchdogSec=$(systemctl show -P WatchdogUSec "$UNIT")) kills and restarts the hung daemon"
check "a new MainPID, the service active again" wait_for 15 pid_changed_and_active "$old_pid"
figure "SIGSTOP to active again: $(seconds_since "$hung") s"
drive_stop
check "systemd counted a restart (NRestarts $restarts_before -> $(systemctl show -P NRestarts "$UNIT"))" \
  test "$(systemctl show -P NRestarts "$UNIT")" -gt "$restarts_before"
check "systemd logged the watchdog timeout" \
  bash -c "journalctl -u $UNIT -o cat --no-pager | grep -qi 'watchdog timeout'"
journalctl -u "$UNIT" -o cat --no-pager | grep -i 'watchdog' | tail -n 2 | sed 's/^/    journal: /'
new_start=$(unit_start_time)
check "the new daemon sends control frames" wait_for 5 new_daemon_sent_a_control_frame "$new_start"
first=$(first_control_frame_since "$new_start")
figure "first control frame of the new daemon (pid $(main_pid)): ${first#* }"
check "the new daemon's first control frame is zero" test "${first#* }" = "$ZERO_FRAME"
check "no non-zero control frame since the hang" test -z "$(frames_since "$hung_after" | nonzero_control_frames)"

note "the latch survives systemctl restart (safety.state_file $(jq -r '.safety.state_file' "$CONFIG"))"
readonly STATE_DIR=/var/lib/wheeltecd STATE_FILE=/var/lib/wheeltecd/safety.json
check "the shipped config keeps the latch in $STATE_FILE" json_is ".safety.state_file == \"$STATE_FILE\"" "$CONFIG"
check "the unit has StateDirectory=wheeltecd" test "$(systemctl show -P StateDirectory "$UNIT")" = wheeltecd
check "$STATE_DIR exists, wheeltec's, 0750 (StateDirectoryMode=)" \
  test "$(stat -c '%U:%G %a' "$STATE_DIR" 2>&1)" = "wheeltec:wheeltec 750"
safety_of() { wheeltecctl --json status 2>/dev/null | jq -c '.safety'; }  # prints the status's safety object
useradd --create-home --shell /bin/bash eve
usermod -aG wheeltec eve  # eve can connect: the socket's group
expect_ok eve estop test
latched=$(safety_of)
figure "safety after eve's estop: $latched"
check "status: latched by a client, reason \"test\", since and by set" json_is \
  '.latched == true and .source == "client" and .reason == "test" and (.since | type) == "number" and (.by | type) == "number"' <<<"$latched"
check "the state file is there after the estop" test -s "$STATE_FILE"
figure "$STATE_FILE: $(stat -c '%U:%G %a' "$STATE_FILE" 2>&1), $(cat "$STATE_FILE" 2>&1)"
old_pid=$(main_pid)
systemctl restart "$UNIT"
check "systemctl restart $UNIT: a new MainPID, active" pid_changed_and_active "$old_pid"
check "the restarted daemon answers" wait_for 10 socket_answers
restored=$(safety_of)
figure "safety after the restart: $restored"
same_latch() {  # the latch of $latched, with the same source, reason and since
  jq -e --argjson before "$latched" \
    '.latched == true and ([.source, .reason, .since] == [$before.source, $before.reason, $before.since])' \
    <<<"$restored" >/dev/null
}
check "status: still latched, same source, reason and since" same_latch
mark=$(bus_mark)
expect_code -32007 root drive 0.25 0 0 --for 1
zero_frames_after_mark() { (($(frames_after "$mark" | control_frames | wc -l) >= 5)); }
check "the latched daemon keeps sending control frames" wait_for 5 zero_frames_after_mark
check "all of them zero" test -z "$(frames_after "$mark" | nonzero_control_frames)"
frames_after "$mark" | control_frames | sort -u -k2,2 | sed 's/^/    bus: /'
expect_ok root release
check "status: not latched" json_is '.latched == false' <<<"$(safety_of)"
mark=$(bus_mark)
expect_ok root drive 0.25 0 0 --for 1
check "a drive then moves: 121#00FA... on the bus" wait_for 5 frame_seen_after "$mark" 121#00FA000000000000

systemctl stop "$UNIT"
finish
