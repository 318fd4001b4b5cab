"""Property-based tests of the REST API from its own OpenAPI document (schemathesis).

Bounded on purpose (a few examples per operation): the point is that no generated request,
valid or not, gets a 5xx or a reply the document does not announce, and that the published
schema is a valid OpenAPI document.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
import schemathesis
from fastapi import FastAPI
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from schemathesis import GenerationMode
from schemathesis.checks import not_a_server_error
from schemathesis.python import asgi
from schemathesis.specs.openapi.checks import (
    content_type_conformance,
    response_schema_conformance,
    status_code_conformance,
)
from sqlalchemy import create_engine

from server.app import create_app
from server.db import Database, error_models, machines, make_engine, maps, measurements, reports
from server.db.tables import Base
from server.settings import Settings
from tests.support.api import backlash_csv
from tests.support.db import postgres_url  # noqa: F401  (fixture)

API_KEY = "fuzz-api-key-0123"
SEEDED = "vmc-01"
EXPENDABLE = "vmc-99"


def _seed(url: str) -> None:
    """A machine with a row in every table, so that generated requests on it reach past the
    404 into the handlers, and one for PATCH and DELETE to change."""
    db = Database(make_engine(url))
    db.create_schema()
    row = db.call(machines.create_machine, name=SEEDED, ip="10.0.0.21", controller="fanuc",
                  description={"name": SEEDED, "controller": "fanuc", "ip": "10.0.0.21",
                               "chain": "w X Y b Z t", "travel_mm": {"x": [0, 500],
                               "y": [0, 300], "z": [-300, 0]}}, secret="seeded-secret")
    db.call(machines.create_machine, name=EXPENDABLE, ip="10.0.0.99", controller="siemens",
            description={"name": EXPENDABLE, "controller": "siemens", "ip": "10.0.0.99",
                         "translational_type": 1, "rotary_type": 0}, secret="seeded-secret")
    db.call(error_models.add_model, row.id, source="fit", body={"terms": []})
    # A real campaign, so that fit, diagnose and verify run on data under generated options.
    readings = backlash_csv(8.0)
    db.call(measurements.add_measurement_set, row.id, name="s1", csv_text=readings,
            row_count=readings.count("\n") - 1)
    db.call(maps.add_map_version, row.id, payload=b"\x00map", model_version=1)
    db.call(maps.record_sent, row.id, 1)
    db.call(reports.add_report, row.id, kind="diagnosis", result={"effect": "none"})
    db.call(reports.add_report, row.id, kind="verification", result={"ok": True})
    db.engine.dispose()


@pytest.fixture(scope="module",
                params=["sqlite", pytest.param("postgresql", marks=pytest.mark.services)])
def fuzzed_app(
    request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory
) -> Iterator[FastAPI]:
    """The app on a seeded database: SQLite, and PostgreSQL (stricter: NUL characters,
    32-bit integers), which the other database tests share and so get back empty."""
    if request.param == "sqlite":
        path: Path = tmp_path_factory.mktemp("fuzz") / "ednc.db"
        url = f"sqlite:///{path}"
    else:
        url = request.getfixturevalue("postgres_url")
    _seed(url)
    try:
        yield create_app(Settings(database_url=url, api_key=API_KEY))
    finally:
        # schemathesis started the app's lifespan on its own event-loop thread; end it.
        asgi.shutdown_lifespans()
        engine = create_engine(url)
        Base.metadata.drop_all(engine)
        engine.dispose()


@pytest.fixture(scope="module")
def api_schema(fuzzed_app: FastAPI) -> schemathesis.BaseSchema:
    return schemathesis.openapi.from_asgi("/openapi.json", fuzzed_app)


def test_openapi_document_is_valid(api_schema: schemathesis.BaseSchema) -> None:
    api_schema.validate()  # raises on a document that breaks the OpenAPI meta-schema
    operations = [op.ok() for op in api_schema.get_all_operations()]
    paths = {op.path for op in operations}
    assert "/api/machines" in paths and "/api/machines/{name}/measurements" in paths
    assert len(operations) >= 20


# No 5xx; and every reply is one the document announces: status code, media type, body.
CHECKS = [not_a_server_error, status_code_conformance, content_type_conformance,
          response_schema_conformance]

# The operations, listed at collection time from a throw-away app (no database is opened
# before the lifespan runs) so that each gets its own test id. schemathesis' own
# ``pytest.from_fixture`` does not work with this pytest (it reads a private node field).
OPERATIONS = [
    result.ok()
    for result in schemathesis.openapi.from_dict(
        create_app(Settings(database_url="sqlite://")).openapi()
    ).get_all_operations()
]


@pytest.mark.parametrize(("path", "method"), [(op.path, op.method) for op in OPERATIONS],
                         ids=[op.label for op in OPERATIONS])
def test_no_request_gets_a_server_error(
    api_schema: schemathesis.BaseSchema, path: str, method: str
) -> None:
    operation = api_schema[path][method]

    # Valid requests and invalid ones (wrong types, missing fields, out-of-range values).
    cases = st.one_of(operation.as_strategy(GenerationMode.POSITIVE),
                      operation.as_strategy(GenerationMode.NEGATIVE))

    @given(case=cases)
    @settings(max_examples=12, deadline=None, database=None,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
    def check(case: schemathesis.Case) -> None:
        # Aim requests at seeded machines so the handlers behind the 404 run too; the ones
        # that may rename or delete a machine get one of their own.
        if "name" in (case.path_parameters or {}):
            changes = method.upper() in ("PATCH", "DELETE")
            case.path_parameters["name"] = EXPENDABLE if changes else SEEDED
        response = case.call(headers={"X-API-Key": API_KEY})
        case.validate_response(response, checks=CHECKS)

    check()
