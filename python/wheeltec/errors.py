"""The package's exceptions: every one is a ``wheeltec.Error``.

``RpcError`` carries the daemon's error object (``code``, ``message``, ``data``); each error
code of the contract has a subclass, so that a script catches the case it handles::

    try:
        robot.drive(vx=0.2)
    except wheeltec.ControlHeld:
        ...
"""
from __future__ import annotations

import builtins
from typing import Any, Dict, Mapping, Optional, Type


class Error(Exception):
    """Base class of every exception this package raises."""


class DaemonUnreachable(Error):
    """No connection to wheeltecd: no socket, connection refused or not permitted, or the
    daemon closed the connection (what wheeltecctl's exit status 3 means)."""


class ProtocolError(Error):
    """The daemon sent something that is not its protocol (not JSON, not an object)."""


class TimeoutError(Error, builtins.TimeoutError):
    """No answer within the client's ``timeout``, or nothing on a subscription for its
    ``timeout``. Also a builtin ``TimeoutError`` (so ``except TimeoutError`` catches it)."""


class RpcError(Error):
    """The daemon answered a request with an error object."""

    #: The error code this class stands for (0 for codes without a class of their own).
    CODE = 0

    def __init__(self, code: int, message: str, data: Any = None) -> None:
        super().__init__(code, message, data)
        self.code = code
        self.message = message
        self.data = data

    def __str__(self) -> str:
        return f"{self.message} ({self.code})"


class ControlHeld(RpcError):
    """-32001: another client holds control."""

    CODE = -32001


class ControlDisabled(RpcError):
    """-32002: control is disabled (``disable``, or ``control.auto_enable`` false)."""

    CODE = -32002


class LinkDown(RpcError):
    """-32003: the CAN bus is down or the serial device unplugged, absent or busy."""

    CODE = -32003


class NoTelemetry(RpcError):
    """-32004: no telemetry record has been accepted since the daemon started."""

    CODE = -32004


class NotPermitted(RpcError):
    """-32005: this user may not drive, enable, disable or release."""

    CODE = -32005


class ChassisNotReady(RpcError):
    """-32006: the chassis is booting, in its self-test or halted."""

    CODE = -32006

    @property
    def phase(self) -> Optional[str]:
        """The chassis phase the daemon reported (``error.data.phase``)."""
        phase = self.data.get("phase") if isinstance(self.data, dict) else None
        return phase if isinstance(phase, str) else None


class EmergencyStopLatched(RpcError):
    """-32007: the emergency stop is latched; ``release`` it first."""

    CODE = -32007

    @property
    def safety(self) -> Mapping[str, Any]:
        """The daemon's ``safety`` object (``latched``, ``source``, ``reason``, ...)."""
        return self.data if isinstance(self.data, dict) else {}


class MethodNotFound(RpcError):
    """-32601: the daemon has no such method (an older daemon, or a typo)."""

    CODE = -32601


class InvalidParams(RpcError):
    """-32602: a parameter is unknown, of the wrong type, not finite or out of range."""

    CODE = -32602


_BY_CODE: Dict[int, Type[RpcError]] = {
    cls.CODE: cls
    for cls in (ControlHeld, ControlDisabled, LinkDown, NoTelemetry, NotPermitted, ChassisNotReady,
                EmergencyStopLatched, MethodNotFound, InvalidParams)
}


def rpc_error(error: Any) -> RpcError:
    """The exception for a response's ``error`` member."""
    if not isinstance(error, dict) or not isinstance(error.get("code"), int):
        return RpcError(0, f"malformed error object from the daemon: {error!r}")
    code: int = error["code"]
    message = error.get("message")
    return _BY_CODE.get(code, RpcError)(code, message if isinstance(message, str) else "", error.get("data"))
