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
  axis so that the controller applies it by direction.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

from volumetric.errors import ComponentErrorSpecError
from volumetric.model.components import (
    Component,
    GeometricErrors,
    Polynomial,
    Sinusoid,
    add_components,
)

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


Term = ThermalTerm | PeriodicTerm | BacklashTerm


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
        return tuple(sorted({t.sensor for t in self.terms if isinstance(t, ThermalTerm)}))

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
                else:
                    raise ComponentErrorSpecError(f"terms[{i}]: unknown effect {effect!r}")
            except (KeyError, TypeError, ValueError) as exc:
                if isinstance(exc, ComponentErrorSpecError):
                    raise
                raise ComponentErrorSpecError(f"terms[{i}]: {exc!r}") from None
        return MachineModel(str(data.get("machine", "")), geometry, tuple(terms), dict(info))
