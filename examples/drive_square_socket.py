#!/usr/bin/env python3
"""Drives the robot around a square (four sides of 2 s at 0.2 m/s, four quarter turns)
through wheeltecd's JSON-RPC socket and prints the odometry at every corner.
Standard library only.

    drive_square_socket.py [SOCKET]   (default: $WHEELTEC_SOCKET, else /run/wheeltecd/wheeltecd.sock)
"""
import json
import math
import os
import select
import socket
import sys
import time

LEG_S = 2.0                         # each side and each turn lasts 2 s
SPEED = 0.2                         # m/s
TURN_RATE = math.pi / 2 / LEG_S     # rad/s: a quarter turn per turn leg
DRIVE_PERIOD_S = 0.1                # well inside the daemon's deadman (0.5 s by default)


class RpcError(Exception):
    def __init__(self, error):
        super().__init__(f"{error['code']} {error['message']}")
        self.code = error["code"]
        self.data = error.get("data")


class Gateway:
    """One connection to wheeltecd: requests and the telemetry notifications between them."""

    def __init__(self, path):
        self.sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self.sock.connect(path)
        self.pending = b""
        self.last_id = 0
        self.telemetry = None       # the latest telemetry record received

    def call(self, method, params=None):
        self.last_id += 1
        request = {"jsonrpc": "2.0", "id": self.last_id, "method": method}
        if params is not None:
            request["params"] = params
        # allow_nan=False: Python would otherwise write NaN or Infinity, which the daemon refuses.
        self.sock.sendall(json.dumps(request, allow_nan=False).encode() + b"\n")
        while True:
            message = self._receive(deadline=None)
            if message.get("id") == self.last_id:
                if "error" in message:
                    raise RpcError(message["error"])
                return message["result"]

    def wait(self, seconds):
        """Takes in notifications for this long."""
        deadline = time.monotonic() + seconds
        while self._receive(deadline) is not None:
            pass

    def _receive(self, deadline):
        """The next message (a notification is also recorded), or None at the deadline."""
        while b"\n" not in self.pending:
            timeout = None if deadline is None else max(0.0, deadline - time.monotonic())
            if not select.select([self.sock], [], [], timeout)[0]:
                return None
            chunk = self.sock.recv(65536)
            if not chunk:
                raise ConnectionError("the daemon closed the connection")
            self.pending += chunk
        line, self.pending = self.pending.split(b"\n", 1)
        message = json.loads(line)
        if message.get("method") == "telemetry":
            self.telemetry = message["params"]
        return message


def wait_until_ready(gateway, timeout_s=30.0):
    """Online and past the controller's boot and self-test (phase absent: protocol 1)."""
    deadline = time.monotonic() + timeout_s
    while True:
        chassis = gateway.call("status")["chassis"]
        if chassis["online"] and chassis.get("phase", "ready") == "ready":
            return
        if time.monotonic() > deadline:
            raise TimeoutError(f"the chassis is not ready: {chassis}")
        gateway.wait(0.2)


def drive_for(gateway, seconds, vx=0.0, wz=0.0):
    """Sends drive every DRIVE_PERIOD_S: each one takes or renews control (the deadman)."""
    end = time.monotonic() + seconds
    while (left := end - time.monotonic()) > 0:
        gateway.call("drive", {"vx": vx, "wz": wz})
        gateway.wait(min(DRIVE_PERIOD_S, left))


def print_corner(gateway, corner):
    odom = gateway.telemetry["odom"]
    print(f"corner {corner}: x {odom['x']:.3f} m, y {odom['y']:.3f} m, yaw {odom['yaw']:.3f} rad", flush=True)


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("WHEELTEC_SOCKET", "/run/wheeltecd/wheeltecd.sock")
    gateway = Gateway(path)
    version = gateway.call("version")
    print(f"wheeltecd {version['version']}, protocol {version['protocol']}")
    wait_until_ready(gateway)
    status = gateway.call("status")
    print(f"chassis {status['chassis']['type']}, battery {status['chassis']['battery_v']} V")

    # After the self-test: the controller's own 0.4 m drive is not part of the square.
    gateway.call("reset_odometry")
    gateway.call("subscribe", {"topics": ["telemetry"]})
    gateway.wait(0.2)
    try:
        for corner in range(4):
            print_corner(gateway, corner)
            drive_for(gateway, LEG_S, vx=SPEED)
            drive_for(gateway, LEG_S, wz=TURN_RATE)
        print_corner(gateway, 4)
    finally:
        gateway.call("stop")    # zero velocity now, and control released
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (OSError, RpcError, TimeoutError) as error:
        print(f"drive_square_socket.py: {error}", file=sys.stderr)
        sys.exit(1)
