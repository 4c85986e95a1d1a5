#!/usr/bin/env python3
"""Drives the robot around a square (four sides of 2 s at 0.2 m/s, four quarter turns) with
the wheeltec package and prints the odometry at every corner.

    drive_square.py [SOCKET]   (default: $WHEELTEC_SOCKET, else /run/wheeltecd/wheeltecd.sock)

From a source tree: PYTHONPATH=python examples/drive_square.py. The same with the bare
socket and the standard library only: examples/drive_square_socket.py.
"""
import math
import sys

import wheeltec

LEG_S = 2.0                         # each side and each turn lasts 2 s
SPEED = 0.2                         # m/s
TURN_RATE = math.pi / 2 / LEG_S     # rad/s: a quarter turn per turn leg


def ready(status):
    return status.chassis.online and status.chassis.phase == "ready"


def wait_until_ready(robot, timeout_s=30.0):
    """Online and past the controller's boot and self-test (a status notification comes on
    every change; TimeoutError when none comes for timeout_s)."""
    with robot.subscribe("status", timeout=timeout_s) as changes:
        status = robot.status()
        while not ready(status):
            status = next(changes)
    return status


def print_corner(robot, corner):
    odom = robot.telemetry().odom
    print(f"corner {corner}: x {odom.x:.3f} m, y {odom.y:.3f} m, yaw {odom.yaw:.3f} rad", flush=True)


def main():
    with wheeltec.Client(sys.argv[1] if len(sys.argv) > 1 else None) as robot:
        version = robot.version()
        print(f"wheeltecd {version.version}, protocol {version.protocol}")
        status = wait_until_ready(robot)
        print(f"chassis {status.chassis.type}, battery {status.chassis.battery_v} V")

        # After the self-test: the controller's own 0.4 m drive is not part of the square.
        robot.reset_odometry()
        next(robot.subscribe("telemetry", count=1))  # a record made after the reset

        # The driver repeats each target every 0.1 s (the daemon's deadman stops a robot
        # whose driver goes quiet) and sends stop when the block ends, also on an error.
        with robot.driver() as drive:
            for corner in range(4):
                print_corner(robot, corner)
                drive.set(vx=SPEED)
                drive.wait(LEG_S)
                drive.set(wz=TURN_RATE)
                drive.wait(LEG_S)
            print_corner(robot, 4)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except wheeltec.Error as error:
        print(f"drive_square.py: {error}", file=sys.stderr)
        sys.exit(1)
