#!/usr/bin/env bash
# systemd.mqtt: wheeltec-mqtt as the package installs it, next to the installed wheeltecd
# and a real mosquitto on 127.0.0.1, set up as docs/fleet.md says (the config 0640
# root:wheeltec, enable --now). Under the unit's hardening the bridge reaches the broker
# and the daemon's socket as the user wheeltec, which may drive: online and status are
# retained, telemetry flows, a drive reaches the bus and the deadman ends it; a clean stop
# leaves online false; a config open to others is refused with exit 2, without restarts.
# shellcheck source=tests/systemd/lib.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

readonly BRIDGE=wheeltec-mqtt
readonly BRIDGE_CONFIG=/etc/wheeltec-mqtt/wheeltec-mqtt.json
readonly PORT=18830
readonly TOPICS=wheeltec/r1
readonly DRIVE_FRAME=121#00FA000000000000  # vx 0.25 m/s

mqtt_log=$work/mqtt.log
emulator_pid=
broker_pid=
subscriber_pid=
cleanup() {
  for pid in $subscriber_pid $broker_pid $emulator_pid; do kill "$pid" 2>/dev/null; done
  if ((failures)); then
    journal_tail "$BRIDGE"
    echo "---- MQTT messages under $TOPICS (last 10)"
    tail -n 10 "$mqtt_log" | cut -c 1-200
  fi
}

bridge_active() { [[ $(systemctl is-active "$BRIDGE") == active ]]; }
broker_answers() { mosquitto_sub -p "$PORT" -t '$SYS/broker/version' -C 1 -W 1 >/dev/null 2>&1; }
published() { grep -q "$1" "$mqtt_log"; }  # REGEX: a message under $TOPICS ("TOPIC PAYLOAD")
# retained TOPIC: the payload a new subscriber gets at once.
retained() { mosquitto_sub -p "$PORT" -t "$1" -C 1 -W 3 2>/dev/null; }

start_ready_chassis

note "a broker on 127.0.0.1:$PORT (Debian's mosquitto)"
printf 'listener %d 127.0.0.1\nallow_anonymous true\npersistence false\n' "$PORT" >"$work/mosquitto.conf"
mosquitto -c "$work/mosquitto.conf" >"$work/mosquitto.log" 2>&1 &
broker_pid=$!
check "mosquitto answers" wait_for 10 broker_answers
mosquitto_sub -p "$PORT" -v -t "$TOPICS/#" >"$mqtt_log" 2>&1 &
subscriber_pid=$!

note "installed disabled; configured and enabled as docs/fleet.md says"
check "$BRIDGE.service is installed disabled" test "$(systemctl is-enabled "$BRIDGE")" = disabled
printf '{"robot": "r1", "broker": {"host": "127.0.0.1", "port": %d}}\n' "$PORT" >"$work/r1.json"
install -d -m 0750 -g wheeltec /etc/wheeltec-mqtt
install -m 0640 -g wheeltec "$work/r1.json" "$BRIDGE_CONFIG"
enabling=$(now)
systemctl enable --now "$BRIDGE"
check "systemctl enable --now $BRIDGE" bridge_active
check "online: true" wait_for 10 published "^$TOPICS/online true$"
figure "enable --now to online true: $(seconds_since "$enabling") s"
check "telemetry records arrive" wait_for 5 published "^$TOPICS/telemetry {"
check "a late subscriber gets the retained status (bus up)" \
  json_is '.bus.state == "up"' <<<"$(retained "$TOPICS/status")"
check "the bridge logs to the journal" \
  bash -c "journalctl -u $BRIDGE -o cat --no-pager | grep -q 'connected to the broker'"

note "a remote drive through the hardened unit: the bridge's user may drive"
mark=$(bus_mark)
driving=$(now)
mosquitto_pub -p "$PORT" -t "$TOPICS/cmd/drive" -m '{"vx": 0.25, "id": "d1", "operator": "alice"}'
reply_d1_is_a_result() {
  sed -n "s|^$TOPICS/cmd/result ||p" "$mqtt_log" |
    jq -e 'select(.id == "d1") | .command == "drive" and (.result | type) == "object"' >/dev/null 2>&1
}
check "the reply on cmd/result is a result" wait_for 5 reply_d1_is_a_result
check "the drive reaches the bus ($DRIVE_FRAME)" wait_for 5 frame_seen_after "$mark" "$DRIVE_FRAME"
figure "publish to the drive frame on the bus: $(seconds_since "$driving") s (upper bound: polled)"
zero_after_drive() { frames_after "$mark" | awk -v d="$DRIVE_FRAME" -v z="$ZERO_FRAME" '$2 == d { seen = 1 } seen && $2 == z { found = 1 } END { exit !found }'; }
check "no repeat: the daemon's deadman sends zero" wait_for 3 zero_after_drive

note "systemctl stop: online false, retained"
systemctl stop "$BRIDGE"
check "online is false for a new subscriber" test "$(retained "$TOPICS/online")" = false

note "a config file others can read: refused, exit 2, no restart loop"
chmod 0644 "$BRIDGE_CONFIG"
systemctl start "$BRIDGE"
check_refused_to_start "$BRIDGE"
check "the journal says why" \
  bash -c "journalctl -u $BRIDGE -o cat --no-pager | grep -q 'readable or writable by others'"

cleanup
finish
