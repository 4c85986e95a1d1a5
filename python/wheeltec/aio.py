"""The client on asyncio: the same shape as ``wheeltec.Client``, with ``await``.

::

    async with wheeltec.aio.Client() as robot:
        status = await robot.status()
        async with robot.driver() as drive:
            await drive.set(vx=0.2)
            await asyncio.sleep(2)
        async for t in robot.subscribe("telemetry", count=20):
            print(t.odom.x)
"""
from __future__ import annotations

import asyncio
import collections
from types import TracebackType
from typing import (Any, AsyncIterator, Awaitable, Deque, Dict, Generic, List, Literal, Mapping, Optional, Tuple,
                    Type, TypeVar, overload)

from . import protocol
from .client import _seconds
from .errors import DaemonUnreachable, Error, ProtocolError, TimeoutError
from .records import DriveResult, Event, Record, Status, Telemetry, Version, notification_record

R = TypeVar("R", covariant=True)
T = TypeVar("T")
_Target = Tuple[float, float, float]


async def _within(awaitable: Awaitable[T], timeout: Optional[float], what: str) -> T:
    if timeout is None:
        return await awaitable
    try:
        return await asyncio.wait_for(awaitable, timeout)
    except asyncio.TimeoutError:
        raise TimeoutError(what) from None


class _Connection:
    """One stream to the daemon; ``call`` takes one request at a time, in order."""

    def __init__(self, path: str, timeout: Optional[float], keep_notifications: bool = False) -> None:
        self.path = path
        self.timeout = timeout
        self.notifications: Deque[Dict[str, Any]] = collections.deque()
        self._keep_notifications = keep_notifications
        self._reader: Optional[asyncio.StreamReader] = None
        self._writer: Optional[asyncio.StreamWriter] = None
        self._lock: Optional[asyncio.Lock] = None  # made in the running loop (Python 3.9 binds it there)
        self._last_id = 0
        self._closed = False

    @property
    def closed(self) -> bool:
        return self._closed

    async def open(self) -> None:
        if self._writer is not None:
            return
        if self._closed:
            raise DaemonUnreachable(f"the connection to wheeltecd at {self.path} is closed")
        try:
            self._reader, self._writer = await _within(
                asyncio.open_unix_connection(self.path, limit=protocol.MAX_LINE), self.timeout,
                f"wheeltecd at {self.path} did not accept the connection within {self.timeout} s")
        except OSError as error:
            self._closed = True
            raise DaemonUnreachable(f"cannot connect to wheeltecd at {self.path}: {error.strerror or error}") from None

    def close(self) -> None:
        """Closes the stream now (the socket itself on the loop's next turn)."""
        self._closed = True
        writer, self._writer = self._writer, None
        if writer is not None:
            try:
                writer.close()
            except RuntimeError:  # the loop is closed already: its transports are gone
                pass

    async def call(self, method: str, params: Optional[Mapping[str, Any]] = None) -> Any:
        if self._lock is None:
            self._lock = asyncio.Lock()
        async with self._lock:
            await self.open()
            self._last_id += 1
            request_id = self._last_id
            writer = self._writer
            if writer is None:
                raise DaemonUnreachable(f"the connection to wheeltecd at {self.path} is closed")
            try:
                writer.write(protocol.encode_request(request_id, method, params))
            except (OSError, RuntimeError) as error:
                self.close()
                raise DaemonUnreachable(f"wheeltecd at {self.path} closed the connection: {error}") from None
            return await _within(self._answer(request_id), self.timeout,
                                 f"wheeltecd did not answer {method} within {self.timeout} s")

    async def _answer(self, request_id: int) -> Any:
        while True:
            message = await self._next_message()
            kind = protocol.classify(message, request_id)
            if kind == protocol.ANSWER:
                return protocol.result_of(message)
            if kind == protocol.NOTIFICATION and self._keep_notifications:
                self.notifications.append(message)

    async def next_notification(self) -> Dict[str, Any]:
        if self.notifications:
            return self.notifications.popleft()
        while True:
            message = await self._next_message()
            if "method" in message:
                return message

    async def _next_message(self) -> Dict[str, Any]:
        reader = self._reader
        if reader is None or self._closed:
            raise DaemonUnreachable(f"the connection to wheeltecd at {self.path} is closed")
        while True:
            try:
                line = await reader.readline()
            except ValueError:  # longer than the reader's limit
                self.close()
                raise ProtocolError(f"the daemon sent a line longer than {protocol.MAX_LINE} bytes") from None
            except OSError as error:
                self.close()
                raise DaemonUnreachable(f"wheeltecd at {self.path} closed the connection: {error.strerror or error}") from None
            if not line.endswith(b"\n"):
                self.close()
                raise DaemonUnreachable(f"wheeltecd at {self.path} closed the connection")
            if line.strip():
                return protocol.decode(line)


class Client:
    """``wheeltec.Client`` on asyncio. Connects on ``async with`` (or ``await connect()``, or
    the first call); ``await close()`` closes the connection."""

    def __init__(self, socket_path: protocol.PathArgument = None, timeout: Optional[float] = 5.0) -> None:
        self.socket_path = protocol.socket_path(socket_path)
        self.timeout = protocol.check_timeout(timeout)
        self._connection = _Connection(self.socket_path, self.timeout)

    async def __aenter__(self) -> Client:
        await self.connect()
        return self

    async def __aexit__(self, exc_type: Optional[Type[BaseException]], exc: Optional[BaseException],
                        tb: Optional[TracebackType]) -> None:
        await self.close()

    def __repr__(self) -> str:
        return f"<wheeltec.aio.Client {self.socket_path!r} {'closed' if self.closed else 'open'}>"

    @property
    def closed(self) -> bool:
        return self._connection.closed

    async def connect(self) -> None:
        await self._connection.open()

    async def close(self) -> None:
        self._connection.close()
        await asyncio.sleep(0)  # the loop's turn in which the transport closes the socket

    async def call(self, method: str, params: Optional[Mapping[str, Any]] = None) -> Any:
        return await self._connection.call(method, params)

    async def _object(self, method: str, params: Optional[Mapping[str, Any]] = None) -> Dict[str, Any]:
        return protocol.result_object(await self._connection.call(method, params), method)

    async def version(self) -> Version:
        return Version.from_json(await self._object("version"))

    async def status(self) -> Status:
        return Status.from_json(await self._object("status"))

    async def telemetry(self) -> Telemetry:
        return Telemetry.from_json(await self._object("telemetry"))

    async def stats(self) -> Dict[str, Any]:
        return await self._object("stats")

    async def drive(self, vx: float = 0.0, vy: float = 0.0, wz: float = 0.0) -> DriveResult:
        return DriveResult.from_json(await self._object("drive", protocol.velocity_params(vx, vy, wz)))

    async def stop(self) -> None:
        await self._connection.call("stop")

    async def enable(self) -> None:
        await self._connection.call("enable")

    async def disable(self) -> None:
        await self._connection.call("disable")

    async def reset_odometry(self) -> None:
        await self._connection.call("reset_odometry")

    async def mark(self, text: str) -> None:
        await self._connection.call("mark", {"text": text})

    async def estop(self, reason: str = "") -> None:
        await self._connection.call("estop", {"reason": reason})

    async def release(self) -> None:
        await self._connection.call("release")

    def driver(self, period: float = 0.1) -> Driver:
        return Driver(self, period)

    async def drive_for(self, seconds: float, vx: float = 0.0, vy: float = 0.0, wz: float = 0.0) -> DriveResult:
        seconds = _seconds(seconds, "seconds")
        async with self.driver() as drive:
            result = await drive.set(vx, vy, wz)
            await drive.wait(seconds)
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
        """An async iterator (``async for``) of the topics' values on a connection of its own,
        opened at the first value (or ``async with``)."""
        return Subscription(self.socket_path, topics, count, timeout, self.timeout)


class Driver:
    """``wheeltec.Driver`` on asyncio: ``async with robot.driver() as drive: await drive.set(...)``;
    a task repeats the target every ``period``; leaving the block sends ``stop``."""

    def __init__(self, client: Client, period: float = 0.1) -> None:
        self.period = protocol.check_timeout(period, "period") or 0.1
        self._client = client
        self._target: Optional[_Target] = None
        self._failure: Optional[Error] = None
        self._last_sent = 0.0
        self._ending = False
        self._task: Optional[asyncio.Task[None]] = None
        self._changed: Optional[asyncio.Condition] = None
        self.last_result: Optional[DriveResult] = None

    async def __aenter__(self) -> Driver:
        if self._task is not None or self._ending:
            raise RuntimeError("a Driver's block can be entered once")
        self._changed = asyncio.Condition()
        self._task = asyncio.ensure_future(self._repeat())
        return self

    async def __aexit__(self, exc_type: Optional[Type[BaseException]], exc: Optional[BaseException],
                        tb: Optional[TracebackType]) -> None:
        self._ending = True
        self._target = None
        task, self._task = self._task, None
        if task is not None:
            task.cancel()
            try:
                await task
            except asyncio.CancelledError:
                pass
        stop_error: Optional[Error] = None
        try:
            await self._client.stop()
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
        return self._target

    def _condition(self) -> asyncio.Condition:
        if self._changed is None:
            raise RuntimeError("use the Driver in an 'async with' block")
        return self._changed

    def _raise_failure(self) -> None:
        failure, self._failure = self._failure, None
        if failure is not None:
            raise failure

    async def set(self, vx: float = 0.0, vy: float = 0.0, wz: float = 0.0) -> DriveResult:
        changed = self._condition()
        async with changed:
            if self._ending:
                raise RuntimeError("the driver's block has ended")
            self._raise_failure()
            self._target = None
            self._last_sent = asyncio.get_running_loop().time()
            result = await self._client.drive(vx, vy, wz)
            self.last_result = result
            self._target = (vx, vy, wz)
            changed.notify_all()
            return result

    async def wait(self, seconds: float) -> None:
        changed = self._condition()
        loop = asyncio.get_running_loop()
        deadline = loop.time() + _seconds(seconds, "seconds")
        async with changed:
            while True:
                self._raise_failure()
                left = deadline - loop.time()
                if left <= 0:
                    return
                try:
                    await asyncio.wait_for(changed.wait(), left)
                except asyncio.TimeoutError:
                    pass

    async def _repeat(self) -> None:
        changed = self._condition()
        loop = asyncio.get_running_loop()
        async with changed:
            while not self._ending:
                target = self._target
                if target is None or self._failure is not None:
                    await changed.wait()
                    continue
                left = self._last_sent + self.period - loop.time()
                if left > 0:
                    try:
                        await asyncio.wait_for(changed.wait(), left)
                    except asyncio.TimeoutError:
                        pass
                    continue
                self._last_sent = loop.time()
                try:
                    self.last_result = await self._client.drive(*target)
                except Error as error:
                    error.__traceback__ = None
                    self._failure = error
                    self._target = None
                    changed.notify_all()


class Subscription(Generic[R]):
    """``wheeltec.Subscription`` on asyncio: ``async for`` (``async with`` too); ``await
    close()`` (or ``aclose()``), the end of the iteration or dropping the last reference
    (an ``async for`` left early) close its connection."""

    def __init__(self, socket_path: str, topics: Tuple[str, ...], count: Optional[int] = None,
                 timeout: Optional[float] = None, call_timeout: Optional[float] = 5.0) -> None:
        if count is not None and (not isinstance(count, int) or count < 0):
            raise ValueError(f"count must be an integer >= 0 or None; got {count!r}")
        self.topics: List[str] = list(topics)
        self.count = count
        self.timeout = protocol.check_timeout(timeout)
        self.delivered = 0
        self._connection: Optional[_Connection] = _Connection(socket_path, call_timeout, keep_notifications=True)
        self._subscribed = False

    async def open(self) -> None:
        """Connects and subscribes (done by the first value when not called)."""
        connection = self._connection
        if connection is None or self._subscribed:
            return
        try:
            await connection.call("subscribe", {"topics": self.topics})
        except BaseException:
            self._close_now()
            raise
        self._subscribed = True
        if self.count == 0:
            self._close_now()

    def __aiter__(self) -> AsyncIterator[R]:
        return self

    async def __anext__(self) -> R:
        await self.open()
        connection = self._connection
        if connection is None:
            raise StopAsyncIteration
        try:
            while True:
                message = await _within(connection.next_notification(), self.timeout,
                                        f"nothing came on {', '.join(self.topics)} for {self.timeout} s")
                record = notification_record(message)
                if record is not None:
                    break
        except BaseException:
            self._close_now()
            raise
        self.delivered += 1
        if self.count is not None and self.delivered >= self.count:
            self._close_now()
        return record  # type: ignore[return-value]

    async def __aenter__(self) -> Subscription[R]:
        await self.open()
        return self

    async def __aexit__(self, exc_type: Optional[Type[BaseException]], exc: Optional[BaseException],
                        tb: Optional[TracebackType]) -> None:
        await self.close()

    def __del__(self) -> None:
        try:
            self._close_now()
        except Exception:  # a loop that is gone, or the interpreter exiting
            pass

    @property
    def closed(self) -> bool:
        return self._connection is None

    def _close_now(self) -> None:
        connection = getattr(self, "_connection", None)
        if connection is not None:
            self._connection = None
            connection.close()

    async def close(self) -> None:
        self._close_now()
        await asyncio.sleep(0)

    aclose = close
