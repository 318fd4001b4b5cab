"""The demo's numeric loop: measure, identify, diagnose, map, verify, follow the heat.

For each machine of :func:`ednc.fleet.demo_fleet`: a simulated measurement campaign
(laser positioning, straightness, angular, diagonals), identification of its rigid model,
the diagnosis of what that model misses, the error map for its controller, and the ISO
230-6 body diagonals measured before and after the map is applied the way its PLC
applies it. Then the machine with a hidden spindle growth warms up, and its map follows
its temperatures.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from rich.console import Console
from rich.table import Table

from ednc.fleet import FleetMachine, demo_fleet
from machine_sim.campaign import map_compensation, run_campaign, standard_campaign
from machine_sim.instruments import SimulatedMachine
from machine_sim.lookup import TablesMap, active_map
from machine_sim.program import Dwell, Program, SpindleOn
from machine_sim.testprograms import diagonal_test
from machine_sim.truth import random_geometry
from protocol.maptables import decode_payload
from server.mapcodec import MapContent, build_for, encode, kind_of
from volumetric.compensate.solver import Weights, compensate
from volumetric.diagnose.diagnosis import Diagnosis, diagnose
from volumetric.identify.fit import fit
from volumetric.measure.measurement import Measurements
from volumetric.model.machine import Machine, parse_machine
from volumetric.model.model import MachineModel
from volumetric.verify.iso230_6 import diagonal_ranges

DIAGONALS = ("diag-PPP", "diag-NPP", "diag-PNP", "diag-PPN")


@dataclass
class MachineResult:
    name: str
    controller: str
    chain: str
    readings: int = 0
    fit_rms_um: float = 0.0
    effect: str = "none"
    map_kind: str = ""
    map_bytes: int = 0
    map_worst_um: float = 0.0
    before_um: float = float("nan")
    after_um: float = float("nan")
    notes: list[str] = field(default_factory=list)

    @property
    def improvement(self) -> float:
        return 1.0 - self.after_um / self.before_um


@dataclass
class Prepared:
    """A machine after the numeric loop: what the center would hold for it."""

    fleet: FleetMachine
    machine: Machine
    sim: SimulatedMachine
    model: MachineModel
    emap: MapContent
    result: MachineResult
    readings: Measurements
    diagnosis: Diagnosis


def prepare(fm: FleetMachine, console: Console) -> Prepared:
    """Measure, identify, diagnose, map and verify one machine."""
    m = parse_machine(fm.description)
    rng = np.random.default_rng(fm.seed)
    sim = SimulatedMachine(m, random_geometry(m, rng, scale=fm.scale), fm.effects, seed=fm.seed)
    res = MachineResult(m.name, m.controller, m.chain)
    t0 = time.perf_counter()
    readings = standard_campaign(sim, rng)
    res.readings = len(readings)
    hours = float(readings.time_s.max()) / 3600
    console.print(f"[bold]{m.name}[/] ({m.controller}, {m.chain}): measured {len(readings)} "
                  f"readings over {hours:.1f} h of simulated laser work")
    result = fit(m, readings)
    res.fit_rms_um = result.rms.get("displacement_um", float("nan"))
    console.print(f"  identified: {len(result.params)} parameters, residual "
                  f"{res.fit_rms_um:.2f} µm; {len(result.unidentifiable)} not identifiable "
                  "(named, fixed at 0)")
    d = diagnose(m, readings)
    model = d.model
    res.effect = "none" if d.effect == "none" else f"{d.effect} {d.axis} {d.sensor or ''}".strip()
    est = ", ".join(f"{k} {v:.3g}" for k, v in d.estimate.items() if isinstance(v, float)
                    and not k.endswith("_std"))
    console.print(f"  diagnosis: [cyan]{res.effect}[/] {est} (held-out RMS "
                  f"{d.rms_before_um:.2f} → {d.rms_after_um:.2f} µm)")
    temps = None
    if model.sensors:
        temps = {s: float(readings.temperatures[s[2:-2]].mean()) for s in model.sensors}
    # the kind its controller evaluates: tables for a Siemens-style endpoint, the smaller of
    # a factored map and a grid for a Fanuc-style PMC ladder
    emap = build_for(m, model, temps, tolerance_um=0.5, max_tolerance_um=4.0)
    assert emap.report is not None
    payload = encode(emap)
    res.map_kind, res.map_bytes = kind_of(emap), len(payload)
    res.map_worst_um = emap.report.worst_error_um
    console.print(f"  map: {res.map_kind}, {res.map_bytes:,d} bytes, worst tool-tip error "
                  f"{emap.report.worst_error_um:.2f} µm as the machine applies it "
                  f"({m.controller}, tolerance {emap.report.tolerance_um:g} µm)")
    if all(a in m.axis_names for a in "XYZ"):
        grid = active_map(decode_payload(payload), temps)  # the machine's own evaluation
        inc = 0.001 if m.controller == "fanuc" else None
        programs = [diagonal_test(m, g, points=20, runs=2) for g in DIAGONALS]
        before = diagonal_ranges(run_campaign(sim, programs).measurements)
        after = diagonal_ranges(run_campaign(
            sim, programs, compensation=map_compensation(m, grid, increment_mm=inc)
        ).measurements)
        res.before_um, res.after_um = max(before.values()), max(after.values())
        console.print(f"  ISO 230-6 diagonals: worst range {res.before_um:.1f} µm → "
                      f"{res.after_um:.2f} µm ([green]{100 * res.improvement:.0f} % better[/])")
    else:
        _shared_axes(m, model, res, console)
    console.print(f"  ({time.perf_counter() - t0:.1f} s)")
    return Prepared(fm, m, sim, model, emap, res, readings, d)


def _shared_axes(m: Machine, model: MachineModel, res: MachineResult, console: Console) -> None:
    """A multi-spindle machine: weighted compensation over both tool tips (first seed)."""
    rng = np.random.default_rng(0)
    q = np.column_stack([rng.uniform(*a.travel, 400) for a in m.axes])
    geometry = model.geometry_at(None)
    for label, w in (("equal weights", [1, 1, 1, 1, 1, 1]),
                     ("spindle 1 x10", [10, 10, 10, 1, 1, 1])):
        c = compensate(m, geometry, q, weights=Weights.parse(m, [float(x) for x in w]))
        worst = np.abs(c.error_um).max(axis=(1, 2))
        left = np.abs(c.residual_um).max(axis=(1, 2))
        console.print(f"  shared axes, {label}: worst error per spindle "
                      f"{' / '.join(f'{v:.1f}' for v in worst)} µm → "
                      f"{' / '.join(f'{v:.1f}' for v in left)} µm")
        if label == "equal weights":
            res.before_um, res.after_um = float(worst.max()), float(left.max())
    res.notes.append("two spindles share x and y: residual split by weights")


def warm_up(p: Prepared, console: Console, steps: int = 6, minutes: float = 10.0) -> None:
    """The machine with a thermal model warms up; one tables map, built once, follows its
    spindle sensor in the machine's own evaluation (no rebuild per temperature)."""
    m, sim = p.machine, p.sim
    programs = [diagonal_test(m, g, points=10, runs=1) for g in DIAGONALS]
    rigid = MachineModel(p.model.machine, p.model.geometry, (), {})
    maps: dict[str, TablesMap] = {}
    for label, model in (("rigid", rigid), ("thermal", p.model)):
        content = build_for(m, model, None, kind="tables", tolerance_um=0.5,
                            controller="siemens")
        amap = active_map(decode_payload(encode(content)))
        assert isinstance(amap, TablesMap)
        maps[label] = amap
    console.print(f"\n[bold]{m.name}[/] warms up at 9000 rpm; one tables map carries the "
                  "thermal terms and the machine applies its latest spindle temperature "
                  "(z shift of the compensated tool tip, µm; map version unchanged):")
    ref: dict[str, float] = {}
    for k in range(steps + 1):
        heat: list[Program] = [[SpindleOn(9000.0), Dwell(60.0 * minutes * k)]] if k else []
        warm = [*heat, *programs]
        probe = run_campaign(sim, warm).measurements
        temps = {col: float(probe.temperatures[s].mean())
                 for s, col in probe.temperature_columns.items()}
        shifts = {}
        for label, amap in maps.items():
            amap.set_temperatures(temps)
            after = run_campaign(sim, warm, compensation=map_compensation(m, amap)).measurements
            offset, *_ = np.linalg.lstsq(after.u, after.value, rcond=None)
            shifts[label] = float(offset[2])
        if not ref:
            ref = dict(shifts)
        spindle = temps.get("T_spindle_C", float("nan"))
        console.print(f"  t = {minutes * k:4.0f} min  spindle {spindle:5.2f} °C   rigid map "
                      f"{shifts['rigid'] - ref['rigid']:+7.2f}   thermal map "
                      f"{shifts['thermal'] - ref['thermal']:+6.2f}")


def summary_table(results: list[MachineResult]) -> Table:
    t = Table(title="Fleet summary")
    for col in ("machine", "controller", "chain", "readings", "fit RMS µm", "diagnosis",
                "map kind", "bytes", "worst µm", "before µm", "after µm", "better"):
        t.add_column(col)
    for r in results:
        t.add_row(r.name, r.controller, r.chain, str(r.readings), f"{r.fit_rms_um:.2f}",
                  r.effect, r.map_kind, f"{r.map_bytes:,d}", f"{r.map_worst_um:.2f}",
                  f"{r.before_um:.1f}", f"{r.after_um:.2f}", f"{100 * r.improvement:.0f} %")
    return t


def run_numeric_demo(console: Console, *, warm: bool = True) -> list[Prepared]:
    prepared = []
    for fm in demo_fleet():
        prepared.append(prepare(fm, console))
    hot = next((p for p in prepared if p.model.sensors), None)
    if hot is not None and warm:
        warm_up(hot, console)
    console.print(summary_table([p.result for p in prepared]))
    return prepared
