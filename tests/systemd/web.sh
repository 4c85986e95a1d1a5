#!/usr/bin/env bash
# systemd.web: wheeltec-web as the package installs it, next to the installed wheeltecd,
# set up as docs/web.md and the unit's comments say (the token in a file 0640
# root:wheeltec, enable --now). Under the unit's hardening it serves the page and Debian's
# dygraphs, answers /api/status from the daemon's socket, and a Foxglove client with the
# token drives through it as the user wheeltec, until the deadman ends it; stopping
# wheeltecd stops it too (Requires=); a token file open to others is refused with exit 2,
# without restarts. Over TLS (a pair made as docs/web.md says): https:// under the
# hardening, 400 for plain HTTP, a wss:// client drives, `systemctl reload` serves a
# renewed certificate, and a key file open to others is refused with exit 2.
# shellcheck source=tests/systemd/lib.sh
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

readonly VIEW=wheeltec-web
readonly VIEW_DIR=/etc/wheeltec-web
readonly URL=http://127.0.0.1:8080
readonly DRIVE_FRAME=121#012C000001F40000  # vx 0.3 m/s, wz 0.5 rad/s: the client's drive

emulator_pid=
cleanup() {
  kill "$emulator_pid" 2>/dev/null
  if ((failures)); then
    journal_tail "$VIEW"
  fi
}

view_active() { [[ $(systemctl is-active "$VIEW") == active ]]; }
view_inactive() { [[ $(systemctl is-active "$VIEW") != active ]]; }
http_status() { curl -s -o /dev/null -w '%{http_code}' --max-time 5 "$@"; }
serves() { [[ $(http_status "$URL/api/status") == 200 ]]; }
foxglove_client() {  # MODE [TOKEN]: tests/web/clients/foxglove_client.cjs, npm's Foxglove client
  NODE_PATH=$WHEELTEC_WEB_NODE_MODULES node "$WHEELTEC_WEB_CLIENTS/foxglove_client.cjs" "$1" ws://127.0.0.1:8080 "${@:2}"
}

start_ready_chassis

note "installed disabled; the token and the config as the unit says, then enable --now"
check "$VIEW.service is installed disabled" test "$(systemctl is-enabled "$VIEW")" = disabled
install -d -m 0755 "$VIEW_DIR"
install -m 0640 -o root -g wheeltec /dev/null "$VIEW_DIR/token"
token=$(head -c 24 /dev/urandom | base64)
echo "$token" >"$VIEW_DIR/token"
echo '{"token_file": "/etc/wheeltec-web/token"}' >"$VIEW_DIR/wheeltec-web.json"
enabling=$(now)
systemctl enable --now "$VIEW"
check "systemctl enable --now $VIEW" view_active
check "GET /api/status answers 200" wait_for 10 serves
figure "enable --now to the first status: $(seconds_since "$enabling") s"
check "the status is the daemon's (bus up, chassis online)" \
  json_is '.bus.state == "up" and .chassis.online' <<<"$(curl -s --max-time 5 "$URL/api/status")"
check "GET / serves the page" bash -c "curl -s --max-time 5 $URL/ | grep -q 'id=\"joystick\"'"
check "Debian's dygraphs is served (ProtectSystem leaves /usr/share/javascript readable)" \
  test "$(http_status "$URL/javascript/dygraphs/dygraph.min.js")" = 200
check "a foreign Origin is refused (403)" \
  test "$(http_status -H 'Connection: Upgrade' -H 'Upgrade: websocket' -H 'Sec-WebSocket-Version: 13' \
    -H 'Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==' -H 'Sec-WebSocket-Protocol: foxglove.websocket.v1' \
    -H 'Origin: https://evil.example' "$URL/")" = 403

note "a Foxglove client with the token drives through the hardened unit, as the user wheeltec"
mark=$(bus_mark)
driving=$(now)
drives_with_token() { foxglove_client drive "$token" >"$work/drive.json"; }
check "the client receives every channel and drives without a refusal" drives_with_token
check "the drive reaches the bus ($DRIVE_FRAME)" frame_seen_after "$mark" "$DRIVE_FRAME"
figure "connect, subscribe and 2 s of driving: $(seconds_since "$driving") s"
zero_after_drive() { frames_after "$mark" | awk -v d="$DRIVE_FRAME" -v z="$ZERO_FRAME" '$2 == d { seen = 1 } seen && $2 == z { found = 1 } END { exit !found }'; }
check "the client gone, zero follows" wait_for 3 zero_after_drive
refused_without_token() { foxglove_client read-only >"$work/read-only.json"; }
check "without the token a publish is refused (-32005)" refused_without_token
check "POST /api/stop works for anyone" test "$(http_status -X POST "$URL/api/stop")" = 200

note "Requires=wheeltecd: stopping the daemon stops the view"
systemctl stop "$UNIT"
check "$VIEW stops with $UNIT" wait_for 10 view_inactive
systemctl start "$UNIT" "$VIEW"
check "and starts again" wait_for 10 serves

note "a token file others can read: refused, exit 2, no restart loop"
systemctl stop "$VIEW"
chmod 0644 "$VIEW_DIR/token"
systemctl start "$VIEW"
check_refused_to_start "$VIEW"

note "TLS as docs/web.md says: a certificate, its key 0640 root:wheeltec, https:// and wss://"
chmod 0640 "$VIEW_DIR/token"
make_pair() {  # NAME: a self-signed pair for 127.0.0.1 in $VIEW_DIR, as the docs make it
  openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes -days 2 -subj "/CN=$1" \
    -addext subjectAltName=IP:127.0.0.1 -keyout "$VIEW_DIR/key.pem" -out "$VIEW_DIR/cert.pem" 2>/dev/null
  chown root:wheeltec "$VIEW_DIR/key.pem" && chmod 0640 "$VIEW_DIR/key.pem"
  cp "$VIEW_DIR/cert.pem" "$work/$1.pem"
}
make_pair first
echo '{"token_file": "/etc/wheeltec-web/token", "tls": {"cert": "/etc/wheeltec-web/cert.pem", "key": "/etc/wheeltec-web/key.pem"}}' \
  >"$VIEW_DIR/wheeltec-web.json"
systemctl reset-failed "$VIEW"
systemctl start "$VIEW"
serves_tls() { [[ $(http_status --cacert "$work/first.pem" "https://127.0.0.1:8080/api/status") == 200 ]]; }
check "the unit serves https:// under its hardening" wait_for 10 serves_tls
check "plain HTTP on the TLS port gets 400" test "$(http_status "$URL/api/status")" = 400
mark=$(bus_mark)
drives_over_wss() {
  NODE_PATH=$WHEELTEC_WEB_NODE_MODULES NODE_EXTRA_CA_CERTS=$work/first.pem \
    node "$WHEELTEC_WEB_CLIENTS/foxglove_client.cjs" drive wss://127.0.0.1:8080 "$token" >"$work/drive-wss.json"
}
check "a Foxglove client over wss:// with the token drives" drives_over_wss
check "its drive reaches the bus ($DRIVE_FRAME)" frame_seen_after "$mark" "$DRIVE_FRAME"
make_pair renewed
systemctl reload "$VIEW"
serves_renewed() { [[ $(http_status --cacert "$work/renewed.pem" "https://127.0.0.1:8080/api/status") == 200 ]]; }
check "systemctl reload: the renewed certificate is served" wait_for 10 serves_renewed
check "without a restart" test "$(systemctl show -P NRestarts "$VIEW")" = 0

note "a key file others can read: refused, exit 2, no restart loop"
systemctl stop "$VIEW"
chmod 0644 "$VIEW_DIR/key.pem"
systemctl start "$VIEW"
check_refused_to_start "$VIEW"
check "naming the key file in the journal" bash -c "journalctl -u $VIEW --no-pager -n 5 | grep -q /etc/wheeltec-web/key.pem"

cleanup
finish
