"""The blocking client: ``wheeltec.Client``, its ``Driver`` and its ``Subscription``."""
from __future__ import annotations

import math
import threading
import time
from types import TracebackType
from typing import Any, Dict, Generic, Iterator, List, Literal, Mapping, Optional, Tuple, Type, TypeVar, overload

from . import protocol
from .connection import Connection
from .errors import Error, TimeoutError
from .records import DriveResult, Event, Record, Status, Telemetry, Version, notification_record

R = TypeVar("R", covariant=True)  # what a Subscription yields: Telemetry, Status, Event or any Record
_Target = Tuple[float, float, float]


class Client:
    """One connection to wheeltecd (the daemon's one client: one id, one owner of control).

    ``socket_path``: the daemon's socket (default $WHEELTEC_SOCKET, else
    /run/wheeltecd/wheeltecd.sock); ``timeout``: seconds to wait for each answer (None: for
    ever). Connects at once (``DaemonUnreachable`` when it cannot). Calls may come from
    several threads; each waits for its own answer. Closing the client (``close()``, or
    leaving its ``with`` block) closes the connection: the daemon releases control it held.
    """

    def __init__(self, socket_path: protocol.PathArgument = None, timeout: Optional[float] = 5.0) -> None:
        self.socket_path = protocol.socket_path(socket_path)
        self.timeout = protocol.check_timeout(timeout)
        self._connection = Connection(self.socket_path, self.timeout)

    def __enter__(self) -> Client:
        return self

    def __exit__(self, exc_type: Optional[Type[BaseException]], exc: Optional[BaseException],
                 tb: Optional[TracebackType]) -> None:
        self.close()

    def __repr__(self) -> str:
        state = "closed" if self.closed else "open"
        return f"<wheeltec.Client {self.socket_path!r} {state}>"

    @property
    def closed(self) -> bool:
        return self._connection.closed

    def close(self) -> None:
        self._connection.close()

    def call(self, method: str, params: Optional[Mapping[str, Any]] = None) -> Any:
        """Any method of the daemon; returns its JSON result, raises its error as an RpcError."""
        return self._connection.call(method, params)

    def version(self) -> Version:
        return Version.from_json(protocol.result_object(self._connection.call("version"), "version"))

    def status(self) -> Status:
        return Status.from_json(protocol.result_object(self._connection.call("status"), "status"))

    def telemetry(self) -> Telemetry:
        """The latest record (``NoTelemetry`` before the daemon has accepted one)."""
        return Telemetry.from_json(protocol.result_object(self._connection.call("telemetry"), "telemetry"))

    def stats(self) -> Dict[str, Any]:
        return protocol.result_object(self._connection.call("stats"), "stats")

    def drive(self, vx: float = 0.0, vy: float = 0.0, wz: float = 0.0) -> DriveResult:
        """One ``drive``: takes or renews control for ``control.command_timeout_s`` (the deadman).
        Use ``driver()`` or ``drive_for()`` to keep driving."""
        result = self._connection.call("drive", protocol.velocity_params(vx, vy, wz))
        return DriveResult.from_json(protocol.result_object(result, "drive"))

    def stop(self) -> None:
        """Zero velocity at once, and control released, whoever holds it."""
        self._connection.call("stop")

    def enable(self) -> None:
        self._connection.call("enable")

    def disable(self) -> None:
        self._connection.call("disable")

    def reset_odometry(self) -> None:
        self._connection.call("reset_odometry")

    def mark(self, text: str) -> None:
        """A ``mark`` event with this text (at most 200 characters) for the black box."""
        self._connection.call("mark", {"text": text})

    def estop(self, reason: str = "") -> None:
        """Latches the emergency stop: zero at once, and every ``drive`` and ``enable`` refused
        (``EmergencyStopLatched``) until ``release()``. Anyone may call it."""
        self._connection.call("estop", {"reason": reason})

    def release(self) -> None:
        """Clears the latched emergency stop (needs the rights of ``drive``); nothing moves
        until the next ``drive``."""
        self._connection.call("release")

    def driver(self, period: float = 0.1) -> Driver:
        """A context manager that holds control: ``set()`` the target, which is sent at once and
        then every ``period`` seconds; leaving the block sends ``stop``."""
        return Driver(self, period)

    def drive_for(self, seconds: float, vx: float = 0.0, vy: float = 0.0, wz: float = 0.0) -> DriveResult:
        """Drives at this velocity for ``seconds`` (repeating it within the deadman), then stops.
        A refusal on the way stops the robot and is raised."""
        seconds = _seconds(seconds, "seconds")
        with self.driver() as drive:
            result = drive.set(vx, vy, wz)
            drive.wait(seconds)
        return result

    @overload
    def subscribe(self, topic: Literal["telemetry"], /, *, count: Optional[int] = None,
                  timeout: Optional[float] = None) -> Subscription[Telemetry]: ...

    @overload
    def subscribe(self, topic: Literal["status"], /, *, count: Optional[int] = None,
                  timeout: Optional[float] = None) -> Subscription[Status]: ...

    @overload
    def subscribe(self, topic: Literal["events"], /, *, count: Optional[int] = None,
                  timeout: Optional[float] = None) -> Subscription[Event]: ...

    @overload
    def subscribe(self, *topics: str, count: Optional[int] = None,
                  timeout: Optional[float] = None) -> Subscription[Record]: ...

    def subscribe(self, *topics: str, count: Optional[int] = None, timeout: Optional[float] = None) -> Subscription[Any]:
        """An iterator of ``Telemetry``, ``Status`` and ``Event`` values (topics ``telemetry``,
        ``status``, ``events``) on a connection of its own, in the order they came. It ends
        after ``count`` values; raises ``TimeoutError`` when nothing came for ``timeout``
        seconds; closing it (or leaving a ``for`` loop early) closes that connection."""
        return Subscription(self.socket_path, topics, count, timeout, self.timeout)


def _seconds(value: float, name: str) -> float:
    seconds = float(value)
    if not seconds >= 0 or math.isinf(seconds):
        raise ValueError(f"{name} must be a finite number of seconds >= 0; got {value!r}")
    return seconds


class Driver:
    """Holds control for a ``with`` block (``Client.driver()``).

    ``set()`` sends the new target at once (raising its refusal), and a background thread
    repeats it every ``period`` seconds, well within the daemon's deadman. The first refusal
    of a repeat stops the repeating (the daemon's deadman then stops the robot) and is raised
    by the next ``set()``, ``wait()`` or at the end of the block. Leaving the block, normally
    or by an exception, sends ``stop``.
    """

    def __init__(self, client: Client, period: float = 0.1) -> None:
        self.period = protocol.check_timeout(period, "period") or 0.1
        self._client = client
        # Held while a drive is sent, so that a repeat never sends a target older than one set.
        self._state = threading.Condition()
        self._target: Optional[_Target] = None
        self._failure: Optional[Error] = None
        self._last_sent = 0.0
        self._ending = False
        self._thread: Optional[threading.Thread] = None
        self.last_result: Optional[DriveResult] = None

    def __enter__(self) -> Driver:
        if self._thread is not None or self._ending:
            raise RuntimeError("a Driver's block can be entered once")
        self._thread = threading.Thread(target=self._repeat, name="wheeltec-driver", daemon=True)
        self._thread.start()
        return self

    def __exit__(self, exc_type: Optional[Type[BaseException]], exc: Optional[BaseException],
                 tb: Optional[TracebackType]) -> None:
        with self._state:
            self._ending = True
            self._target = None
            self._state.notify_all()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join()
        stop_error: Optional[Error] = None
        try:
            self._client.stop()
        except Error as error:
            stop_error = error
        failure, self._failure = self._failure, None
        if exc_type is None:
            if failure is not None:
                raise failure
            if stop_error is not None:
                raise stop_error

    @property
    def target(self) -> Optional[Tuple[float, float, float]]:
        """The (vx, vy, wz) being repeated; None before the first ``set`` or after a refusal."""
        return self._target

    def set(self, vx: float = 0.0, vy: float = 0.0, wz: float = 0.0) -> DriveResult:
        """The new target, sent at once; returns the daemon's result. Raises the refusal of an
        earlier repeat (without sending), or this drive's own refusal."""
        with self._state:
            if self._ending:
                raise RuntimeError("the driver's block has ended")
            self._raise_failure()
            self._target = None
            self._last_sent = time.monotonic()
            result = self._client.drive(vx, vy, wz)
            self.last_result = result
            self._target = (vx, vy, wz)
            self._state.notify_all()
            return result

    def wait(self, seconds: float) -> None:
        """Sleeps for ``seconds`` while the target is repeated; raises a refusal as it comes."""
        deadline = time.monotonic() + _seconds(seconds, "seconds")
        with self._state:
            while True:
                self._raise_failure()
                left = deadline - time.monotonic()
                if left <= 0:
                    return
                self._state.wait(left)

    def _raise_failure(self) -> None:
        failure, self._failure = self._failure, None
        if failure is not None:
            raise failure

    def _repeat(self) -> None:
        with self._state:
            while not self._ending:
                target = self._target
                if target is None or self._failure is not None:
                    self._state.wait()
                    continue
                left = self._last_sent + self.period - time.monotonic()
                if left > 0:
                    self._state.wait(left)
                    continue
                self._last_sent = time.monotonic()
                try:
                    self.last_result = self._client.drive(*target)
                except Error as error:
                    error.__traceback__ = None  # no cycle through this frame while it waits to be raised
                    self._failure = error
                    self._target = None
                    self._state.notify_all()


class Subscription(Generic[R]):
    """Notifications of the daemon's topics on a connection of its own (``Client.subscribe``).

    An iterator and a context manager. It ends after ``count`` values, raises
    ``TimeoutError`` when nothing came for ``timeout`` seconds, and ``DaemonUnreachable``
    when the daemon goes. ``close()``, the end of a ``with`` block, the end of the iteration
    or dropping the last reference (a ``for`` loop left early) close the connection at once.
    """

    def __init__(self, socket_path: str, topics: Tuple[str, ...], count: Optional[int] = None,
                 timeout: Optional[float] = None, call_timeout: Optional[float] = 5.0) -> None:
        if count is not None and (not isinstance(count, int) or count < 0):
            raise ValueError(f"count must be an integer >= 0 or None; got {count!r}")
        self.topics: List[str] = list(topics)
        self.count = count
        self.timeout = protocol.check_timeout(timeout)
        self.delivered = 0
        self._connection: Optional[Connection] = None
        connection = Connection(socket_path, call_timeout, keep_notifications=True)
        try:
            connection.call("subscribe", {"topics": self.topics})
        except BaseException:
            connection.close()
            raise
        self._connection = connection
        if count == 0:
            self.close()

    def __iter__(self) -> Iterator[R]:
        return self

    def __next__(self) -> R:
        connection = self._connection
        if connection is None:
            raise StopIteration
        try:
            while True:
                message = connection.next_notification(self.timeout)
                if message is None:
                    raise TimeoutError(f"nothing came on {', '.join(self.topics)} for {self.timeout} s")
                record = notification_record(message)
                if record is not None:
                    break
        except BaseException:
            self.close()
            raise
        self.delivered += 1
        if self.count is not None and self.delivered >= self.count:
            self.close()
        return record  # type: ignore[return-value]

    def __enter__(self) -> Subscription[R]:
        return self

    def __exit__(self, exc_type: Optional[Type[BaseException]], exc: Optional[BaseException],
                 tb: Optional[TracebackType]) -> None:
        self.close()

    def __del__(self) -> None:
        try:
            self.close()
        except Exception:  # at interpreter exit the socket module may be gone already
            pass

    @property
    def closed(self) -> bool:
        return self._connection is None

    def close(self) -> None:
        """Closes the connection (the daemon drops its subscriptions); the iteration ends."""
        connection = getattr(self, "_connection", None)
        if connection is not None:
            self._connection = None
            connection.close()
