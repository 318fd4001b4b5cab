"""The service's tables (SQLAlchemy 2 declarative mapping), the same on SQLite and PostgreSQL.

Rows are plain mapped classes without relationships: the repository modules load exactly
what a caller needs, and a row handed to another thread after its session closed never
triggers a lazy load.
"""

from __future__ import annotations

import datetime as dt
from typing import Any, ClassVar

from sqlalchemy import (
    JSON,
    BigInteger,
    DateTime,
    Float,
    ForeignKey,
    Index,
    Integer,
    LargeBinary,
    String,
    Text,
    TypeDecorator,
    UniqueConstraint,
    text,
)
from sqlalchemy.engine import Dialect
from sqlalchemy.orm import DeclarativeBase, Mapped, mapped_column


def utcnow() -> dt.datetime:
    return dt.datetime.now(dt.UTC)


class UTCDateTime(TypeDecorator[dt.datetime]):
    """A timezone-aware UTC timestamp on every backend.

    SQLite has no time zones and hands back naive datetimes; without this the API would
    show PostgreSQL rows with ``+00:00`` and SQLite rows without.
    """

    impl = DateTime(timezone=True)
    cache_ok = True

    def process_bind_param(self, value: dt.datetime | None, dialect: Dialect) -> dt.datetime | None:
        if value is None:
            return None
        if value.tzinfo is None:
            raise ValueError(f"naive datetime {value!r}: timestamps must carry a time zone")
        return value.astimezone(dt.UTC)

    def process_result_value(
        self, value: dt.datetime | None, dialect: Dialect
    ) -> dt.datetime | None:
        if value is None:
            return None
        if value.tzinfo is None:
            return value.replace(tzinfo=dt.UTC)
        return value.astimezone(dt.UTC)


class Base(DeclarativeBase):
    type_annotation_map: ClassVar[dict[Any, Any]] = {
        dt.datetime: UTCDateTime, dict[str, Any]: JSON
    }


def _machine_fk() -> ForeignKey:
    # A ForeignKey object belongs to one column: make one per table.
    return ForeignKey("machines.id", ondelete="CASCADE")


class MachineRow(Base):
    """A machine the center knows: identity, description (formats.md §1) and its secret.

    ``secret`` is sealed (AES-GCM, :mod:`server.db.secretbox`) because the center must
    compute HMAC responses with it, so a hash would not do; the API never returns it. 512
    characters: a sealed 256-byte secret takes 388.

    ``ip`` is the key of EDNC logins (the server admits a peer by its address and checks
    it against the Hello's), so it is unique among machines whose ``link`` is ``ednc``;
    machines the center reaches through a controller link may share one (controllers
    behind one gateway). The partial index enforces the first half; the rest, that a link
    machine does not take an EDNC machine's address, is checked by
    :func:`server.db.machines.create_machine` (a rule across rows no portable index holds).
    ``link`` repeats the description's ``link.kind`` for that index.
    """

    __tablename__ = "machines"
    __table_args__ = (
        # SQLite (3.8+) and PostgreSQL both take a partial unique index with this WHERE.
        Index("uq_machines_ednc_ip", "ip", unique=True,
              sqlite_where=text("link = 'ednc'"), postgresql_where=text("link = 'ednc'")),
    )

    id: Mapped[int] = mapped_column(primary_key=True)
    name: Mapped[str] = mapped_column(String(64), unique=True)
    ip: Mapped[str] = mapped_column(String(45), index=True)
    link: Mapped[str] = mapped_column(String(16), default="ednc", server_default="ednc")
    controller: Mapped[str] = mapped_column(String(16))
    description: Mapped[dict[str, Any]]
    secret: Mapped[str] = mapped_column(String(512))
    created_at: Mapped[dt.datetime] = mapped_column(default=utcnow)
    updated_at: Mapped[dt.datetime] = mapped_column(default=utcnow, onupdate=utcnow)


class ModelRow(Base):
    """One version of a machine's error model (JSON body defined by the numeric core)."""

    __tablename__ = "models"
    __table_args__ = (UniqueConstraint("machine_id", "version"),)

    id: Mapped[int] = mapped_column(primary_key=True)
    machine_id: Mapped[int] = mapped_column(_machine_fk(), index=True)
    version: Mapped[int] = mapped_column(Integer)
    source: Mapped[str] = mapped_column(String(16))
    body: Mapped[dict[str, Any]]
    created_at: Mapped[dt.datetime] = mapped_column(default=utcnow)


class MeasurementSetRow(Base):
    """A measurement CSV (formats.md §2) as uploaded, decoded from UTF-8 (a BOM dropped)."""

    __tablename__ = "measurement_sets"
    __table_args__ = (UniqueConstraint("machine_id", "name"),)

    id: Mapped[int] = mapped_column(primary_key=True)
    machine_id: Mapped[int] = mapped_column(_machine_fk(), index=True)
    name: Mapped[str] = mapped_column(String(128))
    csv_text: Mapped[str] = mapped_column(Text)
    row_count: Mapped[int] = mapped_column(Integer)
    size_bytes: Mapped[int] = mapped_column(Integer)
    created_at: Mapped[dt.datetime] = mapped_column(default=utcnow)


class MapVersionRow(Base):
    """An encoded error map as pushed to the machine, with what it was built from."""

    __tablename__ = "map_versions"
    __table_args__ = (UniqueConstraint("machine_id", "version"),)

    id: Mapped[int] = mapped_column(primary_key=True)
    machine_id: Mapped[int] = mapped_column(_machine_fk(), index=True)
    version: Mapped[int] = mapped_column(Integer)
    model_version: Mapped[int | None] = mapped_column(Integer)
    payload: Mapped[bytes] = mapped_column(LargeBinary)
    sha256: Mapped[str] = mapped_column(String(64))
    size_bytes: Mapped[int] = mapped_column(Integer)
    temperatures: Mapped[dict[str, Any]]
    created_at: Mapped[dt.datetime] = mapped_column(default=utcnow)


class MapVersionMarkRow(Base):
    """The highest map version ever stored for a machine name, kept when the machine is
    deleted: a machine registered again under its old name still holds its last map and
    would reject any lower version (STALE_VERSION), so its versions continue above."""

    __tablename__ = "map_version_marks"

    machine: Mapped[str] = mapped_column(String(64), primary_key=True)
    version: Mapped[int] = mapped_column(Integer)


class AppliedRow(Base):
    """One delivery of a map version to its machine: sent at ``applied_at`` (the column's
    old name: it is the send time), then in one ``state`` (:mod:`server.db.maps`):
    ``applied`` (``acked``), ``rejected`` (the machine's verdict in ``reject_reason``, and
    nothing else), ``failed`` (the transport failed before an answer: ``failure``; the map
    is sent again), ``superseded`` (a newer delivery went out before any answer), or
    ``pending``. Rows from before ``state`` existed have it null."""

    __tablename__ = "applied"

    id: Mapped[int] = mapped_column(primary_key=True)
    machine_id: Mapped[int] = mapped_column(_machine_fk(), index=True)
    map_id: Mapped[int] = mapped_column(ForeignKey("map_versions.id", ondelete="CASCADE"))
    map_version: Mapped[int] = mapped_column(Integer)
    applied_at: Mapped[dt.datetime] = mapped_column(default=utcnow)
    acked: Mapped[bool] = mapped_column(default=False)
    reject_reason: Mapped[str | None] = mapped_column(Text)
    state: Mapped[str | None] = mapped_column(String(16), default="pending")
    failure: Mapped[str | None] = mapped_column(Text)
    answered_at: Mapped[dt.datetime | None] = mapped_column()


class DiagnosisRow(Base):
    """A JSON result about a machine: a diagnosis (formats.md §3, ``kind="diagnosis"``) or an
    ISO 230-6 verification report (``kind="verification"``).

    One table for both: they share every column and every query (per machine, newest first),
    and a second table would only duplicate the code.
    """

    __tablename__ = "diagnoses"

    id: Mapped[int] = mapped_column(primary_key=True)
    machine_id: Mapped[int] = mapped_column(_machine_fk(), index=True)
    kind: Mapped[str] = mapped_column(String(16))
    result: Mapped[dict[str, Any]]
    created_at: Mapped[dt.datetime] = mapped_column(default=utcnow)


class EventRow(Base):
    """Something that happened on the machine link (the dashboard's refusal list and log).

    ``machine`` is the machine's name when known, else the peer address: refusals come from
    peers that are, by definition, not known machines, so there is no foreign key.
    """

    __tablename__ = "events"
    __table_args__ = (Index("ix_events_kind_id", "kind", "id"),)

    id: Mapped[int] = mapped_column(primary_key=True)
    time: Mapped[dt.datetime] = mapped_column(default=utcnow, index=True)
    machine: Mapped[str] = mapped_column(String(128), index=True)
    kind: Mapped[str] = mapped_column(String(32))
    detail: Mapped[str] = mapped_column(Text, default="")


class LeaseRow(Base):
    """Which control-center process (node) serves a machine: one row per machine at most.

    The node that holds an unexpired lease is the only one that keeps a session with the
    machine and pushes it maps; it renews the lease while the session lasts and deletes
    the row when the session ends. A node that dies stops renewing, and another node may
    take the lease once ``expires_at`` has passed (:mod:`server.db.leases`).
    """

    __tablename__ = "leases"

    machine_id: Mapped[int] = mapped_column(_machine_fk(), primary_key=True)
    owner: Mapped[str] = mapped_column(String(64), index=True)
    acquired_at: Mapped[dt.datetime]
    expires_at: Mapped[dt.datetime]


class LiveLinkRow(Base):
    """The live link of a machine as the node serving it last wrote it, so that every
    node's dashboard shows the whole plant (:mod:`server.db.live_links`).

    Keyed by machine name, as the in-memory registry is; whether the link is live now is
    read together with the lease (a node that died leaves ``connected`` true behind).
    """

    __tablename__ = "live_links"

    machine: Mapped[str] = mapped_column(String(64), primary_key=True)
    node: Mapped[str] = mapped_column(String(64))
    connected: Mapped[bool]
    address: Mapped[str | None] = mapped_column(String(64))
    connected_since: Mapped[dt.datetime | None]
    last_seen: Mapped[dt.datetime | None]
    telemetry: Mapped[dict[str, Any]]
    updated_at: Mapped[dt.datetime]


class TemperatureReadingRow(Base):
    """One temperature reading of one machine's sensor, as the center accepted it: the
    time series behind the dashboard's plots and later re-identification
    (:mod:`server.db.temperatures`; pruned after a retention period like ``events``).

    ``sensor`` is the model column (``T_spindle_C``); ``time`` when the reading was taken
    (the sender's stamp, else its arrival); ``source`` ``mqtt``, ``rest`` or ``telemetry``.
    The id is 64-bit on PostgreSQL: a plant writes hundreds of rows a second.
    """

    __tablename__ = "temperature_readings"
    __table_args__ = (Index("ix_temperature_readings_machine_sensor_time",
                            "machine_id", "sensor", "time"),)

    id: Mapped[int] = mapped_column(BigInteger().with_variant(Integer, "sqlite"),
                                    primary_key=True)
    machine_id: Mapped[int] = mapped_column(_machine_fk())
    sensor: Mapped[str] = mapped_column(String(64))
    celsius: Mapped[float] = mapped_column(Float)
    time: Mapped[dt.datetime] = mapped_column(index=True)
    source: Mapped[str] = mapped_column(String(16))


class CorrectionSampleRow(Base):
    """The compensation a machine applied along one axis over one sampling period, as its
    telemetry reported it: the history behind the dashboard's correction trends
    (:mod:`server.db.corrections`, written by :mod:`server.dashboard.sampler`, pruned after
    a retention period).

    One row per machine, axis and period (a minute by default) holding the mean, smallest
    and largest value seen (µm; µrad for a rotary axis) and how many telemetry readings
    they summarise, so that a month of history is 43,200 rows per axis, not millions.
    """

    __tablename__ = "correction_samples"
    __table_args__ = (Index("ix_correction_samples_machine_time", "machine_id", "time"),)

    id: Mapped[int] = mapped_column(BigInteger().with_variant(Integer, "sqlite"),
                                    primary_key=True)
    machine_id: Mapped[int] = mapped_column(_machine_fk())
    axis: Mapped[str] = mapped_column(String(8))
    time: Mapped[dt.datetime] = mapped_column(index=True)
    mean: Mapped[float] = mapped_column(Float)
    low: Mapped[float] = mapped_column(Float)
    high: Mapped[float] = mapped_column(Float)
    samples: Mapped[int] = mapped_column(Integer)


class TemperatureMinuteRow(Base):
    """One minute of one sensor's readings, summarised: what long history windows read
    instead of every reading (:func:`server.db.history.roll_up`, run every minute by
    :class:`server.dashboard.rollup.TemperatureRollup`; pruned like the readings).

    ``minute`` is the start of the minute (UTC); ``mean``, ``low``, ``high`` in °C over
    ``count`` readings; ``t_mean`` the mean time of those readings (s since the epoch).
    """

    __tablename__ = "temperature_minutes"

    machine_id: Mapped[int] = mapped_column(_machine_fk(), primary_key=True)
    sensor: Mapped[str] = mapped_column(String(64), primary_key=True)
    minute: Mapped[dt.datetime] = mapped_column(primary_key=True, index=True)
    t_mean: Mapped[float] = mapped_column(Float)
    mean: Mapped[float] = mapped_column(Float)
    low: Mapped[float] = mapped_column(Float)
    high: Mapped[float] = mapped_column(Float)
    count: Mapped[int] = mapped_column(Integer)
