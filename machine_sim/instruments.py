"""A simulated machine's true error and what the instruments read of it.

The true error of the tool tip relative to the workpiece at a reading is the rigid
geometry's exact volumetric error (:func:`volumetric.model.kinematics.volumetric_error`) plus the
effects of :mod:`machine_sim.effects`, each a translation along its axis's line of motion
inserted at that axis's place in the chain, exactly as if it were part of the axis's
positioning error (so on a five-axis machine a table rotation turns it with the
workpiece, and the other axes' angular errors tilt it). A laser or level reads that error
projected on its sensing direction ``u`` (displacement, µm) or the orientation error
about ``u`` (angle, µrad), plus Gaussian noise.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike, NDArray

from volumetric.model.components import GeometricErrors, Polynomial, add_components
from volumetric.model.exact import VolumetricError, volumetric_error
from volumetric.model.kinematics import tool_pose
from volumetric.model.machine import Axis, Machine
from volumetric.model.rigid import rotation_vector

from .effects import Effects, axis_offsets, rotary_shift
from .program import MotionLimits
from .thermal import ThermalConfig, default_thermal

__all__ = ["SimulatedMachine"]

F64 = NDArray[np.float64]
PROBE_UM = 1000.0  # large enough that float round-off of the mm positions is negligible


def _shift_positioning(geometry: GeometricErrors, axis: Axis, by: float) -> GeometricErrors:
    """The geometry with ``by`` (µm) added to the axis's own positioning component."""
    own = "XYZ"[{"X": 0, "Y": 1}.get(axis.name, 2)]
    name = f"E{own}{axis.name}"
    shifted = add_components(geometry.components.get(name), Polynomial((by,)))
    return GeometricErrors({**geometry.components, name: shifted}, geometry.locations)


@dataclass(frozen=True)
class SimulatedMachine:
    """A machine with a physics the control center does not know.

    Attributes
    ----------
    machine : Machine
    geometry : GeometricErrors
        The true rigid errors (e.g. :func:`machine_sim.truth.random_geometry`).
    effects : Effects
        Non-rigid effects and instrument noise; none by default.
    thermal : ThermalConfig or None
        Sensors and shop air; :func:`machine_sim.thermal.default_thermal` when None.
    seed : int
        Seeds the thermal model and the instrument noise: same seed, same readings.
    limits : MotionLimits
    """

    machine: Machine
    geometry: GeometricErrors
    effects: Effects = field(default_factory=Effects)
    thermal: ThermalConfig | None = None
    seed: int = 0
    limits: MotionLimits = field(default_factory=MotionLimits)

    def __post_init__(self) -> None:
        self.geometry.check(self.machine)
        self.effects.check(self.machine, self.thermal_config.names)

    @property
    def thermal_config(self) -> ThermalConfig:
        return self.thermal if self.thermal is not None else default_thermal(self.machine)

    def true_error(
        self,
        q: ArrayLike,
        direction: ArrayLike | None = None,
        temperatures: Mapping[str, ArrayLike] | None = None,
        start_temperatures: Mapping[str, float] | None = None,
        *,
        spindle: str | None = None,
        tool_mm: ArrayLike | None = None,
        compensation: ArrayLike | None = None,
        time_s: ArrayLike | None = None,
    ) -> VolumetricError:
        """The tool tip's true error relative to the workpiece, noise-free.

        With ``compensation`` the axes stand at ``q + compensation`` (what the controller's
        shift does) while the error is still taken against the nominal pose at the
        commanded ``q``: the residual error of a compensated machine.

        Parameters
        ----------
        q : array_like, shape (N, n_axes)
            Commanded positions in ``machine.axes`` order, mm or degrees.
        direction : array_like of int, shape (N, n_axes), optional
            Last direction of motion per axis (-1, 0, +1); zeros when omitted.
        temperatures : mapping of sensor to array_like (N,), optional
            True temperatures at the sensors' places, °C; needed when a thermal effect is on.
        start_temperatures : mapping of sensor to float, optional
            Temperatures at campaign start (thermal drifts without ``reference_C``);
            ``temperatures`` at the first reading when omitted.
        spindle : str, optional
        tool_mm : float or array_like (N,), optional
        compensation : array_like, shape (N, n_axes), optional
            Shift the controller applies per axis, mm or degrees.
        time_s : array_like, shape (N,), optional
            Seconds since the campaign start (time drifts).

        Returns
        -------
        VolumetricError
            Position (µm) and orientation (µrad) errors, shape (N, 3) each.
        """
        qc = np.atleast_2d(np.asarray(q, dtype=float))
        turned = rotary_shift(self.machine, self.effects, qc,
                              None if direction is None else np.asarray(direction))
        if turned is not None:
            # a rotary axis's reversal error puts the axis off its command, as a shift does
            compensation = turned + (0.0 if compensation is None else np.asarray(
                compensation, dtype=float).reshape(qc.shape))
        if compensation is None:
            qa = qc
            rigid = volumetric_error(self.machine, self.geometry, qa, spindle=spindle,
                                     tool_mm=tool_mm)
        else:
            qa = qc + np.asarray(compensation, dtype=float).reshape(qc.shape)
            p_act, r_act = tool_pose(self.machine, qa, self.geometry, spindle=spindle,
                                     tool_mm=tool_mm)
            p_nom, r_nom = tool_pose(self.machine, qc, None, spindle=spindle, tool_mm=tool_mm)
            assert r_act is not None and r_nom is not None
            rigid = VolumetricError((p_act - p_nom) * 1e3,
                                    rotation_vector(r_act @ np.swapaxes(r_nom, 1, 2)) * 1e6)
        e = self.effects
        if not e.active:
            return rigid
        n = qa.shape[0]
        d = (np.zeros(qa.shape, dtype=np.int8) if direction is None
             else np.asarray(direction).reshape(qa.shape))
        temps: dict[str, F64] = {}
        keys = [*e.sensors(), *(d.key for d in e.drift)]
        for s in dict.fromkeys(keys):
            if temperatures is None or s not in temperatures:
                raise ValueError(f"a thermal effect reads {s!r}: pass its temperatures")
            temps[s] = np.broadcast_to(np.asarray(temperatures[s], dtype=float), (n,))
        starts = dict(start_temperatures) if start_temperatures is not None else {
            k: float(v[0]) for k, v in temps.items()}
        times = None if time_s is None else np.broadcast_to(
            np.asarray(time_s, dtype=float), (n,))
        offsets = axis_offsets(self.machine, e, qa, d, temps, starts, times)
        p_rigid, _ = tool_pose(self.machine, qa, self.geometry, spindle=spindle,
                               tool_mm=tool_mm, orientation=False)
        branch = self.machine.branch(spindle)
        extra = np.zeros((n, 3))
        for j, axis in enumerate(self.machine.axes):
            if axis not in branch.links or not np.any(offsets[:, j]):
                continue
            # The tool tip is affine in a translation inserted at one link (it turns
            # nothing), so one probe of PROBE_UM along the axis gives its exact image.
            probe = _shift_positioning(self.geometry, axis, PROBE_UM)
            p_probe, _ = tool_pose(self.machine, qa, probe, spindle=spindle,
                                   tool_mm=tool_mm, orientation=False)
            extra += (p_probe - p_rigid) * (1e3 / PROBE_UM) * offsets[:, j, None]
        return VolumetricError(rigid.position_um + extra, rigid.orientation_urad)

    def read(
        self,
        error: VolumetricError,
        u: ArrayLike,
        is_angle: ArrayLike,
        rng: np.random.Generator | None,
    ) -> F64:
        """Instrument readings of given true errors: projection on u plus noise.

        Parameters
        ----------
        error : VolumetricError
            With orientation, shape (N, 3) each.
        u : array_like, shape (N, 3)
            Unit sensing directions (displacement) or rotation axes (angle).
        is_angle : array_like of bool, shape (N,)
        rng : numpy.random.Generator or None
            Source of the noise; None for the noise-free reading.

        Returns
        -------
        ndarray, shape (N,)
            µm for displacements, µrad for angles.
        """
        uu = np.asarray(u, dtype=float)
        ang = np.asarray(is_angle, dtype=bool)
        if error.orientation_urad is None:
            raise ValueError("readings of angles need the orientation error")
        disp = np.einsum("ni,ni->n", error.position_um, uu)
        rot = np.einsum("ni,ni->n", error.orientation_urad, uu)
        value: F64 = np.where(ang, rot, disp)
        if rng is None:
            return value
        sigma = np.where(ang, self.effects.noise.angle_urad, self.effects.noise.displacement_um)
        out: F64 = value + rng.normal(0.0, 1.0, value.shape) * sigma
        return out
