"""Client.driver() and drive_for() judged by the command frames the controller receives:
wheeltecd on the fake controller's pseudo-terminal (records every 50 ms; the daemon sends a
frame every 50 ms and one at once on a change; its deadman lapses after 0.5 s)."""
from __future__ import annotations

import time
from typing import Iterator, List

import pytest

import wheeltec
from conftest import Rig, elapsed
from support import FakeController, Frame

DEADMAN_S = 0.5


@pytest.fixture(scope="module")
def rig() -> Iterator[Rig]:
    rig = Rig(fake=True)
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
        cleanup.enable()
        cleanup.stop()


def frames_between(fake: FakeController, start: float, end: float) -> List[Frame]:
    return [f for f in fake.frames() if start <= f.time <= end]


def wait_zero_frame(fake: FakeController, after: float, timeout: float = 1.0) -> float:
    """Seconds from ``after`` to the first zero frame read after it."""
    frames = fake.frames()
    start = next((i for i, f in enumerate(frames) if f.time >= after), len(frames))
    index = fake.wait_frame(lambda f: f.time >= after and f.zero, timeout, start)
    assert index is not None, f"no zero frame within {timeout} s"
    return fake.frames()[index].time - after


def test_one_drive_lapses_with_the_deadman(robot: wheeltec.Client, fake: FakeController) -> None:
    """What the driver is for: a single drive is zeroed by the daemon after its deadman."""
    start = time.monotonic()
    robot.drive(vx=0.2)
    assert fake.wait_frame(lambda f: f.time >= start and f.x == 200, 0.5) is not None
    lapse = wait_zero_frame(fake, start, 2.0)
    assert DEADMAN_S - 0.1 < lapse < DEADMAN_S + 0.3


def test_driver_holds_the_target_past_the_deadman_and_stops_on_exit(robot: wheeltec.Client,
                                                                    fake: FakeController) -> None:
    with robot.driver(period=0.1) as drive:
        start = time.monotonic()
        result = drive.set(vx=0.2, wz=0.5)
        assert result == wheeltec.DriveResult(0.2, 0.0, 0.5, False)
        time.sleep(3 * DEADMAN_S)
        held = frames_between(fake, start + 0.05, time.monotonic())
        assert drive.target == (0.2, 0.0, 0.5)
        exit_time = time.monotonic()
    assert len(held) >= 20  # 20 Hz for 1.5 s
    assert all((f.x, f.y, f.z) == (200, 0, 500) and f.well_formed for f in held), held
    assert wait_zero_frame(fake, exit_time) < 0.2  # the stop, not the deadman's 0.5 s
    assert robot.status().control.owner is None


def test_set_changes_the_target_at_once(robot: wheeltec.Client, fake: FakeController) -> None:
    with robot.driver(period=0.4) as drive:  # a repeat would come up to 0.4 s later
        drive.set(vx=0.1)
        time.sleep(0.2)
        changed = time.monotonic()
        drive.set(vx=-0.3, vy=0.1)
        index = fake.wait_frame(lambda f: f.time >= changed and f.x == -300, 1.0)
        assert index is not None and fake.frames()[index].time - changed < 0.15
        assert fake.frames()[index].y == 100  # mecanum: sideways allowed


def test_an_exception_in_the_block_stops_the_robot(robot: wheeltec.Client, fake: FakeController) -> None:
    with pytest.raises(KeyError):
        with robot.driver() as drive:
            drive.set(vx=0.3)
            time.sleep(0.2)
            raised = time.monotonic()
            raise KeyError("the script's own bug")
    assert wait_zero_frame(fake, raised) < 0.2
    assert robot.status().control.owner is None


def test_a_refused_set_raises_at_once(robot: wheeltec.Client, rig: Rig) -> None:
    with rig.client() as owner:
        owner.drive(vx=0.1)
        with robot.driver() as drive:
            with pytest.raises(wheeltec.ControlHeld):
                drive.set(vx=0.2)
            assert drive.target is None  # nothing is repeated


def test_a_refused_repeat_stops_repeating_and_is_raised_by_the_next_set(robot: wheeltec.Client, rig: Rig,
                                                                       fake: FakeController) -> None:
    with robot.driver(period=0.1) as drive:
        drive.set(vx=0.2)
        with rig.client() as other:
            other.stop()          # anyone may stop, and then take control
            other.drive(vx=0.05)
            taken = time.monotonic()
            time.sleep(0.3)       # the driver's repeats are refused with ControlHeld
            assert frames_between(fake, taken + 0.03, time.monotonic())[-1].x == 50  # the other's target
            with pytest.raises(wheeltec.ControlHeld):
                drive.set(vx=0.2)  # not sent: the refusal it raises is the repeat's
            other.stop()
        assert drive.target is None
        assert drive.set(vx=0.1).vx == 0.1  # a later set takes control again
        time.sleep(0.3)
        assert robot.status().control.target.vx == 0.1


def test_a_refusal_is_raised_when_the_block_ends(robot: wheeltec.Client, rig: Rig, fake: FakeController) -> None:
    with pytest.raises(wheeltec.ControlDisabled):
        with robot.driver() as drive:
            drive.set(vx=0.2)
            with rig.client() as other:
                other.disable()   # zero, control released: the next repeat is refused
            time.sleep(0.3)
    with rig.client() as other:
        other.enable()


def test_wait_raises_a_refusal_as_it_comes(robot: wheeltec.Client, rig: Rig) -> None:
    with pytest.raises(wheeltec.ControlDisabled):
        with robot.driver(period=0.05) as drive:
            drive.set(vx=0.2)
            start = time.monotonic()
            with rig.client() as other:
                other.disable()
            try:
                drive.wait(5)
            finally:
                assert elapsed(start) < 1.0
    with rig.client() as other:
        other.enable()


def test_drive_for(robot: wheeltec.Client, fake: FakeController) -> None:
    start = time.monotonic()
    result = robot.drive_for(0.8, vx=0.15)
    took = elapsed(start)
    assert result.vx == 0.15 and 0.75 < took < 1.3
    moving = [f for f in frames_between(fake, start, start + took) if f.x == 150]
    assert moving and moving[-1].time - moving[0].time > 0.7  # held past the deadman
    assert wait_zero_frame(fake, moving[-1].time) < 0.2


def test_a_driver_is_used_in_one_block(robot: wheeltec.Client) -> None:
    drive = robot.driver()
    with drive:
        pass
    with pytest.raises(RuntimeError):
        drive.set(vx=0.1)
    with pytest.raises(ValueError):
        robot.driver(period=0)
    with pytest.raises(ValueError):
        robot.drive_for(-1)
