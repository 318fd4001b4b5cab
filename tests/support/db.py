"""The test databases: SQLite in a temporary directory, and PostgreSQL on loopback with a
fresh database per session (fixtures ``postgres_url``, ``database_url`` and ``db``,
registered for every test module by ``tests/conftest.py``)."""

from __future__ import annotations

import uuid
from collections.abc import Iterator
from pathlib import Path

import psycopg
import pytest
from sqlalchemy import create_engine

from server.db import Database, make_engine
from server.db.tables import Base
from tests.support.services import reachable, require

PG_ADMIN = "host=127.0.0.1 port=5432 user=postgres dbname=postgres connect_timeout=5"


@pytest.fixture(scope="session")
def postgres_url() -> Iterator[str]:
    """A database of its own on the loopback PostgreSQL for this test session, dropped after."""
    require("PostgreSQL", reachable("127.0.0.1", 5432),
            "start it with `pg_ctlcluster <version> main start` (trust auth, user postgres)")
    name = f"ednc_test_{uuid.uuid4().hex[:12]}"
    with psycopg.connect(PG_ADMIN, autocommit=True) as admin:
        admin.execute(f'CREATE DATABASE "{name}"')
    try:
        yield f"postgresql+psycopg://postgres@127.0.0.1:5432/{name}"
    finally:
        with psycopg.connect(PG_ADMIN, autocommit=True) as admin:
            admin.execute(f'DROP DATABASE IF EXISTS "{name}" WITH (FORCE)')


@pytest.fixture(params=["sqlite", pytest.param("postgresql", marks=pytest.mark.services)])
def database_url(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[str]:
    """An empty database: a fresh SQLite file, or the session's PostgreSQL database emptied
    after the test."""
    if request.param == "sqlite":
        yield f"sqlite:///{tmp_path / 'ednc.db'}"
        return
    url: str = request.getfixturevalue("postgres_url")
    yield url
    engine = create_engine(url)
    Base.metadata.drop_all(engine)
    engine.dispose()


@pytest.fixture
def db(database_url: str) -> Iterator[Database]:
    """The center's :class:`~server.db.Database` on :func:`database_url`, schema created."""
    database = Database(make_engine(database_url))
    database.create_schema()
    yield database
    database.engine.dispose()
