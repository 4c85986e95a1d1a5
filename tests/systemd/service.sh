#!/usr/bin/env bash
# systemd.service: the daemon as systemd runs it from the installed unit: ready means
# listening (Type=notify), STATUS= in systemctl status, log priorities in the journal,
# reload, stop with zero velocity then disable, and the scheduling the unit asks for.
# shellcheck source=tests/systemd/lib.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

bus_start

note "systemctl start: Type=notify, ready once the socket listens"
started=$(now)
systemctl start "$UNIT"
start_rc=$?
# One try, no polling: when systemctl start returns, the socket must answer.
socket_answers
answers=$?
figure "systemctl start returned after $(seconds_since "$started") s"
check "systemctl start $UNIT succeeded" test "$start_rc" -eq 0
check "the socket answers right after systemctl start returned" test "$answers" -eq 0
check "the unit is Type=notify" test "$(systemctl show -P Type "$UNIT")" = notify
pid=$(main_pid)

status_text=$(systemctl show -P StatusText "$UNIT")
status_out=$(systemctl status --no-pager "$UNIT")
figure "STATUS= of the daemon: \"$status_text\""
check "the daemon sent a STATUS= line" test -n "$status_text"
check "systemctl status shows it" grep -qF "Status: \"$status_text\"" <<<"$status_out"

note "scheduling: SCHED_RR 10 (ExecStartPost chrt) or the Nice=-10 fallback"
policy=$(chrt -p "$pid" | sed -n 's/.*scheduling policy: //p')
priority=$(chrt -p "$pid" | sed -n 's/.*scheduling priority: //p')
nice=$(awk '{ print $19 }' "/proc/$pid/stat")
if [[ $policy == SCHED_RR && $priority == 10 ]]; then
  figure "scheduling applied: SCHED_RR priority 10 (chrt by ExecStartPost)"
  pass "the daemon runs at SCHED_RR 10"
elif [[ $policy == SCHED_OTHER && $nice == -10 ]]; then
  figure "scheduling applied: SCHED_OTHER nice -10 (the kernel refused SCHED_RR; Nice= fallback)"
  pass "the daemon runs at the Nice=-10 fallback"
else
  fail "the daemon runs at $policy priority $priority nice $nice, neither SCHED_RR 10 nor nice -10"
fi

note "systemctl reload: control.limits.vx 1.0 -> 0.3"
rpc_as root drive 0.8 0 0 --for 0
check "before: drive 0.8 is sent as 0.8" result_is '.vx == 0.8 and .clamped == false'
set_config '.control.limits.vx = 0.3'
systemctl reload "$UNIT"
check "systemctl reload succeeded" test $? -eq 0
clamped_to_0_3() { rpc_as root drive 0.8 0 0 --for 0; result_is '.vx == 0.3 and .clamped == true'; }
mark=$(bus_mark)
check "after reload: drive 0.8 comes back clamped to 0.3" wait_for 5 clamped_to_0_3
check "the frame on the bus says 300 mm/s (121#012C...)" wait_for 2 frame_seen_after "$mark" 121#012C000000000000
check "same main process after reload" test "$(main_pid)" = "$pid"

note "an invalid file is refused and logged; the old configuration keeps working"
cp "$CONFIG" "$work/good.json"
echo '{"control": {"limits": {"vx": "fast"}}}' >"$CONFIG"
reload_marker="invalid config test $(date +%s%N)"
logger -t systemd-test "$reload_marker"
systemctl reload "$UNIT"
refused_logged() {
  journalctl -u "$UNIT" -p err -o cat --no-pager | grep -q 'SIGHUP: .*keeping the running configuration'
}
check "the refusal is in the journal at priority err" wait_for 5 refused_logged
journalctl -u "$UNIT" -p err -o cat --no-pager | grep 'keeping the running configuration' | tail -n 1 | sed 's/^/    journal: /'
check "the service is still active" is_active
check "the old limit still applies: drive 0.8 comes back 0.3" clamped_to_0_3
cp "$work/good.json" "$CONFIG"

note "journal priorities: a warning is a warning, info is not"
# Changing chassis.type needs a restart: reload applies the rest and warns at warn level.
set_config '.chassis.type = "diff"'
systemctl reload "$UNIT"
warned() { journalctl -u "$UNIT" -p warning..warning -o cat --no-pager | grep -q 'SIGHUP: chassis.type changed'; }
check "the daemon's warning is in journalctl -p warning (priority 4 exactly)" wait_for 5 warned
journalctl -u "$UNIT" -p warning..warning -o cat --no-pager | grep 'chassis.type changed' | tail -n 1 | sed 's/^/    journal: /'
reloaded_info() { journalctl -u "$UNIT" -p info..info -o cat --no-pager | grep -q 'SIGHUP: configuration reloaded'; }
check "the info line 'SIGHUP: configuration reloaded' is in the journal at priority info" reloaded_info
check "and it is not under journalctl -p warning" \
  bash -c "! journalctl -u $UNIT -p warning -o cat --no-pager | grep -q 'SIGHUP: configuration reloaded'"
cp "$work/good.json" "$CONFIG"
systemctl reload "$UNIT"

note "systemctl stop while a client drives: zero velocity, then the disable frame"
drive_in_background root 0.25
check "the client drives: 121#00FA... on the bus" wait_for 5 frame_seen_after "" 121#00FA000000000000
mark=$(bus_mark)
stopping=$(now)
systemctl stop "$UNIT"
figure "systemctl stop took $(seconds_since "$stopping") s"
drive_stop
after_stop=$(frames_after "$mark" | awk '$2 ~ /^121#/')
echo "$after_stop" | tail -n 4 | sed 's/^/    bus: /'
last_two=$(tail -n 2 <<<"$after_stop" | awk '{ print $2 }' | tr '\n' ' ')
check "the daemon's last frames: zero control frame, then disable" test "$last_two" = "$ZERO_FRAME $DISABLE_FRAME "
check "the unit's result is success" test "$(systemctl show -P Result "$UNIT")" = success
check "the daemon exited 0" test "$(systemctl show -P ExecMainStatus "$UNIT")" = 0
check "the unit is inactive" test "$(systemctl is-active "$UNIT")" = inactive

finish
