#!/usr/bin/env bash
# systemd.record: wheeltec-record as the package installs it (disabled, hardened), next to
# the installed wheeltecd on the emulated chassis: enabled with a short --after, a mark
# makes one whole file in its state directory, readable by the group wheeltec only; a
# daemon restart is written at once (daemon-lost); a clean stop leaves no .part; a config
# with an unknown key is refused with exit 2, without restarts.
# shellcheck source=tests/systemd/lib.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

readonly RECORDER=wheeltec-record
readonly RECORDER_CONFIG=/etc/wheeltec-record/wheeltec-record.json
readonly RECORDS=/var/lib/wheeltec-record

emulator_pid=
cleanup() {
  kill "$emulator_pid" 2>/dev/null
  if ((failures)); then
    journal_tail "$RECORDER"
    ls -la "$RECORDS" 2>/dev/null
  fi
}

recorder_active() { [[ $(systemctl is-active "$RECORDER") == active ]]; }
files_named() { find "$RECORDS" -maxdepth 1 -name "$1" 2>/dev/null | wc -l; }  # GLOB
has_file() { (($(files_named "$1") >= 1)); }
recording() { journalctl -u "$RECORDER" -o cat --no-pager | grep -q 'recording from'; }

note "installed disabled, hardened"
check "$RECORDER.service is installed disabled" test "$(systemctl is-enabled "$RECORDER")" = disabled
check_exposure "$RECORDER"

start_ready_chassis

note "enabled with a config of its own (after_s 1)"
install -d -m 0755 /etc/wheeltec-record
printf '{"before_s": 5, "after_s": 1}\n' >"$RECORDER_CONFIG"
systemctl enable --now "$RECORDER"
check "systemctl enable --now $RECORDER" recorder_active
check "it subscribes to the daemon" wait_for 10 recording
check "its state directory is wheeltec's, 0750" \
  test "$(stat -c '%U:%G %a' "$RECORDS")" = "wheeltec:wheeltec 750"

note "wheeltecctl mark: one whole file"
sleep 2
marking=$(now)
wheeltecctl mark "from the systemd suite"
check "a -mark.mcap file appears" wait_for 10 has_file '*-mark.mcap'
figure "mark to a finished file: $(seconds_since "$marking") s (after_s 1)"
mark_file=$(find "$RECORDS" -maxdepth 1 -name '*-mark.mcap' | head -n 1)
check "it is wheeltec's, 0640" test "$(stat -c '%U:%G %a' "$mark_file")" = "wheeltec:wheeltec 640"
check "it is MCAP (magic at both ends)" \
  bash -c "head -c 8 '$mark_file' | od -An -tx1 | grep -q '89 4d 43 41 50 30 0d 0a' &&
           tail -c 8 '$mark_file' | od -An -tx1 | grep -q '89 4d 43 41 50 30 0d 0a'"
figure "$(basename "$mark_file"): $(stat -c %s "$mark_file") bytes"

note "the daemon restarted: written at once"
systemctl restart "$UNIT"
check "a -daemon-lost.mcap file appears" wait_for 5 has_file '*-daemon-lost.mcap'
check "the recorder was not restarted with it" test "$(systemctl show -P NRestarts "$RECORDER")" = 0

note "systemctl stop: nothing left half-written"
check "systemctl stop $RECORDER" systemctl stop "$RECORDER"
check "it exited 0" test "$(systemctl show -P ExecMainStatus "$RECORDER")" = 0
check "no .part is left" test "$(files_named '*.part')" = 0

note "a config with an unknown key: refused, exit 2, no restart loop"
printf '{"before_s": 5, "bogus": true}\n' >"$RECORDER_CONFIG"
systemctl start "$RECORDER"
check_refused_to_start "$RECORDER"
check "the journal names the key" \
  bash -c "journalctl -u $RECORDER -o cat --no-pager | grep -q 'bogus: unknown key'"

cleanup
finish
