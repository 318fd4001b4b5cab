"""The persistence layer (server.db) on SQLite and on the real PostgreSQL on loopback.

The database fixtures here are shared with the API tests (imported there).
"""

from __future__ import annotations

import datetime as dt
import hashlib

import pytest
from sqlalchemy import inspect
from sqlalchemy.exc import InvalidRequestError
from sqlalchemy.orm import Session
from sqlalchemy.orm.exc import DetachedInstanceError

from server.db import (
    Database,
    DatabaseUnavailable,
    DuplicateError,
    error_models,
    events,
    machines,
    make_engine,
    maps,
    measurements,
    reports,
)


def _machine(db: Database, name: str = "vmc-01", ip: str = "10.0.0.21") -> int:
    row = db.call(machines.create_machine, name=name, ip=ip, controller="fanuc",
                  description={"name": name, "ip": ip, "controller": "fanuc",
                               "chain": "w X Y b Z t"}, secret="s3cret-s3cret")
    return row.id


def test_schema_has_every_table(db: Database) -> None:
    names = set(inspect(db.engine).get_table_names())
    assert names == {"machines", "models", "measurement_sets", "map_versions", "applied",
                     "diagnoses", "events", "leases", "live_links", "temperature_readings",
                     "map_version_marks", "correction_samples", "temperature_minutes"}


def test_machine_round_trip_keeps_secret_and_description(db: Database) -> None:
    mid = _machine(db)
    row = db.call(machines.get_machine, "vmc-01")
    assert row is not None and row.id == mid
    assert row.secret == "s3cret-s3cret"
    assert row.description["chain"] == "w X Y b Z t"
    assert db.call(machines.get_machine_by_ip, "10.0.0.21") is not None
    assert db.call(machines.get_machine, "nope") is None


@pytest.mark.parametrize(("name", "ip", "field"), [("vmc-01", "10.0.0.99", "name"),
                                                    ("vmc-02", "10.0.0.21", "ip")])
def test_duplicate_machine_names_the_field(db: Database, name: str, ip: str, field: str) -> None:
    _machine(db)
    with pytest.raises(DuplicateError) as info:
        _machine(db, name, ip)
    assert info.value.field == field
    assert len(db.call(machines.list_machines)) == 1


def test_update_renames_and_rejects_taken_ip(db: Database) -> None:
    _machine(db)
    _machine(db, "vmc-02", "10.0.0.22")
    desc = {"name": "vmc-03", "ip": "10.0.0.23", "controller": "siemens", "chain": "w b X Y Z t"}
    row = db.call(machines.update_machine, "vmc-01", description=desc)
    assert row is not None and (row.name, row.ip, row.controller) == ("vmc-03", "10.0.0.23",
                                                                      "siemens")
    assert row.secret == "s3cret-s3cret"  # unchanged when not given
    taken = {**desc, "ip": "10.0.0.22"}
    with pytest.raises(DuplicateError):
        db.call(machines.update_machine, "vmc-03", description=taken)
    assert db.call(machines.update_machine, "vmc-01", description=desc) is None


def test_versions_count_per_machine(db: Database) -> None:
    a, b = _machine(db), _machine(db, "vmc-02", "10.0.0.22")
    versions = [db.call(error_models.add_model, m, source="upload", body={"k": i}).version
                for i, m in enumerate([a, a, b, a])]
    assert versions == [1, 2, 1, 3]
    latest = db.call(error_models.get_model, a)
    assert latest is not None and latest.body == {"k": 3}
    assert [r.version for r in db.call(error_models.list_models, a)] == [3, 2, 1]
    maps_a = [db.call(maps.add_map_version, a, payload=bytes([i]), model_version=1).version
              for i in range(2)]
    assert maps_a == [1, 2]


def test_map_payload_hash_and_delivery_answers(db: Database) -> None:
    mid = _machine(db)
    payload = b"\x00\x01map-bytes\xff"
    row = db.call(maps.add_map_version, mid, payload=payload, model_version=None,
                  temperatures={"T_t1_C": 21.5})
    assert row.sha256 == hashlib.sha256(payload).hexdigest() and row.size_bytes == len(payload)
    stored = db.call(maps.get_map_version, mid, 1)
    assert stored is not None and stored.payload == payload
    assert db.call(maps.record_sent, mid, 7) is None  # no such version
    sent = db.call(maps.record_sent, mid, 1)
    assert sent is not None
    assert db.call(maps.latest_acked, mid) is None
    rejected = db.call(maps.record_answer, sent.id, acked=False, reject_reason="checksum")
    assert rejected is not None and rejected.reject_reason == "checksum"
    again = db.call(maps.record_sent, mid, 1)
    assert again is not None
    db.call(maps.record_answer, again.id, acked=True)
    acked = db.call(maps.latest_acked, mid)
    assert acked is not None and acked.id == again.id
    assert [r.acked for r in db.call(maps.list_applied, mid)] == [True, False]


def test_latest_versions_of_many_machines_in_one_call(db: Database) -> None:
    a, b = _machine(db), _machine(db, "vmc-02", "10.0.0.22")
    _machine(db, "vmc-03", "10.0.0.23")  # registered, never sent a map
    for mid in (a, b):
        for i in range(2):
            db.call(maps.add_map_version, mid, payload=bytes([i]), model_version=None)
    first = db.call(maps.record_sent, a, 1)
    assert first is not None
    db.call(maps.record_answer, first.id, acked=True)
    db.call(maps.record_sent, a, 2)  # sent, not answered
    rejected = db.call(maps.record_sent, b, 2)
    assert rejected is not None
    db.call(maps.record_answer, rejected.id, acked=False, reject_reason="checksum")
    names = ["vmc-01", "vmc-02", "vmc-03", "nobody"]
    got = db.call(maps.latest_versions, names, chunk=2)  # two chunks
    assert got == {"vmc-01": (2, 1), "vmc-02": (2, None), "vmc-03": (None, None)}
    for name, mid in (("vmc-01", a), ("vmc-02", b)):  # as the one-machine queries say
        sent, acked = db.call(maps.latest_sent, mid), db.call(maps.latest_acked, mid)
        assert got[name] == (sent.map_version if sent else None,
                             acked.map_version if acked else None)


def test_delete_machine_cascades_to_its_rows(db: Database) -> None:
    mid = _machine(db)
    keep = _machine(db, "vmc-02", "10.0.0.22")
    db.call(error_models.add_model, mid, source="fit", body={})
    db.call(measurements.add_measurement_set, mid, name="a", csv_text="x\n1\n", row_count=1)
    db.call(maps.add_map_version, mid, payload=b"m", model_version=1)
    db.call(maps.record_sent, mid, 1)
    db.call(reports.add_report, mid, kind="diagnosis", result={"effect": "none"})
    db.call(reports.add_report, keep, kind="diagnosis", result={"effect": "none"})
    assert db.call(machines.delete_machine, "vmc-01") is True
    assert db.call(machines.delete_machine, "vmc-01") is False
    assert db.call(error_models.list_models, mid) == []
    assert db.call(measurements.list_measurement_sets, mid) == []
    assert db.call(maps.list_map_versions, mid) == []
    assert db.call(maps.list_applied, mid) == []
    assert db.call(reports.list_reports, mid, "diagnosis") == []
    assert len(db.call(reports.list_reports, keep, "diagnosis")) == 1


def test_measurement_set_names_are_unique_per_machine(db: Database) -> None:
    a, b = _machine(db), _machine(db, "vmc-02", "10.0.0.22")
    db.call(measurements.add_measurement_set, a, name="run1", csv_text="h\n1\n", row_count=1)
    db.call(measurements.add_measurement_set, b, name="run1", csv_text="h\n2\n", row_count=1)
    with pytest.raises(DuplicateError):
        db.call(measurements.add_measurement_set, a, name="run1", csv_text="h\n", row_count=0)
    row = db.call(measurements.get_measurement_set, b, "run1")
    assert row is not None and row.csv_text == "h\n2\n" and row.size_bytes == 4


def test_listings_leave_the_big_columns_behind(db: Database) -> None:
    mid = _machine(db)
    db.call(measurements.add_measurement_set, mid, name="s", csv_text="h\n1\n", row_count=1)
    db.call(maps.add_map_version, mid, payload=b"m" * 100, model_version=None)
    (listed,) = db.call(measurements.list_measurement_sets, mid)
    meta = db.call(measurements.get_measurement_set, mid, "s", with_text=False)
    (map_listed,) = db.call(maps.list_map_versions, mid)
    map_meta = db.call(maps.get_map_version, mid, 1, with_payload=False)
    assert meta is not None and map_meta is not None
    assert (listed.size_bytes, map_listed.size_bytes) == (4, 100)
    for row, column in [(listed, "csv_text"), (meta, "csv_text"), (map_listed, "payload"),
                        (map_meta, "payload")]:
        # Never a silent lazy load: detached rows refuse, attached ones raise (raiseload).
        with pytest.raises((DetachedInstanceError, InvalidRequestError)):
            getattr(row, column)


def test_reports_are_separated_by_kind_and_machine(db: Database) -> None:
    a, b = _machine(db), _machine(db, "vmc-02", "10.0.0.22")
    diag = db.call(reports.add_report, a, kind="diagnosis", result={"effect": "backlash"})
    ver = db.call(reports.add_report, a, kind="verification", result={"improvement": 0.8})
    assert db.call(reports.get_report, a, "diagnosis", diag.id) is not None
    assert db.call(reports.get_report, a, "verification", diag.id) is None
    assert db.call(reports.get_report, b, "verification", ver.id) is None


def test_events_filter_and_page_newest_first(db: Database) -> None:
    for i in range(5):
        db.call(events.add_event, kind="refused" if i % 2 == 0 else "connected",
                machine=f"10.0.0.{i}", detail=f"#{i}")
    refused = db.call(events.list_events, kind="refused")
    assert [e.detail for e in refused] == ["#4", "#2", "#0"]
    page = db.call(events.list_events, before_id=refused[0].id, limit=2)
    assert [e.detail for e in page] == ["#3", "#2"]
    assert [e.detail for e in db.call(events.list_events, machine="10.0.0.1")] == ["#1"]


def test_timestamps_come_back_as_utc(db: Database) -> None:
    at = dt.datetime(2026, 1, 2, 3, 4, 5, tzinfo=dt.timezone(dt.timedelta(hours=2)))
    db.call(events.add_event, kind="pushed", machine="vmc-01", time=at)
    (row,) = db.call(events.list_events)
    assert row.time == at and row.time.utcoffset() == dt.timedelta(0)
    with pytest.raises(Exception, match="naive datetime"):
        db.call(events.add_event, kind="pushed", machine="m", time=dt.datetime(2026, 1, 1))


async def test_run_executes_on_a_worker_thread(db: Database) -> None:
    import threading

    main = threading.get_ident()

    def where(session: Session) -> int:
        return threading.get_ident()

    assert await db.run(where) != main
    mid = await db.run(machines.create_machine, name="m1", ip="::1", controller="siemens",
                       description={}, secret="x" * 8)
    row = await db.run(machines.get_machine, "m1")
    assert row is not None and row.id == mid.id


def test_failed_call_rolls_back(db: Database) -> None:
    def add_then_fail(session: Session) -> None:
        machines.create_machine(session, name="ghost", ip="10.1.1.1", controller="fanuc",
                                description={}, secret="x" * 8)
        raise RuntimeError("boom")

    with pytest.raises(RuntimeError):
        db.call(add_then_fail)
    assert db.call(machines.get_machine, "ghost") is None


@pytest.mark.parametrize("url", [
    "sqlite:////nonexistent-dir/sub/ednc.db",
    "postgresql+psycopg://nobody:hunter2@127.0.0.1:1/ednc",
])
def test_unreachable_database_is_one_clear_error(url: str) -> None:
    db = Database(make_engine(url))
    with pytest.raises(DatabaseUnavailable) as info:
        db.create_schema()
    message = str(info.value)
    assert message.startswith("cannot open database ") and "hunter2" not in message
    assert len(message.splitlines()) == 1


def test_map_states_of_every_machine_at_once(db: Database) -> None:
    a, b = _machine(db), _machine(db, "vmc-02", "10.0.0.22")
    _machine(db, "vmc-03", "10.0.0.23")  # no maps at all
    for mid in (a, a, a, b):
        db.call(maps.add_map_version, mid, payload=b"m", model_version=None)
    first = db.call(maps.record_sent, a, 1)
    assert first is not None
    db.call(maps.record_answer, first.id, acked=True)
    second = db.call(maps.record_sent, a, 2)
    assert second is not None
    db.call(maps.record_answer, second.id, acked=False, reject_reason="busy")
    db.call(maps.record_sent, b, 1)  # pending
    states = db.call(maps.map_states)
    assert states == {
        a: maps.MapState(latest=3, sent=2, applied=1, reject_reason="busy"),
        b: maps.MapState(latest=1, sent=1, applied=None, reject_reason=None),
    }
    assert db.call(maps.map_states, b) == {b: states[b]}


def test_event_text_from_peers_is_always_storable(db: Database) -> None:
    row = db.call(events.add_event, kind="refused", machine="evil\x00" + "m" * 300,
                  detail="bad\x00hello " + "x" * 5000)
    (stored,) = db.call(events.list_events)
    assert stored.id == row.id
    assert stored.machine.startswith("evil\\0mmm") and len(stored.machine) == 128
    assert stored.machine.endswith("…")
    assert stored.detail.startswith("bad\\0hello") and len(stored.detail) == 2000


def test_old_events_are_deleted(db: Database) -> None:
    now = dt.datetime.now(dt.UTC)
    for days in (40, 31, 1, 0):
        db.call(events.add_event, kind="refused", machine=f"{days}d",
                time=now - dt.timedelta(days=days))
    assert db.call(events.delete_events_before, now - dt.timedelta(days=30)) == 2
    assert [e.machine for e in db.call(events.list_events)] == ["0d", "1d"]
