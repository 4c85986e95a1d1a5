"""What the Python client's tests run against: wheeltecd and wheeltec-emu as processes on a
pseudo-terminal, and a fake controller (the test's own end of a pseudo-terminal, which sees
every command frame the daemon writes)."""
from __future__ import annotations

import json
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import termios
import threading
import time
import tty
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Sequence

REPO_ROOT = Path(__file__).resolve().parents[2]
# Extra seconds for a program to start (a slow host, valgrind), as for the other suites.
START_ALLOWANCE_S = float(os.environ.get("WHEELTEC_TEST_START_ALLOWANCE_S") or 0)


def program(name: str, variable: str) -> str:
    """The program under test: $WHEELTEC_BIN_DIR/NAME (one directory with all programs, such
    as /usr/bin, as for the other suites), else $VARIABLE (ctest passes the build's), else
    this tree's build/."""
    if os.environ.get("WHEELTEC_BIN_DIR"):
        return str(Path(os.environ["WHEELTEC_BIN_DIR"]) / name)
    if os.environ.get(variable):
        return os.environ[variable]
    subdir = {"wheeltecd": "daemon", "wheeltec-emu": "emulator"}[name]
    return str(REPO_ROOT / "build" / subdir / name)


def wait_for(predicate: Callable[[], Any], timeout: float, what: str, interval: float = 0.02) -> Any:
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > deadline:
            raise AssertionError(f"{what}: not within {timeout} s")
        time.sleep(interval)


class TestDirectory:
    """A short path under /tmp (socket paths are limited to 107 bytes), readable by every user
    (the unprivileged test's process connects to a socket in it)."""

    def __init__(self) -> None:
        self.path = Path(tempfile.mkdtemp(prefix="wtpy-", dir="/tmp"))
        self.path.chmod(0o755)

    def remove(self) -> None:
        shutil.rmtree(self.path, ignore_errors=True)


class Process:
    """A program of the project, its output in DIR/NAME.log; stop() ends it (SIGTERM, then KILL)."""

    def __init__(self, name: str, arguments: Sequence[str], directory: Path) -> None:
        self.name = name
        self.log_path = directory / f"{name}.log"
        self._log = open(self.log_path, "wb")
        self.popen = subprocess.Popen(list(arguments), stdout=self._log, stderr=subprocess.STDOUT,
                                      stdin=subprocess.DEVNULL, cwd=directory)

    @property
    def pid(self) -> int:
        return self.popen.pid

    def running(self) -> bool:
        return self.popen.poll() is None

    def signal(self, number: int) -> None:
        if self.running():
            self.popen.send_signal(number)

    def stop(self, timeout: float = 5.0) -> Optional[int]:
        if self.running():
            self.popen.send_signal(signal.SIGCONT)
            self.popen.terminate()
            try:
                self.popen.wait(timeout)
            except subprocess.TimeoutExpired:
                self.popen.kill()
                self.popen.wait()
        self._log.close()
        return self.popen.returncode

    def kill(self) -> None:
        if self.running():
            self.popen.kill()
            self.popen.wait()

    def output(self) -> str:
        self._log.flush()
        return self.log_path.read_text(errors="replace")


class Emulator(Process):
    """wheeltec-emu --serial LINK (the controller on a pseudo-terminal)."""

    def __init__(self, directory: Path, link: Path, *arguments: str, name: str = "wheeltec-emu") -> None:
        super().__init__(name, [program("wheeltec-emu", "WHEELTEC_EMU"), "--serial", str(link), *arguments], directory)


class Daemon(Process):
    """wheeltecd --config FILE --serial LINK --socket SOCK; ``config`` is merged into the file."""

    def __init__(self, directory: Path, link: Path, config: Optional[Dict[str, Any]] = None,
                 name: str = "wheeltecd") -> None:
        self.socket_path = directory / f"{name}.sock"
        settings: Dict[str, Any] = {
            "control": {"auto_enable": True, "command_timeout_s": 0.5},
            "telemetry": {"timeout_s": 0.5},
            "api": {"socket": str(self.socket_path)},
            "log": {"level": "info"},
        }
        for key, value in (config or {}).items():
            if isinstance(value, dict) and isinstance(settings.get(key), dict):
                settings[key].update(value)
            else:
                settings[key] = value
        self.config_path = directory / f"{name}.json"
        self.config_path.write_text(json.dumps(settings, indent=2))
        super().__init__(name, [program("wheeltecd", "WHEELTECD"), "--config", str(self.config_path),
                                "--serial", str(link), "--socket", str(self.socket_path)], directory)
        wait_for(self._listening, 10 + START_ALLOWANCE_S, f"{name}'s socket {self.socket_path}")

    def _listening(self) -> bool:
        if not self.running():
            raise AssertionError(f"{self.name} ended at start-up:\n{self.output()}")
        probe = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        try:
            probe.connect(str(self.socket_path))
            return True
        except OSError:
            return False
        finally:
            probe.close()


@dataclass
class Frame:
    """An 11-byte command frame the daemon wrote: X, Y, Z in mm/s, mm/s, mrad/s."""

    time: float  # monotonic, when it was read
    x: int
    y: int
    z: int
    well_formed: bool

    @property
    def zero(self) -> bool:
        return self.x == 0 and self.y == 0 and self.z == 0


def _int16(high: int, low: int) -> int:
    value = (high << 8) | low
    return value - 0x10000 if value & 0x8000 else value


def record_bytes(vx_mm_s: int = 0, flag_stop: bool = False, battery_mv: int = 12000) -> bytes:
    """A 24-byte telemetry record of a chassis at rest (1 g on z), moving at vx."""
    fields = [vx_mm_s, 0, 0, 0, 0, 16403, 0, 0, 0, battery_mv]
    body = bytes([0x7B, 1 if flag_stop else 0]) + b"".join((v & 0xFFFF).to_bytes(2, "big") for v in fields)
    check = 0
    for byte in body:
        check ^= byte
    return body + bytes([check, 0x7D])


class FakeController:
    """The controller's end of a pseudo-terminal whose other end is published at ``link`` (a
    symlink made by rename, the slave set raw first): a record every 50 ms, and every command
    frame the daemon writes kept with the time it was read."""

    def __init__(self, link: Path, period: float = 0.05) -> None:
        self.link = link
        self.period = period
        self.master, self._slave = os.openpty()
        tty.setraw(self._slave)
        attributes = termios.tcgetattr(self._slave)
        attributes[4] = attributes[5] = termios.B115200
        termios.tcsetattr(self._slave, termios.TCSANOW, attributes)
        temporary = link.with_name(link.name + ".new")
        if temporary.is_symlink():
            temporary.unlink()
        os.symlink(os.ttyname(self._slave), temporary)
        os.rename(temporary, link)
        self._frames: List[Frame] = []
        self._changed = threading.Condition()
        self._stopping = False
        self._threads = [threading.Thread(target=self._read, daemon=True),
                         threading.Thread(target=self._send_records, daemon=True)]
        for thread in self._threads:
            thread.start()

    def close(self) -> None:
        self._stopping = True
        for thread in self._threads:
            thread.join()
        if self.link.is_symlink():
            self.link.unlink()
        os.close(self.master)
        os.close(self._slave)

    def frames(self) -> List[Frame]:
        with self._changed:
            return list(self._frames)

    def wait_frame(self, predicate: Callable[[Frame], bool], timeout: float, start: int = 0) -> Optional[int]:
        """The index of the first frame at or after ``start`` that satisfies ``predicate``."""
        deadline = time.monotonic() + timeout
        with self._changed:
            while True:
                for index in range(start, len(self._frames)):
                    if predicate(self._frames[index]):
                        return index
                start = max(start, len(self._frames))
                left = deadline - time.monotonic()
                if left <= 0:
                    return None
                self._changed.wait(left)

    def _send_records(self) -> None:
        record = record_bytes()
        following = time.monotonic()
        while not self._stopping:
            try:
                os.write(self.master, record)
            except OSError:
                pass
            following += self.period
            time.sleep(max(0.0, following - time.monotonic()))

    def _read(self) -> None:
        import select
        window = bytearray()
        while not self._stopping:
            ready, _, _ = select.select([self.master], [], [], 0.02)
            if not ready:
                continue
            try:
                data = os.read(self.master, 4096)
            except OSError:
                time.sleep(0.01)
                continue
            now = time.monotonic()
            with self._changed:
                for byte in data:
                    if not window and byte != 0x7B:
                        continue
                    window.append(byte)
                    if len(window) == 11:
                        check = 0
                        for b in window[:9]:
                            check ^= b
                        ok = window[1] == 0 and window[2] == 0 and window[10] == 0x7D and window[9] == check
                        self._frames.append(Frame(now, _int16(window[3], window[4]), _int16(window[5], window[6]),
                                                  _int16(window[7], window[8]), ok))
                        window.clear()
                self._changed.notify_all()


def run_as_nobody(script: str, socket_path: str, package_parent: Path) -> Dict[str, Any]:
    """Runs ``script`` (which prints one JSON object) as the user nobody with the package
    copied under ``package_parent`` (a directory every user can read) on its path, and
    returns what it printed. The interpreter is this one when nobody may run it (not one
    under /root), else the system's."""
    import sys
    package = package_parent / "package"
    if not package.exists():
        import wheeltec
        shutil.copytree(Path(wheeltec.__file__).parent, package / "wheeltec")
    prefix = ["setpriv", "--reuid=nobody", "--regid=nogroup", "--clear-groups", "--"]
    python = sys.executable
    if subprocess.run(prefix + [python, "-c", "pass"], capture_output=True, cwd="/").returncode != 0:
        python = "/usr/bin/python3"
    run = subprocess.run(prefix + [python, "-c", script, socket_path],
                         env={"PYTHONPATH": str(package), "PATH": os.environ.get("PATH", "")},
                         capture_output=True, text=True, timeout=30, cwd="/")
    assert run.returncode == 0, run.stderr
    result: Dict[str, Any] = json.loads(run.stdout)
    return result
