"""What CEC tables leave at the tool tip: the model's error before and after them.

The tables are applied by the control's rules (:func:`volumetric.compensate.cec.apply_tables`)
at random commanded positions over the travel with random traversing directions; the
after-error is the model's *exact* tool-tip error at the corrected command against the
nominal tool tip at the commanded one (:func:`volumetric.model.kinematics.tool_pose`), so
it holds the second-order terms the first-order tables ignore. Backlash adds ``∓B/2``
along its axis by the approach direction (to first order, through the model's own
sensitivity of the axis's positioning error).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from volumetric.compensate.cec import CecExport, apply_tables
from volumetric.compensate.cec_plan import DEG_PER_URAD, correction_sensitivity, sample_points
from volumetric.model.components import GeometricErrors
from volumetric.model.kinematics import tool_pose
from volumetric.model.machine import Machine

F64 = NDArray[np.float64]
POINTS = 4000
LONGER_MM = 100.0


@dataclass(frozen=True)
class ToolTip:
    """Tool-tip error figures, µm (norm of the 3-D position error per point).

    Attributes
    ----------
    worst_before_um, rms_before_um : float
        The model's error without the tables.
    worst_after_um, rms_after_um : float
        With the tables applied as the control applies them.
    worst_after_lec_um, rms_after_lec_um : float or None
        With the positioning errors left to the leadscrew tables compensated there too
        (only when the export left them out).
    points : int
    tool_mm : float
    """

    worst_before_um: float
    rms_before_um: float
    worst_after_um: float
    rms_after_um: float
    worst_after_lec_um: float | None
    rms_after_lec_um: float | None
    points: int
    tool_mm: float
    max_total: Mapping[str, float]
    """Largest total correction per output axis over the points, mm or degrees."""
    worst_after_longer_tool_um: float = 0.0
    """With the same tables and a tool :data:`LONGER_MM` longer: the Abbe arms of the
    tool-side angles grow, the tables do not follow."""
    rms_after_longer_tool_um: float = 0.0
    worst_before_zeroed_um: float = 0.0
    """The worst with each axis's mean error removed (what the workpiece zero absorbs),
    before and after."""
    worst_after_zeroed_um: float = 0.0

    def to_json(self) -> dict[str, object]:
        out: dict[str, object] = {k: (round(v, 4) if isinstance(v, float) else v)
                                  for k, v in self.__dict__.items() if k != "max_total"}
        out["max_total"] = {k: round(v, 6) for k, v in self.max_total.items()}
        return out


def tool_tip_error(machine: Machine, geometry: GeometricErrors, q: F64, dq: F64,
                   tool_mm: float, backlash_um: Mapping[str, float] | None = None,
                   direction: F64 | None = None) -> F64:
    """Exact tool-tip error (N, 3) µm at command ``q + dq`` against nominal at ``q``, plus
    the backlash of each axis by its ``direction`` (N, n_axes)."""
    p, _ = tool_pose(machine, q + dq, geometry, tool_mm=tool_mm, orientation=False)
    p0, _ = tool_pose(machine, q, None, tool_mm=tool_mm, orientation=False)
    err: F64 = (p - p0) * 1e3
    if backlash_um and direction is not None:
        sens, _ = correction_sensitivity(machine, q, tool_mm)
        for k, b in backlash_um.items():
            name = f"E{k.upper()}{k.upper()}"
            i = machine.axis_names.index(k.upper())
            if name in sens:
                err = err + sens[name][1] * (-direction[:, i] * b / 2)[:, None]
    return err


def _zeroed(e: F64) -> float:
    """Worst norm with the per-axis mean removed, µm."""
    return float(np.linalg.norm(e - e.mean(axis=0), axis=1).max())


def _norms(e: F64) -> tuple[float, float]:
    n = np.linalg.norm(e, axis=1)
    return float(n.max()), float(np.sqrt(np.mean(n * n)))


def tool_tip(machine: Machine, geometry: GeometricErrors, export: CecExport, *,
             n: int = POINTS, seed: int = 26) -> ToolTip:
    """The figures of :class:`ToolTip` for an export of ``geometry``."""
    q = sample_points(machine, n, seed)
    rng = np.random.default_rng(seed + 1)
    direction = rng.choice([-1.0, 1.0], size=q.shape)
    bl = dict(export.backlash_um)
    before = tool_tip_error(machine, geometry, q, np.zeros_like(q), export.tool_mm, bl,
                            direction)
    dq = apply_tables(export, machine, q, direction)
    after = tool_tip_error(machine, geometry, q, dq, export.tool_mm, bl, direction)
    wb, rb = _norms(before)
    wa, ra = _norms(after)
    wl = rl = None
    if not export.positioning:
        lec = np.zeros_like(q)
        for i, a in enumerate(machine.axes):
            f = geometry.components.get(f"E{a.name}{a.name}")
            if f is not None:
                v = np.asarray(f(q[:, i]), dtype=float)
                lec[:, i] = -v * (1e-3 if a.kind == "linear" else DEG_PER_URAD)
        wl, rl = _norms(tool_tip_error(machine, geometry, q, dq + lec, export.tool_mm, bl,
                                       direction))
    totals = {a.name: float(np.abs(dq[:, i]).max()) for i, a in enumerate(machine.axes)
              if any(t.output == a.name for t in export.tables)}
    wt, rt = _norms(tool_tip_error(machine, geometry, q, dq, export.tool_mm + LONGER_MM, bl,
                                   direction))
    return ToolTip(wb, rb, wa, ra, wl, rl, n, export.tool_mm, totals, wt, rt,
                   _zeroed(before), _zeroed(after))


__all__ = ["LONGER_MM", "POINTS", "ToolTip", "tool_tip", "tool_tip_error"]
