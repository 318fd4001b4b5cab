"""The database handle: one engine, sessions, and the bridge from async code to it.

Why a synchronous engine driven through :func:`asyncio.to_thread` rather than SQLAlchemy's
async engine: SQLite is the embedded default and its async driver (aiosqlite) is not a
dependency; the same synchronous code then runs unchanged on SQLite and on PostgreSQL
(psycopg 3), repository functions stay plain functions that tests and the CLI can call
directly, and the load is small (a handful of writes per machine per push period), so a
thread per call costs nothing that matters while keeping the event loop free.
"""

from __future__ import annotations

import asyncio
import json
import os
import sqlite3
from collections.abc import AsyncIterator, Callable, Iterator
from contextlib import asynccontextmanager, contextmanager
from typing import Any, Concatenate, ParamSpec, TypeVar

from sqlalchemy import (
    Connection,
    Engine,
    MetaData,
    Table,
    create_engine,
    event,
    inspect,
    select,
    text,
    update,
)
from sqlalchemy.engine import make_url
from sqlalchemy.exc import OperationalError
from sqlalchemy.orm import Session, sessionmaker
from sqlalchemy.pool import StaticPool
from sqlalchemy.schema import CreateIndex, CreateTable

from server.db.machines import link_kind
from server.db.secretbox import SecretBox
from server.db.tables import Base

P = ParamSpec("P")
T = TypeVar("T")


class DatabaseUnavailable(RuntimeError):
    """The database cannot be reached or opened; the message names it (without password)."""


def make_engine(url: str) -> Engine:
    """Create the engine for a SQLite or PostgreSQL URL (see :mod:`server.settings`)."""
    parsed = make_url(url)
    if parsed.get_backend_name() != "sqlite":
        # pre_ping: a PostgreSQL restart must not turn the next request into a 500.
        return create_engine(url, pool_pre_ping=True)
    memory = parsed.database in (None, "", ":memory:")
    if not memory and parsed.database is not None:
        _create_private(parsed.database)
    engine = create_engine(
        url,
        # Sessions run on worker threads (asyncio.to_thread); each connection is used by one
        # thread at a time, which is what check_same_thread guards against.
        connect_args={"check_same_thread": False, "timeout": 15.0},
        # An in-memory database exists per connection: share one or it vanishes.
        poolclass=StaticPool if memory else None,
    )

    @event.listens_for(engine, "connect")
    def _sqlite_pragmas(dbapi_connection: Any, _record: Any) -> None:
        cursor = dbapi_connection.cursor()
        # SQLite ignores foreign keys (and so ON DELETE CASCADE) unless asked per connection.
        cursor.execute("PRAGMA foreign_keys=ON")
        if not memory:
            # WAL lets the dashboard read while a push writes.
            cursor.execute("PRAGMA journal_mode=WAL")
        cursor.close()

    return engine


def _create_private(path: str) -> None:
    """Create the SQLite file readable by its owner only (0600) if it does not exist.

    It holds the machines' (sealed) secrets and the plant's models; SQLite would create it
    with the umask's mode, usually 0644. Its -wal and -shm files take the file's mode.
    """
    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except FileExistsError:
        return
    except OSError:
        return  # a directory that does not exist: SQLite's own error names it
    os.close(fd)


_ADDED_COLUMNS: dict[str, tuple[str, ...]] = {
    "applied": ("state", "failure", "answered_at"),
}
"""Nullable columns added to a table after it first shipped: a database made before has
them added at start (``create_all`` makes missing tables only)."""


def _add_missing_columns(engine: Engine) -> None:
    names = inspect(engine).get_table_names()
    for table, columns in _ADDED_COLUMNS.items():
        if table not in names:
            continue
        have = {c["name"] for c in inspect(engine).get_columns(table)}
        for column in columns:
            if column in have:
                continue
            col = Base.metadata.tables[table].c[column]
            kind = col.type.compile(dialect=engine.dialect)
            with engine.begin() as conn:
                conn.execute(text(f"ALTER TABLE {table} ADD COLUMN {column} {kind}"))


def _share_link_ips(engine: Engine) -> None:
    """Bring a ``machines`` table made before link machines could share an ip to today's:
    no unique constraint on ``ip`` alone, a ``link`` column filled from each description,
    the partial unique index on the EDNC machines' ips (:class:`~server.db.tables.MachineRow`).

    Rows, ids and the other tables' foreign keys to ``machines`` are kept. The table made
    by ``create_all`` today has ``link``; one without it is the old schema.
    """
    if "machines" not in inspect(engine).get_table_names():
        return
    if "link" in {c["name"] for c in inspect(engine).get_columns("machines")}:
        return
    if engine.dialect.name == "sqlite":
        _rebuild_sqlite_machines(engine)
    else:
        uniques = inspect(engine).get_unique_constraints("machines")
        with engine.begin() as conn:
            for u in uniques:
                if u["column_names"] == ["ip"] and u["name"]:
                    conn.execute(text(f'ALTER TABLE machines DROP CONSTRAINT "{u["name"]}"'))
            conn.execute(text("ALTER TABLE machines ADD COLUMN IF NOT EXISTS "
                              "link varchar(16) NOT NULL DEFAULT 'ednc'"))
            _fill_link(conn)
            for index in Base.metadata.tables["machines"].indexes:
                index.create(conn, checkfirst=True)


def _fill_link(conn: Connection) -> None:
    """Set ``machines.link`` from each description's ``link.kind`` (in Python: JSON paths
    are spelled differently on SQLite and PostgreSQL)."""
    table = Base.metadata.tables["machines"]
    for machine_id, description in conn.execute(select(table.c.id, table.c.description)):
        kind = link_kind(_json_object(description))
        if kind != "ednc":
            conn.execute(update(table).where(table.c.id == machine_id).values(link=kind))


def _rebuild_sqlite_machines(engine: Engine) -> None:
    """SQLite cannot drop a column's UNIQUE: make the table anew and copy the rows over.

    The order is SQLite's own for schema changes (https://sqlite.org/lang_altertable.html,
    "Making Other Kinds Of Table Schema Changes"): with foreign keys off, create
    ``machines_new``, copy, drop ``machines``, rename ``machines_new``; the other tables'
    ``REFERENCES machines`` are text and name the new table once it has the name.
    Renaming the old table away first instead would rewrite those references to it.
    """
    old = Table("machines", MetaData(), autoload_with=engine)
    new = Base.metadata.tables["machines"].to_metadata(MetaData(), name="machines_new")
    columns = [c.name for c in old.columns if c.name in new.c]
    raw = engine.raw_connection()
    try:
        db = raw.driver_connection
        assert isinstance(db, sqlite3.Connection)
        level = db.isolation_level
        db.isolation_level = None  # autocommit: BEGIN and COMMIT are ours, PRAGMA outside
        try:
            # a no-op inside a transaction, hence before BEGIN
            db.execute("PRAGMA foreign_keys=OFF")
            db.execute("BEGIN IMMEDIATE")
            try:
                db.execute(str(CreateTable(new).compile(dialect=engine.dialect)))
                listed = ", ".join(columns)
                db.execute(f"INSERT INTO machines_new ({listed}) SELECT {listed} FROM machines")
                db.execute("DROP TABLE machines")
                db.execute("ALTER TABLE machines_new RENAME TO machines")
                # in the same transaction: a start that stops half way finds the old table
                for machine_id, stored in db.execute("SELECT id, description FROM machines"):
                    kind = link_kind(_json_object(stored))
                    if kind != "ednc":
                        db.execute("UPDATE machines SET link = ? WHERE id = ?",
                                   (kind, machine_id))
                for index in Base.metadata.tables["machines"].indexes:
                    db.execute(str(CreateIndex(index).compile(dialect=engine.dialect)))
                broken = db.execute("PRAGMA foreign_key_check").fetchall()
                if broken:
                    raise RuntimeError(f"machines rebuild broke foreign keys: {broken[:3]}")
                db.execute("COMMIT")
            except BaseException:
                db.execute("ROLLBACK")
                raise
        finally:
            db.execute("PRAGMA foreign_keys=ON")
            db.isolation_level = level
    finally:
        raw.close()


def _json_object(stored: object) -> dict[str, Any]:
    """A JSON column's text read through the driver: the object, or {} for anything else."""
    value = json.loads(stored) if isinstance(stored, str | bytes) else stored
    return value if isinstance(value, dict) else {}


class Database:
    """An engine plus a session factory; the one object the service holds for persistence.

    Use :meth:`open` from the lifespan. Repository functions (``server.db.machines`` etc.)
    take a :class:`~sqlalchemy.orm.Session` first; async code calls them through
    :meth:`run`, which gives each call its own transaction on a worker thread.
    """

    def __init__(self, engine: Engine) -> None:
        self.engine = engine
        # expire_on_commit=False: rows returned from a committed transaction stay readable
        # after the session is gone (they are handed to the API layer on another thread).
        self._sessions = sessionmaker(engine, expire_on_commit=False)
        self.secrets = SecretBox(None)
        """Seals and opens machine secrets; the app's lifespan gives it the settings' key."""

    @classmethod
    @asynccontextmanager
    async def open(cls, url: str) -> AsyncIterator[Database]:
        """Connect, create missing tables, and dispose of the pool on exit."""
        db = cls(make_engine(url))
        try:
            await asyncio.to_thread(db.create_schema)
            yield db
        finally:
            await asyncio.to_thread(db.engine.dispose)

    def create_schema(self) -> None:
        """Create the tables that do not exist yet (existing data is kept).

        Raises
        ------
        DatabaseUnavailable
            When the database cannot be reached (the first thing that connects at start-up).
        """
        try:
            Base.metadata.create_all(self.engine)
            _add_missing_columns(self.engine)
            _share_link_ips(self.engine)
            if self.engine.dialect.name == "postgresql":
                # tables made before secrets were sealed have varchar(256)
                with self.engine.begin() as conn:
                    width = conn.scalar(text(
                        "SELECT character_maximum_length FROM information_schema.columns "
                        "WHERE table_schema = current_schema() AND table_name = 'machines' "
                        "AND column_name = 'secret'"))
                    if width is not None and width < 512:
                        conn.execute(text(
                            "ALTER TABLE machines ALTER COLUMN secret TYPE varchar(512)"))
        except OperationalError as exc:
            where = self.engine.url.render_as_string(hide_password=True)
            reason = str(exc.orig).strip().splitlines()[0] if exc.orig else str(exc)
            raise DatabaseUnavailable(f"cannot open database {where}: {reason}") from None

    @contextmanager
    def session(self) -> Iterator[Session]:
        """A session inside one transaction: committed on success, rolled back on error."""
        with self._sessions.begin() as session:
            yield session

    def call(
        self, fn: Callable[Concatenate[Session, P], T], *args: P.args, **kwargs: P.kwargs
    ) -> T:
        """Run ``fn(session, *args, **kwargs)`` in its own transaction (blocking)."""
        with self.session() as session:
            return fn(session, *args, **kwargs)

    async def run(
        self, fn: Callable[Concatenate[Session, P], T], *args: P.args, **kwargs: P.kwargs
    ) -> T:
        """Run ``fn(session, *args, **kwargs)`` in its own transaction on a worker thread."""

        def job() -> T:
            return self.call(fn, *args, **kwargs)

        return await asyncio.to_thread(job)
