"""Client.subscribe against wheeltecd and wheeltec-emu: values in order, count and timeout,
and its connection closed at once however the iteration ends (the daemon's client count)."""
from __future__ import annotations

import builtins
import gc
import time
from typing import Any, Iterator, List

import pytest

import wheeltec
from conftest import Rig, elapsed
from support import wait_for


@pytest.fixture(scope="module")
def rig() -> Iterator[Rig]:
    rig = Rig()
    yield rig
    rig.close()


@pytest.fixture
def robot(rig: Rig) -> Iterator[wheeltec.Client]:
    with rig.client() as client:
        yield client


@pytest.fixture
def no_garbage_collector() -> Iterator[None]:
    """Closing must not wait for the cycle collector: reference counting alone must do it."""
    gc.collect()
    gc.disable()
    yield
    gc.enable()


def connections_settle(rig: Rig, expected: int) -> bool:
    try:
        wait_for(lambda: rig.clients() == expected, 2, f"{expected} other connections")
        return True
    except AssertionError:
        return False


def test_telemetry_with_count(robot: wheeltec.Client, rig: Rig) -> None:
    before = rig.clients()
    records = list(robot.subscribe("telemetry", count=5))
    assert len(records) == 5 and all(isinstance(t, wheeltec.Telemetry) for t in records)
    seqs = [t.seq for t in records]
    assert seqs == list(range(seqs[0], seqs[0] + 5))  # every record, in order
    assert records[0].battery.voltage == pytest.approx(12.0, abs=0.1)
    assert connections_settle(rig, before)


def test_status_and_events_in_the_order_they_came(robot: wheeltec.Client, rig: Rig) -> None:
    with robot.subscribe("status", "events", timeout=3) as stream:
        with rig.client() as driver:
            driver.drive(vx=0.1)
            driver.stop()
        seen: List[Any] = []
        for item in stream:
            seen.append(item)
            if isinstance(item, wheeltec.Event) and item.event == "disconnected":
                break
    kinds = [item.event if isinstance(item, wheeltec.Event) else "status" for item in seen]
    assert kinds.index("drive") < kinds.index("stop") < kinds.index("disconnected")
    statuses = [item for item in seen if isinstance(item, wheeltec.Status)]
    assert any(s.control.owner is not None for s in statuses)  # the drive took control ...
    assert statuses[-1].control.owner is None                  # ... and the stop released it
    drive = next(item for item in seen if isinstance(item, wheeltec.Event) and item.event == "drive")
    assert drive.fields["vx"] == 0.1 and drive.fields["clamped"] is False


def test_the_client_goes_on_meanwhile(robot: wheeltec.Client) -> None:
    for t in robot.subscribe("telemetry", count=3):
        assert robot.telemetry().seq >= t.seq
        assert robot.status().chassis.online


def test_timeout_when_nothing_comes(robot: wheeltec.Client, rig: Rig) -> None:
    before = rig.clients()
    stream = robot.subscribe("events", timeout=0.3)
    start = time.monotonic()
    with pytest.raises(wheeltec.TimeoutError) as quiet:
        next(stream)
    assert 0.25 < elapsed(start) < 1.5
    assert isinstance(quiet.value, builtins.TimeoutError)
    assert stream.closed
    assert connections_settle(rig, before)


def test_leaving_a_for_loop_early_closes_the_connection(robot: wheeltec.Client, rig: Rig,
                                                         no_garbage_collector: None) -> None:
    before = rig.clients()
    for t in robot.subscribe("telemetry"):
        assert rig.clients() == before + 1  # the subscription's own connection is open
        break
    assert connections_settle(rig, before)


def test_close_and_with_close_the_connection(robot: wheeltec.Client, rig: Rig, no_garbage_collector: None) -> None:
    before = rig.clients()
    stream = robot.subscribe("telemetry")
    assert isinstance(next(stream), wheeltec.Telemetry)
    assert rig.clients() == before + 1
    stream.close()
    assert connections_settle(rig, before)
    with pytest.raises(StopIteration):
        next(stream)
    with robot.subscribe("telemetry", "status") as both:
        next(both)
        assert rig.clients() == before + 1
    assert both.closed and connections_settle(rig, before)


def test_a_count_of_zero_and_an_unknown_topic(robot: wheeltec.Client, rig: Rig) -> None:
    assert list(robot.subscribe("telemetry", count=0)) == []
    with pytest.raises(wheeltec.InvalidParams):
        robot.subscribe("pictures")
    with pytest.raises(ValueError):
        robot.subscribe("telemetry", count=-1)


def test_the_daemon_going_away_ends_a_subscription(make_rig: Any) -> None:
    rig = make_rig(fake=True)
    with rig.client() as robot:
        stream = robot.subscribe("telemetry", timeout=5)
        next(stream)
        rig.daemon.kill()
        with pytest.raises(wheeltec.DaemonUnreachable):
            for _ in stream:
                pass
        assert stream.closed
