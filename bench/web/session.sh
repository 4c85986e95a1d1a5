#!/usr/bin/env bash
# One session of wheeltec-web's benchmark (scripts/bench-web.sh): wheeltec-emu, wheeltecd and wheeltec-web on
# vcan0 (--serial: a pty), one more over TLS, relay.py, the aiohttp Foxglove server aiohttp_foxglove.py (Debian's
# /usr/bin/python3 with python3-aiohttp; missing, the session fails), Chromium unless --no-browser, then web_bench.cjs.
#   session.sh BUILD_DIR NODE_MODULES TELEMETRY_HZ SECONDS VIEWERS [--no-browser] [--serial]
set -euo pipefail
build=$1 node_modules=$2 hz=$3 seconds=$4 viewers=$5
shift 5
browser='' link=(--interface vcan0)
for flag in "$@"; do
  case $flag in
    --no-browser) browser=--no-browser ;;
    --serial) link=(--serial) ;;
    *) echo "session.sh: unknown flag $flag" >&2; exit 2 ;;
  esac
done
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
work=$(mktemp -d /tmp/bench-web.XXXXXX)
pids=()
# Chromium's children may still write its profile after it exits: the removal is tried again, never failing.
cleanup() {
  kill -CONT "${pids[@]}" 2>/dev/null || true  # web_bench.cjs stops a server at a time, and resumes it
  kill "${pids[@]}" 2>/dev/null || true
  wait 2>/dev/null || true
  rm -rf "$work" 2>/dev/null || { sleep 1; rm -rf "$work" 2>/dev/null; } || true
}
trap cleanup EXIT
port=18090
# Every program with a default configuration file reads this empty one instead: never the host's /etc.
echo '{}' >"$work/empty.json"

[[ ${link[0]} == --serial ]] && link=(--serial "$work/tty")
"$build/emulator/wheeltec-emu" "${link[@]}" --boot-delay 0 --no-self-test --telemetry-hz "$hz" >"$work/emu.log" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [[ ${link[0]} != --serial || -e $work/tty ]] && break; sleep 0.1; done
"$build/daemon/wheeltecd" --config "$work/empty.json" "${link[@]}" --socket "$work/wheeltecd.sock" --log-level warn >"$work/daemon.log" 2>&1 &
pids+=($!)
# What wheeltec-web is compared with (issue #44): a Foxglove server written with aiohttp, on its own port. It
# subscribes before it listens, and before wheeltec-web: the daemon writes each record to its subscribers in the
# order they connected, so the aiohttp server is written to first.
python=/usr/bin/python3
"$python" -c 'import aiohttp' 2>/dev/null ||
  { echo "session.sh: $python cannot import aiohttp, which bench/web/aiohttp_foxglove.py needs: install python3-aiohttp" >&2; exit 1; }
aiohttp_port=$((port + 2))
for _ in $(seq 100); do [[ -S $work/wheeltecd.sock ]] && break; sleep 0.1; done
"$python" "$here/aiohttp_foxglove.py" "$aiohttp_port" "$work/wheeltecd.sock" >"$work/aiohttp.log" 2>&1 &
aiohttp_pid=$!
pids+=("$aiohttp_pid")
for attempt in $(seq 101); do
  curl -s -o /dev/null --max-time 1 "http://127.0.0.1:$aiohttp_port/" 2>/dev/null && break
  kill -0 "$aiohttp_pid" 2>/dev/null || { echo "session.sh: aiohttp_foxglove.py exited: $(cat "$work/aiohttp.log")" >&2; exit 1; }
  ((attempt <= 100)) || { echo "session.sh: aiohttp_foxglove.py did not listen on port $aiohttp_port" >&2; exit 1; }
  sleep 0.1
done

# The page drives (the gamepad's latency) with this token.
token=bench-$RANDOM$RANDOM
(umask 077 && echo "$token" >"$work/token")
"$build/web/wheeltec-web" --config "$work/empty.json" --socket "$work/wheeltecd.sock" --listen "127.0.0.1:$port" --page-dir "$repo/web/page" \
  --token-file "$work/token" --log-level warn >"$work/web.log" 2>&1 &
web_pid=$!
pids+=("$web_pid")
# A second instance over TLS, with a self-signed certificate for 127.0.0.1 that node trusts.
openssl req -x509 -newkey ec -pkeyopt ec_paramgen_curve:P-256 -nodes -days 1 -subj /CN=127.0.0.1 \
  -addext subjectAltName=IP:127.0.0.1 -keyout "$work/key.pem" -out "$work/cert.pem" 2>/dev/null
chmod 0600 "$work/key.pem"
tls_port=$((port + 1))
"$build/web/wheeltec-web" --config "$work/empty.json" --socket "$work/wheeltecd.sock" --listen "127.0.0.1:$tls_port" --page-dir "$repo/web/page" \
  --tls-cert "$work/cert.pem" --tls-key "$work/key.pem" --log-level warn >"$work/web-tls.log" 2>&1 &
tls_web_pid=$!
pids+=("$tls_web_pid")
for _ in $(seq 100); do
  curl -sf --max-time 1 "http://127.0.0.1:$port/api/status" 2>/dev/null | grep -q '"online":true' &&
    curl -sf --max-time 1 --cacert "$work/cert.pem" "https://127.0.0.1:$tls_port/api/status" >/dev/null 2>&1 && break
  sleep 0.1
done

# The floor of one process between the daemon and a subscriber, measured beside wheeltec-web.
python3 "$here/relay.py" "$work/relay.sock" "$work/wheeltecd.sock" 2>"$work/relay.log" &
pids+=($!)
for _ in $(seq 50); do [[ -S $work/relay.sock ]] && break; sleep 0.1; done

args=(--socket "$work/wheeltecd.sock" --relay-socket "$work/relay.sock" --url "http://127.0.0.1:$port" --web-pid "$web_pid" --seconds "$seconds" --viewers "$viewers"
      --tls-url "https://127.0.0.1:$tls_port" --tls-web-pid "$tls_web_pid" --aiohttp-url "ws://127.0.0.1:$aiohttp_port" --aiohttp-pid "$aiohttp_pid")
# strace counts wheeltec-web's system calls per record exactly (UML charges CPU in 10 ms ticks).
strace=$(command -v strace || true)
[[ -n $strace ]] && args+=(--strace "$strace")
if [[ $browser != --no-browser ]]; then
  mkdir -p "$work/home"
  HOME=$work/home /usr/bin/chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
    --disable-background-networking --disable-component-update --disable-sync --user-data-dir="$work/profile" \
    --remote-debugging-port=9224 about:blank >"$work/chromium.log" 2>&1 &
  pids+=($!)
  args+=(--devtools 9224 --token "$token")
fi
NODE_PATH=$node_modules NODE_EXTRA_CA_CERTS=$work/cert.pem node "$here/web_bench.cjs" "${args[@]}"
