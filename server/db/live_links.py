"""Repository: the ``live_links`` table, the plant-wide copy of every node's live links.

Each node writes the links of the machines it serves (:func:`publish`, batched by
:class:`server.plant.LinkPublisher`); every node reads all rows with the lease that says
whether the writer still serves the machine (:func:`plant_links`).

A write that says *connected* always wins (the writer holds the machine's lease, which is
what let its session start); a write that says *disconnected* only changes the writer's
own row, so a node that lost a machine cannot overwrite the row of the node that took it
over. One ``INSERT ... ON CONFLICT DO UPDATE ... WHERE`` statement does both.
"""

from __future__ import annotations

import datetime as dt
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from sqlalchemy import literal, or_, select
from sqlalchemy.dialects import postgresql, sqlite
from sqlalchemy.orm import Session

from server.db.leases import clock
from server.db.tables import LeaseRow, LiveLinkRow, MachineRow, UTCDateTime


@dataclass(frozen=True, slots=True)
class LiveLink:
    """One machine's link as its node wrote it, with whether that node still serves it.

    ``live`` is true when the row says connected and the writing node holds an unexpired
    lease of the machine: a node that died leaves ``connected`` behind, not ``live``.
    """

    machine: str
    node: str
    connected: bool
    address: str | None
    connected_since: dt.datetime | None
    last_seen: dt.datetime | None
    telemetry: dict[str, Any]
    updated_at: dt.datetime
    live: bool


def publish(session: Session, node: str, links: Sequence[dict[str, Any]],
            now: dt.datetime | None = None) -> None:
    """Upsert ``links`` written by ``node`` (module docstring for who wins).

    Parameters
    ----------
    links
        One dict per machine with the keys ``machine``, ``connected``, ``address``,
        ``connected_since``, ``last_seen`` and ``telemetry`` (plain JSON values).
    """
    if not links:
        return
    now = now or dt.datetime.now(dt.UTC)
    rows = [{**link, "node": node, "updated_at": now} for link in links]
    insert = (postgresql.insert(LiveLinkRow)
              if session.get_bind().dialect.name == "postgresql" else sqlite.insert(LiveLinkRow))
    stmt = insert
    new = stmt.excluded
    # executemany: SQLAlchemy batches the rows into multi-row INSERTs itself, with one
    # compiled statement (a literal VALUES list of thousands of rows compiles slowly)
    session.execute(stmt.on_conflict_do_update(
        index_elements=[LiveLinkRow.machine],
        set_={"node": new.node, "connected": new.connected, "address": new.address,
              "connected_since": new.connected_since, "last_seen": new.last_seen,
              "telemetry": new.telemetry, "updated_at": new.updated_at},
        where=or_(new.connected, LiveLinkRow.node == new.node)), rows)


def plant_links(session: Session, now: dt.datetime | None = None) -> list[LiveLink]:
    """Every machine's stored live link, by name, with ``live`` judged on the lease clock."""
    now = now or clock(session)
    lease = (select(LeaseRow.owner, MachineRow.name)
             .join(MachineRow, MachineRow.id == LeaseRow.machine_id)
             .where(LeaseRow.expires_at >= literal(now, UTCDateTime()))
             .subquery())
    t = LiveLinkRow
    rows = session.execute(  # columns, not entities: thousands of rows a second
        select(t.machine, t.node, t.connected, t.address, t.connected_since, t.last_seen,
               t.telemetry, t.updated_at, lease.c.owner)
        .outerjoin(lease, lease.c.name == t.machine)
        .order_by(t.machine))
    return [LiveLink(machine=r.machine, node=r.node, connected=r.connected,
                     address=r.address, connected_since=r.connected_since,
                     last_seen=r.last_seen,
                     telemetry=r.telemetry if isinstance(r.telemetry, dict) else {},
                     updated_at=r.updated_at, live=bool(r.connected and r.owner == r.node))
            for r in rows]


def forget(session: Session, machine: str) -> None:
    """Drop a machine's row (deleted or renamed machine)."""
    row = session.get(LiveLinkRow, machine)
    if row is not None:
        session.delete(row)


__all__ = ["LiveLink", "forget", "plant_links", "publish"]
