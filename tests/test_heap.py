"""The heap keeper freezes the survivors of every full collection while it runs, hands
them back on its refresh and on exit, and leaves no callback behind."""

from __future__ import annotations

import asyncio
import gc

import pytest

from server.heap import HeapKeeper


async def test_survivors_of_a_full_pass_are_frozen_and_handed_back() -> None:
    gc.unfreeze()
    keep = [[i] for i in range(1000)]  # long-lived objects the pass will find alive
    async with HeapKeeper(refresh_s=3600.0) as heap:
        await asyncio.sleep(0)  # the freeze runs on the loop after the start-up pass
        assert heap.stats.full_passes == 1 and gc.get_freeze_count() >= len(keep)
        gc.collect(1)  # a younger pass freezes nothing more
        await asyncio.sleep(0)
        assert heap.stats.full_passes == 1
        await heap._refresh()
        assert gc.get_freeze_count() == 0 and heap.stats.refreshes == 1
        gc.collect()
        await asyncio.sleep(0)
        assert heap.stats.full_passes == 2 and heap.stats.frozen >= len(keep)
        callback = heap._on_collect
        assert callback in gc.callbacks
    assert gc.get_freeze_count() == 0 and callback not in gc.callbacks
    del keep


async def test_a_cycle_among_frozen_objects_is_freed_after_a_refresh() -> None:
    gc.unfreeze()

    class Node:
        other: object = None

    async with HeapKeeper() as heap:
        a, b = Node(), Node()
        a.other, b.other = b, a
        gc.collect()
        await asyncio.sleep(0)
        del a, b  # now a cycle only the collector can free, but it is frozen
        assert gc.collect() == 0
        await asyncio.sleep(0)
        await heap._refresh()
        assert gc.collect() >= 2  # handed back: the next full pass frees it


def test_the_refresh_period_must_be_positive() -> None:
    with pytest.raises(ValueError, match="refresh_s"):
        HeapKeeper(refresh_s=0.0)
