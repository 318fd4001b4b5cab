"""The error as sent of each machine's newest map, for the dashboard and the health rules.

The push does not store its build report, so the center rebuilds the map once per map
version, off the event loop, from what the stored map was built from (the machine's
description, the model version and the temperatures stored with it, the push's default
tolerance), the way the push builds it (:func:`server.push.adapter.build_for`). Only when
the rebuilt payload is byte for byte the stored one (same SHA-256) is its report taken as
the stored map's: its worst tool-tip error as sent (quantised, against the exact model)
and the tolerance it was built for. Otherwise (a machine that declared other formats, a
model gone, a build that fails) the error stays unknown (null), never guessed.

One check runs at a time (a build takes up to seconds of CPU); results are kept per map
row (a stored map never changes).
"""

from __future__ import annotations

import asyncio
import contextlib
import hashlib
import logging
from collections.abc import Iterable
from dataclasses import dataclass
from types import TracebackType
from typing import Final

from sqlalchemy import select
from sqlalchemy.orm import Session

from server import mapcodec
from server.center import Center
from server.dashboard.snapshot import MachineFacts
from server.db import error_models as model_repo
from server.db.tables import MachineRow, MapVersionRow
from server.push.adapter import build_for

log = logging.getLogger(__name__)

PUSH_TOLERANCE_UM: Final = 0.5
"""The push scheduler's default map tolerance (``PushScheduler(tolerance_um=...)``)."""
KEPT: Final = 4096


@dataclass(frozen=True, slots=True)
class Checked:
    """A stored map's error as sent and the tolerance it was built for, µm."""

    error_um: float
    tolerance_um: float


def check_map(machine: MachineRow, map_row: MapVersionRow, payload: bytes,
              model_body: dict[str, object], tolerance_um: float = PUSH_TOLERANCE_UM
              ) -> Checked | None:
    """Rebuild a stored map and return its report when the rebuild is the stored map
    (blocking, seconds at most); None when it is not or cannot be built."""
    temps = {str(k): float(v) for k, v in (map_row.temperatures or {}).items()
             if isinstance(v, int | float) and not isinstance(v, bool)}
    try:
        built = build_for(machine.description, machine.controller, model_body, temps,
                          tolerance_um)
    except ValueError as exc:  # MapBuildError and the description's errors are ValueErrors
        log.info("map v%d of %s not checked: %s", map_row.version, machine.name, exc)
        return None
    again = mapcodec.encode(mapcodec.with_version(built, map_row.version))
    if built.report is None or hashlib.sha256(again).hexdigest() != hashlib.sha256(
            payload).hexdigest():
        return None
    return Checked(error_um=float(built.report.worst_error_um),
                   tolerance_um=float(built.report.tolerance_um))


_RUNNING: dict[int, MapChecks] = {}
"""The running services by ``id`` of their Center (a dataclass, so not hashable)."""


def checks_of(center: Center) -> MapChecks | None:
    """The running Center's map checks (None outside the app's lifespan)."""
    checks = _RUNNING.get(id(center))
    return checks if checks is not None and checks.center is center else None


class MapChecks:
    """Checked maps by map row id, and the one check running (see the module docstring);
    one of the lifespan's services (an async context manager around the Center)."""

    def __init__(self, center: Center, tolerance_um: float = PUSH_TOLERANCE_UM) -> None:
        self.center = center
        self.tolerance_um = tolerance_um
        self.results: dict[int, Checked | None] = {}
        self._running: asyncio.Task[None] | None = None

    def known(self, facts: Iterable[MachineFacts]) -> dict[int, tuple[float, float]]:
        """(error as sent, tolerance) by machine id, for the newest maps checked so far."""
        out = {}
        for f in facts:
            found = None if f.map_row is None else self.results.get(f.map_row.id)
            if found is not None:
                out[f.machine.id] = (found.error_um, found.tolerance_um)
        return out

    def schedule(self, facts: Iterable[MachineFacts]) -> None:
        """Start checking the newest maps not checked yet (one task, in turn)."""
        if self._running is not None and not self._running.done():
            return
        todo = [f for f in facts if f.map_row is not None and f.map_row.id not in self.results
                and f.map_row.model_version is not None]
        if todo:
            self._running = asyncio.create_task(self._check_all(todo), name="map-checks")

    async def wait(self) -> None:
        """Until the running check, if any, is done (tests)."""
        if self._running is not None:
            await asyncio.shield(self._running)

    async def _check_all(self, todo: list[MachineFacts]) -> None:
        for f in todo:
            assert f.map_row is not None
            try:
                loaded = await self.center.db.run(_inputs, f.machine.id, f.map_row)
                self.results[f.map_row.id] = None if loaded is None else await asyncio.to_thread(
                    check_map, f.machine, f.map_row, *loaded, self.tolerance_um)
            except Exception:  # a check must never take the dashboard down
                log.exception("map v%d of %s: check failed", f.map_row.version, f.machine.name)
                self.results[f.map_row.id] = None
            if len(self.results) > KEPT:
                self.results.clear()

    async def __aenter__(self) -> MapChecks:
        _RUNNING[id(self.center)] = self
        return self

    async def __aexit__(self, exc_type: type[BaseException] | None,
                        exc: BaseException | None, tb: TracebackType | None) -> None:
        _RUNNING.pop(id(self.center), None)
        if self._running is not None:
            self._running.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await self._running


def _inputs(session: Session, machine_id: int, map_row: MapVersionRow
            ) -> tuple[bytes, dict[str, object]] | None:
    """The stored payload and the model body it was built from; None without them."""
    payload = session.scalar(select(MapVersionRow.payload).where(MapVersionRow.id == map_row.id))
    model = model_repo.get_model(session, machine_id, map_row.model_version)
    if payload is None or model is None or not isinstance(model.body, dict):
        return None
    return payload, model.body
