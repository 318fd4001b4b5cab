"""Backoff after every failure, also after a session opened; no re-push into a PLC that
has the map or that stopped.

Before: a push refused after the session opened (exception 02 on buffer writes) gave 22
pushes and 21 TCP connects in 12 s, forever, because the backoff started afresh whenever
a session opened.
"""

from __future__ import annotations

import asyncio
import datetime as dt
import itertools
import random
from contextlib import AsyncExitStack
from pathlib import Path

import pytest

from server.links.pacing import ATTEMPTS_PER_MINUTE, Pacer
from tests.support.integration import center, spec, until
from tests.support.pmc import Faults, linked, pmc

GANTRY = spec("gantry-02")


def _attempts(pacer: Pacer, horizon_s: float, *, healthy_every: int = 0) -> list[float]:
    """Attempt times of a link that always fails (a session opened or not), simulated."""
    t, out = 0.0, []
    while t < horizon_s:
        t += pacer.delay(t)
        pacer.attempt(t)
        out.append(t)
        if healthy_every and len(out) % healthy_every == 0:
            pacer.healthy()
        else:
            pacer.failed()
    return out


def _most_in_a_minute(times: list[float]) -> int:
    return max(sum(1 for u in times if t <= u < t + 60.0) for t in times)


def test_a_failing_link_is_tried_at_most_four_times_a_minute() -> None:
    for seed in range(20):
        times = _attempts(Pacer(rng=random.Random(seed)), 900.0)
        assert _most_in_a_minute(times) <= ATTEMPTS_PER_MINUTE, (seed, times[:8])
        gaps = [b - a for a, b in itertools.pairwise(times)]
        assert gaps[0] <= 4.0  # a controller that rebooted is tried again soon
        # the backoff alone keeps the first minute within the budget: no retry is held
        # back beyond the step the operator sees
        assert sum(1 for t in times if t < 60.0) <= ATTEMPTS_PER_MINUTE
        assert max(gaps) <= 60.0 + 1e-9  # capped


def test_only_a_proof_resets_the_backoff() -> None:
    pacer = Pacer(rng=random.Random(1), per_minute=1000)
    for _ in range(6):
        pacer.failed()
    assert pacer.delay(0.0) >= 16.0  # 2^5 s, jitter takes at most half
    pacer.healthy()
    assert pacer.delay(0.0) == 0.0
    # a session that keeps proving itself in between failures is retried at once
    flapping = _attempts(Pacer(rng=random.Random(2)), 300.0, healthy_every=1)
    assert _most_in_a_minute(flapping) <= ATTEMPTS_PER_MINUTE


@pytest.mark.slow
async def test_a_push_refused_after_the_session_opened_is_not_a_storm(
        tmp_path: Path) -> None:
    faults = Faults(refuse_buffer_writes=True)
    async with asyncio.timeout(240), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        cnc = await stack.enter_async_context(pmc(GANTRY, faults=faults))
        s = linked(GANTRY, cnc.server.port)  # type: ignore[attr-defined]
        await plant.register(s)
        await plant.fit_from_campaign(s.name)
        loop = asyncio.get_running_loop()
        await until(lambda: faults.buffer_writes > 0)  # the first push, refused
        # its payload blocks go out together (pipelined) and are all refused; the next
        # push comes after the backoff's first step (>= 1 s)
        await asyncio.sleep(0.3)
        t0, opened0, pushes0 = loop.time(), faults.identity_reads, faults.buffer_writes
        await asyncio.sleep(60.0)
        connects = faults.identity_reads - opened0  # sessions opened after the first
        sent = sorted(dt.datetime.fromisoformat(d["sent_at"])
                      for d in await plant.deliveries(s.name))
        pushes = [t for t in sent if (t - sent[0]).total_seconds() < 60.0]
        assert loop.time() - t0 >= 60.0
        assert connects <= ATTEMPTS_PER_MINUTE, connects
        assert len(pushes) <= ATTEMPTS_PER_MINUTE, sent
        # each later push writes no more blocks than the first
        assert faults.buffer_writes - pushes0 <= ATTEMPTS_PER_MINUTE * pushes0
        st = await plant.status(s.name)
        assert st["link_reason"] == "exception_02" or st["connected"], st
        # said once, then at most once a minute
        said = sorted(dt.datetime.fromisoformat(e["time"])
                      for e in await plant.events(machine=s.name) if e["kind"] == "link")
        assert said and all((b - a).total_seconds() >= 59.9
                            for a, b in itertools.pairwise(said)), said
        # cleared: the map is applied (the backoff step in force, at most 60 s)
        faults.refuse_buffer_writes = False
        await until(plant.applied(s.name, 1))


@pytest.mark.slow
async def test_a_map_the_plc_reports_applied_is_not_sent_again(tmp_path: Path) -> None:
    faults = Faults()
    async with asyncio.timeout(120), AsyncExitStack() as stack:
        plant = await stack.enter_async_context(center(f"sqlite:///{tmp_path / 'c.db'}"))
        cnc = await stack.enter_async_context(pmc(GANTRY, faults=faults))
        s = linked(GANTRY, cnc.server.port)  # type: ignore[attr-defined]
        await plant.register(s)
        await plant.fit_from_campaign(s.name)
        await until(plant.applied(s.name, 1))
        switches = faults.switch_writes
        links = plant.services.controllers
        assert links is not None
        connects = links.connects
        # the session ends (the controller's server restarts): the center connects again
        for session in list(plant.services.server.sessions.values()):
            session.abort(None, "test: session dropped")
        await until(lambda: links.connects > connects)
        await asyncio.sleep(2.0)  # the push worker's first look at the new session
        assert faults.switch_writes == switches, "the applied map was sent again"
        assert len(await plant.deliveries(s.name)) == 1


def test_pushes_count_against_the_budget_too() -> None:
    pacer = Pacer(rng=random.Random(3))
    for k in range(ATTEMPTS_PER_MINUTE):  # a healthy session pushing, failing, again
        pacer.pushed(10.0 * k)
    assert pacer.delay(35.0) == pytest.approx(25.0)  # 60 s after the oldest of the four
    pacer.pushed(61.0)
    assert pacer.delay(61.0) == pytest.approx(9.0)
