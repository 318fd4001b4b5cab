"""A simulated CNC reached through its controller's own server, not the EDNC client.

:class:`WindowCNC` is an async context manager: the controller cycle (motion,
temperatures, the Fanuc ladder or Siemens IPO cycle of :class:`MachineRuntime`) and the
PLC program's map handling (:class:`~machine_sim.plcmap.PlcMapProgram`) run every cycle
over one memory window, which the controller's server (Modbus/TCP for a Fanuc PMC,
:mod:`machine_sim.modbus_server`; OPC UA for a SINUMERIK, :mod:`machine_sim.opcua_server`)
exposes to the center. The machine opens no connection: the center comes to it.

:meth:`restart_plc` simulates a PLC restart (power cycle of the PLC program; the window
is nonvolatile memory and keeps its contents).
"""

from __future__ import annotations

import asyncio
import math
from collections.abc import Callable
from typing import Protocol

import numpy as np

from protocol.ctrlmem import SWITCH_AT, Layout
from volumetric.model.machine import Machine

from .plcmap import PlcMapProgram
from .runtime import MachineRuntime
from .scanned import ScannedController

__all__ = ["ControllerServer", "WindowCNC"]

DEFAULT_CAPACITY = 16_384
"""Payload bytes per buffer: a five-axis factored map (<= 8 kB) twice over."""


class ControllerServer(Protocol):
    """The controller's own server over the window (Modbus/TCP, OPC UA)."""

    port: int

    async def start(self) -> None: ...

    async def stop(self) -> None: ...


class WindowCNC(ScannedController):
    """A machine whose controller serves its memory window to the center.

    Parameters
    ----------
    machine : Machine
    server_factory : callable
        Builds the controller's server from this machine (its window, runtime and name).
    runtime : MachineRuntime, optional
    capacity : int
        Payload bytes per buffer.
    seed : int
    cycle_s : float, optional
        Controller cycle; the controller's own by default.
    wake_grid_s : float, optional
        The scans of the machines in one process wake on a common grid of this step on
        the event loop's clock: a scan due at t runs at the first grid point at or after
        t (never earlier, at most this much later), so machines whose scans fall in one
        step are scanned in one wake-up of the process. Each scan's deadline still
        advances by ``cycle_s``, so none is skipped and the period is kept. By default
        ``cycle_s / 20``; 0 wakes at each deadline exactly.
    switch_scan_s : float, optional
        A new switch word (the center's last write of a push, protocol/README.md §13.2)
        is taken by an extra scan at most this long after it arrives, as a PMC whose
        ladder scans every 8-64 ms takes it; its other scans stay ``cycle_s`` apart.
        None (the default): at the next regular scan. A fleet of simulated PMCs scans
        every second to fit on a few cores; without this each verdict waits up to that
        second, which a real PMC does not make it wait.
    """

    def __init__(self, machine: Machine,
                 server_factory: Callable[[WindowCNC], ControllerServer], *,
                 runtime: MachineRuntime | None = None, capacity: int = DEFAULT_CAPACITY,
                 seed: int = 0, cycle_s: float | None = None,
                 wake_grid_s: float | None = None,
                 switch_scan_s: float | None = None) -> None:
        self.machine = machine
        self.runtime = runtime or MachineRuntime(machine, seed=seed)
        self.layout = Layout(capacity)
        self.window = bytearray(self.layout.size)
        ctl = self.runtime.controller
        increment = float(getattr(ctl.config, "increment_mm", 0.001))
        self.program = PlcMapProgram(self.window, self.layout, ctl,
                                     formats=ctl.store.assembler.accepted,
                                     increment_mm=increment)
        self.cycle_s = cycle_s or self.runtime.cycle_s
        self.wake_grid_s = self.cycle_s / 20 if wake_grid_s is None else float(wake_grid_s)
        # why: on a 2-core VM shared with other work, a wake-up of the process costs
        # about as much CPU as four scans (caches refilled, the timer and epoll in the
        # kernel); 250 PMCs of one process scanned at their own instants cost ~0.38 ms of
        # CPU per PMC-second, the same scans woken together ~0.12 ms (issue 30)
        if not 0 <= self.wake_grid_s <= self.cycle_s:
            raise ValueError(f"wake_grid_s must be in 0..cycle_s, got {wake_grid_s!r}")
        if switch_scan_s is not None and not 0 <= switch_scan_s <= self.cycle_s:
            raise ValueError(f"switch_scan_s must be in 0..cycle_s, got {switch_scan_s!r}")
        self.switch_scan_s = switch_scan_s
        self._switch_seen = bytes(self.window[SWITCH_AT:SWITCH_AT + 2])
        self._poke = asyncio.Event()
        self.server = server_factory(self)
        self.running = True
        """False while the PLC program is stopped (:meth:`stop_plc`)."""

    server: ControllerServer

    def boot(self) -> None:
        """The program's start-up: the window's identity before anyone reads it."""
        self.program.boot(self.now(), self.machine.name)

    def cycle(self) -> None:
        """One controller cycle and one PLC-program scan (what the loop runs)."""
        self._switch_seen = bytes(self.window[SWITCH_AT:SWITCH_AT + 2])
        if not self.running:
            return
        now = self.now()
        applied = self.runtime.step(now)
        self.program.scan(now, np.asarray(self.runtime.positions, dtype=float),
                          np.asarray(applied, dtype=float))

    def window_written(self) -> None:
        """The server wrote into the window: a new switch word is taken within
        ``switch_scan_s`` (when set)."""
        if (self.switch_scan_s is not None
                and self.window[SWITCH_AT:SWITCH_AT + 2] != self._switch_seen):
            self._poke.set()

    def stop_plc(self) -> None:
        """The PLC program stops (its scans and status freeze; the window stays)."""
        self.running = False

    def restart_plc(self) -> None:
        """The PLC program starts again: its working state is lost, the nonvolatile window
        is kept, and it takes its active buffer again only if that still checks out."""
        rt = self.runtime
        old = rt.controller
        # the controller's volatile state (map store, ramps, temperatures) is gone
        new = type(old)(self.machine.name, self.machine.axis_names, old.config)  # type: ignore[arg-type]
        new.temperatures.max_rate_K_per_s = old.temperatures.max_rate_K_per_s
        rt.controller = new
        self.program = PlcMapProgram(self.window, self.layout, rt.controller,
                                     formats=rt.controller.store.assembler.accepted,
                                     increment_mm=self.program.increment_mm)
        self.program.boot(self.now(), self.machine.name)
        self.running = True

    async def _loop(self) -> None:
        loop = asyncio.get_running_loop()
        next_t = loop.time()
        grid = self.wake_grid_s
        while True:
            self.cycle()
            next_t += self.cycle_s
            now = loop.time()
            delay = next_t - now
            if delay < -10 * self.cycle_s:
                next_t = now
            if grid > 0 and delay > 0:  # the grid point at or after the deadline
                wake = math.ceil(next_t / grid) * grid
                delay = (wake if wake >= next_t else wake + grid) - now
            if self.switch_scan_s is None:
                await asyncio.sleep(max(delay, 0.0))
            else:
                await self._until(now + max(delay, 0.0), self.switch_scan_s)

    async def _until(self, deadline: float, switch_scan_s: float) -> None:
        """Wait for the loop time ``deadline`` (the next regular scan), taking each new
        switch word meanwhile by an extra scan ``switch_scan_s`` after it arrives."""
        loop = asyncio.get_running_loop()
        while (left := deadline - loop.time()) > 0:
            self._poke.clear()
            if self.window[SWITCH_AT:SWITCH_AT + 2] == self._switch_seen:
                try:
                    async with asyncio.timeout(left):
                        await self._poke.wait()
                except TimeoutError:
                    return
            await asyncio.sleep(switch_scan_s)
            self.cycle()
