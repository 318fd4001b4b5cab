"""Short garbage-collector passes for a center holding a thousand machine sessions.

CPython's cyclic collector stops the process while it walks every tracked object of the
generations it collects. A center with 1,000 connected machines holds a few million
objects that live as long as the sessions; a full (generation 2) pass over them took
75-210 ms in ``benchmarks/mqtt_to_map.py`` (ten of them in one run), and every
temperature arriving meanwhile waited: in one run such a pass put the p99 at 130 ms. With
the keeper the worst pass of a run was 80-97 ms (the connect storm's, before its
survivors were frozen), most of the others under 50.

So after each full pass (its callback), the objects that survived it, all alive at that
moment since the pass has just freed the cyclic garbage, are moved to the permanent
generation (:func:`gc.freeze`): later passes walk only what was made since. Reference
counting still frees frozen objects; only a cycle among them would wait. Every
``refresh_s`` the frozen objects are handed back (:func:`gc.unfreeze`), the next full
pass looks at everything once and frees such cycles, and its survivors are frozen again:
one long pause an hour at most instead of one whenever the heap has grown by a quarter.
"""

from __future__ import annotations

import asyncio
import gc
import logging
from dataclasses import dataclass
from typing import Any

from server.background import Background, every

log = logging.getLogger(__name__)

REFRESH_S = 3600.0
"""How often the frozen objects are handed back to the collector, s."""


@dataclass
class HeapStats:
    """What the keeper did: full passes seen, refreshes; the objects frozen now."""

    full_passes: int = 0
    refreshes: int = 0

    @property
    def frozen(self) -> int:
        """Objects frozen now, counted when asked: the count walks them all (54 ms at the
        few million of a 1,000-machine center, twice in a fleet re-push when the keeper
        counted after each freeze)."""
        return gc.get_freeze_count()


class HeapKeeper:
    """Freezes the survivors of every full collection while it runs (module docstring).

    Use as ``async with HeapKeeper():``; on exit the callback is removed and every frozen
    object is handed back to the collector.
    """

    def __init__(self, *, refresh_s: float = REFRESH_S) -> None:
        if not refresh_s > 0:
            raise ValueError(f"refresh_s must be > 0, got {refresh_s!r}")
        self.refresh_s = float(refresh_s)
        self.stats = HeapStats()
        self._loop: asyncio.AbstractEventLoop | None = None
        self._pending = False
        self._background = Background()

    async def __aenter__(self) -> HeapKeeper:
        self._loop = asyncio.get_running_loop()
        gc.callbacks.append(self._on_collect)
        gc.collect()  # the start-up objects: modules, settings, the app (frozen after)
        self._background.start(every(self.refresh_s, self._refresh), "heap:refresh")
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self._background.stop()
        if self._on_collect in gc.callbacks:
            gc.callbacks.remove(self._on_collect)
        gc.unfreeze()
        self._loop = None

    def _on_collect(self, phase: str, info: dict[str, Any]) -> None:
        # any thread may trigger a collection (the database's, say): freeze on the loop
        if phase != "stop" or info.get("generation") != 2 or self._pending:
            return
        loop = self._loop
        if loop is None or loop.is_closed():
            return
        self._pending = True
        try:
            loop.call_soon_threadsafe(self._freeze)
        except RuntimeError:  # the loop closed meanwhile
            self._pending = False

    def _freeze(self) -> None:
        self._pending = False
        gc.freeze()
        self.stats.full_passes += 1
        log.debug("full collection %d: its survivors frozen", self.stats.full_passes)

    async def _refresh(self) -> None:
        gc.unfreeze()
        self.stats.refreshes += 1


__all__ = ["REFRESH_S", "HeapKeeper", "HeapStats"]
