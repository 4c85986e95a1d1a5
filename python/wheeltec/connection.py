"""One blocking connection to wheeltecd's socket: requests and their answers in order, and
the notifications between them."""
from __future__ import annotations

import collections
import socket
import threading
import time
from typing import Any, Deque, Dict, Mapping, Optional

from . import protocol
from .errors import DaemonUnreachable, TimeoutError

_RECEIVE_SIZE = 65536


class Connection:
    """A socket to the daemon. ``call`` is safe from several threads (one request at a time);
    notifications that arrive while it waits are kept in ``notifications`` when
    ``keep_notifications``, else dropped. After a timeout the late answer is skipped by its id."""

    def __init__(self, path: str, timeout: Optional[float], keep_notifications: bool = False) -> None:
        self.path = path
        self.timeout = timeout
        self.notifications: Deque[Dict[str, Any]] = collections.deque()
        self._keep_notifications = keep_notifications
        self._lines: Deque[bytes] = collections.deque()
        self._buffer = protocol.LineBuffer()
        self._lock = threading.Lock()
        self._last_id = 0
        self._closed = False
        self._socket = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM | socket.SOCK_CLOEXEC)
        self._socket_timeout = timeout
        try:
            self._socket.settimeout(timeout)
            self._socket.connect(path)
        except socket.timeout:
            self._socket.close()
            raise TimeoutError(f"wheeltecd at {path} did not accept the connection within {timeout} s") from None
        except OSError as error:
            self._socket.close()
            raise DaemonUnreachable(f"cannot connect to wheeltecd at {path}: {error.strerror or error}") from None

    @property
    def closed(self) -> bool:
        return self._closed

    def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        try:
            self._socket.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass
        self._socket.close()

    def call(self, method: str, params: Optional[Mapping[str, Any]] = None) -> Any:
        """Sends one request and returns its result (its error raised as an RpcError)."""
        with self._lock:
            self._last_id += 1
            request_id = self._last_id
            self._send(protocol.encode_request(request_id, method, params), method)
            deadline = None if self.timeout is None else time.monotonic() + self.timeout
            while True:
                message = self._next_message(self.timeout, deadline)
                if message is None:
                    raise TimeoutError(f"wheeltecd did not answer {method} within {self.timeout} s")
                kind = protocol.classify(message, request_id)
                if kind == protocol.ANSWER:
                    return protocol.result_of(message)
                if kind == protocol.NOTIFICATION and self._keep_notifications:
                    self.notifications.append(message)

    def next_notification(self, timeout: Optional[float]) -> Optional[Dict[str, Any]]:
        """The next notification, or None when none came within ``timeout`` (None: wait)."""
        if self.notifications:
            return self.notifications.popleft()
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            message = self._next_message(timeout, deadline)
            timeout = None if deadline is None else deadline - time.monotonic()
            if message is None or "method" in message:
                return message

    def _send(self, data: bytes, method: str) -> None:
        if self._closed:
            raise DaemonUnreachable(f"the connection to wheeltecd at {self.path} is closed")
        try:
            self._socket.sendall(data)
        except socket.timeout:
            raise TimeoutError(f"wheeltecd did not take the request {method} within {self.timeout} s") from None
        except OSError as error:
            self.close()
            raise DaemonUnreachable(f"wheeltecd at {self.path} closed the connection: {error.strerror or error}") from None

    def _next_message(self, wait: Optional[float], deadline: Optional[float]) -> Optional[Dict[str, Any]]:
        """The next line as an object; None when nothing came within ``wait`` seconds for the
        first read (no clock read: the common case) and by ``deadline`` (monotonic) for later ones."""
        first = True
        while not self._lines:
            if self._closed:
                raise DaemonUnreachable(f"the connection to wheeltecd at {self.path} is closed")
            wanted = wait if first else None if deadline is None else deadline - time.monotonic()
            first = False
            if wanted is not None and wanted <= 0:
                return None
            if wanted != self._socket_timeout:
                self._socket.settimeout(wanted)
                self._socket_timeout = wanted
            try:
                chunk = self._socket.recv(_RECEIVE_SIZE)
            except socket.timeout:
                return None
            except OSError as error:
                self.close()
                raise DaemonUnreachable(f"wheeltecd at {self.path} closed the connection: {error.strerror or error}") from None
            if not chunk:
                self.close()
                raise DaemonUnreachable(f"wheeltecd at {self.path} closed the connection")
            self._lines.extend(self._buffer.feed(chunk))
        return protocol.decode(self._lines.popleft())
