"""Effects outside the rigid 21-error model, each switched on and sized by configuration.

Every effect is a displacement of the tool tip relative to the workpiece *along one axis's
own direction of motion* (the ISO 841 sense: +q moves the tool by +q relative to the
workpiece), which adds to that axis's positioning error. The formulas, with ``q`` the
commanded position of the axis (mm), ``q_min`` the start of its travel, ``T`` the true
temperature at a sensor's place (°C) and ``d`` the direction in which the axis last moved
(-1, 0 or +1):

=====================  ==================================================  =============
effect                 error along the axis, µm                            ``ednc diagnose``
=====================  ==================================================  =============
ThermalExpansion       α · (T - T_ref) · (q - q_min) / 1000                ``thermal_expansion``,
                       (α in µm/(m·K))                                     ``um_per_m_K`` = α
ThermalDrift           k · (T - T_0)  (k in µm/K, signed along +axis)      ``thermal_drift``,
                                                                           ``um_per_K`` = k
Backlash               -(B / 2) · d                                        ``backlash``,
                                                                           ``reversal_um`` = B
Periodic               A · sin(2π (q - q_min) / P + φ)                     ``periodic``,
                                                                           ``amplitude_um`` = A,
                                                                           ``period_mm`` = P
TimeDrift              r · t / 3600  (t: s since the campaign start)       ``time_drift``,
                                                                           ``um_per_h`` = r
RotaryBacklash         -(B / 2) · d on a rotary axis's angle (B in µrad)   ``rotary_backlash``,
                                                                           ``reversal_urad`` = B
=====================  ==================================================  =============

A rotary axis's reversal error is not a translation: the axis stands off its command by
that angle, so the whole chain beyond it turns (:func:`rotary_shift`, which the simulated
machine adds to the axes' positions as a controller's shift would).

A thermal drift with ``lag_s > 0`` follows the sensor place's temperature through a
first-order lag of that time constant (a structure that deforms later than its surface
warms): ``T`` is then the lagged temperature, which :func:`lagged_key` names in the
``temperatures`` mapping (:func:`machine_sim.campaign.run_campaign` provides it).

Backlash sign: the tool lags behind the command by half the reversal, against the
direction of the last motion, so an approach from below (d = +1) stops B/2 short and one
from above overshoots by B/2 in the other sense; ISO 230-2's reversal value at a target is
then x̄↑ - x̄↓ = -B, whose magnitude is B. An axis that has not moved since start-up
(d = 0) sits in the middle of its backlash (no error).

A thermal drift's ``T_0`` is ``reference_C`` when given, else the sensor's temperature at
the start of the campaign (the machine is zeroed cold). A spindle growing downwards on a
vertical machine is a drift along z with a *negative* k.

Measurement noise is Gaussian, independent per reading: ``displacement_um`` for
displacements, ``angle_urad`` for angles (standard deviations).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from volumetric.model.machine import Machine

__all__ = [
    "Backlash",
    "Effects",
    "Noise",
    "Periodic",
    "RotaryBacklash",
    "ThermalDrift",
    "ThermalExpansion",
    "TimeDrift",
    "axis_offsets",
    "lagged_key",
    "rotary_shift",
]

F64 = NDArray[np.float64]


def _finite(where: str, value: float) -> None:
    if not np.isfinite(value):
        raise ValueError(f"{where} must be a finite number, got {value!r}")


@dataclass(frozen=True)
class ThermalExpansion:
    """Scale change of an axis with a sensor's temperature: α·(T - T_ref)·(q - q_min).

    Attributes
    ----------
    axis : str
        Axis name or key (``"x"``, ``"Z1"``).
    sensor : str
        Sensor name (the ``T_<sensor>_C`` column).
    um_per_m_K : float
        α, µm per metre of travel per kelvin (steel ballscrew ≈ 11.5; realistic 0.5 to 12
        for the net effect on a machine with partial compensation).
    reference_C : float
        T_ref: the temperature at which the scale is true.
    """

    axis: str
    sensor: str
    um_per_m_K: float
    reference_C: float = 20.0

    def __post_init__(self) -> None:
        _finite("ThermalExpansion.um_per_m_K", self.um_per_m_K)
        _finite("ThermalExpansion.reference_C", self.reference_C)


@dataclass(frozen=True)
class ThermalDrift:
    """A position-independent drift along an axis: k·(T - T_0) (spindle growth).

    Attributes
    ----------
    axis, sensor : str
    um_per_K : float
        k, µm per kelvin along the axis's +direction (signed; realistic |k| 0.5 to 5).
    reference_C : float or None
        T_0; None for the sensor's temperature at the start of the campaign.
    lag_s : float
        First-order lag of the deformation behind the sensor place's temperature, s
        (0: none).
    """

    axis: str
    sensor: str
    um_per_K: float
    reference_C: float | None = None
    lag_s: float = 0.0

    def __post_init__(self) -> None:
        _finite("ThermalDrift.um_per_K", self.um_per_K)
        if self.reference_C is not None:
            _finite("ThermalDrift.reference_C", self.reference_C)
        if not (np.isfinite(self.lag_s) and self.lag_s >= 0):
            raise ValueError(f"ThermalDrift.lag_s must be >= 0, got {self.lag_s!r}")

    @property
    def key(self) -> str:
        """The ``temperatures`` key this drift reads: the sensor, or its lagged series."""
        return self.sensor if self.lag_s == 0 else lagged_key(self.sensor, self.lag_s)


def lagged_key(sensor: str, lag_s: float) -> str:
    """Name of a sensor place's temperature lagged by ``lag_s`` (``"spindle~600s"``)."""
    return f"{sensor}~{lag_s:g}s"


@dataclass(frozen=True)
class TimeDrift:
    """A drift along an axis growing with time: r·t/3600 (t since campaign start, s).

    Attributes
    ----------
    axis : str
    um_per_h : float
        r, µm per hour along the axis's +direction (signed).
    """

    axis: str
    um_per_h: float

    def __post_init__(self) -> None:
        _finite("TimeDrift.um_per_h", self.um_per_h)


@dataclass(frozen=True)
class Backlash:
    """Lost motion on reversal: -(B/2)·d along the axis (see the module docstring).

    Attributes
    ----------
    axis : str
    reversal_um : float
        B, the full reversal, µm (>= 0; realistic 2 to 15).
    """

    axis: str
    reversal_um: float

    def __post_init__(self) -> None:
        _finite("Backlash.reversal_um", self.reversal_um)
        if self.reversal_um < 0:
            raise ValueError(f"Backlash.reversal_um must be >= 0, got {self.reversal_um}")


@dataclass(frozen=True)
class RotaryBacklash:
    """Lost motion of a rotary axis on reversal (a worm's, a clamped table's): the axis
    stands -(B/2)·d off its command, d the direction it last moved (the sign convention of
    :class:`Backlash`: it lags behind the motion).

    Attributes
    ----------
    axis : str
        A rotary axis.
    reversal_urad : float
        B, the full reversal, µrad (>= 0; realistic 5 to 50).
    """

    axis: str
    reversal_urad: float

    def __post_init__(self) -> None:
        _finite("RotaryBacklash.reversal_urad", self.reversal_urad)
        if self.reversal_urad < 0:
            raise ValueError(f"RotaryBacklash.reversal_urad must be >= 0, got "
                             f"{self.reversal_urad}")


@dataclass(frozen=True)
class Periodic:
    """Cyclic (ballscrew pitch) error: A·sin(2π(q - q_min)/P + φ).

    Attributes
    ----------
    axis : str
    amplitude_um : float
        A, µm (>= 0; realistic 0.5 to 5).
    period_mm : float
        P, mm (> 0; realistic 5 to 25, the screw lead).
    phase_rad : float
        φ.
    """

    axis: str
    amplitude_um: float
    period_mm: float
    phase_rad: float = 0.0

    def __post_init__(self) -> None:
        _finite("Periodic.amplitude_um", self.amplitude_um)
        _finite("Periodic.phase_rad", self.phase_rad)
        if self.amplitude_um < 0:
            raise ValueError(f"Periodic.amplitude_um must be >= 0, got {self.amplitude_um}")
        if not (np.isfinite(self.period_mm) and self.period_mm > 0):
            raise ValueError(f"Periodic.period_mm must be > 0, got {self.period_mm!r}")


@dataclass(frozen=True)
class Noise:
    """Standard deviations of the instruments' Gaussian noise."""

    displacement_um: float = 0.0
    angle_urad: float = 0.0

    def __post_init__(self) -> None:
        for name in ("displacement_um", "angle_urad"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v >= 0):
                raise ValueError(f"Noise.{name} must be a finite number >= 0, got {v!r}")


@dataclass(frozen=True)
class Effects:
    """Which effects a simulated machine has; the default has none (the rigid model only).

    Attributes
    ----------
    expansion, drift, backlash, periodic, time : tuple
        Any number of each (several axes); empty tuples switch them off.
    noise : Noise
    """

    expansion: tuple[ThermalExpansion, ...] = ()
    drift: tuple[ThermalDrift, ...] = ()
    backlash: tuple[Backlash, ...] = ()
    periodic: tuple[Periodic, ...] = ()
    noise: Noise = field(default_factory=Noise)
    time: tuple[TimeDrift, ...] = ()
    rotary_backlash: tuple[RotaryBacklash, ...] = ()
    """Reversal errors of rotary axes (:func:`rotary_shift`; not among :attr:`active`,
    which are the translations along linear axes)."""

    @property
    def active(self) -> bool:
        """Any effect besides noise."""
        return bool(self.expansion or self.drift or self.backlash or self.periodic
                    or self.time)

    def lags(self) -> tuple[tuple[str, float], ...]:
        """(sensor, lag_s) of every lagged thermal drift."""
        return tuple(dict.fromkeys((d.sensor, d.lag_s) for d in self.drift if d.lag_s > 0))

    def sensors(self) -> tuple[str, ...]:
        """The temperature sensors the thermal effects read, in order of first use."""
        out: list[str] = []
        thermal: tuple[ThermalExpansion | ThermalDrift, ...] = (*self.expansion, *self.drift)
        for e in thermal:
            if e.sensor not in out:
                out.append(e.sensor)
        return tuple(out)

    def check(self, machine: Machine, sensors: tuple[str, ...] | None = None) -> None:
        """Raise ``ValueError`` naming the effect whose axis (or sensor) does not exist."""
        groups: dict[str, tuple[ThermalExpansion | ThermalDrift | Backlash | Periodic
                                | TimeDrift, ...]]
        groups = {"expansion": self.expansion, "drift": self.drift,
                  "backlash": self.backlash, "periodic": self.periodic, "time": self.time}
        for group, items in groups.items():
            for i, e in enumerate(items):
                try:
                    axis = machine.axis(e.axis)
                except KeyError as exc:
                    raise ValueError(f"Effects.{group}[{i}]: {exc.args[0]}") from None
                if axis.kind != "linear":
                    raise ValueError(f"Effects.{group}[{i}]: axis {axis.name} is rotary; "
                                     "these effects act along linear axes")
        for i, rb in enumerate(self.rotary_backlash):
            try:
                axis = machine.axis(rb.axis)
            except KeyError as exc:
                raise ValueError(f"Effects.rotary_backlash[{i}]: {exc.args[0]}") from None
            if axis.kind != "rotary":
                raise ValueError(f"Effects.rotary_backlash[{i}]: axis {axis.name} is linear; "
                                 "use Backlash")
        if sensors is not None:
            thermal: tuple[ThermalExpansion | ThermalDrift, ...] = (*self.expansion,
                                                                    *self.drift)
            for t in thermal:
                if t.sensor not in sensors:
                    raise ValueError(f"effect on axis {t.axis} reads sensor {t.sensor!r}, "
                                     f"which the thermal model does not have ({sensors})")


def axis_offsets(
    machine: Machine,
    effects: Effects,
    q: F64,
    direction: NDArray[np.integer],
    temperatures: Mapping[str, F64],
    start_temperatures: Mapping[str, float],
    time_s: F64 | None = None,
) -> F64:
    """The effects' error along each axis at given readings (module docstring formulas).

    Parameters
    ----------
    machine : Machine
    effects : Effects
    q : ndarray, shape (N, n_axes)
        Commanded positions in ``machine.axes`` order, mm or degrees.
    direction : ndarray of int, shape (N, n_axes)
        Direction each axis last moved: -1, 0 or +1.
    temperatures : mapping of str to ndarray, shape (N,)
        True temperature at each sensor's place at the reading times, °C; lagged drifts
        read their :func:`lagged_key`.
    start_temperatures : mapping of str to float
        Each sensor's temperature at the start of the campaign, °C (for drifts without
        ``reference_C``).
    time_s : ndarray, shape (N,), optional
        Seconds since the campaign start (needed by time drifts).

    Returns
    -------
    ndarray, shape (N, n_axes)
        µm along each axis's own direction (zero for axes without effects).
    """
    n = q.shape[0]
    out = np.zeros((n, len(machine.axes)))
    for e in effects.expansion:
        j = machine.axis_names.index(machine.axis(e.axis).name)
        lo = machine.axes[j].travel[0]
        dt = temperatures[e.sensor] - e.reference_C
        out[:, j] += e.um_per_m_K * dt * (q[:, j] - lo) * 1e-3
    for d in effects.drift:
        j = machine.axis_names.index(machine.axis(d.axis).name)
        t0 = start_temperatures[d.sensor] if d.reference_C is None else d.reference_C
        out[:, j] += d.um_per_K * (temperatures[d.key] - t0)
    for b in effects.backlash:
        j = machine.axis_names.index(machine.axis(b.axis).name)
        out[:, j] += -0.5 * b.reversal_um * np.sign(direction[:, j])
    for p in effects.periodic:
        j = machine.axis_names.index(machine.axis(p.axis).name)
        lo = machine.axes[j].travel[0]
        out[:, j] += p.amplitude_um * np.sin(2 * np.pi * (q[:, j] - lo) / p.period_mm
                                             + p.phase_rad)
    for r in effects.time:
        if time_s is None:
            raise ValueError(f"a time drift on axis {r.axis} needs the reading times")
        j = machine.axis_names.index(machine.axis(r.axis).name)
        out[:, j] += r.um_per_h * np.asarray(time_s, dtype=float) / 3600.0
    return out


def rotary_shift(machine: Machine, effects: Effects, q: F64,
                 direction: NDArray[np.integer] | None) -> F64 | None:
    """Where the rotary axes' reversal errors put them off their command, degrees, shape
    (N, n_axes) (zero for the other axes), or None without any.

    Parameters
    ----------
    machine : Machine
    effects : Effects
    q : ndarray, shape (N, n_axes)
        Commanded positions (only the shape is used).
    direction : ndarray of int, shape (N, n_axes), optional
        Direction each axis last moved: -1, 0 or +1 (0 when omitted: no reversal error).
    """
    if not effects.rotary_backlash:
        return None
    out = np.zeros(q.shape)
    if direction is None:
        return out
    d = np.asarray(direction).reshape(q.shape)
    for b in effects.rotary_backlash:
        j = machine.axis_names.index(machine.axis(b.axis).name)
        out[:, j] += np.rad2deg(-0.5 * b.reversal_urad * 1e-6) * np.sign(d[:, j])
    return out
