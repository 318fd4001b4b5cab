"""The PLC program of ``plc/`` (IEC 61131-3 Structured Text), compiled by MATIEC and gcc,
as a simulated controller's PLC.

:class:`StPlc` is one machine's PLC running ``PRG_Ednc`` of ``plc/ednc_program.st``: its
window is the program's own ``window`` variable (a controller's server can serve it
directly, :attr:`StPlc.window` is a writable view of it), its inputs the commanded
positions in counts and a millisecond clock, its outputs the corrections in counts. It
stands where :class:`machine_sim.plcmap.PlcMapProgram` and the Fanuc ladder stand
together: window protocol, map evaluation, reversal, clamp and step limit are all the
compiled program's.
"""

from __future__ import annotations

import ctypes
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from protocol.ctrlmem import Layout
from volumetric.model.machine import Machine

from .iec import ROOT, StProgram, StVar, build_program
from .runtime import MachineRuntime
from .scanned import ScannedController

__all__ = ["ST_SOURCES", "ST_VARIABLES", "WINDOW_CAPACITY", "StPlc", "StWindowCNC", "st_library"]

PLC_DIR = ROOT / "plc"
ST_SOURCES = tuple(PLC_DIR / f for f in (
    "ednc_types.st", "ednc_bytes.st", "ednc_names.st", "ednc_factored.st", "ednc_f64.st",
    "ednc_grid.st", "ednc_tables.st", "ednc_thermal.st", "ednc_window.st",
    "ednc_program.st"))
WINDOW_CAPACITY = 16_384
"""Payload bytes per buffer the program is built for (T_Window, T_Copy)."""
MAX_AXES = 8

ST_VARIABLES = (
    StVar("window", ctypes.c_uint8, Layout(WINDOW_CAPACITY).size),
    StVar("machine", ctypes.c_uint8, 32),
    StVar("nAxes", ctypes.c_int16),
    StVar("axisName", ctypes.c_uint8, 32),
    StVar("incrementNm", ctypes.c_uint32),
    StVar("countsPerUnit", ctypes.c_int32),
    StVar("formats", ctypes.c_uint16),
    StVar("channelLimit", ctypes.c_int32),
    StVar("maxStep", ctypes.c_int32),
    StVar("alarmOnJump", ctypes.c_uint8),
    StVar("resetAlarm", ctypes.c_uint8),
    StVar("tempMin", ctypes.c_int32),
    StVar("tempMax", ctypes.c_int32),
    StVar("tempRate", ctypes.c_int32),
    StVar("tempAllowance", ctypes.c_int32),
    StVar("q", ctypes.c_int32, MAX_AXES),
    StVar("nowMs", ctypes.c_int32),
    StVar("applied", ctypes.c_int32, MAX_AXES),
    StVar("target", ctypes.c_int32, MAX_AXES),
    StVar("state", ctypes.c_uint16),
    StVar("c0", ctypes.c_int64, MAX_AXES),
    StVar("c1", ctypes.c_int64, MAX_AXES),
    StVar("negative", ctypes.c_uint8, MAX_AXES),
)

FORMATS = 0x19
"""INT32_INCREMENTS | THERMAL | FACTORED: int32 grids with their thermal records and
factored maps (Hello's map_formats bits)."""


def st_library() -> Path:
    """The compiled program (built once, cached by content)."""
    return build_program(ST_SOURCES, "PRG_Ednc", ST_VARIABLES)


def _name_bytes(text: str, size: int) -> bytes:
    raw = text.encode("ascii")
    if len(raw) > size:
        raise ValueError(f"{text!r} is longer than {size} bytes")
    return raw + bytes(size - len(raw))


class StPlc:
    """One machine's PLC running the compiled Structured Text program.

    Parameters
    ----------
    machine : str
        The machine's name (its maps carry it).
    axes : sequence of str
        Its axes in the machine's order (at most 8).
    channel_limit : int
        The compensation channel's range, ± counts.
    max_step : int
        Largest change of a correction per scan, counts.
    formats : int
        Map formats the program declares (Hello's map_formats bits).
    increment_nm : int
    temperature_screen : (int, int, int, int)
        Plausible range (m°C), rate (m°C per s) and jump allowance (m°C) of the
        program's temperature screen.
    alarm_on_jump : bool
        A step larger than ``max_step`` raises the alarm and holds the corrections until
        :meth:`reset_alarm` (instead of ramping).
    """

    def __init__(self, machine: str, axes: Sequence[str], *, channel_limit: int = 500,
                 max_step: int = 5, formats: int = FORMATS, increment_nm: int = 1000,
                 temperature_screen: tuple[int, int, int, int] = (-20000, 100000, 1000,
                                                                   10000),
                 alarm_on_jump: bool = False) -> None:
        if not 1 <= len(axes) <= MAX_AXES:
            raise ValueError(f"1 to {MAX_AXES} axes, got {len(axes)}")
        self.machine = machine
        self.axes = tuple(a.upper() for a in axes)
        self.settings = (channel_limit, max_step, formats, increment_nm)
        self.screen = temperature_screen
        self.alarm_on_jump = alarm_on_jump
        self.layout = Layout(WINDOW_CAPACITY)
        self.program = StProgram(st_library(), ST_VARIABLES)
        self.program.init()
        self._configure()
        self.now_ms = 0

    def _configure(self) -> None:
        p = self.program
        channel_limit, max_step, formats, increment_nm = self.settings
        p.var("machine")[:] = list(_name_bytes(self.machine, 32))
        p.var("axisName")[:] = list(b"".join(_name_bytes(a, 4) for a in self.axes)
                                    .ljust(32, b"\0"))
        p.var("nAxes")[0] = len(self.axes)
        p.var("incrementNm")[0] = increment_nm
        p.var("formats")[0] = formats
        p.var("channelLimit")[0] = channel_limit
        p.var("maxStep")[0] = max_step
        p.var("alarmOnJump")[0] = int(self.alarm_on_jump)
        for name, value in zip(("tempMin", "tempMax", "tempRate", "tempAllowance"),
                               self.screen, strict=True):
            p.var(name)[0] = value

    @property
    def window(self) -> memoryview:
        """The program's window variable, writable in place (bytes)."""
        return memoryview(self.program.var("window")).cast("B")

    def restart(self) -> None:
        """A PLC restart: every variable to its initial value but the window, which is
        retentive (PMC D area, a retentive DB) and keeps its bytes."""
        kept = bytes(self.window)
        self.program.init()
        self.window[:] = kept
        self._configure()

    def scan(self, q_counts: Sequence[int] | NDArray[np.int64], dt_ms: int = 8
             ) -> NDArray[np.int64]:
        """One scan at the commanded positions (counts, machine axis order); returns the
        applied corrections (counts)."""
        p = self.program
        qv = p.var("q")
        for k in range(len(self.axes)):
            qv[k] = int(q_counts[k])
        self.now_ms += dt_ms
        p.var("nowMs")[0] = self.now_ms
        p.scan()
        p.var("resetAlarm")[0] = 0
        return self.applied

    def reset_alarm(self) -> None:
        """The operator's reset: the next scan clears the step alarm."""
        self.program.var("resetAlarm")[0] = 1

    @property
    def applied(self) -> NDArray[np.int64]:
        return np.array(self.program.var("applied")[:len(self.axes)], dtype=np.int64)

    @property
    def target(self) -> NDArray[np.int64]:
        """What the corrections ramp to (before the step limit), counts."""
        return np.array(self.program.var("target")[:len(self.axes)], dtype=np.int64)

    @property
    def thermal_constants(self) -> tuple[list[int], list[int]]:
        """c0 (2^-16 counts) and c1 (2^-32 counts per count) per map axis (output)."""
        n = len(self.axes)
        return (list(self.program.var("c0")[:n]), list(self.program.var("c1")[:n]))

    @property
    def directions(self) -> list[int]:
        """+1 or -1 per axis: the sign of its last move (+1 before any)."""
        return [-1 if v else 1 for v in self.program.var("negative")[:len(self.axes)]]

    @property
    def state(self) -> int:
        return int(self.program.var("state")[0])

    def lookup(self, q_counts: Sequence[int], negative: Sequence[bool]) -> NDArray[np.int64]:
        """The target at q_counts with each axis last moved in the direction given
        (two scans: one a count away on the side it came from, one at q)."""
        before = [int(q) + (1 if neg else -1) for q, neg in zip(q_counts, negative,
                                                                  strict=True)]
        self.scan(before, 0)
        self.scan(q_counts, 0)
        return self.target


class StWindowCNC(ScannedController):
    """A simulated machine whose PLC is the compiled program: the controller's server
    (Modbus/TCP for a Fanuc PMC, :class:`machine_sim.modbus_server.PmcModbusServer`)
    serves the program's own window variable, and every cycle the program scans at the
    machine's commanded positions (counts of 0.001 mm / 0.001°). An async context
    manager, like :class:`machine_sim.windowcnc.WindowCNC`.

    Parameters
    ----------
    machine : Machine
    server_factory : callable
        Builds the controller's server from this machine (it reads ``window``).
    seed : int
        Seed of the simulated motion.
    cycle_s : float
        PLC scan period, s.
    channel_limit, max_step : int
        The program's settings (counts; counts per scan).
    """

    def __init__(self, machine: Machine, server_factory: Callable[[StWindowCNC], Any], *,
                 seed: int = 0, cycle_s: float = 0.008, channel_limit: int = 500,
                 max_step: int = 5) -> None:
        self.machine = machine
        self.runtime = MachineRuntime(machine, seed=seed)  # its motion
        self.plc = StPlc(machine.name, machine.axis_names, channel_limit=channel_limit,
                         max_step=max_step)
        self.layout = self.plc.layout
        self.window = self.plc.window
        self.cycle_s = float(cycle_s)
        self.server = server_factory(self)

    task_name = "st-plc"

    def boot(self) -> None:
        """The first scan writes the identity before anyone reads it."""
        self.cycle()

    def cycle(self) -> None:
        """One scan at the machine's commanded positions now."""
        positions, _ = self.runtime.motion.at(self.now())
        counts = np.rint(np.asarray(positions, dtype=float) * 1000.0).astype(np.int64)
        self.plc.scan(counts, round(self.cycle_s * 1000))
