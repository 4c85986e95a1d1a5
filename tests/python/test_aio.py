"""wheeltec.aio against wheeltecd on the fake controller: the same shape as the blocking
client, on asyncio (each test runs its own event loop)."""
from __future__ import annotations

import asyncio
import builtins
import gc
import time
from typing import Any, Awaitable, Iterator, List, TypeVar

import pytest

import wheeltec
from conftest import Rig, elapsed
from support import FakeController, wait_for

T = TypeVar("T")


def run(coroutine: Awaitable[T]) -> T:
    return asyncio.run(asyncio.wait_for(coroutine, 20))


@pytest.fixture(scope="module")
def rig() -> Iterator[Rig]:
    rig = Rig(fake=True)
    yield rig
    rig.close()


@pytest.fixture
def fake(rig: Rig) -> FakeController:
    assert rig.fake is not None
    return rig.fake


def test_every_method(rig: Rig) -> None:
    async def main() -> None:
        async with wheeltec.aio.Client(rig.socket) as robot:
            version = await robot.version()
            assert isinstance(version, wheeltec.Version) and version.protocol >= 4
            status = await robot.status()
            assert status.chassis.phase == "ready" and status.bus.transport == "serial"
            telemetry = await robot.telemetry()
            assert isinstance(telemetry, wheeltec.Telemetry) and telemetry.battery.voltage == pytest.approx(12.0)
            assert (await robot.stats())["records_accepted"] > 0
            assert await robot.drive(vx=0.2) == wheeltec.DriveResult(0.2, 0.0, 0.0, False)
            assert (await robot.status()).control.owner is not None
            assert await robot.stop() is None
            assert await robot.disable() is None
            with pytest.raises(wheeltec.ControlDisabled):
                await robot.drive(vx=0.1)
            assert await robot.enable() is None
            assert await robot.reset_odometry() is None
            assert await robot.mark("from asyncio") is None
            assert await robot.call("version") == version.raw
            with pytest.raises(wheeltec.MethodNotFound):
                await robot.call("no_such_method")
            with pytest.raises(wheeltec.InvalidParams):
                await robot.mark("x" * 201)
        assert robot.closed
    run(main())


def test_calls_connect_without_async_with_and_run_concurrently(rig: Rig) -> None:
    async def main() -> None:
        robot = wheeltec.aio.Client(rig.socket)
        results = await asyncio.gather(*(robot.status() for _ in range(20)), robot.version(), robot.telemetry())
        assert [type(r).__name__ for r in results] == ["Status"] * 20 + ["Version", "Telemetry"]
        await robot.close()
    run(main())


def test_control_held_and_unreachable(rig: Rig) -> None:
    async def main() -> None:
        async with wheeltec.aio.Client(rig.socket) as owner, wheeltec.aio.Client(rig.socket) as other:
            await owner.drive(vx=0.1)
            with pytest.raises(wheeltec.ControlHeld):
                await other.drive(vx=0.1)
            await other.stop()
        with pytest.raises(wheeltec.DaemonUnreachable):
            async with wheeltec.aio.Client("/nonexistent/wheeltecd.sock"):
                pass
    run(main())


def test_driver_holds_and_stops_on_exit(rig: Rig, fake: FakeController) -> None:
    async def main() -> float:
        async with wheeltec.aio.Client(rig.socket) as robot:
            async with robot.driver(period=0.1) as drive:
                start = time.monotonic()
                assert (await drive.set(vx=0.25)).vx == 0.25
                await asyncio.sleep(1.2)
                held = [f for f in fake.frames() if f.time > start + 0.05]
                assert len(held) >= 15 and all(f.x == 250 for f in held)
                ended = time.monotonic()
            assert (await robot.status()).control.owner is None
            return ended
    ended = run(main())
    assert fake.wait_frame(lambda f: f.time >= ended and f.zero, 1.0) is not None
    assert next(f for f in fake.frames() if f.time >= ended and f.zero).time - ended < 0.2


def test_driver_stops_on_an_exception_and_raises_a_refused_repeat(rig: Rig, fake: FakeController) -> None:
    async def main() -> float:
        async with wheeltec.aio.Client(rig.socket) as robot, wheeltec.aio.Client(rig.socket) as other:
            with pytest.raises(ZeroDivisionError):
                async with robot.driver() as drive:
                    await drive.set(vx=0.2)
                    await asyncio.sleep(0.1)
                    raised = time.monotonic()
                    1 / 0
            async with robot.driver() as drive:
                await drive.set(vx=0.2)
                await other.disable()
                start = time.monotonic()
                with pytest.raises(wheeltec.ControlDisabled):
                    await drive.wait(5)
                assert elapsed(start) < 1.0
                await other.enable()
                assert (await drive.set(vx=0.1)).vx == 0.1
            return raised
    raised = run(main())
    assert next(f for f in fake.frames() if f.time >= raised and f.zero).time - raised < 0.2


def test_drive_for(rig: Rig, fake: FakeController) -> None:
    async def main() -> None:
        async with wheeltec.aio.Client(rig.socket) as robot:
            start = time.monotonic()
            assert (await robot.drive_for(0.7, vx=0.12)).vx == 0.12
            assert 0.65 < elapsed(start) < 1.2
            moving = [f for f in fake.frames() if f.time >= start and f.x == 120]
            assert moving[-1].time - moving[0].time > 0.6
    run(main())


def test_subscribe(rig: Rig) -> None:
    async def main() -> None:
        async with wheeltec.aio.Client(rig.socket) as robot:
            records = [t async for t in robot.subscribe("telemetry", count=4)]
            assert [type(t).__name__ for t in records] == ["Telemetry"] * 4
            assert [t.seq for t in records] == list(range(records[0].seq, records[0].seq + 4))
            async with robot.subscribe("events", timeout=3) as events:
                await robot.mark("aio mark")
                async for event in events:
                    if event.event == "mark":
                        assert event.fields["text"] == "aio mark"
                        break
            assert events.closed
            quiet = robot.subscribe("events", timeout=0.3)
            with pytest.raises(wheeltec.TimeoutError) as timeout:
                await quiet.__anext__()
            assert isinstance(timeout.value, builtins.TimeoutError) and quiet.closed
            with pytest.raises(wheeltec.InvalidParams):
                await robot.subscribe("pictures").__anext__()
    run(main())


def test_an_async_for_left_early_closes_the_connection(rig: Rig) -> None:
    before = rig.clients()
    during: List[int] = []

    async def main() -> None:
        async with wheeltec.aio.Client(rig.socket) as robot:
            async for _ in robot.subscribe("telemetry"):
                during.append(rig.clients())
                break
            await asyncio.sleep(0)  # the loop's turn that closes the transport's socket
            wait_for(lambda: rig.clients() == before + 1, 2, "only the client's own connection")  # (blocking is fine here)
            stream = robot.subscribe("telemetry")
            await stream.__anext__()
            await stream.close()
            await asyncio.sleep(0)
            wait_for(lambda: rig.clients() == before + 1, 2, "the closed subscription gone")

    gc.collect()
    gc.disable()
    try:
        run(main())
    finally:
        gc.enable()
    assert during == [before + 2]  # the client and the subscription


def test_timeout_of_a_call(make_rig: Any) -> None:
    rig = make_rig(fake=True)

    async def main() -> None:
        async with wheeltec.aio.Client(rig.socket, timeout=0.3) as robot:
            rig.daemon.signal(19)
            start = time.monotonic()
            with pytest.raises(wheeltec.TimeoutError):
                await robot.status()
            assert 0.25 < elapsed(start) < 1.5
            rig.daemon.signal(18)
            assert isinstance(await robot.version(), wheeltec.Version)
            rig.daemon.kill()
            with pytest.raises(wheeltec.DaemonUnreachable):
                await robot.status()
    run(main())
