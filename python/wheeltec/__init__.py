"""Python client of wheeltecd, the WHEELTEC chassis gateway (its JSON-RPC socket).

::

    import wheeltec
    with wheeltec.Client() as robot:          # socket: argument, $WHEELTEC_SOCKET, default path
        print(robot.version().protocol)
        t = robot.telemetry()                  # wheeltec.Telemetry
        with robot.driver() as drive:          # repeats the target within the deadman, stops on exit
            drive.set(vx=0.2, wz=0.3)
            time.sleep(2)
        for t in robot.subscribe("telemetry", count=20):
            print(t.odom.x)

``wheeltec.aio`` is the same on asyncio. Standard library only; docs/python.md.
"""
from . import aio
from .client import Client, Driver, Subscription
from .errors import (ChassisNotReady, ControlDisabled, ControlHeld, DaemonUnreachable, EmergencyStopLatched, Error,
                     InvalidParams, LinkDown, MethodNotFound, NoTelemetry, NotPermitted, ProtocolError, RpcError,
                     TimeoutError)
from .protocol import DEFAULT_SOCKET
from .records import (AxisLimits, Battery, Bus, Chassis, Control, Dock, DriveResult, Event, Odometry, OdometryScale,
                      Orientation, Pose2D, Record, Safety, Status, Telemetry, Vector3, Velocity, Version)

__version__ = "0.1.0"

__all__ = [
    "aio", "Client", "Driver", "Subscription", "DEFAULT_SOCKET",
    "Error", "DaemonUnreachable", "ProtocolError", "TimeoutError", "RpcError", "ControlHeld", "ControlDisabled",
    "LinkDown", "NoTelemetry", "NotPermitted", "ChassisNotReady", "EmergencyStopLatched", "InvalidParams",
    "MethodNotFound",
    "Telemetry", "Velocity", "Vector3", "Battery", "Pose2D", "Orientation", "Status", "Bus", "Chassis", "Dock",
    "Control", "AxisLimits", "Safety", "Odometry", "OdometryScale", "Event", "Version", "DriveResult", "Record",
]
