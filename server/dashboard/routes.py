"""The dashboard's HTTP surface.

``api`` (under ``/api``, in the OpenAPI document):

* ``GET /dashboard``: the whole snapshot (:class:`DashboardSnapshot`);
* ``GET /live``: the same as server-sent events (``text/event-stream``, left out of the
  OpenAPI document: a stream has no response schema, and a fuzzer would wait on it);
* ``GET /machines/{name}/dashboard``: a machine's page data (description, row, model);
* ``GET /machines/{name}/maps/latest/grid``, ``/maps/{version}/grid``: a map slice;
* ``GET /machines/{name}/verifications/latest/diagonals``, ``/{id}/diagonals``: the
  diagonal profiles of a verification report.

``pages`` (at the root, not in the OpenAPI document): ``/``, ``/dashboard``,
``/machines/{name}`` and ``/static/...``, the files in ``server/static``.
"""

from __future__ import annotations

import asyncio
import datetime as dt
import html
import io
import logging
import mimetypes
from pathlib import Path
from typing import Annotated, Any

from fastapi import APIRouter, HTTPException, Query, Request, status
from fastapi.responses import FileResponse, HTMLResponse, StreamingResponse
from sqlalchemy.exc import SQLAlchemyError
from sqlalchemy.orm import Session

from protocol.mapfactored import FactoredPayload
from protocol.maptables import TablesPayload
from server.api.deps import CenterDep, DatabaseDep, MachineDep, ReportId, Version
from server.api.errors import NOT_FOUND, Problem, unprocessable
from server.center import Center
from server.dashboard.diagonals import diagonal_profiles
from server.dashboard.live import LiveFeed, sse_stream
from server.dashboard.mapcheck import checks_of
from server.dashboard.mapgrid import MapSliceError, decode_stored, slice_map, slice_tables
from server.dashboard.modelview import ModelViewError, model_view
from server.dashboard.schemas import (
    DashboardSnapshot,
    DiagonalPlots,
    DiagonalProfile,
    MachineDetail,
    MapGrid,
)
from server.dashboard.snapshot import (
    build_snapshot,
    load_facts,
    machine_card,
    machine_facts,
)
from server.db import DatabaseUnavailable
from server.db import error_models as model_repo
from server.db import history as history_repo
from server.db import machines as machine_repo
from server.db import maps as map_repo
from server.db import measurements as measurement_repo
from server.db import reports as report_repo
from server.db.tables import DiagnosisRow, MachineRow
from server.metrics import machine_samples
from server.plant import plant_view
from volumetric.errors import MachineSpecError
from volumetric.measure.measurement import MeasurementFormatError, read_measurements
from volumetric.model.machine import parse_machine
from volumetric.verify.iso230_6 import DiagonalTestError

STATIC = Path(__file__).resolve().parent.parent / "static"
log = logging.getLogger(__name__)

api = APIRouter(tags=["dashboard"])
pages = APIRouter(include_in_schema=False)

_STORED: dict[int | str, dict[str, Any]] = {
    409: {"model": Problem, "description": "The stored item cannot be shown (says why)."}
}
AxisQuery = Annotated[str | None, Query(pattern=r"^[A-Za-z][A-Za-z0-9]{0,3}$",
                                        description="A grid axis of the map, e.g. X.")]


async def snapshot_of(center: Center) -> DashboardSnapshot:
    """The dashboard now (and the newest maps not checked yet go to the map checks)."""
    facts = await center.db.run(load_facts)
    checks = checks_of(center)
    known = None
    if checks is not None:
        checks.schedule(facts.machines)
        known = checks.known(facts.machines)
    return build_snapshot(facts, await plant_view(center), node_id=center.settings.node_id,
                          temperatures=center.temperatures, map_checks=known)


async def refresh_machine_metrics(center: Center) -> None:
    """Set the per-machine metric series from a fresh snapshot (at every scrape). A
    database that does not answer leaves the previous series (logged)."""
    try:
        snapshot = await snapshot_of(center)
        rejects = await center.db.run(history_repo.rejects_by_machine)
    except (SQLAlchemyError, DatabaseUnavailable) as exc:
        log.warning("per-machine metrics not refreshed: %s", str(exc).splitlines()[0])
        return
    center.metrics.set_machines(machine_samples(snapshot, rejects))


def live_feed(request: Request, center: Center) -> LiveFeed:
    """The app's shared feed, made on first use for the running Center."""
    feed = getattr(request.app.state, "dashboard_feed", None)
    if not isinstance(feed, LiveFeed) or feed.owner is not center:
        feed = LiveFeed(lambda: snapshot_of(center), owner=center)
        request.app.state.dashboard_feed = feed
    return feed


@api.get("/dashboard")
async def dashboard(center: CenterDep) -> DashboardSnapshot:
    """Every registered machine's live row and the recent events (what ``/api/live``
    streams)."""
    return await snapshot_of(center)


@api.get("/live", include_in_schema=False)
async def live(request: Request, center: CenterDep) -> StreamingResponse:
    """Server-sent events: ``snapshot`` (a :class:`DashboardSnapshot` as JSON) at connect
    and after every change, about once a second; see :mod:`server.dashboard.live`."""
    return StreamingResponse(
        sse_stream(live_feed(request, center)), media_type="text/event-stream",
        headers={"Cache-Control": "no-store", "X-Accel-Buffering": "no"},
    )


@api.get("/machines/{name}/dashboard", responses=NOT_FOUND)
async def machine_detail(center: CenterDep, machine: MachineDep) -> MachineDetail:
    """A machine's page: description, live row and its newest model's terms."""
    facts = await center.db.run(machine_facts, machine)
    model = await center.db.run(model_repo.get_model, machine.id)
    links = await plant_view(center)
    checks = checks_of(center)
    card = machine_card(facts, links.get(machine.name), now=dt.datetime.now(dt.UTC),
                        board=center.temperatures,
                        map_check=None if checks is None else
                        checks.known([facts]).get(machine.id))
    view, problem = None, None
    if model is not None:
        try:
            view = await asyncio.to_thread(
                model_view, model.body, machine.description, version=model.version,
                source=model.source, created_at=model.created_at)
        except ModelViewError as exc:
            problem = f"model v{model.version}: {exc}"
    return MachineDetail(card=card, description=machine.description, model=view,
                         model_problem=problem)


async def _grid(db: DatabaseDep, machine: MachineRow, version: int | None,
                u: str | None, v: str | None) -> MapGrid:
    row = await db.run(map_repo.get_map_version, machine.id, version)
    if row is None:
        which = "no map" if version is None else f"no map version {version}"
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"machine {machine.name!r} has {which}")
    try:
        payload = await asyncio.to_thread(decode_stored, row.payload)
    except MapSliceError as exc:
        raise HTTPException(status.HTTP_409_CONFLICT,
                            f"map v{row.version} of {machine.name!r}: {exc}") from None
    try:
        if isinstance(payload, TablesPayload | FactoredPayload):
            try:
                described = parse_machine(machine.description)
            except MachineSpecError as exc:
                raise MapSliceError(f"the registered description does not parse: {exc}"
                                    ) from None
            grid = await asyncio.to_thread(slice_tables, payload, described, u, v)
        else:
            grid = await asyncio.to_thread(slice_map, payload, u, v)
    except MapSliceError as exc:
        raise unprocessable(["query"], str(exc), "grid_axis") from None
    temps = row.temperatures if isinstance(row.temperatures, dict) else {}
    return grid.model_copy(update={
        "thermal_records": len(payload.thermal), "bytes": row.size_bytes,
        "built_at_C": {str(k): float(t) for k, t in temps.items()
                       if isinstance(t, int | float) and not isinstance(t, bool)}})


@api.get("/machines/{name}/maps/latest/grid", responses={**NOT_FOUND, **_STORED})
async def latest_map_grid(db: DatabaseDep, machine: MachineDep, u: AxisQuery = None,
                          v: AxisQuery = None) -> MapGrid:
    """The newest map over grid axes ``u`` and ``v`` (default: the first two), the other
    grid axes at mid-travel; values in µm (µrad for rotary outputs)."""
    return await _grid(db, machine, None, u, v)


@api.get("/machines/{name}/maps/{version}/grid", responses={**NOT_FOUND, **_STORED})
async def map_grid(db: DatabaseDep, machine: MachineDep, version: Version,
                   u: AxisQuery = None, v: AxisQuery = None) -> MapGrid:
    """One map version over grid axes ``u`` and ``v`` (see ``.../maps/latest/grid``)."""
    return await _grid(db, machine, version, u, v)


def _profiles(session: Session, machine: MachineRow, report: DiagnosisRow) -> DiagonalPlots:
    """Re-read the report's measurement sets and profile their diagonals (blocking)."""
    result = report.result if isinstance(report.result, dict) else {}
    names = {"before": result.get("before_set"), "after": result.get("after_set")}
    if not isinstance(names["before"], str):
        raise ValueError(f"report {report.id} names no 'before_set'")
    profiles = {}
    for which, set_name in names.items():
        if not isinstance(set_name, str):
            continue
        stored = measurement_repo.get_measurement_set(session, machine.id, set_name)
        if stored is None:
            raise ValueError(f"measurement set {set_name!r} of report {report.id} is gone")
        stream = io.StringIO(stored.csv_text)
        stream.name = set_name
        try:
            profiles[which] = diagonal_profiles(read_measurements(stream))
        except (MeasurementFormatError, DiagonalTestError) as exc:
            raise ValueError(f"measurement set {set_name!r}: {exc}") from None
    before, after = profiles["before"], profiles.get("after", {})
    diagonals = []
    for label, p in before.items():
        a = after.get(label)
        diagonals.append(DiagonalProfile(
            label=label, along_mm=p.along_mm.tolist(), before_um=p.mean_um.tolist(),
            after_along_mm=None if a is None else a.along_mm.tolist(),
            after_um=None if a is None else a.mean_um.tolist(),
            range_before_um=p.range_um, range_after_um=None if a is None else a.range_um,
        ))
    return DiagonalPlots(machine=machine.name, report_id=report.id, before_set=names["before"],
                         after_set=names["after"] if isinstance(names["after"], str) else None,
                         diagonals=diagonals)


async def _diagonals(db: DatabaseDep, machine: MachineRow, report_id: int | None
                     ) -> DiagonalPlots:
    def job(session: Session) -> DiagonalPlots | None:
        if report_id is None:
            rows = report_repo.list_reports(session, machine.id, "verification", limit=1)
            report = rows[0] if rows else None
        else:
            report = report_repo.get_report(session, machine.id, "verification", report_id)
        return None if report is None else _profiles(session, machine, report)

    try:
        plots = await db.run(job)
    except ValueError as exc:
        raise HTTPException(status.HTTP_409_CONFLICT, str(exc)) from None
    if plots is None:
        which = "no verification report" if report_id is None \
            else f"no verification report {report_id}"
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"machine {machine.name!r} has {which}")
    return plots


@api.get("/machines/{name}/verifications/latest/diagonals", responses={**NOT_FOUND, **_STORED})
async def latest_diagonals(db: DatabaseDep, machine: MachineDep) -> DiagonalPlots:
    """Deviation along each body diagonal, before and after, of the newest verification."""
    return await _diagonals(db, machine, None)


@api.get("/machines/{name}/verifications/{report_id}/diagonals",
         responses={**NOT_FOUND, **_STORED})
async def report_diagonals(db: DatabaseDep, machine: MachineDep, report_id: ReportId
                           ) -> DiagonalPlots:
    """Deviation along each body diagonal, before and after, of one verification."""
    return await _diagonals(db, machine, report_id)


def _page(name: str) -> FileResponse:
    return FileResponse(STATIC / name, media_type="text/html; charset=utf-8",
                        headers={"Cache-Control": "no-cache"})


@pages.get("/")
async def index() -> FileResponse:
    return _page("dashboard.html")


@pages.get("/dashboard")
async def dashboard_page() -> FileResponse:
    return _page("dashboard.html")


@pages.get("/machines/{name}", response_model=None)
async def machine_page(db: DatabaseDep, name: str) -> FileResponse | HTMLResponse:
    if await db.run(machine_repo.get_machine, name) is None:
        return HTMLResponse(f"<!doctype html><title>No machine</title><p>No machine named "
                            f"{html.escape(name)}. <a href='/'>Dashboard</a></p>", status_code=404)
    return _page("machine.html")


@pages.get("/static/{path:path}")
async def static_file(path: str) -> FileResponse:
    """A file under ``server/static`` (nothing outside it, whatever the path says)."""
    target = (STATIC / path).resolve()
    if not target.is_relative_to(STATIC) or not target.is_file():
        raise HTTPException(status.HTTP_404_NOT_FOUND, f"no static file {path!r}")
    media_type = mimetypes.guess_type(target.name)[0] or "application/octet-stream"
    if media_type.startswith("text/") or media_type.endswith("javascript"):
        media_type += "; charset=utf-8"
    return FileResponse(target, media_type=media_type, headers={"Cache-Control": "no-cache"})
