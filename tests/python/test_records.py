"""The typed records, without a daemon: unknown keys ignored, missing keys defaulted, the
JSON kept as raw, frozen, and a record read lazily equal to one built whole."""
from __future__ import annotations

import copy
import dataclasses
import pickle

import pytest

import wheeltec
from wheeltec.records import notification_record

STATUS_5 = {
    "version": "0.1.0", "uptime_s": 12.3,
    "bus": {"transport": "serial", "interface": "/dev/wheeltec_controller", "state": "up"},
    "chassis": {"type": "diff", "online": True, "telemetry_age_s": 0.02, "stopped": False, "battery_v": 22.58,
                "battery_low": False, "phase": "ready", "commands_ignored": False},
    "dock": {"present": True, "charging": True, "ir": [True, False, False, True]},
    "control": {"enabled": True, "owner": 3, "target": {"vx": 0.2, "vy": 0.0, "wz": 0.5},
                "sent": {"vx": 0.1, "vy": 0.0, "wz": 0.25}, "limits": {"vx": 1.0, "vy": 1.0, "wz": 3.0},
                "accel": {"vx": 0.5, "vy": None, "wz": None}, "decel": {"vx": 1.0, "vy": None, "wz": None}},
    "safety": {"latched": True, "source": "client", "reason": "operator pressed E-STOP", "since": 1764600000.12,
               "by": 3},
    "odometry": {"scale": {"x": 0.97, "y": 1.0, "yaw_positive": 1.02, "yaw_negative": 0.99}},
}
TELEMETRY = {"seq": 42, "time": 1763800000.123456, "stopped": False,
             "velocity": {"vx": 0.257, "vy": 0.001, "wz": 0.0},
             "accel": {"x": -0.2165, "y": -0.3361, "z": 9.8756}, "gyro": {"x": -0.00133, "y": 0.00187, "z": 0.00027},
             "battery": {"voltage": 22.584, "low": False}, "odom": {"x": 0.5, "y": -0.25, "yaw": 1.5},
             "orientation": {"w": 1.0, "x": 0.0, "y": 0.0, "z": 0.0, "roll": 0.1, "pitch": -0.2, "yaw": 0.3}}


def test_status_of_protocol_5() -> None:
    status = wheeltec.Status.from_json(STATUS_5)
    assert status.bus == wheeltec.Bus("serial", "/dev/wheeltec_controller", "up")
    assert status.chassis.phase == "ready" and status.chassis.dialect is None and status.chassis.battery_v == 22.58
    assert status.dock == wheeltec.Dock(True, True, (True, False, False, True))
    assert status.control.owner == 3 and status.control.target == wheeltec.Velocity(0.2, 0.0, 0.5)
    assert status.control.sent == wheeltec.Velocity(0.1, 0.0, 0.25)
    assert status.control.limits == wheeltec.Velocity(1.0, 1.0, 3.0)
    assert status.control.accel == wheeltec.AxisLimits(0.5, None, None)
    assert status.control.decel.vx == 1.0
    assert status.safety == wheeltec.Safety(True, "client", "operator pressed E-STOP", 1764600000.12, 3)
    assert status.odometry.scale.yaw_positive == 1.02
    assert status.raw is STATUS_5 and status.chassis.raw is STATUS_5["chassis"]


def test_unknown_keys_are_ignored_and_missing_ones_defaulted() -> None:
    newer = copy.deepcopy(STATUS_5)
    newer["weather"] = {"rain": True}
    newer["chassis"]["temperature_c"] = 40
    newer["safety"]["acknowledged"] = False
    status = wheeltec.Status.from_json(newer)
    assert status.chassis.phase == "ready" and status.safety.latched
    assert status.raw["weather"] == {"rain": True}  # still in raw
    older = copy.deepcopy(STATUS_5)
    for key in ("safety", "odometry"):
        del older[key]
    for key in ("sent", "limits", "accel", "decel"):
        del older["control"][key]
    del older["bus"]["transport"]
    status = wheeltec.Status.from_json(older)
    assert status.safety == wheeltec.Safety() and status.safety.latched is False
    assert status.control.sent is None and status.control.limits is None
    assert status.control.accel == wheeltec.AxisLimits(None, None, None)
    assert status.odometry.scale == wheeltec.OdometryScale(1.0, 1.0, 1.0, 1.0)
    assert status.bus.transport == "can"  # protocol 2 had CAN only
    assert wheeltec.Telemetry.from_json({"seq": 1}).orientation.w == 1.0  # protocol 1: no orientation


def test_telemetry() -> None:
    t = wheeltec.Telemetry.from_json(TELEMETRY)
    assert (t.seq, t.time, t.stopped) == (42, 1763800000.123456, False)
    assert t.velocity == wheeltec.Velocity(0.257, 0.001, 0.0)
    assert t.accel == wheeltec.Vector3(-0.2165, -0.3361, 9.8756) and t.gyro.z == 0.00027
    assert t.battery == wheeltec.Battery(22.584, False) and t.odom == wheeltec.Pose2D(0.5, -0.25, 1.5)
    assert t.orientation == wheeltec.Orientation(1.0, 0.0, 0.0, 0.0, 0.1, -0.2, 0.3)


def test_a_record_read_lazily_equals_one_built_whole() -> None:
    lazy = wheeltec.Telemetry.from_json(TELEMETRY)
    whole = wheeltec.Telemetry(42, 1763800000.123456, False, wheeltec.Velocity(0.257, 0.001, 0.0),
                               wheeltec.Vector3(-0.2165, -0.3361, 9.8756), wheeltec.Vector3(-0.00133, 0.00187, 0.00027),
                               wheeltec.Battery(22.584, False), wheeltec.Pose2D(0.5, -0.25, 1.5),
                               wheeltec.Orientation(1.0, 0.0, 0.0, 0.0, 0.1, -0.2, 0.3))
    assert lazy == whole and hash(lazy) == hash(whole) and repr(lazy) == repr(whole)
    assert wheeltec.Telemetry.from_json(TELEMETRY) == whole  # compared before any attribute was read
    assert pickle.loads(pickle.dumps(wheeltec.Telemetry.from_json(TELEMETRY))) == whole
    assert dataclasses.asdict(wheeltec.Status.from_json(STATUS_5))["safety"]["reason"] == "operator pressed E-STOP"
    assert dataclasses.replace(lazy, seq=43).velocity == whole.velocity
    assert [f.name for f in dataclasses.fields(wheeltec.Status)] == [
        "version", "uptime_s", "bus", "chassis", "dock", "control", "safety", "odometry", "raw"]


def test_records_are_frozen() -> None:
    status = wheeltec.Status.from_json(STATUS_5)
    with pytest.raises(dataclasses.FrozenInstanceError):
        status.chassis = wheeltec.Chassis()  # type: ignore[misc]
    with pytest.raises(dataclasses.FrozenInstanceError):
        status.control.owner = 4  # type: ignore[misc]
    with pytest.raises(AttributeError):
        status.no_such_member  # type: ignore[attr-defined]


def test_event_fields_are_the_kind_s_own_members() -> None:
    event = wheeltec.Event.from_json({"time": 1.5, "event": "refused", "client": 6, "method": "drive",
                                      "code": -32001, "message": "control is held by client 5"})
    assert (event.time, event.event, event.client) == (1.5, "refused", 6)
    assert event.fields == {"method": "drive", "code": -32001, "message": "control is held by client 5"}
    assert hash(event) == hash(wheeltec.Event(1.5, "refused", 6))  # fields are compared, not hashed


def test_results() -> None:
    assert wheeltec.Version.from_json({"version": "0.1.0", "protocol": 5}) == wheeltec.Version("0.1.0", 5)
    drive = wheeltec.DriveResult.from_json({"vx": 1.0, "vy": 0.0, "wz": 0.5, "clamped": True})
    assert drive == wheeltec.DriveResult(1.0, 0.0, 0.5, True)


def test_notifications() -> None:
    assert isinstance(notification_record({"method": "telemetry", "params": TELEMETRY}), wheeltec.Telemetry)
    assert isinstance(notification_record({"method": "status", "params": STATUS_5}), wheeltec.Status)
    mark = notification_record({"method": "event", "params": {"time": 1.0, "event": "mark", "client": 2, "text": "x"}})
    assert isinstance(mark, wheeltec.Event) and mark.fields == {"text": "x"}
    assert notification_record({"method": "weather", "params": {}}) is None  # a newer daemon's topic
    assert notification_record({"method": "telemetry", "params": None}) is None
