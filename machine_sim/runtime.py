"""A running simulated machine: motion, temperatures and its controller, step by step.

Synchronous and free of I/O: :mod:`machine_sim.link` drives it from the event loop.

* Motion: every axis follows its own slow sine inside its travel (a part program's
  envelope); the last direction of motion is the sign of the velocity.
* Temperatures: the machine's thermal model (:mod:`machine_sim.thermal`) integrated ahead
  for ``hours`` of a shop duty cycle (spindle 40 min on at ``duty_rpm``, 20 min off, axes
  moving while it runs), read with sensor noise and wrapped around after that.
* Controller: :class:`~machine_sim.fanuc.FanucPMC` (``scan``) or
  :class:`~machine_sim.siemens.SiemensNC` (``ipo_cycle``) by the machine's ``controller``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from volumetric.model.machine import Machine

from .fanuc import FanucConfig, FanucPMC
from .siemens import SiemensConfig, SiemensNC
from .thermal import ThermalConfig, ThermalHistory, default_thermal, simulate_thermal

__all__ = ["MachineRuntime", "Motion", "duty_cycle_thermal"]

F64 = NDArray[np.float64]


@dataclass(frozen=True)
class Motion:
    """Per-axis sine motion: ``centre + amplitude · sin(2π t / period + phase)``."""

    centre: F64
    amplitude: F64
    period_s: F64
    phase: F64
    _w: F64 = field(init=False, repr=False, compare=False)
    """2π / period_s, rad/s: the same array every call, so computed once."""

    def __post_init__(self) -> None:
        object.__setattr__(self, "_w", 2 * np.pi / self.period_s)

    @staticmethod
    def random(machine: Machine, rng: np.random.Generator) -> Motion:
        lo, hi = machine.travel_lo, machine.travel_hi
        centre = 0.5 * (lo + hi)
        amplitude = 0.45 * (hi - lo) * rng.uniform(0.3, 1.0, lo.shape)
        return Motion(centre, amplitude, rng.uniform(20.0, 120.0, lo.shape),
                      rng.uniform(0.0, 2 * np.pi, lo.shape))

    def at(self, t: float) -> tuple[F64, NDArray[np.int8]]:
        """Positions (n_axes,) and last directions (n_axes,) at time t, s."""
        w = self._w
        arg = w * t + self.phase
        q: F64 = self.centre + self.amplitude * np.sin(arg)
        d = np.sign(np.cos(arg)).astype(np.int8)
        return q, d


def duty_cycle_thermal(config: ThermalConfig, *, hours: float = 12.0, step_s: float = 5.0,
                       duty_rpm: float = 6000.0, seed: int = 0,
                       warmup: bool = False) -> ThermalHistory:
    """Temperatures over a shop duty cycle (module docstring), or, with ``warmup``, a cold
    machine whose spindle runs without a pause (temperatures rise over the whole span)."""
    t = np.arange(0.0, hours * 3600.0, step_s)
    on = np.ones(t.shape, dtype=bool) if warmup else (t % 3600.0) < 2400.0
    rpm = np.where(on, duty_rpm, 0.0)
    speeds: dict[str, F64] = {}
    for s in config.sensors:
        for key, _ in s.motion_K_per_m_min:
            speeds[key] = np.where(on, 2.0, 0.2)  # m/min while a part runs, creeping else
    return simulate_thermal(config, t, rpm, speeds, seed)


class MachineRuntime:
    """One machine's motion, temperatures and controller.

    Parameters
    ----------
    machine : Machine
    seed : int
    thermal : ThermalConfig, optional
    fanuc, siemens : config, optional
        Controller settings for the machine's controller family.
    thermal_speedup : float
        Machine-temperature seconds per second of run time: a demo shows an hour of
        warm-up in a minute with 60; motion and controller keep real time (the
        controller's plausible temperature rate is scaled by it).
    own_sensors : bool, optional
        The controller reads the machine's sensors itself (stored in
        ``controller.temperatures`` every ``sensor_period_s``); by default a Siemens-style
        NC does (its sensors are on the PLC) and a Fanuc-style one does not (its sensors
        publish to MQTT and the center forwards them in Temperatures messages).
    sensor_period_s : float
        How often the controller reads its own sensors, s (not every cycle: a reading
        costs more than a cycle's budget and temperatures move over minutes).
    warmup : bool
        A cold machine whose spindle runs at 9000 rpm without a pause, instead of the shop
        duty cycle (the demo's warm-up).
    """

    def __init__(self, machine: Machine, *, seed: int = 0, thermal: ThermalConfig | None = None,
                 fanuc: FanucConfig | None = None, siemens: SiemensConfig | None = None,
                 thermal_speedup: float = 1.0, own_sensors: bool | None = None,
                 sensor_period_s: float = 1.0, warmup: bool = False) -> None:
        if not thermal_speedup > 0:
            raise ValueError(f"thermal_speedup must be > 0, got {thermal_speedup!r}")
        self.machine = machine
        self.thermal_speedup = float(thermal_speedup)
        rng = np.random.default_rng(seed)
        self.motion = Motion.random(machine, rng)
        self.thermal = duty_cycle_thermal(thermal or default_thermal(machine), seed=seed,
                                          warmup=warmup,
                                          duty_rpm=9000.0 if warmup else 6000.0)
        self._noise = np.random.default_rng([seed, 7])
        self.controller: FanucPMC | SiemensNC
        if machine.controller == "siemens":
            self.controller = SiemensNC(machine.name, machine.axis_names, siemens)
            self.cycle_s = self.controller.config.ipo_s
        else:
            self.controller = FanucPMC(machine.name, machine.axis_names, fanuc)
            self.cycle_s = self.controller.config.scan_s
        # the temperatures' plausible rate of change is in machine-temperature time
        self.controller.temperatures.max_rate_K_per_s *= self.thermal_speedup
        self.positions, self.directions = self.motion.at(0.0)
        self.own_sensors = (machine.controller == "siemens" if own_sensors is None
                            else bool(own_sensors))
        self.sensor_period_s = float(sensor_period_s)
        self._sensors_read_s = float("-inf")

    def read_own_sensors(self, now_s: float) -> None:
        """Store the machine's own sensor readings at ``now_s`` in the controller's
        temperatures, at most every ``sensor_period_s`` (no-op without own sensors)."""
        if not self.own_sensors or now_s - self._sensors_read_s < self.sensor_period_s:
            return
        self._sensors_read_s = now_s
        store = self.controller.temperatures
        for sensor, celsius in self.temperatures(now_s).items():
            store.update(sensor, celsius, now_s, "sensor")

    def step(self, now_s: float) -> F64:
        """Move to time ``now_s`` and run one controller cycle; returns the applied
        compensation per axis, mm (degrees)."""
        self.positions, self.directions = self.motion.at(now_s)
        self.read_own_sensors(now_s)
        c = self.controller
        if isinstance(c, SiemensNC):
            return c.ipo_cycle(now_s, self.positions, self.directions)
        c.scan(now_s, self.positions, self.directions)
        return c.applied_mm()

    def temperatures(self, now_s: float) -> dict[str, float]:
        """Sensor readings at ``now_s`` (wrapping around the precomputed span), °C."""
        span = float(self.thermal.time_s[-1])
        t = np.array([(now_s * self.thermal_speedup) % span])
        return {k: float(v[0]) for k, v in self.thermal.read_at(t, self._noise).items()}
