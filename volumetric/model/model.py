"""What the center knows of one machine: its rigid geometry plus physical extension terms.

A :class:`MachineModel` is what ``ednc fit`` writes, what ``ednc diagnose`` extends and
what the server turns into error maps. Extension terms (:mod:`formats.md` section 3 effect
names) fold into the geometry at given temperatures:

* ``thermal_expansion``: ``ΔE_KK = α·(T − T_ref)·(q − q_min)`` on axis K's positioning,
  α in µm/(m·K);
* ``thermal_drift``: ``ΔE_KK = k·(T − T_ref)``, a position-independent drift along K, µm/K;
* ``periodic``: ``ΔE_KK = a·sin(2π q / p + φ)``;
* ``backlash``: a reversal B (µm) of axis K: the tool lags by B/2 behind the direction of
  the last motion. It cannot fold into a direction-free geometry; error maps carry it per
  axis so that the controller applies it by direction;
* ``thermal_dynamic``: a drift along K that follows the temperatures' history,
  ``ΔE_KK = c + Σ_j b_j·x_j(t)`` with ``x_j`` a sensor's level, its first-order lag of
  time constant τ_j (``τ dx/dt = T − x``) or the time since ``t0_s`` in hours
  (:class:`DynamicThermalTerm`). Over a time series (``ednc predict``) the lags run from
  the state saved at the end of the fitted readings when the series continues them, else
  from rest at the first reading; at one set of temperatures (``ednc map``, ``ednc
  compensate --temperature``) every lag is taken at its steady state, the temperature
  itself. The center's maps apply it live instead: records on lag states it follows
  from the machine's readings and sends as temperatures (:mod:`volumetric.model.live`).

``info["offsets_um"]``, when present, holds the constant tool-tip offsets the fit found
(``OFFSET_X`` ...: the readings' zero); ``ednc predict`` adds them, since a prediction is
judged as it would be applied.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from volumetric.errors import ComponentErrorSpecError
from volumetric.model.components import (
    Component,
    GeometricErrors,
    Polynomial,
    Sinusoid,
    add_components,
)
from volumetric.model.lag import first_order_lag

FORMAT = "ednc-model/1"


@dataclass(frozen=True)
class ThermalTerm:
    """A temperature-driven positioning error of one axis.

    Attributes
    ----------
    kind : {"thermal_expansion", "thermal_drift"}
    axis : str
        ``"x"``, ``"y"``, ``"z"`` (lower case, as in formats.md).
    sensor : str
        The temperature column, e.g. ``"T_spindle_C"``.
    coefficient : float
        µm/(m·K) for expansion, µm/K for drift.
    t_ref_C : float
        Temperature at which the term is zero, °C.
    q_min : float
        Expansion reference position, mm (the axis's lower travel).
    """

    kind: Literal["thermal_expansion", "thermal_drift"]
    axis: str
    sensor: str
    coefficient: float
    t_ref_C: float
    q_min: float = 0.0

    def component(self, temperature_C: float) -> Polynomial:
        dt = temperature_C - self.t_ref_C
        if self.kind == "thermal_drift":
            return Polynomial((self.coefficient * dt,))
        # α [µm/(m·K)] · ΔT [K] · (q − q_min) [mm] · 1e-3 [m/mm]
        slope = self.coefficient * dt * 1e-3
        return Polynomial((-slope * self.q_min, slope))


@dataclass(frozen=True)
class PeriodicTerm:
    """A cyclic positioning error of one axis (ballscrew pitch)."""

    axis: str
    amplitude_um: float
    period_mm: float
    phase_rad: float = 0.0


@dataclass(frozen=True)
class BacklashTerm:
    """The reversal of one axis, µm (positive)."""

    axis: str
    reversal_um: float


@dataclass(frozen=True)
class LagColumn:
    """One regressor of a :class:`DynamicThermalTerm`.

    Attributes
    ----------
    kind : {"level", "lag", "time"}
    sensor : str
        Temperature column (``T_t1_C``); empty for ``time``.
    tau_s : float
        Time constant of a ``lag``, s (0 otherwise).
    coefficient : float
        µm/K (level, lag) or µm/h (time).
    std : float
        Its standard uncertainty, same unit.
    state_C : float or None
        The lag's state at ``DynamicThermalTerm.t_state_s`` (°C), to continue the series.
    input_C : float or None
        The sensor's temperature at that time (°C): the lag's input is interpolated
        linearly from it to the next reading.
    """

    kind: Literal["level", "lag", "time"]
    sensor: str
    tau_s: float
    coefficient: float
    std: float = 0.0
    state_C: float | None = None
    input_C: float | None = None

    def to_json(self) -> dict[str, Any]:
        return {"kind": self.kind, "sensor": self.sensor, "tau_s": self.tau_s,
                "coefficient": self.coefficient, "std": self.std, "state_C": self.state_C,
                "input_C": self.input_C}


@dataclass(frozen=True)
class DynamicThermalTerm:
    """A drift along one axis that follows the temperatures' history (module docstring).

    Attributes
    ----------
    axis : str
        ``"x"``, ``"y"`` or ``"z"``.
    intercept_um : float
        Constant c, µm.
    columns : tuple of LagColumn
    t0_s : float
        Origin of the time column, s.
    t_state_s : float or None
        Time (s) of the last fitted reading, at which the lag states were saved.
    """

    axis: str
    intercept_um: float
    columns: tuple[LagColumn, ...]
    t0_s: float = 0.0
    t_state_s: float | None = None

    @property
    def sensors(self) -> tuple[str, ...]:
        return tuple(sorted({c.sensor for c in self.columns if c.kind != "time"}))

    def series(self, t_s: NDArray[np.float64], temps: Mapping[str, NDArray[np.float64]]
               ) -> NDArray[np.float64]:
        """The drift (µm) over a time series.

        Parameters
        ----------
        t_s : ndarray, shape (N,)
            Non-decreasing times, s.
        temps : mapping of str to ndarray, shape (N,)
            Temperatures, °C; must hold every sensor of the term.

        Returns
        -------
        ndarray, shape (N,)
        """
        t = np.asarray(t_s, dtype=float)
        out = np.full(t.shape, self.intercept_um)
        cont = (self.t_state_s is not None and t.size > 0 and t[0] >= self.t_state_s)
        for c in self.columns:
            if c.kind == "time":
                out += c.coefficient * (t - self.t0_s) / 3600.0
                continue
            x = np.asarray(temps[c.sensor], dtype=float)
            if c.kind == "level":
                out += c.coefficient * x
            elif cont and c.state_C is not None and c.input_C is not None:
                assert self.t_state_s is not None
                # continue the fitted series: the lag relaxes from its saved state
                tt = np.concatenate(([self.t_state_s], t))
                xx = np.concatenate(([c.input_C], x))
                out += c.coefficient * first_order_lag(tt, xx, c.tau_s, x0=c.state_C)[1:]
            else:
                # no history: the structure starts in equilibrium with the first reading
                out += c.coefficient * first_order_lag(t, x, c.tau_s)
        return out

    def steady_um(self, temperatures: Mapping[str, float]) -> float:
        """The drift (µm) with every lag at its steady state (the temperature itself) and
        the time column at the saved state's time."""
        v = self.intercept_um
        for c in self.columns:
            if c.kind == "time":
                t = self.t_state_s if self.t_state_s is not None else self.t0_s
                v += c.coefficient * (t - self.t0_s) / 3600.0
            else:
                v += c.coefficient * float(temperatures[c.sensor])
        return v

    def steady_um_per_K(self) -> dict[str, float]:
        """What each sensor 1 K warmer moves :meth:`steady_um` by (µm/K): the sum of its
        level and lag coefficients, by sensor in column order."""
        out: dict[str, float] = {}
        for c in self.columns:
            if c.kind != "time":
                out[c.sensor] = out.get(c.sensor, 0.0) + c.coefficient
        return out

    def to_json(self) -> dict[str, Any]:
        return {"effect": "thermal_dynamic", "axis": self.axis,
                "intercept_um": self.intercept_um, "t0_s": self.t0_s,
                "t_state_s": self.t_state_s, "columns": [c.to_json() for c in self.columns]}

    @staticmethod
    def from_json(t: Mapping[str, Any]) -> DynamicThermalTerm:
        cols = []
        for c in t["columns"]:
            kind = str(c["kind"])
            if kind not in ("level", "lag", "time"):
                raise ComponentErrorSpecError(f"column kind {kind!r} is not level, lag or time")
            tau = float(c.get("tau_s", 0.0))
            if kind == "lag" and not (math.isfinite(tau) and tau > 0):
                raise ComponentErrorSpecError(f"a lag needs a positive tau_s, got {tau!r}")
            cols.append(LagColumn(
                kind, str(c.get("sensor", "")), tau,  # type: ignore[arg-type]
                float(c["coefficient"]), float(c.get("std", 0.0)),
                None if c.get("state_C") is None else float(c["state_C"]),
                None if c.get("input_C") is None else float(c["input_C"])))
        ts = t.get("t_state_s")
        return DynamicThermalTerm(str(t["axis"]), float(t.get("intercept_um", 0.0)),
                                  tuple(cols), float(t.get("t0_s", 0.0)),
                                  None if ts is None else float(ts))


Term = ThermalTerm | PeriodicTerm | BacklashTerm | DynamicThermalTerm


@dataclass(frozen=True)
class MachineModel:
    """A machine's identified model.

    Attributes
    ----------
    machine : str
        The machine's name.
    geometry : GeometricErrors
        The rigid-body component and location errors.
    terms : tuple of Term
        Extensions found by the diagnosis.
    info : mapping
        Fit statistics: degrees chosen, uncertainties, unidentifiable parameters, RMS.
    """

    machine: str
    geometry: GeometricErrors
    terms: tuple[Term, ...] = ()
    info: Mapping[str, Any] = field(default_factory=dict)

    @property
    def sensors(self) -> tuple[str, ...]:
        """Temperature columns the model needs."""
        out = {t.sensor for t in self.terms if isinstance(t, ThermalTerm)}
        for t in self.terms:
            if isinstance(t, DynamicThermalTerm):
                out.update(t.sensors)
        return tuple(sorted(out))

    def geometry_at(self, temperatures: Mapping[str, float] | None = None) -> GeometricErrors:
        """The geometry with thermal and periodic terms folded in.

        Raises
        ------
        ValueError
            When a thermal term's sensor has no temperature.
        """
        temps = dict(temperatures or {})
        missing = [s for s in self.sensors if s not in temps]
        if missing:
            raise ValueError(f"the model needs temperatures of {missing}; have {sorted(temps)}")
        comps: dict[str, Component] = dict(self.geometry.components)
        for t in self.terms:
            name = f"E{t.axis.upper()}{t.axis.upper()}"
            if isinstance(t, ThermalTerm):
                comps[name] = add_components(comps.get(name), t.component(temps[t.sensor]))
            elif isinstance(t, PeriodicTerm):
                comps[name] = add_components(
                    comps.get(name), Sinusoid(t.amplitude_um, t.period_mm, t.phase_rad)
                )
            elif isinstance(t, DynamicThermalTerm):
                comps[name] = add_components(comps.get(name),
                                             Polynomial((t.steady_um(temps),)))
        return GeometricErrors(comps, dict(self.geometry.locations))

    def reversal_um(self) -> dict[str, float]:
        """Backlash per axis (lower-case axis name → µm)."""
        return {t.axis: t.reversal_um for t in self.terms if isinstance(t, BacklashTerm)}

    def with_terms(self, *terms: Term) -> MachineModel:
        return MachineModel(self.machine, self.geometry, (*self.terms, *terms), self.info)

    def to_json(self) -> dict[str, Any]:
        terms: list[dict[str, Any]] = []
        for t in self.terms:
            if isinstance(t, ThermalTerm):
                terms.append({"effect": t.kind, "axis": t.axis, "sensor": t.sensor,
                              "coefficient": t.coefficient, "t_ref_C": t.t_ref_C,
                              "q_min": t.q_min})
            elif isinstance(t, PeriodicTerm):
                terms.append({"effect": "periodic", "axis": t.axis,
                              "amplitude_um": t.amplitude_um, "period_mm": t.period_mm,
                              "phase_rad": t.phase_rad})
            elif isinstance(t, DynamicThermalTerm):
                terms.append(t.to_json())
            else:
                terms.append({"effect": "backlash", "axis": t.axis,
                              "reversal_um": t.reversal_um})
        return {"format": FORMAT, "machine": self.machine, **self.geometry.to_json(),
                "terms": terms, "info": dict(self.info)}

    @staticmethod
    def from_json(data: Mapping[str, Any]) -> MachineModel:
        """Inverse of :meth:`to_json`; errors name the entry."""
        if not isinstance(data, Mapping):
            raise ComponentErrorSpecError("a model must be a JSON object")
        geometry = GeometricErrors.from_json(data)
        terms: list[Term] = []
        raw_terms = data.get("terms", [])
        if not isinstance(raw_terms, list):
            raise ComponentErrorSpecError("terms: expected a list")
        info = data.get("info", {})
        if not isinstance(info, Mapping):
            raise ComponentErrorSpecError("info: expected an object")
        for i, t in enumerate(raw_terms):
            if not isinstance(t, Mapping):
                raise ComponentErrorSpecError(f"terms[{i}]: expected an object")
            try:
                effect = t["effect"]
                if effect in ("thermal_expansion", "thermal_drift"):
                    terms.append(ThermalTerm(effect, str(t["axis"]), str(t["sensor"]),
                                             float(t["coefficient"]), float(t["t_ref_C"]),
                                             float(t.get("q_min", 0.0))))
                elif effect == "periodic":
                    terms.append(PeriodicTerm(str(t["axis"]), float(t["amplitude_um"]),
                                              float(t["period_mm"]),
                                              float(t.get("phase_rad", 0.0))))
                elif effect == "backlash":
                    terms.append(BacklashTerm(str(t["axis"]), float(t["reversal_um"])))
                elif effect == "thermal_dynamic":
                    terms.append(DynamicThermalTerm.from_json(t))
                else:
                    raise ComponentErrorSpecError(f"terms[{i}]: unknown effect {effect!r}")
            except (KeyError, TypeError, ValueError) as exc:
                if isinstance(exc, ComponentErrorSpecError):
                    raise
                raise ComponentErrorSpecError(f"terms[{i}]: {exc!r}") from None
        return MachineModel(str(data.get("machine", "")), geometry, tuple(terms), dict(info))
