"""Fixtures of the Python client's tests: rigs of wheeltecd on a pseudo-terminal, with
wheeltec-emu or the fake controller on the other end.

The package under test comes from $WHEELTEC_PYTHON_DIR (default: python/ of this tree);
the programs from $WHEELTECD and $WHEELTEC_EMU (default: build/)."""
from __future__ import annotations

import functools
import json
import os
import socket
import sys
import time
from pathlib import Path
from typing import Any, Dict, Iterator, Optional, Sequence

import pytest

sys.path.insert(0, os.environ.get("WHEELTEC_PYTHON_DIR") or str(Path(__file__).resolve().parents[2] / "python"))

import wheeltec  # noqa: E402
from support import START_ALLOWANCE_S, Daemon, Emulator, FakeController, TestDirectory, wait_for  # noqa: E402

# The emulator's controller, ready soon: 0.3 s of boot, no self-test drive (the daemon's
# self-test phase still lasts 0.4 s).
QUICK_BOOT = ("--boot-delay", "0.3", "--no-self-test")


class Rig:
    """A test directory, the controller at DIR/tty (emulator or fake) and wheeltecd on it."""

    def __init__(self, emulator: Optional[Sequence[str]] = QUICK_BOOT, fake: bool = False,
                 config: Optional[Dict[str, Any]] = None, ready: bool = True) -> None:
        self.directory = TestDirectory()
        self.link = self.directory.path / "tty"
        self.emulator: Optional[Emulator] = None
        self.fake: Optional[FakeController] = None
        self.daemon: Optional[Daemon] = None
        try:
            if fake:
                self.fake = FakeController(self.link)
            elif emulator is not None:
                self.emulator = Emulator(self.directory.path, self.link, *emulator)
            self.daemon = Daemon(self.directory.path, self.link, config)
            if ready:
                self.wait_status(lambda s: s.chassis.phase == "ready", 10 + START_ALLOWANCE_S, "chassis ready")
        except BaseException:
            self.close()
            raise

    @property
    def socket(self) -> str:
        assert self.daemon is not None
        return str(self.daemon.socket_path)

    def client(self, timeout: Optional[float] = 5.0) -> wheeltec.Client:
        return wheeltec.Client(self.socket, timeout=timeout)

    def wait_status(self, predicate: Any, timeout: float, what: str) -> wheeltec.Status:
        with self.client() as client:
            last: list = []

            def check() -> Any:
                status = client.status()
                last[:] = [status]
                return status if predicate(status) else None
            try:
                return wait_for(check, timeout, what)  # type: ignore[no-any-return]
            except AssertionError as error:
                raise AssertionError(f"{error}; last status {last[0].raw if last else None}\n{self.logs()}") from None

    def clients(self) -> int:
        with self.client() as client:
            return int(client.stats()["clients"]) - 1  # not counting this one

    def logs(self) -> str:
        parts = []
        for process in (self.emulator, self.daemon):
            if process is not None:
                parts.append(f"--- {process.name}\n{process.output()}")
        return "\n".join(parts)

    def close(self) -> None:
        if self.daemon is not None:
            self.daemon.stop()
        if self.emulator is not None:
            self.emulator.stop()
        if self.fake is not None:
            self.fake.close()
        self.directory.remove()


@pytest.fixture
def make_rig() -> Iterator[Any]:
    """Rigs made in one test, closed after it."""
    rigs = []

    def make(**options: Any) -> Rig:
        rig = Rig(**options)
        rigs.append(rig)
        return rig
    yield make
    for rig in rigs:
        rig.close()


@functools.lru_cache(maxsize=None)
def daemon_protocol() -> int:
    """The protocol of the wheeltecd under test (asked once, of a daemon with no chassis)."""
    directory = TestDirectory()
    daemon = Daemon(directory.path, directory.path / "absent")
    try:
        with wheeltec.Client(str(daemon.socket_path)) as client:
            return client.version().protocol
    finally:
        daemon.stop()
        directory.remove()


def raw_call(path: str, method: str, params: Optional[Dict[str, Any]] = None) -> Any:
    """One request on a bare socket: what the daemon answers, read without the package."""
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as raw:
        raw.settimeout(5)
        raw.connect(path)
        request: Dict[str, Any] = {"jsonrpc": "2.0", "id": 1, "method": method}
        if params is not None:
            request["params"] = params
        raw.sendall(json.dumps(request).encode() + b"\n")
        data = b""
        while True:
            data += raw.recv(65536)
            for line in data.split(b"\n")[:-1]:
                message = json.loads(line)
                if message.get("id") == 1:
                    return message


def elapsed(since: float) -> float:
    return time.monotonic() - since
