#!/usr/bin/env bash
# systemd.serial: the installed unit drives a chassis over the serial link. wheeltec-emu
# plays the controller on a pseudo-terminal published at a symlink in /run (a path the
# unit's sandbox sees: PrivateTmp= hides /tmp); the slave gets the group wheeltec and mode
# 0660 as the package's udev rule gives a real adapter. The daemon, in the unit's sandbox
# (ProtectSystem=strict, PrivateTmp=, DevicePolicy=closed), opens it, drives, sees the
# hang-up when the emulator dies, reopens the new pty published at the same path, comes
# back on it after being killed (Restart=on-failure), and stops cleanly.
# shellcheck source=tests/systemd/lib.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

readonly LINK_DIR=/run/wheeltec-test
readonly LINK=$LINK_DIR/controller
readonly DRIVE_VX=0.2
emulator_pid=

status_is() { wheeltecctl --json status 2>/dev/null | json_is "$1"; }
bus_down() { status_is '.bus.state == "down"'; }
link_published() { [[ -L $LINK && -c $(readlink -f "$LINK") ]]; }

# start_emulator: wheeltec-emu on a new pty at $LINK (pid in $emulator_pid, log appended to
# $work/emu.log); the slave then gets the daemon's group and mode 0660, as udev gives a
# real adapter. $accessible: the time just before that (no open by the daemon could
# succeed earlier).
start_emulator() {
  wheeltec-emu --serial "$LINK" --boot-delay 1 --no-self-test >>"$work/emu.log" 2>&1 &
  emulator_pid=$!
  if ! wait_for 10 link_published; then
    fail "wheeltec-emu published no pty at $LINK"
    tail -n 20 "$work/emu.log" | sed 's/^/    emu: /'
    return 1
  fi
  local slave
  slave=$(readlink -f "$LINK")
  accessible=$(now)
  chgrp wheeltec "$slave" && chmod 0660 "$slave"
  figure "wheeltec-emu (pid $emulator_pid): $LINK -> $slave ($(stat -c '%U:%G %a' "$slave"))"
}
stop_emulator() {  # SIGNAL
  [[ -n $emulator_pid ]] || return 0
  kill -"$1" "$emulator_pid" 2>/dev/null
  wait "$emulator_pid" 2>/dev/null
  emulator_pid=
}

# logged_at EPOCH REGEX: when the daemon logged its first journal line at or after EPOCH
# whose message matches REGEX (epoch seconds, journald's receive time: an upper bound);
# empty if none. Each wheeltecctl call costs a process start, which in a busy UML session
# can take seconds: the daemon's own journal dates what it saw, not a poll.
logged_at() {
  local since_us
  since_us=$(awk -v t="$1" 'BEGIN { printf "%.0f", t * 1e6 }')
  journalctl -u "$UNIT" --since "@${1%.*}" -o json --no-pager 2>/dev/null |
    jq -r --arg p "$2" --argjson since "$since_us" '
      select((.MESSAGE | type) == "string" and (.MESSAGE | test($p)))
      | (._SOURCE_REALTIME_TIMESTAMP // .__REALTIME_TIMESTAMP | tonumber) | select(. >= $since)' |
    head -n 1 | awk '{ printf "%.6f", $1 / 1e6 }'
}
# within SECONDS FROM TO: TO is set and TO - FROM <= SECONDS.
within() { [[ -n $3 ]] && at_most "$(diff_s "$2" "$3")" "$1"; }
span() { if [[ -n $2 ]]; then diff_s "$1" "$2"; else echo "?"; fi; }  # FROM TO

# drive_and_measure VX SECONDS: `wheeltecctl drive VX 0 0 --for SECONDS` while
# `wheeltecctl watch` records the telemetry, until a record a second after the drive.
# Sets DRIVE_RC, MOVING (records with a measured vx of at least VX/2), MOVING_VX (their
# median) and FINAL_VX (the last record's vx).
drive_and_measure() {
  local target=$1 seconds=$2 watch_pid until
  : >"$work/watch.json"
  wheeltecctl --json watch >"$work/watch.json" 2>/dev/null &
  watch_pid=$!
  wait_for 10 test -s "$work/watch.json"
  wheeltecctl --json drive "$target" 0 0 --for "$seconds" >"$work/drive.out" 2>&1
  DRIVE_RC=$?
  until=$(awk -v t="$(now)" 'BEGIN { printf "%.3f", t + 1 }')
  wait_for 10 last_record_after "$until"
  kill "$watch_pid" 2>/dev/null
  wait "$watch_pid" 2>/dev/null
  jq -cR 'fromjson? // empty' "$work/watch.json" >"$work/records.json"
  MOVING=$(jq -s --argjson t "$target" '[.[].velocity.vx | select(. >= $t / 2)] | length' "$work/records.json")
  MOVING_VX=$(jq -s --argjson t "$target" \
    '[.[].velocity.vx | select(. >= $t / 2)] | sort | if length == 0 then null else .[length / 2 | floor] end' \
    "$work/records.json")
  FINAL_VX=$(jq -s '.[-1].velocity.vx' "$work/records.json")
}
last_record_after() { tail -n 1 "$work/watch.json" | jq -e --argjson t "$1" '.time >= $t' >/dev/null 2>&1; }
near() { awk -v v="$1" -v t="$2" 'BEGIN { d = v - t; if (d < 0) d = -d; exit !(v != "null" && d <= 0.1 * t) }'; }
check_drive() {  # VX SECONDS
  drive_and_measure "$1" "$2"
  check "wheeltecctl drive $1 0 0 --for $2 succeeded" test "$DRIVE_RC" -eq 0
  ((DRIVE_RC == 0)) || sed 's/^/    drive: /' "$work/drive.out"
  figure "measured vx while driving at $1: median $MOVING_VX m/s over $MOVING records; 1 s after: $FINAL_VX m/s"
  check "the chassis moved: at least $(($2 * 5)) records at vx >= $1/2" test "$MOVING" -ge $(($2 * 5))
  check "the measured vx is within 10 % of $1" near "$MOVING_VX" "$1"
  check "the chassis stopped after the drive (|vx| < 0.01)" \
    awk -v v="$FINAL_VX" 'BEGIN { exit !(v != "null" && v < 0.01 && v > -0.01) }'
}

note "pseudo-terminals: devpts on /dev/pts"
if [[ $(stat -f -c %T /dev/pts 2>/dev/null) != devpts ]]; then
  mkdir -p /dev/pts && mount -t devpts devpts /dev/pts
  figure "mounted devpts on /dev/pts"
fi
check "/dev/pts is a devpts mount" test "$(stat -f -c %T /dev/pts 2>/dev/null)" = devpts

note "wheeltec-emu plays the controller on a pty at $LINK"
mkdir -p "$LINK_DIR"
start_emulator

note "the installed unit on the serial link: transport serial, serial.device $LINK"
set_config ".transport = \"serial\" | .serial.device = \"$LINK\""
started=$(now)
systemctl start "$UNIT"
check "systemctl start $UNIT" is_active
serial_up=".bus.transport == \"serial\" and .bus.interface == \"$LINK\" and .bus.state == \"up\""
if wait_for 10 status_is "$serial_up"; then
  pass "status: bus serial $LINK up"
else
  fail "status: bus not serial $LINK up"
  note "the daemon cannot use the pty? its journal:"
  journalctl -u "$UNIT" -o cat --no-pager | grep -i serial | tail -n 5 | sed 's/^/    journal: /'
fi
check "the chassis is online and ready" wait_for 15 chassis_ready
figure "systemctl start to phase ready: $(span "$started" "$(logged_at "$started" '^chassis phase ready')") s (journal)"
wheeltecctl status 2>&1 | sed 's/^/    status: /'

note "driving: wheeltecctl drive $DRIVE_VX 0 0 --for 2, the telemetry recorded by wheeltecctl watch"
check_drive "$DRIVE_VX" 2
rpc_as root stats
figure "stats.serial: $(jq -c '.serial' <<<"$RPC_OUT" 2>/dev/null)"
check "stats: serial.bytes_received > 0" result_is '.serial.bytes_received > 0'
check "stats: serial.reopens == 0 (never lost)" result_is '.serial.reopens == 0'

note "unplug: wheeltec-emu is killed, its pty hangs up"
killed=$(now)
stop_emulator KILL
check "status: bus down" wait_for 10 bus_down
# The daemon logs the hang-up and sets the link down in the same step (SerialPort::go_down).
down_at=$(logged_at "$killed" 'end of file|read failed|write failed')
figure "hang-up to bus down: $(span "$killed" "$down_at") s (journal)"
check "the daemon saw the hang-up within 2 s" within 2 "$killed" "$down_at"
check "the daemon keeps running" is_active
expect_code -32003 root drive 0.1 0 0 --for 0

note "replug: a new wheeltec-emu on a new pty at the same path"
rm -f "$LINK"  # udev removes the symlink of an unplugged adapter
start_emulator
check "status: bus serial $LINK up again" wait_for 10 status_is "$serial_up"
up_at=$(logged_at "$accessible" '^serial .*: open, [0-9]+ baud')
figure "pty accessible to bus up: $(span "$accessible" "$up_at") s (journal)"
check "the daemon reopened the port within 2 s of the new pty" within 2 "$accessible" "$up_at"
check "the chassis is online and ready again" wait_for 15 chassis_ready
figure "pty accessible to phase ready: $(span "$accessible" "$(logged_at "$accessible" '^chassis phase ready')") s (journal, --boot-delay 1)"
rpc_as root stats
figure "stats.serial: $(jq -c '.serial' <<<"$RPC_OUT" 2>/dev/null)"
check "stats: serial.reopens >= 1" result_is '.serial.reopens >= 1'
check_drive "$DRIVE_VX" 1
journalctl -u "$UNIT" -o cat --no-pager | grep -E "^serial $LINK" | tail -n 4 | sed 's/^/    journal: /'

note "a killed daemon: Restart=on-failure brings it back on the same pty"
killed=$(now)
systemctl kill --kill-whom=main --signal=KILL "$UNIT"
if wait_for 20 eval '[[ -n $(logged_at "$killed" "^serial .*: open, [0-9]+ baud") ]]'; then
  pass "the restarted daemon reopened the same pty (no exclusive flag left behind)"
else
  fail "the restarted daemon did not reopen the same pty"
  journalctl -u "$UNIT" -o cat --no-pager | grep -E "^serial " | tail -n 3 | sed 's/^/    journal: /'
fi
check "status: bus serial $LINK up after the restart" wait_for 10 status_is "$serial_up"

note "systemctl stop"
stopping=$(now)
systemctl stop "$UNIT"
figure "systemctl stop took $(seconds_since "$stopping") s"
check "the unit is inactive" test "$(systemctl is-active "$UNIT")" = inactive
check "the unit's result is success" test "$(systemctl show -P Result "$UNIT")" = success
check "the daemon exited 0" test "$(systemctl show -P ExecMainStatus "$UNIT")" = 0
journalctl -u "$UNIT" -p warning -o cat --no-pager --since "@${stopping%.*}" | sed 's/^/    journal (warning) at stop: /'

stop_emulator TERM
rm -rf -- "$LINK_DIR"
finish
