"""Simulated temperatures of a machine tool: structure, sensors and shop air.

Model (one lumped first-order body per sensor place, exact for inputs held over a step):

* Shop air: ``T_air(t) = mean + amplitude · cos(2π (h(t) - peak_hour) / 24) + w(t)`` with
  ``h`` the time of day in hours and ``w`` an Ornstein-Uhlenbeck wander (stationary
  standard deviation ``wander_K``, correlation time ``wander_tau_s``).
* Each sensor's place ``i`` follows ``τ_i dT_i/dt = T_air + offset_i + ΔT_i(t) - T_i``
  where the steady rise ``ΔT_i`` is ``spindle_K_per_krpm · rpm / 1000`` plus, per axis,
  ``K_per_m_min · v̄`` with ``v̄`` the axis's mean speed over the step (m/min). ``τ = 0``
  makes the place follow the air at once (the air sensor itself).
* The sensor (PT100-like) lags its place by a first-order ``lag_s`` and reads with
  Gaussian noise ``noise_K``.

The *true* temperature (no lag, no noise) drives the thermal effects of
:mod:`machine_sim.effects`; the *reading* goes into the ``T_<sensor>_C`` columns. A model
is deterministic given its seed: the air wander and the reading noise come from
``numpy.random.default_rng(seed)`` streams of their own.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray
from scipy.signal import lfilter

from volumetric.model.machine import Machine

__all__ = [
    "Sensor",
    "ShopAir",
    "ThermalConfig",
    "ThermalHistory",
    "default_thermal",
    "lag_series",
    "simulate_thermal",
]

F64 = NDArray[np.float64]


@dataclass(frozen=True)
class Sensor:
    """One temperature sensor and the structure it sits on.

    Attributes
    ----------
    name : str
        Column ``T_<name>_C``; letters, digits and underscores.
    tau_s : float
        Thermal time constant of the place, s (0: follows the air at once).
    spindle_K_per_krpm : float
        Steady-state rise over air per 1000 spindle rpm, K.
    motion_K_per_m_min : tuple of (str, float)
        Steady-state rise per m/min of an axis's mean speed, K, by axis key.
    offset_K : float
        Steady offset over air with everything at rest (a warm cabinet nearby), K.
    lag_s : float
        The sensor's own first-order lag, s.
    noise_K : float
        Standard deviation of the reading noise, K.
    """

    name: str
    tau_s: float
    spindle_K_per_krpm: float = 0.0
    motion_K_per_m_min: tuple[tuple[str, float], ...] = ()
    offset_K: float = 0.0
    lag_s: float = 20.0
    noise_K: float = 0.02

    def __post_init__(self) -> None:
        if not self.name or not self.name.replace("_", "a").isalnum():
            raise ValueError(f"sensor name {self.name!r} must be letters, digits, underscores")
        for attr in ("tau_s", "lag_s", "noise_K"):
            v = getattr(self, attr)
            if not (np.isfinite(v) and v >= 0):
                raise ValueError(f"sensor {self.name}: {attr} must be finite and >= 0, "
                                 f"got {v!r}")
        for attr in ("spindle_K_per_krpm", "offset_K"):
            if not np.isfinite(getattr(self, attr)):
                raise ValueError(f"sensor {self.name}: {attr} must be finite")


@dataclass(frozen=True)
class ShopAir:
    """Shop air temperature: a daily cycle plus a slow random wander.

    Attributes
    ----------
    mean_C, daily_amplitude_K : float
    peak_hour : float
        Hour of day of the warmest air.
    start_hour : float
        Hour of day at campaign time 0.
    wander_K, wander_tau_s : float
        Stationary standard deviation (K) and correlation time (s) of the wander.
    """

    mean_C: float = 20.0
    daily_amplitude_K: float = 1.5
    peak_hour: float = 15.0
    start_hour: float = 7.0
    wander_K: float = 0.15
    wander_tau_s: float = 1800.0


@dataclass(frozen=True)
class ThermalConfig:
    """Sensors, shop air and the integration step."""

    sensors: tuple[Sensor, ...]
    air: ShopAir = field(default_factory=ShopAir)
    step_s: float = 2.0

    def __post_init__(self) -> None:
        names = [s.name for s in self.sensors]
        if len(set(names)) != len(names):
            raise ValueError(f"sensor names must be unique, got {names}")
        if not (np.isfinite(self.step_s) and self.step_s > 0):
            raise ValueError(f"step_s must be > 0, got {self.step_s!r}")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(s.name for s in self.sensors)


def default_thermal(machine: Machine, *, step_s: float = 2.0) -> ThermalConfig:
    """The usual sensor set: spindle, one per linear axis's ballscrew, column, bed, air.

    Sizes are those of a mid-size machining centre: the spindle housing rises ~1.2 K per
    1000 rpm with a 25 min time constant; a ballscrew ~1.5 K per m/min of mean speed
    (15 min); the column follows the spindle slowly (1.5 h); the bed barely moves (4 h).
    """
    linear = [a.key for a in machine.axes if a.kind == "linear"]
    sensors = [Sensor("spindle", tau_s=1500.0, spindle_K_per_krpm=1.2)]
    for k in linear:
        sensors.append(Sensor(f"{k}_screw", tau_s=900.0, motion_K_per_m_min=((k, 1.5),),
                              spindle_K_per_krpm=0.05))
    sensors.append(Sensor("column", tau_s=5400.0, spindle_K_per_krpm=0.35))
    sensors.append(Sensor("bed", tau_s=14400.0, spindle_K_per_krpm=0.08, offset_K=0.3))
    sensors.append(Sensor("air", tau_s=0.0, lag_s=10.0))
    return ThermalConfig(tuple(sensors), ShopAir(), step_s)


@dataclass(frozen=True)
class ThermalHistory:
    """Temperatures over a time grid; interpolate between its steps.

    Attributes
    ----------
    time_s : ndarray, shape (M,)
    true_C : dict of str to ndarray (M,)
        Temperature at each sensor's place.
    sensed_C : dict of str to ndarray (M,)
        What the lagged sensor shows, before noise.
    noise_K : dict of str to float
    seed : int
    """

    time_s: F64
    true_C: dict[str, F64]
    sensed_C: dict[str, F64]
    noise_K: dict[str, float]
    seed: int

    def true_at(self, t: F64) -> dict[str, F64]:
        """True temperatures at times t (N,), °C."""
        return {k: np.interp(t, self.time_s, v) for k, v in self.true_C.items()}

    def start(self) -> dict[str, float]:
        """True temperatures at the first grid time, °C."""
        return {k: float(v[0]) for k, v in self.true_C.items()}

    def read_at(self, t: F64, rng: np.random.Generator) -> dict[str, F64]:
        """Sensor readings at times t (N,): lagged values plus noise from ``rng``, °C."""
        out = {}
        for k, v in self.sensed_C.items():
            out[k] = np.interp(t, self.time_s, v) + rng.normal(0.0, self.noise_K[k], t.shape)
        return out


def _lag(x: F64, tau_s: float, dt: float, y0: float) -> F64:
    """First-order lag of x sampled every dt with y[0] = y0 (exact for held inputs)."""
    if tau_s <= 0:
        return x.copy()
    a = float(np.exp(-dt / tau_s))
    # y[n] = a y[n-1] + (1 - a) x[n-1]: filter x shifted by one step
    # (transposed direct form: y[0] = zi = y0)
    y, _ = lfilter([0.0, 1.0 - a], [1.0, -a], x, zi=[y0])
    out: F64 = np.asarray(y, dtype=float)
    return out


def lag_series(time_s: F64, values: F64, lag_s: float) -> F64:
    """A series sampled on a regular grid passed through a first-order lag of ``lag_s``,
    starting in equilibrium with its first value."""
    if time_s.size < 2:
        return values.copy()
    return _lag(values, lag_s, float(time_s[1] - time_s[0]), float(values[0]))


def simulate_thermal(
    config: ThermalConfig,
    time_s: F64,
    spindle_rpm: F64,
    axis_speed_m_min: Mapping[str, F64],
    seed: int,
) -> ThermalHistory:
    """Integrate the model over a regular time grid.

    Parameters
    ----------
    config : ThermalConfig
    time_s : ndarray, shape (M,)
        Regular grid, s, starting at campaign time 0 (or wherever the inputs start).
    spindle_rpm : ndarray, shape (M,)
        Mean spindle speed over the step that starts at each grid time (last unused).
    axis_speed_m_min : mapping of axis key to ndarray (M,)
        Mean speed of each axis over the same steps, m/min.
    seed : int

    Returns
    -------
    ThermalHistory
        Every place starts in equilibrium with the air at time_s[0] (a cold machine).
    """
    t = np.asarray(time_s, dtype=float)
    if t.ndim != 1 or t.size < 2:
        raise ValueError("the thermal time grid needs at least two times")
    dt = float(t[1] - t[0])
    rng = np.random.default_rng([seed, 1])
    air = config.air
    hours = air.start_hour + t / 3600.0
    t_air = air.mean_C + air.daily_amplitude_K * np.cos(2 * np.pi * (hours - air.peak_hour) / 24)
    if air.wander_K > 0 and air.wander_tau_s > 0:
        a = float(np.exp(-dt / air.wander_tau_s))
        shocks = rng.normal(0.0, air.wander_K * np.sqrt(1 - a * a), t.size)
        w0 = rng.normal(0.0, air.wander_K)
        wander, _ = lfilter([1.0], [1.0, -a], shocks, zi=[a * w0])
        t_air = t_air + np.asarray(wander, dtype=float)
    true: dict[str, F64] = {}
    sensed: dict[str, F64] = {}
    for s in config.sensors:
        target = t_air + s.offset_K + s.spindle_K_per_krpm * spindle_rpm / 1000.0
        for key, gain in s.motion_K_per_m_min:
            speed = axis_speed_m_min.get(key)
            if speed is not None:
                target = target + gain * speed
        start = float(t_air[0] + s.offset_K)
        place = _lag(target, s.tau_s, dt, start)
        true[s.name] = place
        sensed[s.name] = _lag(place, s.lag_s, dt, start)
    return ThermalHistory(t, true, sensed, {s.name: s.noise_K for s in config.sensors}, seed)
