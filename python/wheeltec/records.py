"""The daemon's JSON objects as typed, frozen records.

Each record keeps the object it was made from as ``raw`` (not compared, not shown by
``repr``) and reads only the keys it knows: keys a newer daemon adds are ignored, and keys
an older daemon lacks take their defaults (``Status.safety`` of a protocol 4 daemon is
"not latched", ``Control.sent`` is None). No I/O here.

``from_json`` is the fast way in: it fills the record's ``__dict__`` directly (a frozen
dataclass' ``__init__`` costs as much as parsing the JSON line), and a nested record
(``Status.chassis``, ``Telemetry.velocity``, ...) is made from ``raw`` the first time it is
read. A record made by calling its class is complete at once; both compare, hash and print
the same.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, ClassVar, Dict, Mapping, Optional, Tuple, Union

JsonObject = Mapping[str, Any]
_new = object.__new__
_fill = object.__setattr__


def _raw() -> Any:
    return field(default_factory=dict, compare=False, repr=False)


def _as_object(value: Any) -> JsonObject:
    return value if isinstance(value, dict) else {}


class _Nested:
    """Makes a nested record that ``from_json`` left out from ``raw`` when it is first read."""

    _nested: ClassVar[Mapping[str, Callable[[Any], Any]]] = {}

    if not TYPE_CHECKING:  # mypy keeps checking attribute names
        def __getattr__(self, name: str) -> Any:
            make = type(self)._nested.get(name)
            raw = self.__dict__.get("raw")
            if make is None or raw is None:
                raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
            value = make(raw.get(name))
            _fill(self, name, value)
            return value


@dataclass(frozen=True)
class Velocity:
    """m/s forward (vx) and to the left (vy), rad/s counter-clockwise (wz)."""

    vx: float = 0.0
    vy: float = 0.0
    wz: float = 0.0
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Velocity:
        get = obj.get
        record = _new(cls)
        _fill(record, "__dict__", {"vx": get("vx", 0.0), "vy": get("vy", 0.0), "wz": get("wz", 0.0), "raw": obj})
        return record


@dataclass(frozen=True)
class Vector3:
    """accel (m/s²) or gyro (rad/s) in the robot's frame: x forward, y left, z up."""

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Vector3:
        get = obj.get
        record = _new(cls)
        _fill(record, "__dict__", {"x": get("x", 0.0), "y": get("y", 0.0), "z": get("z", 0.0), "raw": obj})
        return record


@dataclass(frozen=True)
class Battery:
    """Voltage in V; ``low`` below the daemon's ``telemetry.low_battery_v``."""

    voltage: float = 0.0
    low: bool = False
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Battery:
        record = _new(cls)
        _fill(record, "__dict__", {"voltage": obj.get("voltage", 0.0), "low": obj.get("low", False), "raw": obj})
        return record


@dataclass(frozen=True)
class Pose2D:
    """Odometry: x, y in m from where it started (or was reset), yaw in rad in (-pi, pi]."""

    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Pose2D:
        get = obj.get
        record = _new(cls)
        _fill(record, "__dict__", {"x": get("x", 0.0), "y": get("y", 0.0), "yaw": get("yaw", 0.0), "raw": obj})
        return record


@dataclass(frozen=True)
class Orientation:
    """The chassis' attitude: a unit quaternion (w, x, y, z) and roll, pitch, yaw in rad."""

    w: float = 1.0
    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    roll: float = 0.0
    pitch: float = 0.0
    yaw: float = 0.0
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Orientation:
        get = obj.get
        record = _new(cls)
        _fill(record, "__dict__", {"w": get("w", 1.0), "x": get("x", 0.0), "y": get("y", 0.0), "z": get("z", 0.0),
                                   "roll": get("roll", 0.0), "pitch": get("pitch", 0.0), "yaw": get("yaw", 0.0),
                                   "raw": obj})
        return record


@dataclass(frozen=True)
class Telemetry(_Nested):
    """One telemetry record (the ``telemetry`` method's result, a ``telemetry`` notification)."""

    seq: int = 0
    time: float = 0.0
    stopped: bool = False
    velocity: Velocity = field(default_factory=Velocity)
    accel: Vector3 = field(default_factory=Vector3)
    gyro: Vector3 = field(default_factory=Vector3)
    battery: Battery = field(default_factory=Battery)
    odom: Pose2D = field(default_factory=Pose2D)
    orientation: Orientation = field(default_factory=Orientation)
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Telemetry:
        get = obj.get
        record = _new(cls)
        _fill(record, "__dict__", {"seq": get("seq", 0), "time": get("time", 0.0), "stopped": get("stopped", False),
                                   "raw": obj})
        return record


@dataclass(frozen=True)
class Bus:
    """``status.bus``: the link to the chassis (``transport`` ``can`` or ``serial``)."""

    transport: str = "can"
    interface: str = ""
    state: str = "down"
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Bus:
        get = obj.get
        record = _new(cls)
        _fill(record, "__dict__", {"transport": get("transport", "can"), "interface": get("interface", ""),
                                   "state": get("state", "down"), "raw": obj})
        return record


@dataclass(frozen=True)
class Chassis:
    """``status.chassis``; ``phase`` is ``booting``, ``self-test``, ``ready``, ``halted`` or None."""

    type: str = ""
    dialect: Optional[str] = None
    online: bool = False
    telemetry_age_s: Optional[float] = None
    stopped: Optional[bool] = None
    battery_v: Optional[float] = None
    battery_low: Optional[bool] = None
    phase: Optional[str] = None
    commands_ignored: bool = False
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Chassis:
        get = obj.get
        record = _new(cls)
        _fill(record, "__dict__", {"type": get("type", ""), "dialect": get("dialect"), "online": get("online", False),
                                   "telemetry_age_s": get("telemetry_age_s"), "stopped": get("stopped"),
                                   "battery_v": get("battery_v"), "battery_low": get("battery_low"),
                                   "phase": get("phase"), "commands_ignored": get("commands_ignored", False),
                                   "raw": obj})
        return record


@dataclass(frozen=True)
class Dock:
    """``status.dock``: ``charging`` and ``ir`` (four receivers) only while ``present``."""

    present: bool = False
    charging: Optional[bool] = None
    ir: Optional[Tuple[bool, ...]] = None
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Dock:
        ir = obj.get("ir")
        record = _new(cls)
        _fill(record, "__dict__", {"present": obj.get("present", False), "charging": obj.get("charging"),
                                   "ir": tuple(ir) if isinstance(ir, list) else None, "raw": obj})
        return record


@dataclass(frozen=True)
class AxisLimits:
    """Per-axis limits (``control.accel``, ``control.decel``); None: no limit."""

    vx: Optional[float] = None
    vy: Optional[float] = None
    wz: Optional[float] = None
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> AxisLimits:
        get = obj.get
        record = _new(cls)
        _fill(record, "__dict__", {"vx": get("vx"), "vy": get("vy"), "wz": get("wz"), "raw": obj})
        return record


def _velocity_or_none(value: Any) -> Optional[Velocity]:
    return Velocity.from_json(value) if isinstance(value, dict) else None


@dataclass(frozen=True)
class Control(_Nested):
    """``status.control``. ``target`` is the velocity asked for; ``sent`` what the last
    control frame carried, ``limits``, ``accel`` and ``decel`` the configured values
    (protocol 5: ``sent`` and ``limits`` are None from an older daemon)."""

    enabled: bool = False
    owner: Optional[int] = None
    target: Velocity = field(default_factory=Velocity)
    sent: Optional[Velocity] = field(default_factory=lambda: None)
    limits: Optional[Velocity] = field(default_factory=lambda: None)
    accel: AxisLimits = field(default_factory=AxisLimits)
    decel: AxisLimits = field(default_factory=AxisLimits)
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Control:
        record = _new(cls)
        _fill(record, "__dict__", {"enabled": obj.get("enabled", False), "owner": obj.get("owner"), "raw": obj})
        return record


@dataclass(frozen=True)
class Safety:
    """``status.safety`` (protocol 5): the latched emergency stop. ``source`` is ``client``,
    ``collision``, ``tilt`` or ``stall``; ``by`` the client id for ``client``."""

    latched: bool = False
    source: Optional[str] = None
    reason: Optional[str] = None
    since: Optional[float] = None
    by: Optional[int] = None
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Safety:
        get = obj.get
        record = _new(cls)
        _fill(record, "__dict__", {"latched": get("latched", False), "source": get("source"), "reason": get("reason"),
                                   "since": get("since"), "by": get("by"), "raw": obj})
        return record


@dataclass(frozen=True)
class OdometryScale:
    """``status.odometry.scale``: the factors applied to the measured velocities."""

    x: float = 1.0
    y: float = 1.0
    yaw_positive: float = 1.0
    yaw_negative: float = 1.0
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> OdometryScale:
        get = obj.get
        record = _new(cls)
        _fill(record, "__dict__", {"x": get("x", 1.0), "y": get("y", 1.0), "yaw_positive": get("yaw_positive", 1.0),
                                   "yaw_negative": get("yaw_negative", 1.0), "raw": obj})
        return record


@dataclass(frozen=True)
class Odometry(_Nested):
    """``status.odometry``."""

    scale: OdometryScale = field(default_factory=OdometryScale)
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Odometry:
        record = _new(cls)
        _fill(record, "__dict__", {"raw": obj})
        return record


@dataclass(frozen=True)
class Status(_Nested):
    """The status object (the ``status`` method's result, a ``status`` notification)."""

    version: str = ""
    uptime_s: float = 0.0
    bus: Bus = field(default_factory=Bus)
    chassis: Chassis = field(default_factory=Chassis)
    dock: Dock = field(default_factory=Dock)
    control: Control = field(default_factory=Control)
    safety: Safety = field(default_factory=Safety)
    odometry: Odometry = field(default_factory=Odometry)
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Status:
        record = _new(cls)
        _fill(record, "__dict__", {"version": obj.get("version", ""), "uptime_s": obj.get("uptime_s", 0.0), "raw": obj})
        return record


def _nested(make: Callable[[JsonObject], Any]) -> Callable[[Any], Any]:
    return lambda value: make(_as_object(value))


Telemetry._nested = {"velocity": _nested(Velocity.from_json), "accel": _nested(Vector3.from_json),
                     "gyro": _nested(Vector3.from_json), "battery": _nested(Battery.from_json),
                     "odom": _nested(Pose2D.from_json), "orientation": _nested(Orientation.from_json)}
Control._nested = {"target": _nested(Velocity.from_json), "sent": _velocity_or_none, "limits": _velocity_or_none,
                   "accel": _nested(AxisLimits.from_json), "decel": _nested(AxisLimits.from_json)}
Odometry._nested = {"scale": _nested(OdometryScale.from_json)}
Status._nested = {"bus": _nested(Bus.from_json), "chassis": _nested(Chassis.from_json), "dock": _nested(Dock.from_json),
                  "control": _nested(Control.from_json), "safety": _nested(Safety.from_json),
                  "odometry": _nested(Odometry.from_json)}

_EVENT_KEYS = ("time", "event", "client")


@dataclass(frozen=True)
class Event:
    """One event of the ``events`` topic: ``time``, ``event`` (its kind), ``client`` (None for
    the daemon's own) and the kind's other members as ``fields``
    (``Event.fields["text"]`` of a ``mark``)."""

    time: float = 0.0
    event: str = ""
    client: Optional[int] = None
    fields: Mapping[str, Any] = field(default_factory=dict, hash=False)
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Event:
        record = _new(cls)
        _fill(record, "__dict__", {"time": obj.get("time", 0.0), "event": obj.get("event", ""),
                                   "client": obj.get("client"),
                                   "fields": {key: value for key, value in obj.items() if key not in _EVENT_KEYS},
                                   "raw": obj})
        return record


@dataclass(frozen=True)
class Version:
    """The ``version`` method's result: the daemon's version and its protocol number."""

    version: str = ""
    protocol: int = 0
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> Version:
        record = _new(cls)
        _fill(record, "__dict__", {"version": obj.get("version", ""), "protocol": obj.get("protocol", 0), "raw": obj})
        return record


@dataclass(frozen=True)
class DriveResult:
    """The ``drive`` method's result: the velocity as sent (clamped to the daemon's limits,
    in steps of 0.001) and whether a limit changed it."""

    vx: float = 0.0
    vy: float = 0.0
    wz: float = 0.0
    clamped: bool = False
    raw: JsonObject = _raw()

    @classmethod
    def from_json(cls, obj: JsonObject) -> DriveResult:
        get = obj.get
        record = _new(cls)
        _fill(record, "__dict__", {"vx": get("vx", 0.0), "vy": get("vy", 0.0), "wz": get("wz", 0.0),
                                   "clamped": get("clamped", False), "raw": obj})
        return record


Record = Union[Telemetry, Status, Event]

_NOTIFICATIONS: Dict[str, Callable[[JsonObject], Record]] = {
    "telemetry": Telemetry.from_json, "status": Status.from_json, "event": Event.from_json}


def notification_record(message: JsonObject) -> Optional[Record]:
    """The record a notification carries; None for a notification this package does not know."""
    make = _NOTIFICATIONS.get(message.get("method", ""))
    params = message.get("params")
    if make is None or not isinstance(params, dict):
        return None
    return make(params)
