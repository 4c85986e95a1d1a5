"""The wire format without a socket: the socket path, requests, lines, answers and errors."""
from __future__ import annotations

import json
import math

import pytest

import wheeltec
from wheeltec import protocol
from wheeltec.errors import rpc_error


def test_socket_path(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("WHEELTEC_SOCKET", raising=False)
    assert protocol.socket_path() == "/run/wheeltecd/wheeltecd.sock" == wheeltec.DEFAULT_SOCKET
    monkeypatch.setenv("WHEELTEC_SOCKET", "/tmp/env.sock")
    assert protocol.socket_path() == "/tmp/env.sock"
    assert protocol.socket_path("/tmp/argument.sock") == "/tmp/argument.sock"
    monkeypatch.setenv("WHEELTEC_SOCKET", "")
    assert protocol.socket_path() == "/run/wheeltecd/wheeltecd.sock"


def test_requests() -> None:
    line = protocol.encode_request(7, "drive", protocol.velocity_params(0.2, 0, 1))
    assert line.endswith(b"\n") and line.count(b"\n") == 1
    assert json.loads(line) == {"jsonrpc": "2.0", "id": 7, "method": "drive",
                                "params": {"vx": 0.2, "vy": 0.0, "wz": 1.0}}
    assert json.loads(protocol.encode_request(8, "status")) == {"jsonrpc": "2.0", "id": 8, "method": "status"}
    assert json.loads(protocol.encode_request(9, "mark", {"text": 'a "quoted" é\n'}))["params"]["text"] == 'a "quoted" é\n'
    # Not a number: sent as it is, for the daemon to refuse (-32602), never turned into 1.0.
    assert protocol.velocity_params(True, "1", None) == {"vx": True, "vy": "1", "wz": None}
    assert b"NaN" in protocol.encode_request(1, "drive", protocol.velocity_params(math.nan, 0, 0))


def test_lines() -> None:
    lines = protocol.LineBuffer(max_line=100)
    assert lines.feed(b'{"a":1}\n') == [b'{"a":1}']
    assert lines.feed(b'{"b"') == [] and lines.pending == b'{"b"'
    assert lines.feed(b':2}\n{"c":3}\n\n{"d"') == [b'{"b":2}', b'{"c":3}']
    assert lines.feed(b":4}\n") == [b'{"d":4}'] and lines.pending == b""
    with pytest.raises(wheeltec.ProtocolError):
        lines.feed(b"x" * 101)


def test_decode_and_classify() -> None:
    assert protocol.decode(b'{"id":1,"result":{}}') == {"id": 1, "result": {}}
    for bad in (b"not json", b"[1,2]", b"\xff\xfe"):
        with pytest.raises(wheeltec.ProtocolError):
            protocol.decode(bad)
    assert protocol.classify({"method": "telemetry", "params": {}}, 3) == protocol.NOTIFICATION
    assert protocol.classify({"id": 3, "result": {}}, 3) == protocol.ANSWER
    assert protocol.classify({"id": 2, "result": {}}, 3) == protocol.OTHER  # late, after a timeout
    assert protocol.classify({"id": None, "error": {"code": -32000, "message": "too many clients"}}, 3) == protocol.ANSWER
    assert protocol.result_of({"id": 3, "result": {"x": 1}}) == {"x": 1}
    with pytest.raises(wheeltec.ControlHeld):
        protocol.result_of({"id": 3, "error": {"code": -32001, "message": "control is held by client 5"}})


def test_each_code_has_its_exception() -> None:
    expected = {-32001: wheeltec.ControlHeld, -32002: wheeltec.ControlDisabled, -32003: wheeltec.LinkDown,
                -32004: wheeltec.NoTelemetry, -32005: wheeltec.NotPermitted, -32006: wheeltec.ChassisNotReady,
                -32007: wheeltec.EmergencyStopLatched, -32601: wheeltec.MethodNotFound,
                -32602: wheeltec.InvalidParams}
    for code, cls in expected.items():
        error = rpc_error({"code": code, "message": "m", "data": {"phase": "booting"}})
        assert type(error) is cls and cls.CODE == code
        assert (error.code, error.message, error.data) == (code, "m", {"phase": "booting"})
        assert isinstance(error, wheeltec.RpcError) and isinstance(error, wheeltec.Error)
    other = rpc_error({"code": -32000, "message": "too many clients"})
    assert type(other) is wheeltec.RpcError and str(other) == "too many clients (-32000)"
    assert rpc_error({"code": -32006, "message": "booting", "data": {"phase": "booting"}}).phase == "booting"  # type: ignore[attr-defined]
    latched = rpc_error({"code": -32007, "message": "latched", "data": {"latched": True, "source": "tilt"}})
    assert latched.safety["source"] == "tilt"  # type: ignore[attr-defined]
    assert rpc_error("garbage").code == 0
    for cls in (wheeltec.DaemonUnreachable, wheeltec.TimeoutError, wheeltec.ProtocolError, wheeltec.RpcError):
        assert issubclass(cls, wheeltec.Error)
    assert issubclass(wheeltec.TimeoutError, TimeoutError)
