"""wheeltecd's wire format without I/O: where the socket is, requests as bytes, the byte
stream cut into lines, and a line read as a response or a notification.

Both clients (``wheeltec.Client`` on blocking sockets, ``wheeltec.aio`` on asyncio) use it.
"""
from __future__ import annotations

import functools
import json
import math
import numbers
import os
from typing import Any, Dict, List, Mapping, Optional, Union

from .errors import ProtocolError, rpc_error

DEFAULT_SOCKET = "/run/wheeltecd/wheeltecd.sock"
SOCKET_ENVIRONMENT = "WHEELTEC_SOCKET"
# The daemon's own lines are a few hundred bytes; a longer one than this is not the protocol
# and must not make the client hold unbounded memory.
MAX_LINE = 16 * 1024 * 1024

PathArgument = Union[str, "os.PathLike[str]", None]


def socket_path(argument: PathArgument = None) -> str:
    """The socket to connect to: the argument, else $WHEELTEC_SOCKET, else the default."""
    if argument is not None:
        return os.fspath(argument)
    return os.environ.get(SOCKET_ENVIRONMENT) or DEFAULT_SOCKET


def check_timeout(timeout: Optional[float], name: str = "timeout") -> Optional[float]:
    """``timeout`` as a float (None: wait for ever); ValueError unless it is > 0."""
    if timeout is None:
        return None
    value = float(timeout)
    if not value > 0 or math.isinf(value):
        raise ValueError(f"{name} must be a finite number of seconds > 0, or None; got {timeout!r}")
    return value


@functools.lru_cache(maxsize=64)
def _method_json(method: str) -> str:
    return json.dumps(method)


def encode_request(request_id: int, method: str, params: Optional[Mapping[str, Any]] = None) -> bytes:
    """One request line. NaN and infinity go out as JSON's NaN/Infinity tokens, which the
    daemon answers with -32602 naming the param, as it does for any other bad value."""
    if params is None:
        text = f'{{"jsonrpc":"2.0","id":{request_id},"method":{_method_json(method)}}}\n'
    else:
        text = (f'{{"jsonrpc":"2.0","id":{request_id},"method":{_method_json(method)},'
                f'"params":{json.dumps(params, separators=(",", ":"))}}}\n')
    return text.encode()


def number(value: Any) -> Any:
    """A velocity for the request: any real number as a float (numpy's included); anything
    else (bool, str, None) is sent as it is, for the daemon to refuse with -32602."""
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        return float(value)
    return value


def velocity_params(vx: float, vy: float, wz: float) -> Dict[str, Any]:
    return {"vx": number(vx), "vy": number(vy), "wz": number(wz)}


class LineBuffer:
    """Cuts the bytes received into lines (without their ``\\n``); blank lines are dropped."""

    def __init__(self, max_line: int = MAX_LINE) -> None:
        self._pending = b""
        self._max_line = max_line

    def feed(self, data: bytes) -> List[bytes]:
        if self._pending:
            data = self._pending + data
        newline = data.find(b"\n")
        if newline == len(data) - 1:  # the usual case: exactly one whole line
            self._pending = b""
            return [data[:-1]] if newline > 0 else []
        if newline < 0:
            lines = []
            self._pending = data
        else:
            lines = data.split(b"\n")
            self._pending = lines.pop()
        if len(self._pending) > self._max_line:
            self._pending = b""
            raise ProtocolError(f"the daemon sent a line longer than {self._max_line} bytes")
        return [line for line in lines if line.strip()]

    @property
    def pending(self) -> bytes:
        """Bytes received after the last whole line."""
        return self._pending


def decode(line: bytes) -> Dict[str, Any]:
    """A line from the daemon as a JSON object."""
    try:
        message = json.loads(line)
    except ValueError as error:  # JSONDecodeError and UnicodeDecodeError
        raise ProtocolError(f"the daemon sent a line that is not JSON ({error}): {line[:200]!r}") from None
    if not isinstance(message, dict):
        raise ProtocolError(f"the daemon sent a line that is not a JSON object: {line[:200]!r}")
    return message


# What a line is, for a client waiting for the answer to request `request_id`.
NOTIFICATION = 1  # a notification (a method without an id): for subscribers
ANSWER = 2        # the answer to this request
OTHER = 3         # an answer to an earlier request that timed out: skipped


def classify(message: Mapping[str, Any], request_id: int) -> int:
    if "method" in message:
        return NOTIFICATION
    answer_id = message.get("id")
    if answer_id == request_id and not isinstance(answer_id, bool):
        return ANSWER
    # The daemon answers with id null what it could not read as a request, and sends -32000
    # (too many clients) with id null before it closes a connection: this request's answer.
    if answer_id is None and "error" in message:
        return ANSWER
    return OTHER


def result_of(message: Mapping[str, Any]) -> Any:
    """The answer's result; its error as an RpcError (raised)."""
    if "error" in message:
        raise rpc_error(message["error"])
    if "result" not in message:
        raise ProtocolError(f"the daemon's answer has neither result nor error: {dict(message)!r}")
    return message["result"]


def result_object(result: Any, method: str) -> Dict[str, Any]:
    if not isinstance(result, dict):
        raise ProtocolError(f"the daemon's result of {method} is not an object: {result!r}")
    return result
