# shellcheck shell=bash
# Helpers of the systemd suite (tests/systemd/*.sh). Sourced by test scripts that
# scripts/systemd-uml runs as root inside User-Mode Linux, under the real systemd, with
# the package installed (or, for lifecycle.sh, installable from $SYSTEMD_UML_DEB) and
# the vcan interface can0 up.
set -uo pipefail

# shellcheck disable=SC2034 # for the test scripts
readonly UNIT=wheeltecd
readonly IFACE=${WHEELTEC_TEST_INTERFACE:-can0}
readonly CONFIG=/etc/wheeltecd/wheeltecd.json
readonly ZERO_FRAME=121#0000000000000000
readonly ENABLE_FRAME=121#0A0C0F13181E2501
readonly DISABLE_FRAME=121#0A0C0F13181E2500
readonly MARKER_ID=7FE       # frames the test puts on the bus to mark a moment; the daemon ignores them
export WHEELTEC_SOCKET=/run/wheeltecd/wheeltecd.sock
export SYSTEMD_COLORS=0 SYSTEMD_PAGER='' PAGER=cat

failures=0
checks=0
suite_started=$(date +%s.%N)
work=$(mktemp -d /tmp/systemd-test.XXXXXX)

pass() { checks=$((checks + 1)); echo "PASS: $*"; }
fail() { checks=$((checks + 1)); failures=$((failures + 1)); echo "FAIL: $*"; }
# check DESCRIPTION COMMAND...: passes when COMMAND succeeds.
check() { local what=$1; shift; if "$@"; then pass "$what"; else fail "$what"; fi; }
note() { echo "---- $*"; }
figure() { echo "FIGURE: $*"; }

finish() {
  bus_stop 2>/dev/null
  local took
  took=$(seconds_since "$suite_started")
  if ((failures)); then
    echo "RESULT: $failures of $checks checks failed ($took s)"
    echo "---- journal of $UNIT (last 40 lines)"
    journalctl -u "$UNIT" --no-pager -n 40 -o short-precise 2>/dev/null
    exit 1
  fi
  echo "RESULT: all $checks checks passed ($took s)"
  exit 0
}

now() { date +%s.%N; }
seconds_since() { awk -v a="$1" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }'; }
diff_s() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", b - a }'; }
# at_most A B: A <= B (decimal numbers)
at_most() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a <= b) }'; }

# wait_for SECONDS COMMAND...: polls COMMAND every 50 ms until it succeeds (0) or the
# deadline passes (1).
wait_for() {
  local deadline
  deadline=$(awk -v s="$1" -v n="$(date +%s.%N)" 'BEGIN { printf "%.3f", n + s }')
  shift
  while :; do
    "$@" && return 0
    awk -v d="$deadline" -v n="$(date +%s.%N)" 'BEGIN { exit !(n > d) }' && return 1
    sleep 0.05
  done
}

# check_exposure UNIT: `systemd-analyze security` rates the unit 2.0 or less.
check_exposure() {
  local exposure
  exposure=$(systemd-analyze security --no-pager "$1.service" 2>&1 |
    sed -n "s/.*Overall exposure level for $1.service: \([0-9.]*\).*/\1/p")
  figure "systemd-analyze security $1.service: ${exposure:-none}"
  check "its exposure (${exposure:-none}) is 2.0 or less" at_most "${exposure:-99}" 2.0
}
# journal_tail UNIT: the unit's last 30 journal lines, for a failure report.
journal_tail() {
  echo "---- journal of $1 (last 30 lines)"
  journalctl -u "$1" --no-pager -n 30 -o short-precise 2>/dev/null
}
unit_failed() { [[ $(systemctl is-active "$1") == failed ]]; }  # UNIT
# check_refused_to_start UNIT: the unit, just started, fails with exit status 2 and is not
# restarted (its RestartPreventExitStatus=2).
check_refused_to_start() {
  check "the unit fails" wait_for 10 unit_failed "$1"
  check "with exit status 2" test "$(systemctl show -P ExecMainStatus "$1")" = 2
  check "and is not restarted (RestartPreventExitStatus=2)" test "$(systemctl show -P NRestarts "$1")" = 0
}

main_pid() { systemctl show -P MainPID "$UNIT"; }
is_active() { [[ $(systemctl is-active "$UNIT") == active ]]; }
pid_changed_and_active() {  # OLD_PID
  local pid
  pid=$(main_pid)
  [[ $pid != 0 && $pid != "$1" ]] && is_active
}
socket_answers() { wheeltecctl --json version >/dev/null 2>&1; }

# rpc_as USER ARGS...: wheeltecctl --json ARGS as USER (root: directly). Sets RPC_OUT,
# RPC_ERR and RPC_RC.
rpc_as() {
  local user=$1
  shift
  local runner=()
  [[ $user == root ]] || runner=(runuser -u "$user" --)
  RPC_OUT=$("${runner[@]}" wheeltecctl --json "$@" 2>"$work/rpc.err")
  RPC_RC=$?
  RPC_ERR=$(<"$work/rpc.err")
}
expect_ok() {  # USER ARGS...
  rpc_as "$@"
  if ((RPC_RC == 0)); then pass "$1: wheeltecctl ${*:2} succeeds"
  else fail "$1: wheeltecctl ${*:2} exited $RPC_RC: $RPC_ERR"; fi
}
expect_code() {  # CODE USER ARGS...
  local code=$1
  shift
  rpc_as "$@"
  if ((RPC_RC == 1)) && [[ $RPC_ERR == *"(code $code)"* ]]; then pass "$1: wheeltecctl ${*:2} refused with $code"
  else fail "$1: wheeltecctl ${*:2}: expected error $code, got exit $RPC_RC: $RPC_OUT $RPC_ERR"; fi
}
expect_unreachable() {  # USER ARGS...
  rpc_as "$@"
  if ((RPC_RC == 3)); then pass "$1: cannot connect (exit 3: $RPC_ERR)"
  else fail "$1: wheeltecctl ${*:2}: expected exit 3, got $RPC_RC: $RPC_OUT $RPC_ERR"; fi
}

# result_is JQ-FILTER: the last wheeltecctl call succeeded and its first result matches.
result_is() {
  ((RPC_RC == 0)) && [[ -n $RPC_OUT ]] && jq -e "$1" <<<"$(head -n 1 <<<"$RPC_OUT")" >/dev/null
}

# json_is JQ-FILTER [FILE]: the JSON in FILE (default stdin) matches the filter.
json_is() { jq -e "$1" "${2:-/dev/stdin}" >/dev/null; }

# set_config JQ-FILTER: edits the configuration file in place.
set_config() {
  jq "$1" "$CONFIG" >"$work/config.new" && cat "$work/config.new" >"$CONFIG"
}

# The bus: candump -L of $IFACE into a file, "(SECONDS.USEC) IFACE ID#DATA" per frame.
BUS_LOG=$work/bus.log
bus_pid=
bus_start() {
  : >"$BUS_LOG"
  candump -L "$IFACE" >"$BUS_LOG" &
  bus_pid=$!
  # candump may not have bound its socket yet: a marker sent before then is never
  # recorded, so each poll sends a new one.
  wait_for 5 bus_records_new_mark || { fail "candump does not record $IFACE"; return 1; }
}
# start_ready_chassis: the bus recorded, wheeltec-emu on $IFACE (pid in $emulator_pid, log in
# $work/emu.log), $UNIT started, and its status saying the chassis is online and ready.
chassis_ready() {
  wheeltecctl --json status 2>/dev/null | json_is '.chassis.online and .chassis.phase == "ready"'
}
start_ready_chassis() {
  bus_start
  wheeltec-emu --interface "$IFACE" --boot-delay 0 --no-self-test >"$work/emu.log" 2>&1 &
  emulator_pid=$!
  systemctl start "$UNIT"
  check "systemctl start $UNIT" is_active
  check "the chassis (wheeltec-emu) is online and ready" wait_for 10 chassis_ready
}
bus_records_new_mark() {
  local mark
  mark=$(bus_mark)
  sleep 0.05
  grep -q "$mark" "$BUS_LOG"
}
bus_stop() {
  [[ -n $bus_pid ]] || return 0
  kill "$bus_pid" 2>/dev/null
  wait "$bus_pid" 2>/dev/null
  bus_pid=
}
# bus_mark: puts a marker frame on the bus and prints its ID#DATA (unique per call).
# Callers run it in a command substitution, a subshell: the count lives in a file.
bus_mark() {
  local count frame
  count=$(($(cat "$work/marker.count" 2>/dev/null || echo 0) + 1))
  echo "$count" >"$work/marker.count"
  frame=$(printf '%s#%08X' "$MARKER_ID" "$count")
  cansend "$IFACE" "$frame"
  echo "$frame"
}
# frames_after MARKER: the frames recorded after the marker frame (all of them when
# MARKER is empty), "TIMESTAMP ID#DATA" per line.
frames_after() {
  awk -v m="${1:-}" 'm == "" { seen = 1 } seen && $3 !~ /^7FE#/ { gsub(/[()]/, "", $1); print $1, $3 } $3 == m { seen = 1 }' "$BUS_LOG"
}
# frames_since SECONDS: the frames with a timestamp at or after SECONDS (epoch).
frames_since() {
  awk -v t="$1" '{ ts = $1; gsub(/[()]/, "", ts) } ts + 0 >= t + 0 && $3 !~ /^7FE#/ { print ts, $3 }' "$BUS_LOG"
}
# Control frames of the manual dialect: 0x121 with 00 00 in bytes 6-7 (the enable and
# disable frames end in 25 01 / 25 00).
# (No regex intervals: Debian's awk is mawk.)
control_frames() { awk 'substr($2, 1, 4) == "121#" && length($2) == 20 && substr($2, 17) == "0000"'; }
nonzero_control_frames() { control_frames | awk -v z="$ZERO_FRAME" '$2 != z'; }
frame_seen_after() {  # MARKER FRAME
  frames_after "$1" | awk -v f="$2" '$2 == f { found = 1 } END { exit !found }'
}
nonzero_frame_seen_after() { [[ -n $(frames_after "$1" | nonzero_control_frames) ]]; }

# drive_in_background USER VX: a client that keeps driving (wheeltecctl drive --for 60).
drive_pid=
drive_in_background() {
  local runner=()
  [[ $1 == root ]] || runner=(runuser -u "$1" --)
  "${runner[@]}" wheeltecctl --json drive "$2" 0 0 --for 60 >"$work/drive.out" 2>&1 &
  drive_pid=$!
}
drive_stop() {
  [[ -n $drive_pid ]] || return 0
  kill "$drive_pid" 2>/dev/null
  wait "$drive_pid" 2>/dev/null
  drive_pid=
}

# unit_start_time: when systemd started the unit's main process, in epoch seconds (the
# bus log's clock): its monotonic start time plus the realtime-monotonic offset that the
# journal's last entry carries (both clocks read by journald at the same moment).
unit_start_time() {
  local start_us
  start_us=$(systemctl show -P ExecMainStartTimestampMonotonic "$UNIT")
  journalctl -n 1 -o export --no-pager |
    awk -F= -v s="$start_us" '/^__REALTIME_TIMESTAMP=/ { r = $2 } /^__MONOTONIC_TIMESTAMP=/ { m = $2 }
      END { printf "%.6f", (r - m + s) / 1e6 }'
}

# The one command of docs/deploy.md that lets a user drive, as the installed docs say it,
# run for USER (as root, so `sudo` is the command itself).
deploy_doc=/usr/share/doc/wheeltec-gateway/deploy.md
drive_permission_command() { grep -m1 -E '^sudo usermod ' "$deploy_doc"; }
run_doc_command_for() {  # USER COMMAND
  USER=$1 bash -c "sudo() { \"\$@\"; }; $2"
}

trap 'drive_stop; bus_stop; rm -rf -- "$work"' EXIT
