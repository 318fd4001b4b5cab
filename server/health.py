"""A machine's accuracy state: how far the center can vouch for the machine's accuracy now.

"Map delivered" is not "machine accurate". The state here weighs what accuracy rests on:
the last ISO 230-6 verification's residual against the machine's tolerance, how old the
model and the applied map are and whether the map left more error as sent than it was
built for, whether the machine still reports (telemetry age) and still gets temperatures
(stale sensors), and what it rejected. Every problem found is a :class:`Reason`; the state
is the worst of them, and the reasons say why, worst first. The dashboard's colour, the
``ednc_machine_accuracy_state`` metric and the example alert rules all read this one
function, :func:`assess`, so that they cannot disagree.

Pure: inputs in, state out (no database, no clock: ``now`` is an input), so that each rule
is tested on its own (tests/test_health.py).
"""

from __future__ import annotations

import datetime as dt
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Final, Literal

State = Literal["ok", "unknown", "warn", "offline", "alarm", "out_of_tolerance"]
"""``ok``: verified within tolerance, map applied, everything fresh. ``unknown``: accuracy
never measured (no verification, no model). ``warn``: accuracy at risk (old model or map,
map over its tolerance as sent, stale telemetry or temperatures, rejects). ``offline``: not
connected. ``alarm``: the machine reports an alarm or rejected its newest map. ``out_of_
tolerance``: the last verification left more than the machine's tolerance."""

STATES: Final[tuple[State, ...]] = ("ok", "unknown", "warn", "offline", "alarm",
                                     "out_of_tolerance")
"""Every state, least severe first (the index is the severity, and the metric's value)."""

SEVERITY: Final[dict[State, int]] = {s: i for i, s in enumerate(STATES)}

LABELS: Final[dict[State, str]] = {
    "ok": "OK", "unknown": "UNKNOWN", "warn": "ATTENTION", "offline": "OFFLINE",
    "alarm": "ALARM", "out_of_tolerance": "OUT OF TOLERANCE",
}

TOLERANCE_KEY: Final = "accuracy_tolerance_um"
"""Optional key of a machine description: the largest body-diagonal range (ISO 230-6,
compensated) the machine may show, µm. Without it, :attr:`Limits.tolerance_um`."""

DAY_S: Final = 86400.0


@dataclass(frozen=True, slots=True)
class Limits:
    """Where a fact turns into a problem.

    Attributes
    ----------
    tolerance_um : float
        Accuracy tolerance of a machine whose description has no ``accuracy_tolerance_um``:
        the largest compensated body-diagonal range allowed, µm.
    model_age_s : float
        A model older than this is due for re-measurement, s (180 days).
    map_age_s : float
        An applied map older than this is suspect, s (7 days: a thermal map is rebuilt
        as temperatures move, a static one is re-sent at every session).
    verification_age_s : float
        A verification older than this no longer vouches for the machine, s (365 days).
    """

    tolerance_um: float = 10.0
    model_age_s: float = 180 * DAY_S
    map_age_s: float = 7 * DAY_S
    verification_age_s: float = 365 * DAY_S


DEFAULT_LIMITS: Final = Limits()


@dataclass(frozen=True, slots=True)
class Inputs:
    """What the state is computed from (the dashboard snapshot gathers it).

    Times are timezone-aware UTC; ages are computed against ``now``. None means "none
    known" (no verification, no model, no map...).
    """

    now: dt.datetime
    connected: bool
    tolerance_um: float
    link_text: str = ""
    """Why a machine without a session has none (its link's state and reason), if known."""
    machine_state: str | None = None
    telemetry_age_s: float | None = None
    telemetry_stale: bool = False
    stale_sensors: tuple[tuple[str, float | None], ...] = ()
    """Sensors whose readings stopped: (name, age s)."""
    residual_um: float | None = None
    """The last verification's largest diagonal range, µm: with compensation when the
    report has a compensated run, else without."""
    residual_compensated: bool = False
    verified_at: dt.datetime | None = None
    model_version: int | None = None
    model_at: dt.datetime | None = None
    map_latest: int | None = None
    map_model_version: int | None = None
    """The model version the newest map was built from."""
    map_applied: int | None = None
    map_applied_at: dt.datetime | None = None
    """When the applied map was sent (its delivery that the machine acknowledged)."""
    map_sent: int | None = None
    map_sent_state: str | None = None
    reject_reason: str | None = None
    map_error_um: float | None = None
    """The newest map's worst tool-tip error as sent (quantised), µm, when known."""
    map_tolerance_um: float | None = None
    """The tolerance the newest map was built for, µm, when known."""
    rejects: int = 0
    """Deliveries the machine rejected recently (the snapshot counts the last 24 h)."""


@dataclass(frozen=True, slots=True)
class Reason:
    """One finding: the state it calls for, a stable code (for tests and tools), a text."""

    state: State
    code: str
    text: str


@dataclass(frozen=True, slots=True)
class Accuracy:
    """The state and every finding behind it, worst first."""

    state: State
    reasons: tuple[Reason, ...]

    @property
    def summary(self) -> str:
        """The first reason's text (the one to act on first)."""
        return self.reasons[0].text if self.reasons else ""


def tolerance_of(description: Mapping[str, Any], limits: Limits = DEFAULT_LIMITS) -> float:
    """The machine's accuracy tolerance, µm: its description's ``accuracy_tolerance_um`` when
    that is a finite number > 0, else ``limits.tolerance_um``."""
    value = description.get(TOLERANCE_KEY)
    if isinstance(value, int | float) and not isinstance(value, bool):
        number = float(value)
        if math.isfinite(number) and number > 0:
            return number
    return limits.tolerance_um


def duration(seconds: float) -> str:
    """A duration for an operator: "40 s", "12 min", "5.0 h", "9 d"."""
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 2 * DAY_S:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / DAY_S:.0f} d"


def _age(now: dt.datetime, then: dt.datetime | None) -> float | None:
    return None if then is None else max(0.0, (now - then).total_seconds())


def _verification(i: Inputs, limits: Limits) -> list[Reason]:
    if i.residual_um is None:
        return [Reason("unknown", "not_verified",
                       "never verified: no ISO 230-6 diagonal test recorded, accuracy unknown")]
    how = "with compensation" if i.residual_compensated else "without compensation"
    measured = f"last verification: {i.residual_um:.1f} µm diagonal range {how}"
    out = []
    if i.residual_um > i.tolerance_um:
        out.append(Reason("out_of_tolerance", "residual",
                          f"{measured}, over the {i.tolerance_um:g} µm tolerance"))
    elif not i.residual_compensated:
        out.append(Reason("unknown", "not_verified_compensated",
                          f"{measured} (within {i.tolerance_um:g} µm); no compensated run "
                          "verified yet"))
    age = _age(i.now, i.verified_at)
    if age is not None and age > limits.verification_age_s:
        out.append(Reason("warn", "verification_old",
                          f"last verification is {duration(age)} old (limit "
                          f"{duration(limits.verification_age_s)}): verify again"))
    if (i.verified_at is not None and i.model_at is not None and i.model_at > i.verified_at
            and i.model_version is not None):
        out.append(Reason("warn", "verification_before_model",
                          f"model v{i.model_version} is newer than the last verification: "
                          "verify again"))
    return out


def _model_and_map(i: Inputs, limits: Limits) -> list[Reason]:
    out = []
    if i.map_sent_state == "rejected":
        now_on = f"v{i.map_applied}" if i.map_applied else "no map"
        out.append(Reason("alarm", "map_rejected",
                          f"map v{i.map_sent} rejected ({i.reject_reason or 'no reason'}): "
                          f"the machine still applies {now_on}"))
    elif i.map_sent_state == "failed":
        out.append(Reason("warn", "delivery_failed",
                          f"map v{i.map_sent} not delivered (the link failed before the "
                          "machine answered): the center sends it again"))
    elif i.rejects > 0:
        out.append(Reason("warn", "rejects",
                          f"{i.rejects} map deliver{'y' if i.rejects == 1 else 'ies'} "
                          "rejected in the last 24 h"))
    if i.model_version is None:
        return [*out, Reason("unknown", "no_model",
                             "no error model uploaded: the machine runs uncompensated")]
    model_age = _age(i.now, i.model_at)
    if model_age is not None and model_age > limits.model_age_s:
        out.append(Reason("warn", "model_old",
                          f"model v{i.model_version} is {duration(model_age)} old (limit "
                          f"{duration(limits.model_age_s)}): measure the machine again"))
    if i.map_latest is None:
        out.append(Reason("warn", "no_map", "no error map built from the model yet"))
        return out
    if i.map_model_version is not None and i.map_model_version < i.model_version:
        out.append(Reason("warn", "map_behind_model",
                          f"newest map v{i.map_latest} was built from model "
                          f"v{i.map_model_version}, v{i.model_version} is newer"))
    if i.map_applied != i.map_latest and i.map_sent_state != "rejected":
        out.append(Reason("warn", "map_not_applied", f"map v{i.map_latest} not applied yet"))
    map_age = _age(i.now, i.map_applied_at)
    if i.map_applied is not None and map_age is not None and map_age > limits.map_age_s:
        out.append(Reason("warn", "map_old",
                          f"applied map v{i.map_applied} is {duration(map_age)} old (limit "
                          f"{duration(limits.map_age_s)})"))
    if (i.map_error_um is not None and i.map_tolerance_um is not None
            and i.map_error_um > i.map_tolerance_um):
        out.append(Reason("warn", "map_over_tolerance",
                          f"map v{i.map_latest} leaves {i.map_error_um:.2f} µm as sent, over "
                          f"the {i.map_tolerance_um:g} µm it was built for"))
    return out


def _live(i: Inputs) -> list[Reason]:
    if not i.connected:
        return [Reason("offline", "offline", i.link_text or "not connected")]
    out = []
    if i.machine_state == "alarm":
        out.append(Reason("alarm", "machine_alarm", "machine reports alarm"))
    if i.telemetry_stale:
        text = "telemetry stale: nothing received yet" if i.telemetry_age_s is None \
            else f"telemetry stale: last {duration(i.telemetry_age_s)} ago"
        out.append(Reason("warn", "telemetry_stale", text))
    if i.stale_sensors:
        ages = ", ".join(name if age is None else f"{name} {duration(age)}"
                         for name, age in i.stale_sensors)
        plural = "s" if len(i.stale_sensors) > 1 else ""
        out.append(Reason("warn", "temperatures_stale",
                          f"temperature{plural} stale ({ages} since the last reading): the "
                          "thermal compensation holds the last good value"))
    return out


def assess(inputs: Inputs, limits: Limits = DEFAULT_LIMITS) -> Accuracy:
    """The machine's accuracy state and why (see the module docstring).

    Returns
    -------
    Accuracy
        ``state`` the most severe finding's (``ok`` without any); ``reasons`` every
        finding, most severe first, and for an ``ok`` machine the verification it rests on.
    """
    found = _live(inputs) + _verification(inputs, limits) + _model_and_map(inputs, limits)
    found.sort(key=lambda r: -SEVERITY[r.state])  # stable: same severity keeps rule order
    if not found:
        assert inputs.residual_um is not None  # else "not_verified" was found
        return Accuracy("ok", (Reason(
            "ok", "verified", f"verified {inputs.residual_um:.1f} µm, within the "
                              f"{inputs.tolerance_um:g} µm tolerance; map v{inputs.map_applied} "
                              "applied"),))
    return Accuracy(found[0].state, tuple(found))


__all__ = ["DEFAULT_LIMITS", "LABELS", "SEVERITY", "STATES", "TOLERANCE_KEY", "Accuracy",
           "Inputs", "Limits",
           "Reason", "State", "assess", "duration", "tolerance_of"]
