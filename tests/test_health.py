"""The accuracy state (server/health.py): each rule on its own, and the worst one wins."""

from __future__ import annotations

import dataclasses
import datetime as dt

import pytest

from server.health import Inputs, Limits, assess, duration, tolerance_of

NOW = dt.datetime(2026, 11, 27, 12, 0, tzinfo=dt.UTC)
DAY = dt.timedelta(days=1)

GOOD = Inputs(
    now=NOW, connected=True, tolerance_um=10.0, telemetry_age_s=0.5,
    residual_um=4.2, residual_compensated=True, verified_at=NOW - 2 * DAY,
    model_version=2, model_at=NOW - 3 * DAY, map_latest=5, map_model_version=2,
    map_applied=5, map_applied_at=NOW - dt.timedelta(hours=1), map_sent=5,
    map_sent_state="applied", map_error_um=0.3, map_tolerance_um=0.5,
)


def with_(**changes: object) -> Inputs:
    return dataclasses.replace(GOOD, **changes)  # type: ignore[arg-type]


def codes(i: Inputs) -> list[str]:
    return [r.code for r in assess(i).reasons]


def test_a_verified_machine_with_its_map_applied_is_ok_and_says_on_what() -> None:
    a = assess(GOOD)
    assert a.state == "ok"
    assert a.summary == "verified 4.2 µm, within the 10 µm tolerance; map v5 applied"


def test_a_residual_over_the_tolerance_is_out_of_tolerance_whatever_else() -> None:
    a = assess(with_(residual_um=19.1, telemetry_stale=True, map_latest=6))
    assert a.state == "out_of_tolerance"
    assert a.reasons[0].text == ("last verification: 19.1 µm diagonal range with "
                                 "compensation, over the 10 µm tolerance")
    # the lesser findings are still listed, after it
    assert codes(with_(residual_um=19.1, telemetry_stale=True))[1:] == ["telemetry_stale"]
    assert assess(with_(residual_um=10.0)).state == "ok"  # at the tolerance is within it


def test_a_machine_never_verified_or_without_model_is_unknown_not_ok() -> None:
    a = assess(with_(residual_um=None, verified_at=None))
    assert (a.state, a.reasons[0].code) == ("unknown", "not_verified")
    a = assess(with_(model_version=None, model_at=None))
    assert (a.state, [r.code for r in a.reasons]) == ("unknown", ["no_model"])
    a = assess(with_(residual_compensated=False, residual_um=6.0))
    assert (a.state, a.reasons[0].code) == ("unknown", "not_verified_compensated")


@pytest.mark.parametrize(("changes", "code"), [
    ({"model_at": NOW - 200 * DAY, "verified_at": NOW - 199 * DAY}, "model_old"),
    ({"map_applied_at": NOW - 8 * DAY}, "map_old"),
    ({"verified_at": NOW - 400 * DAY, "model_at": NOW - 401 * DAY},
     "verification_old model_old"),
    ({"model_at": NOW - DAY}, "verification_before_model"),
    ({"map_error_um": 0.705}, "map_over_tolerance"),
    ({"telemetry_stale": True, "telemetry_age_s": 42.0}, "telemetry_stale"),
    ({"stale_sensors": (("spindle", 125.0),)}, "temperatures_stale"),
    ({"rejects": 2}, "rejects"),
    ({"map_latest": 6, "map_model_version": 2}, "map_not_applied"),
    ({"map_latest": None, "map_applied": None}, "no_map"),
    ({"map_model_version": 1}, "map_behind_model"),
])
def test_each_risk_turns_a_good_machine_warn_and_names_itself(
        changes: dict[str, object], code: str) -> None:
    a = assess(with_(**changes))
    assert a.state == "warn", a
    assert [r.code for r in a.reasons] == code.split()


def test_texts_say_the_figures() -> None:
    a = assess(with_(map_error_um=0.706))
    assert a.summary == "map v5 leaves 0.71 µm as sent, over the 0.5 µm it was built for"
    a = assess(with_(stale_sensors=(("spindle", 125.0), ("bed", None))))
    assert a.summary.startswith("temperatures stale (spindle 2 min, bed since")
    a = assess(with_(telemetry_stale=True, telemetry_age_s=42.0))
    assert a.summary == "telemetry stale: last 42 s ago"
    a = assess(with_(model_at=NOW - 200 * DAY, verified_at=NOW - 199 * DAY))
    assert a.summary == "model v2 is 200 d old (limit 180 d): measure the machine again"


def test_alarms_and_rejections_rank_above_warnings_and_offline_above_them() -> None:
    a = assess(with_(machine_state="alarm", telemetry_stale=True))
    assert (a.state, codes(with_(machine_state="alarm"))) == ("alarm", ["machine_alarm"])
    a = assess(with_(map_sent=6, map_latest=6, map_sent_state="rejected",
                     reject_reason="CHECKSUM", rejects=1))
    assert a.state == "alarm"
    assert a.summary == "map v6 rejected (CHECKSUM): the machine still applies v5"
    assert "rejects" not in [r.code for r in a.reasons]  # the rejection is said once
    a = assess(with_(connected=False, telemetry_stale=True))
    assert (a.state, a.summary) == ("offline", "not connected")
    assert assess(with_(connected=False, residual_um=30.0)).state == "out_of_tolerance"


def test_the_tolerance_comes_from_the_description_when_it_is_a_sound_number() -> None:
    assert tolerance_of({"accuracy_tolerance_um": 5}) == 5.0
    for bad in (None, "5", True, float("nan"), float("inf"), -1.0, 0):
        assert tolerance_of({"accuracy_tolerance_um": bad}) == Limits().tolerance_um
    assert tolerance_of({}, Limits(tolerance_um=7.5)) == 7.5


def test_durations_read_as_an_operator_would_say_them() -> None:
    assert [duration(s) for s in (3, 119, 600, 3 * 3600, 9 * 86400)] == [
        "3 s", "119 s", "10 min", "3.0 h", "9 d"]
