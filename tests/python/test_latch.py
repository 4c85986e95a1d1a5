"""The latched emergency stop (protocol 5) through the package: estop(), release(),
EmergencyStopLatched, status.safety and the events, with the frames the controller sees."""
from __future__ import annotations

import asyncio
import shutil
import time
from typing import Iterator, List

import pytest

import wheeltec
from conftest import Rig, daemon_protocol
from support import FakeController, Frame, run_as_nobody

pytestmark = pytest.mark.skipif(daemon_protocol() < 5, reason=(
    f"the wheeltecd under test speaks protocol {daemon_protocol()}: estop and release (protocol 5) are not there yet"))


@pytest.fixture(scope="module")
def rig() -> Iterator[Rig]:
    rig = Rig(fake=True, config={"api": {"mode": "0666"}})
    yield rig
    rig.close()


@pytest.fixture
def fake(rig: Rig) -> FakeController:
    assert rig.fake is not None
    return rig.fake


@pytest.fixture
def robot(rig: Rig) -> Iterator[wheeltec.Client]:
    with rig.client() as client:
        yield client
    with rig.client() as cleanup:
        cleanup.release()
        cleanup.enable()
        cleanup.stop()


def frames_after(fake: FakeController, start: float) -> List[Frame]:
    return [f for f in fake.frames() if f.time >= start]


def own_id(robot: wheeltec.Client) -> int:
    robot.drive(vx=0.0)
    owner = robot.status().control.owner
    robot.stop()
    assert isinstance(owner, int)
    return owner


def test_estop_latches_until_release(robot: wheeltec.Client, rig: Rig, fake: FakeController) -> None:
    me = own_id(robot)
    with robot.subscribe("events", "status", timeout=3) as stream:
        robot.drive(vx=0.3)
        pressed = time.monotonic()
        assert robot.estop("operator pressed E-STOP") is None
        zero = fake.wait_frame(lambda f: f.time >= pressed and f.zero, 0.5)
        assert zero is not None and fake.frames()[zero].time - pressed < 0.2

        safety = robot.status().safety
        assert (safety.latched, safety.source, safety.reason, safety.by) == (True, "client", "operator pressed E-STOP", me)
        assert safety.since == pytest.approx(time.time(), abs=5)
        with pytest.raises(wheeltec.EmergencyStopLatched) as refused:
            robot.drive(vx=0.1)
        assert refused.value.code == -32007 and "emergency stop" in refused.value.message
        assert refused.value.safety == safety.raw and refused.value.data["latched"] is True
        with rig.client() as other:
            with pytest.raises(wheeltec.EmergencyStopLatched):
                other.drive(vx=0.1)
            assert other.estop("another reason") is None  # changes nothing
        assert robot.status().safety.reason == "operator pressed E-STOP"

        held = time.monotonic()
        time.sleep(0.5)
        frames = frames_after(fake, held)
        assert len(frames) >= 8 and all(f.zero for f in frames)  # held at zero, at rate_hz

        assert robot.stop() is None  # stop and disable still work
        robot.disable()
        with pytest.raises(wheeltec.EmergencyStopLatched):
            robot.enable()
        assert robot.release() is None
        robot.enable()
        assert robot.status().safety == wheeltec.Safety(False, None, None, None, None)
        assert robot.release() is None  # not latched: nothing to do
        assert robot.drive(vx=0.1).vx == 0.1
        robot.stop()

        seen = []
        for item in stream:
            seen.append(item)
            if isinstance(item, wheeltec.Event) and item.event == "release":
                break
    estops = [e for e in seen if isinstance(e, wheeltec.Event) and e.event == "estop"]
    assert estops[0].client == me and estops[0].fields["source"] == "client"
    assert estops[0].fields["reason"] == "operator pressed E-STOP"
    assert seen[-1].client == me  # the release
    latched = [s for s in seen if isinstance(s, wheeltec.Status) and s.safety.latched]
    assert latched and latched[0].safety.source == "client"


def test_estop_params(robot: wheeltec.Client) -> None:
    with pytest.raises(wheeltec.InvalidParams):
        robot.estop("x" * 201)
    with pytest.raises(wheeltec.InvalidParams):
        robot.estop(42)  # type: ignore[arg-type]
    assert robot.status().safety.latched is False
    robot.estop()
    assert robot.status().safety.reason == ""


def test_a_driver_refused_by_the_latch(robot: wheeltec.Client, rig: Rig, fake: FakeController) -> None:
    with robot.driver(period=0.1) as drive:
        drive.set(vx=0.2)
        time.sleep(0.2)
        with rig.client() as operator:
            pressed = time.monotonic()
            operator.estop("operator")
        zero = fake.wait_frame(lambda f: f.time >= pressed and f.zero, 0.5)
        assert zero is not None and fake.frames()[zero].time - pressed < 0.2
        time.sleep(0.3)
        with pytest.raises(wheeltec.EmergencyStopLatched) as refused:
            drive.set(vx=0.2)
        assert refused.value.safety["reason"] == "operator"
        assert all(f.zero for f in frames_after(fake, pressed + 0.05))


def test_estop_and_release_on_asyncio(rig: Rig) -> None:
    async def main() -> None:
        async with wheeltec.aio.Client(rig.socket) as robot:
            await robot.estop("from asyncio")
            assert (await robot.status()).safety.latched
            with pytest.raises(wheeltec.EmergencyStopLatched):
                await robot.drive(vx=0.1)
            await robot.release()
            assert not (await robot.status()).safety.latched
    asyncio.run(main())


def test_anyone_may_estop_but_not_release(rig: Rig) -> None:
    if shutil.which("setpriv") is None:
        pytest.skip("setpriv (util-linux) is not installed")
    script = """
import json, sys, wheeltec
outcome = {}
with wheeltec.Client(sys.argv[1]) as robot:
    robot.estop("from nobody")
    outcome["latched"] = robot.status().safety.latched
    try:
        robot.release()
        outcome["release"] = "ok"
    except wheeltec.RpcError as error:
        outcome["release"] = type(error).__name__
print(json.dumps(outcome))
"""
    assert run_as_nobody(script, rig.socket, rig.directory.path) == {"latched": True, "release": "NotPermitted"}
    with rig.client() as root:
        assert root.status().safety.reason == "from nobody"
        root.release()
