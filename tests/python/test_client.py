"""wheeltec.Client against wheeltecd and wheeltec-emu: every method, and each error the
daemon gives, as the exception of its code."""
from __future__ import annotations

import builtins
import math
import shutil
import threading
import time
from pathlib import Path
from typing import Any, Dict, Iterator

import pytest

import wheeltec
from conftest import Rig, daemon_protocol, elapsed, raw_call
from support import run_as_nobody, wait_for


@pytest.fixture(scope="module")
def rig() -> Iterator[Rig]:
    # api.mode 0666: the unprivileged user's test connects too (and is refused control).
    rig = Rig(config={"api": {"mode": "0666"}})
    yield rig
    rig.close()


@pytest.fixture
def robot(rig: Rig) -> Iterator[wheeltec.Client]:
    with rig.client() as client:
        yield client
        if not client.closed:
            client.stop()


def test_socket_comes_from_the_argument_then_the_environment(rig: Rig, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("WHEELTEC_SOCKET", rig.socket)
    with wheeltec.Client() as robot:
        assert robot.socket_path == rig.socket
        assert robot.version().version
    with wheeltec.Client(Path(rig.socket)) as robot:
        assert robot.socket_path == rig.socket
    monkeypatch.setenv("WHEELTEC_SOCKET", "/nonexistent/wheeltecd.sock")
    with wheeltec.Client(rig.socket) as robot:  # the argument wins
        assert robot.status().chassis.phase == "ready"
    monkeypatch.delenv("WHEELTEC_SOCKET")
    try:
        wheeltec.Client().close()
    except wheeltec.DaemonUnreachable as error:
        assert "/run/wheeltecd/wheeltecd.sock" in str(error)


def test_version(robot: wheeltec.Client, rig: Rig) -> None:
    version = robot.version()
    answer = raw_call(rig.socket, "version")["result"]
    assert isinstance(version, wheeltec.Version)
    assert (version.version, version.protocol) == (answer["version"], answer["protocol"])
    assert version.protocol >= 4
    assert version.raw == answer
    assert wheeltec.__version__ == version.version  # built from the same tree


def test_status(robot: wheeltec.Client, rig: Rig) -> None:
    status = robot.status()
    assert isinstance(status, wheeltec.Status)
    assert status.bus == wheeltec.Bus("serial", str(rig.link), "up")
    assert status.chassis.type == "mecanum" and status.chassis.online and status.chassis.phase == "ready"
    assert status.chassis.battery_v == pytest.approx(12.0, abs=0.1)
    assert status.chassis.commands_ignored is False and status.chassis.stopped is False
    assert status.dock.present is False and status.dock.ir is None
    assert status.control.enabled and status.control.owner is None
    assert status.control.target == wheeltec.Velocity(0.0, 0.0, 0.0)
    assert status.safety.latched is False and status.safety.source is None
    assert status.odometry.scale == wheeltec.OdometryScale(1.0, 1.0, 1.0, 1.0)
    assert status.uptime_s > 0 and status.version == robot.version().version
    assert status.raw["chassis"]["phase"] == "ready" and status.chassis.raw == status.raw["chassis"]
    with pytest.raises(AttributeError):
        status.version = "1.2.3"  # type: ignore[misc]
    if daemon_protocol() >= 5:
        assert status.control.limits == wheeltec.Velocity(1.0, 1.0, 3.0)
        assert status.control.sent == wheeltec.Velocity(0.0, 0.0, 0.0)
        assert status.control.accel == wheeltec.AxisLimits(None, None, None)
    else:
        assert "safety" not in status.raw  # an older daemon: the defaults stand in
        assert status.control.sent is None and status.control.limits is None


def test_telemetry(robot: wheeltec.Client) -> None:
    first = robot.telemetry()
    assert isinstance(first, wheeltec.Telemetry)
    assert first.seq > 0 and first.time == pytest.approx(time.time(), abs=5)
    assert first.stopped is False
    assert first.battery.voltage == pytest.approx(12.0, abs=0.1) and first.battery.low is False
    assert first.accel.z == pytest.approx(9.8, abs=0.2)
    assert abs(first.gyro.z) < 0.05
    assert first.orientation.w == pytest.approx(1.0, abs=0.01) and abs(first.orientation.roll) < 0.05
    assert isinstance(first.odom, wheeltec.Pose2D) and isinstance(first.velocity, wheeltec.Velocity)
    assert first.raw["battery"]["voltage"] == first.battery.voltage
    later = wait_for(lambda: (lambda t: t if t.seq > first.seq else None)(robot.telemetry()), 2, "a newer record")
    assert later.time > first.time


def test_stats(robot: wheeltec.Client) -> None:
    stats = robot.stats()
    assert isinstance(stats, dict)
    assert stats["records_accepted"] > 0 and stats["clients"] >= 1
    assert stats["serial"]["records"] > 0


def test_drive_and_stop(robot: wheeltec.Client, rig: Rig) -> None:
    result = robot.drive(vx=0.2, wz=0.5)
    assert result == wheeltec.DriveResult(0.2, 0.0, 0.5, False)
    with rig.client() as other:
        control = other.status().control
        assert control.owner is not None and control.target == wheeltec.Velocity(0.2, 0.0, 0.5)
    clamped = robot.drive(5, 0, -10)  # positional: vx, vy, wz
    assert clamped.clamped and (clamped.vx, clamped.wz) == (1.0, -3.0)
    assert robot.drive(vx=0.1234).vx == pytest.approx(0.123)
    assert robot.stop() is None
    control = robot.status().control
    assert control.owner is None and control.target == wheeltec.Velocity()


def test_enable_and_disable(robot: wheeltec.Client) -> None:
    try:
        assert robot.disable() is None
        assert robot.status().control.enabled is False
        with pytest.raises(wheeltec.ControlDisabled) as refused:
            robot.drive(vx=0.1)
        assert refused.value.code == -32002 and refused.value.CODE == -32002
    finally:
        assert robot.enable() is None
    assert robot.status().control.enabled is True
    assert robot.drive(vx=0.1).vx == 0.1


def test_reset_odometry(robot: wheeltec.Client) -> None:
    robot.drive_for(0.5, vx=0.3)
    still = wait_for(lambda: (lambda t: t if abs(t.velocity.vx) < 0.002 else None)(robot.telemetry()), 3,
                     "the robot at rest")
    assert still.odom.x > 0.05
    assert robot.reset_odometry() is None
    after = wait_for(lambda: (lambda t: t if t.seq > still.seq + 3 else None)(robot.telemetry()), 2,
                     "records after the reset")
    assert abs(after.odom.x) < 0.005


def test_mark_and_its_event(robot: wheeltec.Client) -> None:
    with robot.subscribe("events", timeout=5) as events:
        assert robot.mark("bumped the door") is None
        event = next(e for e in events if e.event == "mark")
    assert isinstance(event, wheeltec.Event)
    assert event.fields == {"text": "bumped the door"} and event.raw["text"] == "bumped the door"
    assert isinstance(event.client, int) and event.time == pytest.approx(time.time(), abs=5)
    with pytest.raises(wheeltec.InvalidParams):
        robot.mark("x" * 201)


def test_call_for_any_method(robot: wheeltec.Client, rig: Rig) -> None:
    assert robot.call("version") == raw_call(rig.socket, "version")["result"]
    assert robot.call("subscribe", {"topics": ["status"]}) == {"topics": ["status"]}
    with pytest.raises(wheeltec.MethodNotFound) as unknown:
        robot.call("no_such_method")
    assert unknown.value.code == -32601 and "no_such_method" in unknown.value.message
    with pytest.raises(wheeltec.InvalidParams) as bad:
        robot.call("drive", {"vx": 0.1, "speed": 1})
    assert "speed" in str(bad.value)


def test_invalid_params(robot: wheeltec.Client) -> None:
    with pytest.raises(wheeltec.InvalidParams) as nan:
        robot.drive(vx=math.nan)
    assert nan.value.code == -32602 and "vx" in nan.value.message
    with pytest.raises(wheeltec.InvalidParams):
        robot.drive(wz=math.inf)
    with pytest.raises(wheeltec.InvalidParams):
        robot.drive(vx=True)  # a bool is not a speed (not sent as 1.0)
    with pytest.raises(wheeltec.InvalidParams):
        robot.drive(vx="0.2")  # type: ignore[arg-type]
    assert robot.status().control.owner is None  # nothing of it was driven


def test_control_held_by_another_client(robot: wheeltec.Client, rig: Rig) -> None:
    robot.drive(vx=0.1)
    with rig.client() as other:
        with pytest.raises(wheeltec.ControlHeld) as held:
            other.drive(vx=-0.1)
        error = held.value
        assert isinstance(error, wheeltec.RpcError) and isinstance(error, wheeltec.Error)
        assert error.code == -32001 and error.message and str(error).endswith("(-32001)")
        other.stop()  # anyone may stop
    assert robot.status().control.owner is None


def test_estop_and_release_of_an_older_daemon_are_method_not_found(robot: wheeltec.Client) -> None:
    if daemon_protocol() >= 5:
        pytest.skip("this daemon has estop and release (tests/python/test_latch.py)")
    with pytest.raises(wheeltec.MethodNotFound):
        robot.estop("operator")
    with pytest.raises(wheeltec.MethodNotFound):
        robot.release()


def test_notifications_between_answers_do_not_confuse_the_client(robot: wheeltec.Client) -> None:
    robot.call("subscribe", {"topics": ["telemetry", "status", "events"]})
    seen = set()
    for i in range(40):
        status = robot.status()
        assert isinstance(status, wheeltec.Status)
        seen.add(robot.telemetry().seq)
        assert robot.version().protocol >= 4
        robot.mark(f"mark {i}")  # an event notification on this very connection
        time.sleep(0.01)
    assert len(seen) > 5  # telemetry notifications were arriving all along


def test_calls_from_several_threads(robot: wheeltec.Client) -> None:
    results: Dict[str, Any] = {}

    def work(name: str) -> None:
        results[name] = [type(robot.status()).__name__ for _ in range(50)] + [type(robot.telemetry()).__name__]

    threads = [threading.Thread(target=work, args=(str(n),)) for n in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert all(r == ["Status"] * 50 + ["Telemetry"] for r in results.values())


def test_not_permitted_for_an_unprivileged_user(rig: Rig) -> None:
    if shutil.which("setpriv") is None:
        pytest.skip("setpriv (util-linux) is not installed")
    script = """
import json, sys, wheeltec
outcome = {}
with wheeltec.Client(sys.argv[1]) as robot:
    outcome["status"] = robot.status().chassis.phase
    robot.stop()
    outcome["stop"] = "ok"
    robot.mark("from nobody")
    for name in ("drive", "enable", "disable", "release"):
        try:
            getattr(robot, name)()
            outcome[name] = "ok"
        except wheeltec.RpcError as error:
            outcome[name] = type(error).__name__
print(json.dumps(outcome))
"""
    outcome = run_as_nobody(script, rig.socket, rig.directory.path)
    assert outcome["status"] == "ready" and outcome["stop"] == "ok"
    assert outcome["drive"] == outcome["enable"] == outcome["disable"] == "NotPermitted"
    assert outcome["release"] == ("NotPermitted" if daemon_protocol() >= 5 else "MethodNotFound")


# Each of these needs a daemon of its own.

def test_unreachable_socket() -> None:
    with pytest.raises(wheeltec.DaemonUnreachable) as missing:
        wheeltec.Client("/nonexistent/wheeltecd.sock")
    assert "/nonexistent/wheeltecd.sock" in str(missing.value)
    assert isinstance(missing.value, wheeltec.Error)


def test_no_telemetry_and_link_down_without_a_controller(make_rig: Any) -> None:
    rig = make_rig(emulator=None, ready=False)
    with rig.client() as robot:
        with pytest.raises(wheeltec.NoTelemetry) as none:
            robot.telemetry()
        assert none.value.code == -32004
        assert robot.status().bus.state == "down"
        with pytest.raises(wheeltec.LinkDown) as down:
            robot.drive(vx=0.1)
        assert down.value.code == -32003


def test_chassis_not_ready_then_link_down_when_unplugged(make_rig: Any) -> None:
    rig = make_rig(emulator=("--boot-delay", "1.0", "--no-self-test", "--unplug-after", "2.0"), ready=False)
    rig.wait_status(lambda s: s.chassis.phase == "booting", 5, "chassis booting")
    with rig.client() as robot:
        with pytest.raises(wheeltec.ChassisNotReady) as booting:
            robot.drive(vx=0.1)
        assert booting.value.code == -32006 and booting.value.phase == "booting"
        assert booting.value.data == {"phase": "booting"}
        rig.wait_status(lambda s: s.bus.state == "down", 5, "the link down after the unplug")
        with pytest.raises(wheeltec.LinkDown):
            robot.drive(vx=0.1)


def test_timeout_and_the_late_answer_skipped(make_rig: Any) -> None:
    rig = make_rig(fake=True)
    assert rig.daemon is not None
    with rig.client(timeout=0.3) as robot:
        robot.call("subscribe", {"topics": ["telemetry"]})
        rig.daemon.signal(19)  # SIGSTOP: the daemon takes the request and answers nothing
        start = time.monotonic()
        with pytest.raises(wheeltec.TimeoutError) as late:
            robot.status()
        assert 0.25 < elapsed(start) < 1.5
        assert isinstance(late.value, builtins.TimeoutError) and isinstance(late.value, wheeltec.Error)
        rig.daemon.signal(18)  # SIGCONT: the late status answer and a backlog of telemetry arrive
        assert isinstance(robot.version(), wheeltec.Version)
        assert isinstance(robot.telemetry(), wheeltec.Telemetry)


def test_daemon_killed_mid_call(make_rig: Any) -> None:
    rig = make_rig(fake=True)
    assert rig.daemon is not None
    robot = rig.client(timeout=20)
    outcome: Dict[str, Any] = {}

    def call() -> None:
        start = time.monotonic()
        try:
            robot.status()
            outcome["result"] = "answered"
        except wheeltec.Error as error:
            outcome["result"] = error
        outcome["after"] = elapsed(start)

    rig.daemon.signal(19)  # stopped, so that the call is surely in flight when it dies
    caller = threading.Thread(target=call)
    caller.start()
    time.sleep(0.3)
    rig.daemon.kill()
    caller.join(10)
    assert isinstance(outcome["result"], wheeltec.DaemonUnreachable), outcome
    assert outcome["after"] < 5
    with pytest.raises(wheeltec.DaemonUnreachable):
        robot.version()
    robot.close()
    with pytest.raises(wheeltec.DaemonUnreachable):
        wheeltec.Client(rig.socket)  # the socket file is left, nobody listens
