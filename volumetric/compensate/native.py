"""Compensation in controllers' native formats, for machines without our endpoint.

* Siemens CEC tables: :mod:`volumetric.compensate.cec` (what the tables are and how the
  control combines them), :mod:`~volumetric.compensate.cec_plan` (the model's errors in
  the shapes CEC holds), :mod:`~volumetric.compensate.cec_select` (which tables within a
  control's limits), :mod:`~volumetric.compensate.cec_check` (the tool-tip error before
  and after), :mod:`~volumetric.compensate.cec_text` (the file);
* ISO 230-1 component tables: :mod:`volumetric.compensate.iso230_1`.

:func:`model_geometry` gives what both export: the model's geometry with its periodic
terms folded in, and the terms neither carries as geometry named.
"""

from __future__ import annotations

from collections.abc import Mapping

from volumetric.model.components import GeometricErrors, Sinusoid, add_components
from volumetric.model.machine import Machine
from volumetric.model.model import (
    BacklashTerm,
    DynamicThermalTerm,
    MachineModel,
    PeriodicTerm,
    ThermalTerm,
)


def model_geometry(model: MachineModel, temperatures: Mapping[str, float] | None,
                   machine: Machine | None = None
                   ) -> tuple[GeometricErrors, dict[str, float], list[tuple[str, str]]]:
    """The geometry to export, the backlash per axis (``X`` → µm) and the thermal terms
    left to the temperature path (name, what it does).

    Periodic terms fold into the axis's positioning error. Thermal terms fold in at the
    given temperatures when there are any (the tables then hold that state only), else
    they are named: a static table cannot follow the temperatures, with what 1 K moves
    the tool by (the expansion over the axis's travel, given ``machine``).
    """
    if temperatures:
        geo = model.geometry_at(temperatures)
        thermal: list[tuple[str, str]] = []
    else:
        comps = dict(model.geometry.components)
        for t in model.terms:
            if isinstance(t, PeriodicTerm):
                name = f"E{t.axis.upper()}{t.axis.upper()}"
                comps[name] = add_components(comps.get(name),
                                             Sinusoid(t.amplitude_um, t.period_mm,
                                                      t.phase_rad))
        geo = GeometricErrors(comps, dict(model.geometry.locations))
        thermal = []
        for t in model.terms:
            if isinstance(t, ThermalTerm):
                unit = "µm/K" if t.kind == "thermal_drift" else "µm/(m·K)"
                per_k = abs(t.coefficient)
                if t.kind == "thermal_expansion" and machine is not None:
                    lo, hi = machine.axis(t.axis).travel
                    per_k = abs(t.coefficient) * max(abs(hi - t.q_min), abs(lo - t.q_min)) / 1e3
                thermal.append((f"{t.kind} {t.axis} ({t.sensor})",
                                f"{t.coefficient:g} {unit} from {t.t_ref_C:g} °C, up to "
                                f"{per_k:.3g} µm per K at the tool tip"))
            elif isinstance(t, DynamicThermalTerm):
                sens = ", ".join(f"{s} {v:g} µm/K" for s, v in t.steady_um_per_K().items())
                thermal.append((f"thermal_dynamic {t.axis}", sens or "time column only"))
    backlash = {t.axis.upper(): t.reversal_um for t in model.terms
                if isinstance(t, BacklashTerm)}
    return geo, backlash, thermal


__all__ = ["model_geometry"]
