#!/usr/bin/env bash
# systemd.safety: the robot is stopped when the daemon itself fails under the installed
# unit. SIGKILL: systemd restarts it and its first control frame is zero. A hung daemon
# (SIGSTOP while a client drives): the kernel's deadman (CAN_BCM) puts the zero frame on
# the bus within 1 s, then the watchdog kills and restarts the daemon.
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

systemctl stop "$UNIT"
finish
