#!/usr/bin/env python3
"""What the wheeltec package costs a script (issue 43's speed goals), printed, not judged:

1. status() round trip: wheeltec.Client.status() against the same call on a bare socket with
   json (one connection each to the same wheeltecd, calls alternating one by one so that both
   see the same machine): median, p99 and the ratio of the medians (goal: at most 1.2).
2. A subscription's records/s as Telemetry values (each read: velocity.vx, odom.x, seq):
   (a) through wheeltecd from wheeltec-emu at --telemetry-hz 1000, with the records lost
   (gaps in seq) and the subscriber's CPU per record (goal: keeps up with 1,000/s);
   (b) the package's ceiling: a fake daemon process writes telemetry notifications as fast
   as the socket takes them.

    python_bench.py [--quick] [--json FILE] [--wheeltecd PATH] [--emu PATH]

wheeltecd and wheeltec-emu come from --wheeltecd/--emu, else $BUILD_DIR (default build/).
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Callable, Dict, List

REPO_ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO_ROOT / "python"))

import wheeltec  # noqa: E402

FAKE_DAEMON = r"""
import json, os, socket, sys
path = sys.argv[1]
record = {"seq": 0, "time": 1796163000.080813, "stopped": False, "velocity": {"vx": 0.2, "vy": 0.0, "wz": 0.1},
          "accel": {"x": -0.0012, "y": -0.0054, "z": 9.799}, "gyro": {"x": 0.0, "y": 0.0008, "z": 0.00053},
          "battery": {"voltage": 11.999, "low": False}, "odom": {"x": 1.0, "y": 0.5, "yaw": 0.25},
          "orientation": {"w": 1.0, "x": -2.3e-05, "y": -8.4e-05, "z": 1.4e-05, "roll": -4.5e-05,
                          "pitch": -0.000168, "yaw": 2.7e-05}}
block = []
for seq in range(1, 1001):
    record["seq"] = seq
    block.append(json.dumps({"jsonrpc": "2.0", "method": "telemetry", "params": record}, separators=(",", ":")))
block = ("\n".join(block) + "\n").encode()
server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
server.bind(path)
server.listen(1)
print("listening", flush=True)
connection, _ = server.accept()
request = b""
while b"\n" not in request:
    request += connection.recv(4096)
answer = {"jsonrpc": "2.0", "result": {"topics": ["telemetry"]}, "id": json.loads(request.split(b"\n")[0])["id"]}
connection.sendall(json.dumps(answer).encode() + b"\n")
try:
    while True:
        connection.sendall(block)
except OSError:
    pass
"""


def percentile(values: List[float], fraction: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(fraction * len(ordered)))]


class Chassis:
    """wheeltec-emu --serial and wheeltecd in a directory of their own."""

    def __init__(self, wheeltecd: str, emu: str, *emulator_arguments: str) -> None:
        self.directory = Path(tempfile.mkdtemp(prefix="wtpy-bench-", dir="/tmp"))
        link = self.directory / "tty"
        self.socket = str(self.directory / "wheeltecd.sock")
        log = open(self.directory / "log", "wb")
        self.processes = [
            subprocess.Popen([emu, "--serial", str(link), "--boot-delay", "0.3", "--no-self-test", *emulator_arguments],
                             stdout=log, stderr=subprocess.STDOUT),
            subprocess.Popen([wheeltecd, "--serial", str(link), "--socket", self.socket], stdout=log,
                             stderr=subprocess.STDOUT)]
        deadline = time.monotonic() + 15
        while True:
            try:
                with wheeltec.Client(self.socket, timeout=1) as robot:
                    if robot.status().chassis.phase == "ready":
                        return
            except wheeltec.Error:
                pass
            if time.monotonic() > deadline:
                self.close()
                raise SystemExit("python_bench: the chassis did not become ready within 15 s")
            time.sleep(0.05)

    def close(self) -> None:
        for process in self.processes:
            process.terminate()
        for process in self.processes:
            process.wait()
        shutil.rmtree(self.directory, ignore_errors=True)


def bare_status_call(path: str) -> Callable[[int], Any]:
    """status() as a script without the package would write it."""
    bare = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    bare.connect(path)

    def call(request_id: int) -> Any:
        bare.sendall(json.dumps({"jsonrpc": "2.0", "id": request_id, "method": "status"}).encode() + b"\n")
        data = bare.recv(65536)
        while not data.endswith(b"\n"):
            data += bare.recv(65536)
        return json.loads(data)["result"]
    return call


def round_trip(path: str, calls: int) -> Dict[str, Any]:
    bare = bare_status_call(path)
    with wheeltec.Client(path) as robot:
        for i in range(200):  # warm up both
            bare(i)
            robot.status()
        bare_us: List[float] = []
        package_us: List[float] = []
        clock = time.perf_counter
        for i in range(calls):
            start = clock()
            bare(i)
            middle = clock()
            robot.status()
            end = clock()
            bare_us.append((middle - start) * 1e6)
            package_us.append((end - middle) * 1e6)
    result = {"calls": calls}
    for name, values in (("bare", bare_us), ("package", package_us)):
        result[name] = {"median_us": statistics.median(values), "p99_us": percentile(values, 0.99)}
    result["ratio_median"] = result["package"]["median_us"] / result["bare"]["median_us"]
    result["ratio_p99"] = result["package"]["p99_us"] / result["bare"]["p99_us"]
    return result


def consume(stream: Any, seconds: float) -> Dict[str, Any]:
    """Reads Telemetry values for `seconds`, touching what a script reads."""
    count = lost = 0
    last_seq = None
    checksum = 0.0
    cpu = time.process_time()
    start = time.monotonic()
    end = start + seconds
    for t in stream:
        checksum += t.velocity.vx + t.odom.x
        if last_seq is not None and t.seq != last_seq + 1:
            lost += t.seq - last_seq - 1
        last_seq = t.seq
        count += 1
        if count % 64 == 0 and time.monotonic() >= end:
            break
    took = time.monotonic() - start
    return {"records": count, "seconds": took, "records_per_s": count / took, "lost": lost,
            "cpu_us_per_record": (time.process_time() - cpu) / max(count, 1) * 1e6}


def through_daemon(wheeltecd: str, emu: str, seconds: float) -> Dict[str, Any]:
    chassis = Chassis(wheeltecd, emu, "--telemetry-hz", "1000")
    try:
        with wheeltec.Client(chassis.socket) as robot:
            with robot.subscribe("telemetry", timeout=5) as stream:
                next(stream)
                accepted = robot.stats()["records_accepted"]
                result = consume(stream, seconds)
                stats = robot.stats()
        result["published_per_s"] = (stats["records_accepted"] - accepted) / result["seconds"]
        result["daemon_notifications_dropped"] = stats["notifications_dropped"]
        return result
    finally:
        chassis.close()


def ceiling(seconds: float) -> Dict[str, Any]:
    directory = Path(tempfile.mkdtemp(prefix="wtpy-bench-", dir="/tmp"))
    path = str(directory / "fake.sock")
    fake = subprocess.Popen([sys.executable, "-c", FAKE_DAEMON, path], stdout=subprocess.PIPE)
    try:
        assert fake.stdout is not None and fake.stdout.readline().strip() == b"listening"
        stream = wheeltec.Subscription(path, ("telemetry",), timeout=5)
        try:
            result = consume(stream, seconds)
            result["lost"] = None  # the fake's seq repeats 1 to 1000
            return result
        finally:
            stream.close()
    finally:
        fake.kill()
        fake.wait()
        shutil.rmtree(directory, ignore_errors=True)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="short runs, to check that everything works")
    parser.add_argument("--json", help="write the figures to this file too")
    build = Path(os.environ.get("BUILD_DIR", REPO_ROOT / "build"))
    parser.add_argument("--wheeltecd", default=str(build / "daemon" / "wheeltecd"))
    parser.add_argument("--emu", default=str(build / "emulator" / "wheeltec-emu"))
    arguments = parser.parse_args()
    calls, seconds = (500, 1.0) if arguments.quick else (5000, 5.0)

    figures: Dict[str, Any] = {"python": platform.python_version(), "cpus": os.cpu_count()}
    chassis = Chassis(arguments.wheeltecd, arguments.emu)
    try:
        figures["status_round_trip"] = rt = round_trip(chassis.socket, calls)
    finally:
        chassis.close()
    figures["subscription_1000hz"] = sub = through_daemon(arguments.wheeltecd, arguments.emu, seconds)
    figures["subscription_ceiling"] = top = ceiling(seconds)

    print(f"== the wheeltec Python package (Python {figures['python']}, {figures['cpus']} CPUs) ==")
    print("| figure | bare socket + json | wheeltec | ratio | goal |")
    print("|---|---|---|---|---|")
    print(f"| status() round trip, median (us), n={calls} | {rt['bare']['median_us']:.1f} | "
          f"{rt['package']['median_us']:.1f} | {rt['ratio_median']:.2f}x | <= 1.2x |")
    print(f"| status() round trip, p99 (us) | {rt['bare']['p99_us']:.1f} | {rt['package']['p99_us']:.1f} | "
          f"{rt['ratio_p99']:.2f}x | |")
    print()
    print("| subscription, as Telemetry values | records/s delivered | of records/s published | lost | "
          "subscriber CPU per record (us) | goal |")
    print("|---|---|---|---|---|---|")
    print(f"| through wheeltecd, emulator at 1000 Hz, {sub['seconds']:.1f} s | {sub['records_per_s']:.0f} | "
          f"{sub['published_per_s']:.0f} | {sub['lost']} (daemon dropped {sub['daemon_notifications_dropped']}) | "
          f"{sub['cpu_us_per_record']:.1f} | 1,000/s |")
    print(f"| ceiling: a fake daemon writing as fast as it can, {top['seconds']:.1f} s | {top['records_per_s']:.0f} | "
          f"| | {top['cpu_us_per_record']:.1f} | |")
    if arguments.json:
        Path(arguments.json).write_text(json.dumps(figures, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
