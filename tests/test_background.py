"""server.background: services' tasks stop with the service, even stubborn ones."""

from __future__ import annotations

import asyncio
import logging

import pytest

from server.background import Background, every


async def test_stop_cancels_and_awaits_every_task() -> None:
    background = Background()
    ran = asyncio.Event()

    async def forever() -> None:
        ran.set()
        await asyncio.sleep(3600)

    tasks = [background.start(forever(), f"t{i}") for i in range(3)]
    await ran.wait()
    assert len(background) == 3
    await background.stop()
    assert all(t.cancelled() for t in tasks)
    assert len(background) == 0


async def test_a_task_that_swallows_one_cancel_gets_a_second_after_the_grace() -> None:
    background = Background(grace_s=0.05)
    swallowed = []

    async def stubborn() -> None:  # as aiomqtt waiting for a broker inside its cleanup
        try:
            await asyncio.sleep(3600)
        except asyncio.CancelledError:
            swallowed.append(1)
        await asyncio.sleep(3600)

    task = background.start(stubborn(), "stubborn")
    await asyncio.sleep(0)
    async with asyncio.timeout(5):
        await background.stop()
    assert swallowed == [1]
    assert task.cancelled()


async def test_a_task_that_failed_is_logged_at_stop(caplog: pytest.LogCaptureFixture) -> None:
    background = Background()

    async def broken() -> None:
        raise RuntimeError("boom")

    background.start(broken(), "broken")
    await asyncio.sleep(0.01)
    with caplog.at_level(logging.ERROR, logger="server.background"):
        await background.stop()
    assert "broken" in caplog.text and "boom" in caplog.text


async def test_every_goes_on_after_the_errors_it_is_told_of_and_ends_on_others() -> None:
    calls: list[int] = []

    async def step() -> None:
        calls.append(len(calls))
        if len(calls) in (1, 2):
            raise ConnectionError("database busy")
        if len(calls) == 4:
            raise KeyError("a bug")

    with pytest.raises(KeyError):
        async with asyncio.timeout(5):
            await every(0.001, step, errors=(ConnectionError,), what="test step")
    assert calls == [0, 1, 2, 3]
