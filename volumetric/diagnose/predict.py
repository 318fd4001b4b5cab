"""A saved model applied to readings it was not fitted on (``ednc predict``).

Every term of the model predicts: the rigid geometry (exact volumetric error, projected on
each reading's sensing direction, or the orientation error for angles), the constant
tool-tip offsets the fit found (``info["offsets_um"]``), and the extension terms along
their axis's direction, as the diagnosis fitted them: a thermal term at each reading's
temperature, a dynamic thermal term over the readings' time series (its lags continue the
saved state when the series follows the fitted one), a ballscrew period at the position,
a backlash by the approach direction. Nothing is refitted and no offset is removed: the
residual is what the machine would show with the model applied.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from volumetric.identify.design import axis_positions, branch_rows
from volumetric.measure.measurement import Measurements
from volumetric.model.exact import volumetric_error
from volumetric.model.machine import Machine
from volumetric.model.model import (
    BacklashTerm,
    DynamicThermalTerm,
    MachineModel,
    PeriodicTerm,
    ThermalTerm,
)

F64 = NDArray[np.float64]


class PredictionError(ValueError):
    """The model cannot be applied to these readings; the message says why."""


@dataclass(frozen=True)
class Prediction:
    """Residuals of a model applied to readings.

    Attributes
    ----------
    rigid, full : ndarray, shape (N,)
        Prediction of the rigid part (geometry and offsets) and of the whole model, in
        the readings' units (µm, µrad).
    residual, residual_rigid : ndarray, shape (N,)
        Reading minus prediction.
    """

    rigid: F64
    full: F64
    residual: F64
    residual_rigid: F64
    m: Measurements = field(repr=False)

    def to_json(self) -> dict[str, Any]:
        disp = ~self.m.is_angle
        tests = []
        for label in dict.fromkeys(self.m.test[disp].tolist()):
            rows = disp & (self.m.test == label)
            tests.append({"test": label, "n_readings": int(rows.sum()),
                          "rms_um": _rms(self.residual[rows]),
                          "rms_rigid_um": _rms(self.residual_rigid[rows]),
                          "max_abs_um": float(np.abs(self.residual[rows]).max())})
        return {"rms_um": _rms(self.residual[disp]),
                "rms_rigid_um": _rms(self.residual_rigid[disp]),
                "max_abs_um": float(np.abs(self.residual[disp]).max()) if disp.any() else None,
                "n_readings": int(disp.sum()), "tests": tests}


def _rms(r: F64) -> float:
    return float(np.sqrt(np.mean(r * r))) if r.size else math.nan


def predict(machine: Machine, model: MachineModel, m: Measurements) -> Prediction:
    """Apply ``model`` to the readings ``m`` (module docstring).

    Raises
    ------
    PredictionError
        A temperature column the model needs is missing, or no displacement readings.
    """
    if not (~m.is_angle).any():
        raise PredictionError("no displacement readings to judge the model on")
    have = {m.temperature_columns[s]: v for s, v in m.temperatures.items()}
    missing = [s for s in model.sensors if s not in have]
    if missing:
        raise PredictionError(f"the model needs temperature columns {missing}; the readings "
                              f"have {sorted(have)}")
    q = axis_positions(machine, m)
    rigid = np.zeros(len(m))
    periodic = MachineModel(model.machine, model.geometry,
                            tuple(t for t in model.terms if isinstance(t, PeriodicTerm)))
    extended = np.zeros(len(m))
    offsets = dict(model.info.get("offsets_um", {}) or {})
    try:
        rows_of = branch_rows(machine, m)
    except ValueError as exc:
        raise PredictionError(str(exc)) from None
    for bname, rows in rows_of.items():
        if rows.size == 0:
            continue
        for geometry, out in ((model.geometry, rigid), (periodic.geometry_at({}), extended)):
            ve = volumetric_error(machine, geometry, q[rows], spindle=bname,
                                  tool_mm=m.tool_mm[rows])
            u = m.u[rows]
            pos = np.einsum("ni,ni->n", u, ve.position_um)
            ang = (np.einsum("ni,ni->n", u, ve.orientation_urad)
                   if ve.orientation_urad is not None else np.zeros(rows.size))
            out[rows] = np.where(m.is_angle[rows], ang, pos)
        for i, c in enumerate("XYZ"):
            name = f"OFFSET_{c}" if len(machine.branches) == 1 else f"OFFSET_{c}_{bname}"
            off = float(offsets.get(name, 0.0))
            shift = np.where(m.is_angle[rows], 0.0, m.u[rows, i] * off)
            rigid[rows] += shift
            extended[rows] += shift
    extended += _axis_terms(machine, model, m, q, have)
    return Prediction(rigid, extended, m.value - extended, m.value - rigid, m)


def _axis_terms(machine: Machine, model: MachineModel, m: Measurements, q: F64,
                temps: dict[str, F64]) -> F64:
    """The non-geometric terms, each a displacement along its axis (µm), projected."""
    out = np.zeros(len(m))
    order = np.argsort(m.time_s, kind="stable")
    for t in model.terms:
        if isinstance(t, PeriodicTerm):
            continue  # folded into the geometry
        k = "xyz".index(t.axis)
        uk = np.where(m.is_angle, 0.0, m.u[:, k])
        if isinstance(t, ThermalTerm):
            dt = temps[t.sensor] - t.t_ref_C
            if t.kind == "thermal_drift":
                along = t.coefficient * dt
            else:
                j = machine.axis_names.index(machine.axis(t.axis).name)
                along = t.coefficient * dt * (q[:, j] - t.q_min) * 1e-3
        elif isinstance(t, BacklashTerm):
            along = -0.5 * t.reversal_um * m.direction[:, k].astype(float)
        elif isinstance(t, DynamicThermalTerm):
            sorted_series = t.series(m.time_s[order], {s: v[order] for s, v in temps.items()})
            along = np.empty(len(m))
            along[order] = sorted_series
        else:  # pragma: no cover - the union is closed
            raise PredictionError(f"unknown term {t!r}")
        out += uk * along
    return out
