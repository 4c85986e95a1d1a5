#!/usr/bin/python3
"""wheeltec-bench-mqtt's reference: the MQTT bridge a user would write with paho-mqtt (Debian's 1.6.1).
One daemon connection; PREFIX/ROBOT/cmd/drive becomes `drive` (the daemon's auto_enable enables),
cmd/stop and a lost broker `stop`; the replies are read and dropped by a thread; loop_forever reconnects.

    /usr/bin/python3 paho_bridge.py --socket PATH --broker 127.0.0.1:1883 --robot py1
"""

import argparse
import itertools
import json
import socket
import threading

import paho.mqtt.client as mqtt


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--socket", required=True, help="wheeltecd's Unix socket")
    parser.add_argument("--broker", default="127.0.0.1:1883", help="HOST:PORT")
    parser.add_argument("--robot", default="py1")
    parser.add_argument("--prefix", default="wheeltec")
    args = parser.parse_args()
    host, port = args.broker.rsplit(":", 1)

    daemon = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    daemon.connect(args.socket)
    send_lock = threading.Lock()
    ids = itertools.count(1)

    def call(method, params=None):
        request = {"jsonrpc": "2.0", "id": next(ids), "method": method}
        if params:
            request["params"] = params
        with send_lock:
            daemon.sendall((json.dumps(request) + "\n").encode())

    def read_replies():
        for _ in daemon.makefile("rb"):
            pass

    threading.Thread(target=read_replies, daemon=True).start()

    drive_topic = f"{args.prefix}/{args.robot}/cmd/drive"
    stop_topic = f"{args.prefix}/{args.robot}/cmd/stop"

    def on_connect(client, userdata, flags, rc):
        if rc == 0:
            client.subscribe([(drive_topic, 0), (stop_topic, 0)])

    def on_message(client, userdata, message):
        if message.topic == stop_topic:
            call("stop")
            return
        try:
            command = json.loads(message.payload)
            params = {key: float(command[key]) for key in ("vx", "vy", "wz") if key in command}
        except (ValueError, TypeError):
            return
        call("drive", params)

    def on_disconnect(client, userdata, rc):
        call("stop")

    client = mqtt.Client(client_id=f"paho-bridge-{args.robot}")
    client.on_connect = on_connect
    client.on_message = on_message
    client.on_disconnect = on_disconnect
    client.reconnect_delay_set(min_delay=1, max_delay=2)
    client.connect(host, int(port), keepalive=60)
    client.loop_forever(retry_first_connection=True)


if __name__ == "__main__":
    main()
