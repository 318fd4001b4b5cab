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
from sqlalchemy.orm import Session

from server.dashboard.schemas import (
    DashboardSnapshot,
    DiagnosisSummary,
    Health,
    MachineCard,
    MapVersions,
    TemperatureLive,
    VerificationSummary,
)
from server.dashboard.telemetry import live_values
from server.db import events as event_repo
from server.db import machines as machine_repo
from server.db.tables import AppliedRow, DiagnosisRow, MachineRow, MapVersionRow
from server.plant import PlantView
from server.schemas.event import EventPublic
from server.state import LinkState, Registry
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


@dataclass(frozen=True, slots=True)
class Facts:
    """The database half of a snapshot."""

    machines: list[MachineFacts]
    events: list[EventPublic]


def _newest(session: Session, row: Any, query: Any, machine_id: int | None) -> dict[int, Any]:
    """The row with the highest id per machine among ``query``'s, by machine id."""
    newest = select(func.max(row.id)).where(*query)
    if machine_id is not None:
        newest = newest.where(row.machine_id == machine_id)
    rows = session.scalars(select(row).where(row.id.in_(newest.group_by(row.machine_id))))
    return {r.machine_id: r for r in rows}


def load_machine_facts(session: Session, machines: list[MachineRow],
                       machine_id: int | None = None) -> list[MachineFacts]:
    """Facts of ``machines`` in six grouped queries, whatever their number (``machine_id``
    restricts them to one machine)."""
    latest_query = select(MapVersionRow.machine_id, func.max(MapVersionRow.version))
    if machine_id is not None:
        latest_query = latest_query.where(MapVersionRow.machine_id == machine_id)
    latest = {mid: v for mid, v in session.execute(
        latest_query.group_by(MapVersionRow.machine_id))}
    sent = _newest(session, AppliedRow, (), machine_id)
    applied = _newest(session, AppliedRow, (AppliedRow.acked,), machine_id)
    verifications = _newest(session, DiagnosisRow, (DiagnosisRow.kind == "verification",),
                            machine_id)
    diagnoses = _newest(session, DiagnosisRow, (DiagnosisRow.kind == "diagnosis",), machine_id)
    return [MachineFacts(machine=m, latest_map=latest.get(m.id), sent=sent.get(m.id),
                         applied=applied.get(m.id), verification=verifications.get(m.id),
                         diagnosis=diagnoses.get(m.id)) for m in machines]


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


def _health(card: dict[str, Any], maps: MapVersions) -> tuple[Health, str]:
    """The row's colour and why: the first problem an operator should act on."""
    if not card["connected"]:
        return "offline", "not connected"
    if card["state"] == "alarm":
        return "alarm", "machine reports alarm"
    if maps.sent_state == "rejected":
        return "alarm", f"map v{maps.sent} rejected: {maps.reject_reason or 'no reason'}"
    if card["telemetry_stale"]:
        return "warn", "telemetry stale"
    if maps.latest is None:
        return "warn", "no error map built"
    if maps.applied != maps.latest:
        return "warn", f"map v{maps.latest} not applied yet"
    return "ok", f"map v{maps.applied} applied"


def machine_card(facts: MachineFacts, link: LinkState, now: dt.datetime,
                 stale_after_s: float = STALE_AFTER_S) -> MachineCard:
    """One machine's dashboard row from its facts and its live link."""
    m = facts.machine
    live = live_values(link.telemetry)
    measured_at = live.measured_at or (link.last_seen if link.telemetry else None)
    age = None if measured_at is None else max(0.0, (now - measured_at).total_seconds())
    stale = not link.connected or age is None or age > stale_after_s
    sent = facts.sent
    sent_state = None if sent is None else (
        "applied" if sent.acked else "rejected" if sent.reject_reason else "pending")
    maps = MapVersions(
        latest=facts.latest_map, sent=None if sent is None else sent.map_version,
        sent_at=None if sent is None else sent.applied_at, sent_state=sent_state,
        applied=None if facts.applied is None else facts.applied.map_version,
        reported=live.map_version, reject_reason=None if sent is None else sent.reject_reason,
    )
    fields: dict[str, Any] = {
        "name": m.name, "controller": m.controller, "ip": m.ip,
        "chain": chain_text(m.description if isinstance(m.description, Mapping) else {}),
        "connected": link.connected, "owner": link.owner, "address": link.address,
        "connected_since": link.connected_since, "last_seen": link.last_seen,
        "telemetry_age_s": age, "telemetry_stale": stale,
        "state": live.state, "axes": list(live.axes),
        "temperatures": [TemperatureLive(name=t.name, celsius=t.celsius, stale=stale)
                         for t in live.temperatures],
        "maps": maps,
        "verification": None if facts.verification is None
        else verification_summary(facts.verification),
        "diagnosis": None if facts.diagnosis is None else diagnosis_summary(facts.diagnosis),
    }
    health, reason = _health(fields, maps)
    return MachineCard(health=health, health_reason=reason, **fields)


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


def thermal_stale_reason(stale: list[TemperatureLive]) -> str:
    """The health reason of a machine whose temperatures stopped: which, how old, and what
    the machine does meanwhile (holds the last good value, machine_sim/temperatures.py)."""
    ages = ", ".join(f"{t.name} {t.age_s:.1f} s" if t.age_s is not None else t.name
                     for t in stale)
    return (f"temperature{'s' if len(stale) > 1 else ''} stale ({ages} since the last "
            "reading): the thermal compensation holds the last good value")


def with_board(card: MachineCard, board: TemperatureBoard | None) -> MachineCard:
    """The card with the board's readings in place of (or added to) the telemetry's.

    A machine otherwise in order whose board readings are stale (older than the board's
    ``stale_after_s``, ``EDNC_TEMPERATURE_STALE_S``, or their broker gone) is shown
    ``warn`` with :func:`thermal_stale_reason`: its map is applied, but the thermal part
    follows no temperature any more. A worse state (offline, alarm, a map not applied)
    keeps its own reason; the stale readings are marked on their rows either way.
    """
    if board is None:
        return card
    extra = board_temperatures(board, card.name, card.telemetry_stale)
    if not extra:
        return card
    names = {t.name for t in extra}
    merged = [t for t in card.temperatures if t.name not in names] + extra
    update: dict[str, Any] = {"temperatures": merged}
    stale = [t for t in extra if t.stale]
    if stale and card.health == "ok":
        update["health"] = "warn"
        update["health_reason"] = thermal_stale_reason(stale)
    return card.model_copy(update=update)


def build_snapshot(facts: Facts, registry: Registry | PlantView, *, node_id: str,
                   now: dt.datetime | None = None, stale_after_s: float = STALE_AFTER_S,
                   temperatures: TemperatureBoard | None = None) -> DashboardSnapshot:
    """The whole dashboard: every registered machine, live or not, and recent events.

    ``temperatures`` is the service's board (:mod:`server.temperatures`), when it runs:
    Fanuc-style machines report their sensors over MQTT, not in telemetry.
    """
    now = now or dt.datetime.now(dt.UTC)
    return DashboardSnapshot(
        generated_at=now, version=__version__, node_id=node_id, stale_after_s=stale_after_s,
        machines=[
            with_board(machine_card(f, registry.get(f.machine.name), now, stale_after_s),
                       temperatures)
            for f in facts.machines
        ],
        events=facts.events,
    )
