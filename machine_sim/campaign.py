"""Measurement campaigns on a simulated machine: programs in, measurement CSV rows out.

:func:`run_campaign` executes the programs one after the other, integrates the thermal
model over the whole campaign (spindle and axis motion heat the structure, the shop air
follows its day), and at every :class:`~machine_sim.program.Measure` reads the true error
through the instrument with the sensors' temperatures at that moment.

Columns beyond formats.md section 2's required ones (all documented here):

* ``a_deg``, ``b_deg``, ``c_deg`` for the rotary axes the machine has;
* ``<key>_mm`` and ``dir_<key>`` for every axis that has no standard column (the spindle
  axes ``Z1``, ``Z2`` of a multi-spindle machine), and ``dir_a``/``dir_b``/``dir_c`` for
  rotary axes; :func:`machine_positions` and :func:`machine_directions` put every column
  back in ``machine.axes`` order;
* ``spindle`` (the tool branch) on machines with named spindles;
* ``spindle_rpm``: the spindle speed at the reading;
* ``T_<sensor>_C`` for every sensor of the thermal model.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from volumetric.measure.measurement import Measurements, write_measurements
from volumetric.model.machine import Machine

from .effects import lagged_key
from .instruments import SimulatedMachine
from .lookup import ActiveMap
from .program import (
    Dwell,
    Instruction,
    MachineState,
    Measure,
    Program,
    SpindleOff,
    SpindleOn,
    Trajectory,
    concatenate,
    execute,
)
from .testprograms import (
    angular_test,
    diagonal_test,
    positioning_test,
    rotary_positioning_test,
    rtest,
    rtest_balls,
    straightness_test,
    targets_along,
)
from .thermal import ThermalHistory, lag_series, simulate_thermal

__all__ = [
    "CampaignResult",
    "Compensation",
    "machine_directions",
    "machine_positions",
    "map_compensation",
    "run_campaign",
    "standard_campaign",
    "standard_programs",
    "write_campaign",
]

F64 = NDArray[np.float64]
Compensation = Callable[[F64, NDArray[np.int8]], F64]
STANDARD = {"X": 0, "Y": 1, "Z": 2, "A": 3, "B": 4, "C": 5}


@dataclass(frozen=True)
class CampaignResult:
    """What a campaign produced: the readings and the truth behind them.

    Attributes
    ----------
    measurements : Measurements
    trajectory : Trajectory
        The whole motion.
    thermal : ThermalHistory
        True and sensed temperatures over the campaign.
    true_value : ndarray, shape (N,)
        The noise-free reading of every row (µm or µrad).
    """

    measurements: Measurements
    trajectory: Trajectory
    thermal: ThermalHistory
    true_value: F64


def _has_named_spindles(machine: Machine) -> bool:
    return len(machine.branches) > 1 or machine.branches[0].name != "main"


def run_campaign(
    sim: SimulatedMachine,
    programs: Sequence[Program],
    *,
    start: MachineState | None = None,
    compensation: Compensation | None = None,
) -> CampaignResult:
    """Execute ``programs`` in order on ``sim`` and take every reading they ask for.

    Parameters
    ----------
    sim : SimulatedMachine
    programs : sequence of Program
    start : MachineState, optional
        Home position at time 0 by default.
    compensation : callable, optional
        ``compensation(q, direction)`` with q (N, n_axes) commanded positions and direction
        (N, n_axes) last directions gives the shift (N, n_axes) the controller applies at
        each reading, mm or degrees (e.g. :func:`map_compensation`): the campaign then
        measures the compensated machine (a verification run).

    Returns
    -------
    CampaignResult
        Deterministic given ``sim.seed``.

    Raises
    ------
    ValueError
        No readings in the programs; :class:`~machine_sim.program.ProgramError` for a
        program the machine cannot run.
    """
    machine = sim.machine
    state = start or MachineState.home(machine)
    parts = []
    for prog in programs:
        traj = execute(machine, prog, start=state, limits=sim.limits)
        parts.append(traj)
        state = traj.final
    if not parts:
        raise ValueError("run_campaign needs at least one program")
    trajectory = concatenate(parts)
    marks = trajectory.marks
    if not marks:
        raise ValueError("the programs take no readings (no Measure instruction)")
    config = sim.thermal_config
    t_end = float(trajectory.knots_s[-1])
    t0 = float(trajectory.knots_s[0])
    steps = int(np.ceil((t_end - t0) / config.step_s)) + 2
    grid = np.asarray(t0 + np.arange(steps) * config.step_s, dtype=np.float64)
    rpm, speeds = trajectory.loads(grid, machine)
    history = simulate_thermal(config, grid, rpm, speeds, sim.seed)

    n = len(marks)
    time_s = np.array([mk.time_s for mk in marks])
    q = np.array([mk.q for mk in marks])
    direction = np.array([mk.direction for mk in marks], dtype=np.int8)
    u = np.array([mk.measure.u for mk in marks], dtype=float)
    is_angle = np.array([mk.measure.quantity == "angle" for mk in marks])
    branch = [machine.branch(mk.measure.spindle).name for mk in marks]
    tool = np.array([machine.branch(mk.measure.spindle).tool_length_mm
                     if mk.measure.tool_mm is None else mk.measure.tool_mm for mk in marks])
    true_temps = history.true_at(time_s)
    for sensor, lag in sim.effects.lags():
        lagged = lag_series(history.time_s, history.true_C[sensor], lag)
        true_temps[lagged_key(sensor, lag)] = np.interp(time_s, history.time_s, lagged)
    starts = history.start()
    true_value = np.empty(n)
    for name in dict.fromkeys(branch):
        rows = np.flatnonzero(np.array(branch) == name)
        temps = {k: v[rows] for k, v in true_temps.items()}
        shift = None if compensation is None else compensation(q[rows], direction[rows])
        err = sim.true_error(q[rows], direction[rows], temps, starts, spindle=name,
                             tool_mm=tool[rows], compensation=shift,
                             time_s=time_s[rows] - t0)
        true_value[rows] = sim.read(err, u[rows], is_angle[rows], None)
    noise = np.where(is_angle, sim.effects.noise.angle_urad, sim.effects.noise.displacement_um)
    value = true_value + np.random.default_rng([sim.seed, 2]).normal(0.0, 1.0, n) * noise
    readings = history.read_at(time_s, np.random.default_rng([sim.seed, 3]))

    q6 = np.zeros((n, 6))
    dir3 = np.zeros((n, 3), dtype=np.int8)
    extra: dict[str, NDArray[Any]] = {}
    for j, a in enumerate(machine.axes):
        if a.name in STANDARD:
            q6[:, STANDARD[a.name]] = q[:, j]
            if a.name in ("X", "Y", "Z"):
                dir3[:, STANDARD[a.name]] = direction[:, j]
            else:
                extra[f"dir_{a.key}"] = direction[:, j].astype(float)
        else:
            extra[f"{a.key}_mm"] = q[:, j].copy()
            extra[f"dir_{a.key}"] = direction[:, j].astype(float)
    extra["spindle_rpm"] = np.array([mk.spindle_rpm for mk in marks])
    has_rotary = tuple(name in machine.axis_names for name in ("A", "B", "C"))
    m = Measurements(
        test=np.array([mk.measure.test for mk in marks]),
        run=np.array([mk.measure.run for mk in marks], dtype=np.int64),
        time_s=time_s - t0,
        q=q6,
        direction=dir3,
        tool_mm=tool,
        is_angle=is_angle,
        u=u,
        value=value,
        has_rotary=(has_rotary[0], has_rotary[1], has_rotary[2]),
        temperatures={k: v for k, v in readings.items()},
        temperature_columns={k: f"T_{k}_C" for k in readings},
        spindle=np.array(branch) if _has_named_spindles(machine) else None,
        extra=extra,
    )
    return CampaignResult(m, trajectory, history, true_value)


def map_compensation(machine: Machine, grid_map: ActiveMap, *,
                     increment_mm: float | None = None) -> Compensation:
    """The shift a controller applies from an error map, as a campaign ``compensation``.

    Looks the map up at the commanded coordinates of its input axes (a grid's axes and
    those of its thermal records, at the temperatures last given to the map), adds an output's
    reversal value where that axis last moved negative (protocol/README.md section 6),
    and rounds to ``increment_mm`` when given (a Fanuc-style controller). Rate limits and
    ramps are left out: a verification reading is taken at rest, long after any change.

    Raises
    ------
    ValueError
        A grid or output axis the machine does not have.
    """
    names = machine.axis_names
    for a in (*grid_map.inputs, *grid_map.outputs):
        if a not in names:
            raise ValueError(f"map axis {a!r} is not an axis of {machine.name} ({names})")
    cols = [names.index(g) for g in grid_map.inputs]
    outs = [names.index(o) for o in grid_map.outputs]

    def shift(q: F64, direction: NDArray[np.int8]) -> F64:
        values = grid_map.lookup(q[:, cols])
        values = values + np.where(direction[:, outs] < 0, grid_map.reversal, 0.0)
        if increment_mm is not None:
            values = np.rint(values / increment_mm) * increment_mm
        out = np.zeros(q.shape)
        out[:, outs] = values
        return out

    return shift


def machine_positions(machine: Machine, m: Measurements) -> F64:
    """Commanded positions of readings in ``machine.axes`` order, shape (N, n_axes).

    Standard axes come from ``x_mm .. c_deg``, others from their ``<key>_mm`` column.

    Raises
    ------
    ValueError
        A spindle axis without its ``<key>_mm`` column.
    """
    out = np.zeros((len(m), len(machine.axes)))
    for j, a in enumerate(machine.axes):
        if a.name in STANDARD:
            out[:, j] = m.q[:, STANDARD[a.name]]
        elif f"{a.key}_mm" in m.extra and m.extra[f"{a.key}_mm"].dtype.kind == "f":
            out[:, j] = m.extra[f"{a.key}_mm"]
        else:
            raise ValueError(f"the readings have no numeric column {a.key}_mm for axis "
                             f"{a.name}")
    return out


def machine_directions(machine: Machine, m: Measurements) -> NDArray[np.int8]:
    """Last direction of motion per axis in ``machine.axes`` order, shape (N, n_axes).

    Rotary axes without a ``dir_<key>`` column get 0.
    """
    out = np.zeros((len(m), len(machine.axes)), dtype=np.int8)
    for j, a in enumerate(machine.axes):
        if a.name in ("X", "Y", "Z"):
            out[:, j] = m.direction[:, STANDARD[a.name]]
        elif f"dir_{a.key}" in m.extra:
            out[:, j] = m.extra[f"dir_{a.key}"].astype(np.int8)
    return out


def _renumber(program: Program, run: int) -> list[Instruction]:
    return [replace(i, run=run) if isinstance(i, Measure) else i for i in program]


def standard_programs(
    machine: Machine,
    rng: np.random.Generator,
    *,
    runs: int = 5,
    targets: int = 21,
    side_runs: int = 2,
    diagonal_runs: int = 3,
    fine_length_mm: float = 40.0,
    fine_step_mm: float = 1.0,
    setup_s: float = 600.0,
    warmup_rpm: float = 8000.0,
    warm_fraction: float = 0.5,
) -> list[Program]:
    """The usual campaign as programs, in the order a technician would run them.

    Positioning runs of every linear axis are spread over the whole campaign in ``runs``
    blocks (run k of every axis in block k), so the campaign sees the machine warm up and
    cool down: between tests the technician re-aligns the optics (``setup_s``) while the
    spindle runs a warm-up at ``warmup_rpm`` during the first ``warm_fraction`` of the
    set-ups and stands still afterwards. The other tests are dealt over the blocks:
    straightness (both directions across each axis), angular (all three rotations),
    a fine positioning test (``<AX>-positioning-fine``: ``fine_step_mm`` steps over
    ``fine_length_mm`` in the middle of the travel, ``side_runs`` cycles, which resolves a
    ballscrew's periodic error) and the four body diagonals when the machine has X, Y and Z.
    A rotary axis gets an angular positioning test (``<AX>-positioning``) and two R-tests
    (``<AX>-rtest-1``, ``-2``, :func:`~machine_sim.testprograms.rtest_balls`).

    Returns
    -------
    list of Program
        Set-up dwells and tests alternating.
    """
    if runs < 1 or side_runs < 1 or diagonal_runs < 1:
        raise ValueError(f"runs, side_runs and diagonal_runs must be >= 1, got {runs}, "
                         f"{side_runs}, {diagonal_runs}")
    if not (setup_s >= 0 and warmup_rpm >= 0 and 0 <= warm_fraction <= 1):
        raise ValueError("setup_s and warmup_rpm must be >= 0, warm_fraction in [0, 1]")
    linear = [a for a in machine.axes if a.kind == "linear"]
    # one set of ISO 230-2 targets per axis, kept for all its runs
    spread = {a.name: targets_along(a, targets, rng=rng) for a in linear}
    blocks: list[list[Program]] = [[] for _ in range(runs)]
    for k in range(runs):
        for a in linear:
            prog = positioning_test(machine, a.name, targets=spread[a.name], runs=1)
            blocks[k].append(_renumber(prog, k + 1))
    others: list[Program] = []
    for a in linear:
        own = "Z" if a.name not in ("X", "Y", "Z") else a.name
        suffix = a.name[1:] if a.name not in ("X", "Y", "Z") else ""
        for sense in "XYZ":
            if sense != own:
                label = sense + (suffix if sense == "Y" and suffix else "")
                others.append(straightness_test(machine, a.name, label, targets=targets,
                                                runs=side_runs))
        for about in "ABC":
            others.append(angular_test(machine, a.name, about, targets=targets,
                                       runs=side_runs))
        lo, hi = a.travel
        mid = 0.5 * (lo + hi)
        half = min(fine_length_mm, 0.8 * (hi - lo)) / 2
        fine = np.arange(mid - half, mid + half + 1e-9, fine_step_mm)
        others.append(positioning_test(machine, a.name, targets=fine, runs=side_runs,
                                       settle_s=3.0, label=f"{a.name}-positioning-fine"))
    if all(k in machine.axis_names for k in ("X", "Y", "Z")):
        for label in ("diag-PPP", "diag-NPP", "diag-PNP", "diag-PPN"):
            others.append(diagonal_test(machine, label, points=targets, runs=diagonal_runs))
        for a in machine.axes:
            if a.kind != "rotary":
                continue
            others.append(rotary_positioning_test(machine, a.name, runs=side_runs))
            for k, st in enumerate(rtest_balls(machine, a.name), start=1):
                others.append(rtest(machine, a.name, st.ball_mm, label=f"{a.name}-rtest-{k}",
                                    tool_mm=st.tool_mm, angles_deg=st.angles_deg,
                                    runs=side_runs))
    for i, prog in enumerate(others):
        blocks[i % runs].append(prog)
    tests = [p for block in blocks for p in block]
    out: list[Program] = []
    n_warm = round(warm_fraction * len(tests))
    for i, prog in enumerate(tests):
        if i < n_warm and warmup_rpm > 0:
            out.append([SpindleOn(warmup_rpm), Dwell(setup_s), SpindleOff()])
        else:
            out.append([Dwell(setup_s)])
        out.append(prog)
    return out



def standard_campaign(sim: SimulatedMachine, rng: np.random.Generator,
                      **options: Any) -> Measurements:
    """Run :func:`standard_programs` on ``sim``: a few thousand readings over hours.

    ``rng`` draws the positioning targets' random offsets; ``options`` go to
    :func:`standard_programs`.
    """
    return run_campaign(sim, standard_programs(sim.machine, rng, **options)).measurements


def write_campaign(path: str | Path, m: Measurements) -> None:
    """Write readings as a measurement CSV (formats.md section 2)."""
    write_measurements(path, m)
