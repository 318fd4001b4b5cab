"""A SINUMERIK with nothing of ours in its PLC: its NC's own compensations, set from outside.

Issue 31, item 4. The machine runs no EDNC program at all: no map window, no PLC lookup.
What compensates it is the NC's standard function set (function manual K3):

* **temperature compensation** per axis, ``ΔK = SD43900 + SD43910 · (P - SD43920)``
  (offset, slope tan β, reference position; P the axis's machine position), the offset
  only where MD32750 ``TEMP_COMP_TYPE`` bit 0 is on, the position-dependent part only
  where bit 1 is. The center writes these setting data itself over the controller's OPC UA
  server (a user with ``SeaWrite``; :class:`~machine_sim.opcua_server.SinumerikOpcuaServer`
  answers a write the NC refuses with ``BadNotWritable`` / ``BadOutOfRange``);
* **CEC tables** (interpolatory compensation), loaded once from the file ``ednc export
  --format cec`` wrote (:class:`~machine_sim.cec_tables.CecTables`): the geometry.

Every interpolation cycle the NC applies the sum, and the applied value follows a change
at no more than MD32760 ``COMP_ADD_VELO_FACTOR`` × MD32000 ``MAX_AX_VELO`` per cycle (K3:
"the maximum distance that can be traversed in an IPO cycle as a result of the
temperature compensation"). Every setting-data write is logged with its arrival time
(:attr:`NativeSinumerikNC.sd_log`) so a test can judge the writer's rate and limits from
the machine's side.

:class:`NativeSinumerik` is the machine: motion and temperatures
(:class:`~machine_sim.runtime.MachineRuntime`), the NC above, and the OPC UA server, as an
async context manager. Its PLC data block is empty: any ``/Plc/DB...`` access answers
``BadOutOfRange`` (there is nothing of ours to reach).
"""

from __future__ import annotations

import asyncio
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, cast

import numpy as np
from numpy.typing import NDArray

from volumetric.model.machine import Machine

from .cec_tables import CecTables
from .opcua_server import OpcuaUser, SinumerikOpcuaServer
from .runtime import MachineRuntime
from .scanned import ScannedController
from .siemens import (
    MD_TEMP_COMP_TYPE,
    MD_VELO_FACTOR,
    SD_ABS_VALUE,
    SD_REF_POSITION,
    SD_SLOPE,
    SiemensAlarm,
    SiemensConfig,
    SiemensNC,
)

if TYPE_CHECKING:
    from .windowcnc import WindowCNC

__all__ = ["NativeSinumerik", "NativeSinumerikNC", "SdWriteRecord"]

F64 = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class SdWriteRecord:
    """One setting-data write as the NC received it.

    Attributes
    ----------
    time_s : float
        Arrival, s (``time.monotonic``: what a rate is judged by).
    axis : str
    number : int
        43900, 43910 or 43920.
    value : float
        mm, mm/mm or mm.
    accepted : bool
        False when the NC refused it (alarm; the value was not taken).
    """

    time_s: float
    axis: str
    number: int
    value: float
    accepted: bool


class NativeSinumerikNC(SiemensNC):
    """The NC of a SINUMERIK without our PLC program (module docstring).

    Parameters
    ----------
    machine : str
    axes : sequence of str
    config : SiemensConfig, optional
        ``limit_mm``: the largest |SD43900| accepted; ``temp_comp_type``: MD32750 of every
        axis (3: offset and slope).
    clock : callable, optional
        Arrival times of writes, s (``time.monotonic`` by default).
    """

    def __init__(self, machine: str, axes: Sequence[str], config: SiemensConfig | None = None,
                 *, clock: Callable[[], float] = time.monotonic) -> None:
        super().__init__(machine, axes, config)
        self.cec: CecTables | None = None
        self.clock = clock
        self.sd_log: list[SdWriteRecord] = []

    def load_cec(self, text: str, axis_names: Mapping[str, str] | None = None) -> None:
        """Load a CEC file (MPF run or INI at start-up); raises ``ValueError`` for a file
        the NC would refuse, keeping the tables it had."""
        self.cec = CecTables(text, self.axes, axis_names)

    def write_sd(self, number: int, axis: str, value: float) -> None:
        """Set setting data (refused as :meth:`SiemensNC.write_sd` refuses, and a slope
        steeper than MD32760 allows: K3, "MD32760 also limits the maximum gradient of the
        error line (tan β)"), logged."""
        try:
            limit = self.read_md(MD_VELO_FACTOR, axis)
            if number == SD_SLOPE and not abs(float(value)) <= limit:
                raise SiemensAlarm("SD43910_RANGE", f"axis {axis.upper()}: SD43910 = "
                                   f"{value!r} is steeper than MD32760 = {limit:g}")
            super().write_sd(number, axis, value)
        except Exception:
            self.sd_log.append(SdWriteRecord(self.clock(), axis.upper(), number, float(value),
                                             False))
            raise
        self.sd_log.append(SdWriteRecord(self.clock(), axis.upper(), number, float(value),
                                         True))

    def compensation_mm(self, q: F64, direction: NDArray[np.integer] | None = None) -> F64:
        """What the NC applies at machine positions ``q`` (N, n_axes) once settled: CEC
        tables plus the temperature compensation where MD32750 enables it, mm (N, n_axes).
        """
        q = np.atleast_2d(np.asarray(q, dtype=float))
        comp_type = self.md[MD_TEMP_COMP_TYPE].astype(np.int64)
        out: F64 = (np.where(comp_type & 1, self.sd[SD_ABS_VALUE], 0.0)
                    + np.where(comp_type & 2, self.sd[SD_SLOPE]
                               * (q - self.sd[SD_REF_POSITION]), 0.0))
        if self.cec is not None:
            out = out + self.cec.compensation_mm(q, direction)
        return out

    def ipo_cycle(self, now_s: float, positions: Mapping[str, float] | F64,
                  directions: Mapping[str, int] | NDArray[np.integer] | None = None) -> F64:
        """One interpolation cycle: the compensation the NC's own functions want at the
        axes' positions, reached at MD32760's rate; returns it per axis, mm."""
        self.now_s = now_s
        pos = self._vector(positions, float)
        d = None if directions is None else self._vector(directions, float).astype(np.int64)
        desired = self.compensation_mm(pos[None, :], None if d is None else d[None, :])[0]
        step = self.max_step_mm()
        self._last_desired = desired
        self.applied = self.applied + np.clip(desired - self.applied, -step, step)
        self.cycles += 1
        return self.applied


class NativeSinumerik(ScannedController):
    """A simulated SINUMERIK reached only through its OPC UA server's NC data.

    Parameters
    ----------
    machine : Machine
    users : mapping of str to OpcuaUser
        Who may log in; the center needs ``SeaWrite`` (and a read right to check).
    config : SiemensConfig, optional
    seed : int
    cycle_s : float, optional
        Controller cycle of the simulation loop (the NC's IPO cycle by default).
    thermal_speedup : float
        Machine-temperature seconds per second (:class:`~machine_sim.runtime.
        MachineRuntime`).
    **server : Any
        Keywords of its :class:`~machine_sim.opcua_server.SinumerikOpcuaServer` (the
        endpoints offered, the clients trusted, busy answers...).
    """

    def __init__(self, machine: Machine, users: Mapping[str, OpcuaUser], *,
                 config: SiemensConfig | None = None, seed: int = 0,
                 cycle_s: float | None = None, thermal_speedup: float = 1.0,
                 **server: Any) -> None:
        if machine.controller != "siemens":
            raise ValueError(f"machine {machine.name!r} has a {machine.controller} controller")
        self.machine = machine
        self.runtime = MachineRuntime(machine, seed=seed, siemens=config,
                                      thermal_speedup=thermal_speedup)
        self.nc = NativeSinumerikNC(machine.name, machine.axis_names, config)
        self.runtime.controller = self.nc
        self.window = bytearray()  # no PLC data block of ours
        self.cycle_s = cycle_s or self.nc.config.ipo_s
        # the OPC UA server reads machine, window, runtime.controller and runtime.positions
        # only: this machine offers those without the window program of a WindowCNC
        self.server = SinumerikOpcuaServer(cast("WindowCNC", self), users, **server)

    server: SinumerikOpcuaServer
    task_name = "nc"

    @property
    def endpoint(self) -> str:
        return self.server.endpoint

    def cycle(self) -> None:
        """One IPO cycle of motion, temperatures and the NC's compensation."""
        self.runtime.step(self.now())

    async def _loop(self) -> None:
        while True:
            self.runtime.step(self.now())
            await asyncio.sleep(self.cycle_s)
