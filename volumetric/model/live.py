"""A model as a machine applies it live: the lag states of its thermal history as sensors.

A :class:`~volumetric.model.model.DynamicThermalTerm` (what ``ednc diagnose`` saves when a
lagged thermal model is behind its figure) follows the temperatures' history. A
controller applies thermal records, ``k·(T − T_ref)`` per sensor, to the temperatures it
is sent, and keeps no history. So the center keeps it: it follows each lag state from
the readings of its sensors (:func:`volumetric.model.lag.lag_step`, the recursion
:func:`~volumetric.model.lag.first_order_lag` runs over a series) and sends it to the
machine as the temperature of a sensor of its own, ``lag1``, ``lag2``, ... (column
``T_lag1_C`` ...), numbered over the model's dynamic terms in order.

The lag is linear, so the lags of one time constant over several sensors are one lag of
their weighted sum: ``Σ_s b_s lag_τ(T_s) = k·lag_τ(Σ_s w_s T_s)`` with ``w_s = b_s/k``,
``k = Σ_s |b_s|`` (from the same states at rest or saved). A model that averages every
sensor's lags at five time constants (sixteen sensors: 80 lag columns) is thus five
records, not eighty, within what a map carries (:data:`protocol.mapformat.MAX_THERMAL`).
The state sent is ``T_REF + Σ_s w_s (y_s − T_REF)``, with ``y_s`` the lag of sensor s
and ``T_REF`` 20 °C: a temperature within the range of its sensors' lags whatever the
signs of the weights, so it passes as a temperature anywhere one is checked, and a
single sensor's lag is sent as it is (``w = 1``). :func:`live_model` is the model with
every dynamic term written that way:

* ``level`` columns of sensor s: one drift record on s (their coefficients summed);
* ``lag`` columns of one time constant: one drift record on its lag sensor;
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
    """One lag state the center follows for a machine: the lag of one sensor, or of a
    weighted sum of several (module docstring).

    Attributes
    ----------
    column : str
        The column it is sent as, ``T_lag1_C``.
    weights : tuple of (str, float)
        The temperature columns it follows and their weights ``w_s`` (``Σ |w_s| = 1``;
        one sensor: ``(("T_t4_C", 1.0),)``).
    tau_s : float
        Its time constant, s.
    """

    column: str
    weights: tuple[tuple[str, float], ...]
    tau_s: float

    @property
    def sources(self) -> tuple[str, ...]:
        """The temperature columns it follows."""
        return tuple(s for s, _ in self.weights)

    def state(self, lags: Mapping[str, float]) -> float:
        """The value sent, °C, from each source's own lag state ``lags[s]`` (°C, at the
        time constant ``tau_s``): ``T_REF + Σ w_s (y_s − T_REF)``."""
        if len(self.weights) == 1:
            return float(lags[self.weights[0][0]])  # sent as it is, not re-rounded
        return REFERENCE_C + sum(w * (float(lags[s]) - REFERENCE_C) for s, w in self.weights)


def _lag_groups(term: DynamicThermalTerm) -> list[tuple[float, dict[str, float]]]:
    """The term's lag columns by time constant (in order of first appearance), each as
    sensor -> summed coefficient (µm/K); sensors of zero coefficient left out (the center
    would wait for their readings for nothing), and groups left empty."""
    groups: dict[float, dict[str, float]] = {}
    for c in term.columns:
        if c.kind == "lag":
            by_sensor = groups.setdefault(c.tau_s, {})
            by_sensor[c.sensor] = by_sensor.get(c.sensor, 0.0) + c.coefficient
    kept = [(tau, {s: v for s, v in b.items() if v != 0.0}) for tau, b in groups.items()]
    return [(tau, b) for tau, b in kept if b]


def _live_lags(terms: Iterable[DynamicThermalTerm]
               ) -> list[tuple[DynamicThermalTerm, list[tuple[LiveLag, float]]]]:
    """Each term with its lag states numbered over all of them and the gain ``k`` (µm/K)
    of each state's record."""
    out: list[tuple[DynamicThermalTerm, list[tuple[LiveLag, float]]]] = []
    n = 0
    for term in terms:
        lags = []
        for tau, b in _lag_groups(term):
            n += 1
            column = f"T_{LAG_SENSOR.format(n)}_C"
            if len(b) == 1:
                ((sensor, k),) = b.items()
                lags.append((LiveLag(column, ((sensor, 1.0),), tau), k))
                continue
            k = sum(abs(v) for v in b.values())
            lags.append((LiveLag(column, tuple((s, v / k) for s, v in b.items()), tau), k))
        out.append((term, lags))
    return out


def live_lags(model: MachineModel) -> tuple[LiveLag, ...]:
    """The lag states of ``model``'s dynamic thermal terms, numbered as :func:`live_model`
    names them."""
    return _numbered(t for t in model.terms if isinstance(t, DynamicThermalTerm))


def _numbered(terms: Iterable[DynamicThermalTerm]) -> tuple[LiveLag, ...]:
    return tuple(lag for _, lags in _live_lags(terms) for lag, _ in lags)


def _saved_state(term: DynamicThermalTerm, lag: LiveLag) -> float:
    """The lag state sent as ``lag`` would have been when the term was saved (°C): the
    record's reference, at which a machine that has no value for it leaves it."""
    states = {}
    for c in term.columns:
        if c.kind == "lag" and c.tau_s == lag.tau_s:
            known = c.state_C if c.state_C is not None else c.input_C
            states[c.sensor] = REFERENCE_C if known is None else known
    return lag.state(states)


def live_model(model: MachineModel) -> MachineModel:
    """``model`` with its dynamic thermal terms as drift records and a constant (module
    docstring); a model without them is returned as it is."""
    if not any(isinstance(t, DynamicThermalTerm) for t in model.terms):
        return model
    dynamic = iter(_live_lags(t for t in model.terms if isinstance(t, DynamicThermalTerm)))
    terms: list[Term] = []
    for term in model.terms:
        if not isinstance(term, DynamicThermalTerm):
            terms.append(term)
            continue
        _, lags = next(dynamic)
        constant = term.intercept_um
        levels: dict[str, tuple[float, float | None]] = {}  # sensor -> (coefficient, ref)
        for c in term.columns:
            if c.kind == "time":
                held = term.t_state_s if term.t_state_s is not None else term.t0_s
                constant += c.coefficient * (held - term.t0_s) / 3600.0
            elif c.kind == "level":
                k, ref = levels.get(c.sensor, (0.0, c.input_C))
                levels[c.sensor] = (k + c.coefficient, ref)
        for sensor, (k, ref) in levels.items():
            ref_c = REFERENCE_C if ref is None else ref
            terms.append(ThermalTerm("thermal_drift", term.axis, sensor, k, ref_c))
            constant += k * ref_c
        for lag, k in lags:
            ref_c = _saved_state(term, lag)
            terms.append(ThermalTerm("thermal_drift", term.axis, lag.column, k, ref_c))
            # Σ b_s y_s = k·Σ w_s y_s = k·(x − ref) + k·(ref − T_REF·(1 − Σ w_s)), x sent
            constant += k * (ref_c - REFERENCE_C * (1.0 - sum(w for _, w in lag.weights)))
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
    sources = {s for lag in lags for s in lag.sources}
    return LiveNeeds(records, frozenset(plain | levels | sources), lags)


__all__ = ["LAG_SENSOR", "LiveLag", "LiveNeeds", "live_lags", "live_model", "live_needs",
           "plain_thermal_sensors"]
