"""The dashboard snapshot: the database's facts per machine joined with the live registry.

The live half is the whole plant's (:class:`server.plant.PlantView`: this node's registry
merged with the links other nodes store), so every node's dashboard shows every machine
and the node serving it (``owner``).

The database half (:func:`load_facts`) runs in one transaction on a worker thread; the
registry half (:func:`build_snapshot`) runs on the event loop, which owns the registry.
Stored reports are JSON that the format may extend and old rows may lack keys, so the
summaries read them defensively: a key that is missing or of the wrong type shows as
absent, never as an error on the whole dashboard.
"""

from __future__ import annotations

import datetime as dt
import math
import time
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from sqlalchemy import func, select
from sqlalchemy.orm import Session, defer

from protocol.mapfactored import FactoredPayload
from protocol.maptables import TablesPayload
from server.dashboard.mapgrid import MapSliceError, decode_stored
from server.dashboard.schemas import (
    AccuracyReason,
    AccuracyView,
    DashboardSnapshot,
    DiagnosisSummary,
    MachineCard,
    MapVersions,
    TemperatureLive,
    VerificationSummary,
)
from server.dashboard.telemetry import live_values
from server.db import events as event_repo
from server.db import machines as machine_repo
from server.db.machines import link_kind
from server.db.maps import delivery_state
from server.db.tables import AppliedRow, DiagnosisRow, MachineRow, MapVersionRow, ModelRow
from server.health import DEFAULT_LIMITS, LABELS, Inputs, Limits, assess, tolerance_of
from server.plant import PlantView
from server.schemas.event import EventPublic
from server.state import LinkState, Registry, shown_state
from server.temperatures import TemperatureBoard
from server.version import __version__

STALE_AFTER_S = 10.0
"""Telemetry older than this is stale: ten default telemetry periods (1 s, protocol §9),
and less than the 15 s after which the center declares a silent machine dead."""

EVENTS_SHOWN = 30


@dataclass(frozen=True, slots=True)
class MachineFacts:
    """What the database knows about one machine for its dashboard row."""

    machine: MachineRow
    latest_map: int | None
    sent: AppliedRow | None
    applied: AppliedRow | None
    verification: DiagnosisRow | None
    diagnosis: DiagnosisRow | None
    model: tuple[int, dt.datetime] | None = None
    """The newest model's version and creation time."""
    map_row: MapVersionRow | None = None
    """The newest map (without its payload)."""
    map_kind: str | None = None
    rejects: int = 0
    """Deliveries the machine rejected in the last :data:`REJECTS_WINDOW_S`."""


@dataclass(frozen=True, slots=True)
class Facts:
    """The database half of a snapshot."""

    machines: list[MachineFacts]
    events: list[EventPublic]


REJECTS_WINDOW_S = 86400.0

_KINDS: dict[tuple[int, str], str] = {}
"""Map kind by map row id and SHA-256 (a stored map never changes; decoding it once is
enough; the hash tells apart the rows of two databases a process may serve, as tests do)."""
_KINDS_KEPT = 4096


def _newest(session: Session, row: Any, query: Any, machine_id: int | None) -> dict[int, Any]:
    """The row with the highest id per machine among ``query``'s, by machine id."""
    newest = select(func.max(row.id)).where(*query)
    if machine_id is not None:
        newest = newest.where(row.machine_id == machine_id)
    rows = session.scalars(select(row).where(row.id.in_(newest.group_by(row.machine_id))))
    return {r.machine_id: r for r in rows}


def _map_kinds(session: Session, rows: list[MapVersionRow]) -> dict[int, str]:
    """The kind of each stored map of ``rows`` by row id (decoded once, then remembered)."""
    missing = [r.id for r in rows if (r.id, r.sha256) not in _KINDS]
    if missing:
        if len(_KINDS) > _KINDS_KEPT:
            _KINDS.clear()
        for map_id, sha, payload in session.execute(
                select(MapVersionRow.id, MapVersionRow.sha256, MapVersionRow.payload)
                .where(MapVersionRow.id.in_(missing))):
            try:
                decoded = decode_stored(payload)
            except MapSliceError:
                continue
            _KINDS[(map_id, sha)] = (
                "tables" if isinstance(decoded, TablesPayload) else
                "factored" if isinstance(decoded, FactoredPayload) else "grid")
    return {r.id: _KINDS[(r.id, r.sha256)] for r in rows if (r.id, r.sha256) in _KINDS}


def load_machine_facts(session: Session, machines: list[MachineRow],
                       machine_id: int | None = None,
                       now: dt.datetime | None = None) -> list[MachineFacts]:
    """Facts of ``machines`` in a few grouped queries, whatever their number (``machine_id``
    restricts them to one machine)."""
    now = now or dt.datetime.now(dt.UTC)

    def only(query: Any, column: Any) -> Any:
        return query if machine_id is None else query.where(column == machine_id)

    latest = {mid: v for mid, v in session.execute(only(
        select(MapVersionRow.machine_id, func.max(MapVersionRow.version)),
        MapVersionRow.machine_id).group_by(MapVersionRow.machine_id))}
    sent = _newest(session, AppliedRow, (), machine_id)
    applied = _newest(session, AppliedRow, (AppliedRow.acked,), machine_id)
    verifications = _newest(session, DiagnosisRow, (DiagnosisRow.kind == "verification",),
                            machine_id)
    diagnoses = _newest(session, DiagnosisRow, (DiagnosisRow.kind == "diagnosis",), machine_id)
    newest_model = only(select(func.max(ModelRow.id)), ModelRow.machine_id).group_by(
        ModelRow.machine_id)
    models = {mid: (version, at) for mid, version, at in session.execute(
        select(ModelRow.machine_id, ModelRow.version, ModelRow.created_at)
        .where(ModelRow.id.in_(newest_model)))}
    newest_map = only(select(func.max(MapVersionRow.id)), MapVersionRow.machine_id).group_by(
        MapVersionRow.machine_id)
    map_rows = {r.machine_id: r for r in session.scalars(
        select(MapVersionRow).options(defer(MapVersionRow.payload, raiseload=True))
        .where(MapVersionRow.id.in_(newest_map)))}
    kinds = _map_kinds(session, list(map_rows.values()))
    since = now - dt.timedelta(seconds=REJECTS_WINDOW_S)
    rejects = dict(session.execute(only(
        select(AppliedRow.machine_id, func.count()).where(
            AppliedRow.reject_reason.is_not(None), AppliedRow.applied_at >= since),
        AppliedRow.machine_id).group_by(AppliedRow.machine_id)).all())
    out = []
    for m in machines:
        map_row = map_rows.get(m.id)
        out.append(MachineFacts(
            machine=m, latest_map=latest.get(m.id), sent=sent.get(m.id),
            applied=applied.get(m.id), verification=verifications.get(m.id),
            diagnosis=diagnoses.get(m.id), model=models.get(m.id), map_row=map_row,
            map_kind=None if map_row is None else kinds.get(map_row.id),
            rejects=int(rejects.get(m.id, 0))))
    return out


def machine_facts(session: Session, machine: MachineRow) -> MachineFacts:
    """One machine's facts."""
    return load_machine_facts(session, [machine], machine.id)[0]


def load_facts(session: Session, events: int = EVENTS_SHOWN) -> Facts:
    """Every machine's facts and the newest ``events`` events."""
    rows = event_repo.list_events(session, limit=events)
    return Facts(
        machines=load_machine_facts(session, machine_repo.list_machines(session)),
        events=[EventPublic.model_validate(r, from_attributes=True) for r in rows],
    )


def _float(value: Any) -> float | None:
    if isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return float(value) if math.isfinite(value) else None


def _floats(value: Any) -> dict[str, float] | None:
    """A JSON object of numbers, keeping only the numeric entries; None if not an object."""
    if not isinstance(value, Mapping):
        return None
    out = {str(k): _float(v) for k, v in value.items()}
    return {k: v for k, v in out.items() if v is not None}


def _text(value: Any) -> str | None:
    return value if isinstance(value, str) else None


def verification_summary(row: DiagnosisRow) -> VerificationSummary:
    """The dashboard's view of a stored ISO 230-6 report (``server.numeric.verify_diagonals``)."""
    result = row.result if isinstance(row.result, Mapping) else {}
    gain = _floats(result.get("improvement"))
    acceptance = _float(result.get("acceptance"))
    accepted = result.get("accepted")
    return VerificationSummary(
        id=row.id, created_at=row.created_at,
        ranges_before_um=_floats(result.get("ranges_before_um")) or {},
        ranges_after_um=_floats(result.get("ranges_after_um")),
        improvement_pct=None if gain is None else {k: 100.0 * v for k, v in gain.items()},
        accepted=accepted if isinstance(accepted, bool) else None,
        acceptance_pct=None if acceptance is None else 100.0 * acceptance,
    )


def diagnosis_summary(row: DiagnosisRow) -> DiagnosisSummary:
    """The dashboard's view of a stored diagnosis (formats.md §3)."""
    result = row.result if isinstance(row.result, Mapping) else {}
    return DiagnosisSummary(
        id=row.id, created_at=row.created_at,
        effect=_text(result.get("effect")) or "unknown",
        axis=_text(result.get("axis")), sensor=_text(result.get("sensor")),
        estimate=_floats(result.get("estimate")) or {},
        rms_before_um=_float(result.get("rms_before_um")),
        rms_after_um=_float(result.get("rms_after_um")),
    )


def chain_text(description: Mapping[str, Any]) -> str:
    """The chain, or the generalized model's type numbers when the description has none."""
    chain = description.get("chain")
    if isinstance(chain, str):
        return chain
    return (f"type {description.get('translational_type', '?')}"
            f"/{description.get('rotary_type', 0)}")


def residual(v: VerificationSummary | None) -> tuple[float | None, bool]:
    """The verification's largest diagonal range, µm, and whether it is the compensated
    run's (the "after" ranges when the report has them)."""
    if v is None:
        return None, False
    ranges, compensated = (v.ranges_after_um, True) if v.ranges_after_um else (
        v.ranges_before_um, False)
    return (max(ranges.values()) if ranges else None), compensated


def _map_versions(facts: MachineFacts, reported: int | None, now: dt.datetime) -> MapVersions:
    sent, applied, row = facts.sent, facts.applied, facts.map_row
    sent_state = None if sent is None else delivery_state(sent)
    temps = row.temperatures if row is not None and isinstance(row.temperatures, Mapping) \
        else {}
    return MapVersions(
        latest=facts.latest_map, sent=None if sent is None else sent.map_version,
        sent_at=None if sent is None else sent.applied_at, sent_state=sent_state,
        applied=None if applied is None else applied.map_version,
        reported=reported,
        reject_reason=None if sent is None or sent_state != "rejected" else sent.reject_reason,
        kind=facts.map_kind,
        bytes=None if row is None else row.size_bytes,
        built_at=None if row is None else row.created_at,
        model_version=None if row is None else row.model_version,
        built_at_C={str(k): v for k, v in temps.items() if _float(v) is not None},
        applied_at=None if applied is None else applied.applied_at,
        age_s=None if applied is None else max(0.0, (now - applied.applied_at).total_seconds()),
    )


def board_temperatures(board: TemperatureBoard, machine: str, telemetry_stale: bool
                       ) -> list[TemperatureLive]:
    """The machine's readings on the service's temperature board (MQTT and telemetry).

    A reading is stale when the board says so, when it is older than the board's limit,
    or, for one from telemetry, when the telemetry is.
    """
    now = time.monotonic()
    out = []
    for column, r in sorted(board.readings(machine).items()):
        name = column[2:-2] if column.startswith("T_") and column.endswith("_C") else column
        age = max(0.0, now - r.received)
        stale = r.stale or age > board.stale_after_s or (
            r.source == "telemetry" and telemetry_stale)
        out.append(TemperatureLive(name=name, celsius=r.celsius, stale=stale,
                                   source=r.source, age_s=age,
                                   follows=board.notes.get((machine, column))))
    return out


def accuracy_of(facts: MachineFacts, card: MachineCard, board_stale: list[TemperatureLive],
                now: dt.datetime, limits: Limits = DEFAULT_LIMITS) -> AccuracyView:
    """The card's accuracy state (:func:`server.health.assess`) from its facts and row.

    Only the board's stale readings count as stale sensors: telemetry temperatures go
    stale with the telemetry, which is its own reason.
    """
    description = facts.machine.description if isinstance(
        facts.machine.description, Mapping) else {}
    value, compensated = residual(card.verification)
    maps = card.maps
    model_version, model_at = facts.model if facts.model is not None else (None, None)
    inputs = Inputs(
        now=now, connected=card.connected, tolerance_um=tolerance_of(description, limits),
        link_text=_link_line(card),
        machine_state=card.state, telemetry_age_s=card.telemetry_age_s,
        telemetry_stale=card.telemetry_stale,
        stale_sensors=tuple((t.name, t.age_s) for t in board_stale),
        residual_um=value, residual_compensated=compensated,
        verified_at=None if card.verification is None else card.verification.created_at,
        model_version=model_version, model_at=model_at, map_latest=maps.latest,
        map_model_version=maps.model_version, map_applied=maps.applied,
        map_applied_at=maps.applied_at, map_sent=maps.sent, map_sent_state=maps.sent_state,
        reject_reason=maps.reject_reason, map_error_um=maps.error_um,
        map_tolerance_um=maps.tolerance_um, rejects=facts.rejects,
    )
    found = assess(inputs, limits)
    return AccuracyView(
        state=found.state, label=LABELS[found.state],
        reasons=[AccuracyReason(state=r.state, code=r.code, text=r.text) for r in found.reasons],
        tolerance_um=inputs.tolerance_um, residual_um=value, residual_compensated=compensated,
        verified_at=inputs.verified_at, model_version=model_version, model_at=model_at,
        model_age_s=None if model_at is None else max(0.0, (now - model_at).total_seconds()),
    )


def _link_line(card: MachineCard) -> str:
    """Why a machine without a session has none, for the row's reason: the link's state
    and what was seen (``unreachable: Modbus/TCP 10.0.0.5:502: cannot connect``)."""
    if card.connected or card.link_state in ("offline", "connected"):
        return ""
    head = card.link_state.replace("_", " ")
    return f"{head}: {card.link_text}" if card.link_text else head


def machine_card(facts: MachineFacts, link: LinkState, now: dt.datetime,
                 stale_after_s: float = STALE_AFTER_S,
                 board: TemperatureBoard | None = None,
                 map_check: tuple[float, float] | None = None) -> MachineCard:
    """One machine's dashboard row from its facts, its live link and the temperature
    board (the service's, when it runs: Fanuc-style machines report their sensors over
    MQTT, not in telemetry); ``map_check`` is the newest map's (error as sent, tolerance)
    in µm when known."""
    m = facts.machine
    live = live_values(link.telemetry)
    measured_at = live.measured_at or (link.last_seen if link.telemetry else None)
    age = None if measured_at is None else max(0.0, (now - measured_at).total_seconds())
    stale = not link.connected or age is None or age > stale_after_s
    maps = _map_versions(facts, live.map_version, now)
    if map_check is not None:
        maps = maps.model_copy(update={"error_um": map_check[0], "tolerance_um": map_check[1]})
    temperatures = [TemperatureLive(name=t.name, celsius=t.celsius, stale=stale)
                    for t in live.temperatures]
    extra = [] if board is None else board_temperatures(board, m.name, stale)
    names = {t.name for t in extra}
    temperatures = [t for t in temperatures if t.name not in names] + extra
    card = MachineCard(
        name=m.name, controller=m.controller, ip=m.ip,
        chain=chain_text(m.description if isinstance(m.description, Mapping) else {}),
        link=link_kind(m.description if isinstance(m.description, Mapping) else {}),
        health="unknown", health_reason="", connected=link.connected, owner=link.owner,
        address=link.address, connected_since=link.connected_since, last_seen=link.last_seen,
        link_state=shown_state(link),
        link_reason=link.link_reason, link_text=link.link_text, telemetry_age_s=age,
        telemetry_stale=stale, state=live.state, axes=list(live.axes),
        temperatures=temperatures, maps=maps,
        verification=None if facts.verification is None
        else verification_summary(facts.verification),
        diagnosis=None if facts.diagnosis is None else diagnosis_summary(facts.diagnosis),
    )
    accuracy = accuracy_of(facts, card, [t for t in extra if t.stale], now)
    return card.model_copy(update={"health": accuracy.state,
                                   "health_reason": accuracy.reasons[0].text,
                                   "accuracy": accuracy})


def build_snapshot(facts: Facts, registry: Registry | PlantView, *, node_id: str,
                   now: dt.datetime | None = None, stale_after_s: float = STALE_AFTER_S,
                   temperatures: TemperatureBoard | None = None,
                   map_checks: Mapping[int, tuple[float, float]] | None = None
                   ) -> DashboardSnapshot:
    """The whole dashboard: every registered machine, live or not, and recent events.

    ``temperatures`` is the service's board (:mod:`server.temperatures`), when it runs:
    Fanuc-style machines report their sensors over MQTT, not in telemetry. ``map_checks``
    holds, by machine id, the newest map's error as sent and tolerance (µm) where known.
    """
    now = now or dt.datetime.now(dt.UTC)
    return DashboardSnapshot(
        generated_at=now, version=__version__, node_id=node_id, stale_after_s=stale_after_s,
        machines=[
            machine_card(f, registry.get(f.machine.name), now, stale_after_s, temperatures,
                         (map_checks or {}).get(f.machine.id))
            for f in facts.machines
        ],
        events=facts.events,
    )
