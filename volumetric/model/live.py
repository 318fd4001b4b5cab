"""A model as a machine applies it live: the lag states of its thermal history as sensors.

A :class:`~volumetric.model.model.DynamicThermalTerm` (what ``ednc diagnose`` saves when a
lagged thermal model is behind its figure) follows the temperatures' history. A
controller applies thermal records, ``k·(T − T_ref)`` per sensor, to the temperatures it
is sent, and keeps no history. So the center keeps it: each lag column's state is
followed from the readings of its sensor (:func:`volumetric.model.lag.lag_step`, the
recursion :func:`~volumetric.model.lag.first_order_lag` runs over a series) and sent to
the machine as the temperature of a sensor of its own, ``lag1``, ``lag2``, ... (column
``T_lag1_C`` ...), numbered over the model's dynamic terms and their columns in order.
:func:`live_model` is the model with every dynamic term written that way:

* a ``level`` column of sensor s: a drift record on s;
* a ``lag`` column: a drift record on its lag sensor;
* a ``time`` column: held at the time the fit's states were saved (a trend in time
  continued live would grow without bound);
* the intercept, the held time column and every record's reference value: one constant,
  so that the sum equals the dynamic term's at any temperatures and lag states.

The machine thus applies ``c + Σ b_j x_j``, with ``x_j`` the lag states the center
sent, exactly what :meth:`DynamicThermalTerm.series` gives over the same readings from a
structure at rest at the first of them.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from volumetric.model.model import DynamicThermalTerm, MachineModel, Term, ThermalTerm

LAG_SENSOR = "lag{}"
"""The sensor name of the n-th lag state (1-based): short, since the map's thermal records
and the protocol's Temperatures message carry at most 16 bytes of name."""
REFERENCE_C = 20.0
"""The records' reference temperature where the term saved none (ISO 1: 20 °C); any value
gives the same sum, the constant takes the rest."""


@dataclass(frozen=True)
class LiveLag:
    """One lag state the center follows for a machine.

    Attributes
    ----------
    column : str
        The column it is sent as, ``T_lag1_C``.
    source : str
        The temperature column it follows, ``T_t4_C``.
    tau_s : float
        Its time constant, s.
    """

    column: str
    source: str
    tau_s: float


def live_lags(model: MachineModel) -> tuple[LiveLag, ...]:
    """The lag states of ``model``'s dynamic thermal terms, numbered as :func:`live_model`
    names them."""
    return _numbered(t for t in model.terms if isinstance(t, DynamicThermalTerm))


def _numbered(terms: Iterable[DynamicThermalTerm]) -> tuple[LiveLag, ...]:
    out: list[LiveLag] = []
    for term in terms:
        for c in term.columns:
            if c.kind == "lag":
                column = f"T_{LAG_SENSOR.format(len(out) + 1)}_C"
                out.append(LiveLag(column, c.sensor, c.tau_s))
    return tuple(out)


def live_model(model: MachineModel) -> MachineModel:
    """``model`` with its dynamic thermal terms as drift records and a constant (module
    docstring); a model without them is returned as it is."""
    if not any(isinstance(t, DynamicThermalTerm) for t in model.terms):
        return model
    lags = iter(live_lags(model))
    terms: list[Term] = []
    for term in model.terms:
        if not isinstance(term, DynamicThermalTerm):
            terms.append(term)
            continue
        constant = term.intercept_um
        for c in term.columns:
            if c.kind == "time":
                held = term.t_state_s if term.t_state_s is not None else term.t0_s
                constant += c.coefficient * (held - term.t0_s) / 3600.0
                continue
            sensor = c.sensor if c.kind == "level" else next(lags).column
            ref = c.input_C if c.input_C is not None else REFERENCE_C
            terms.append(ThermalTerm("thermal_drift", term.axis, sensor, c.coefficient, ref))
            constant += c.coefficient * ref
        # a dynamic term without columns is its constant at any temperatures
        terms.append(DynamicThermalTerm(term.axis, constant, (), term.t0_s, term.t_state_s))
    return MachineModel(model.machine, model.geometry, tuple(terms), model.info)


@dataclass(frozen=True)
class LiveNeeds:
    """What the live form of a stored model needs, read from its JSON terms.

    Attributes
    ----------
    records : frozenset of str
        The columns of its thermal records (sensors, and lag states as ``T_lag1_C``).
    inputs : frozenset of str
        The columns the center must receive: the records' real sensors and every lag's.
    lags : tuple of LiveLag
    """

    records: frozenset[str]
    inputs: frozenset[str]
    lags: tuple[LiveLag, ...]


def plain_thermal_sensors(terms: Sequence[Any]) -> frozenset[str]:
    """The sensors of a model's JSON ``terms`` that are plain thermal records
    (``thermal_expansion``, ``thermal_drift``), read without judging the other terms."""
    return frozenset(str(t["sensor"]) for t in terms if isinstance(t, Mapping)
                     and t.get("effect") in ("thermal_expansion", "thermal_drift")
                     and "sensor" in t)


def live_needs(terms: Sequence[Any]) -> LiveNeeds:
    """:class:`LiveNeeds` of a model's JSON ``terms`` (without reading its geometry).

    Raises
    ------
    ComponentErrorSpecError, KeyError, TypeError, ValueError
        A dynamic term that cannot be read.
    """
    plain = plain_thermal_sensors(terms)
    dynamic = tuple(DynamicThermalTerm.from_json(t) for t in terms
                    if isinstance(t, Mapping) and t.get("effect") == "thermal_dynamic")
    lags = _numbered(dynamic)
    levels = {c.sensor for d in dynamic for c in d.columns if c.kind == "level"}
    records = frozenset(plain | levels | {lag.column for lag in lags})
    return LiveNeeds(records, frozenset(plain | levels | {lag.source for lag in lags}),
                     lags)


__all__ = ["LAG_SENSOR", "LiveLag", "LiveNeeds", "live_lags", "live_model", "live_needs",
           "plain_thermal_sensors"]
