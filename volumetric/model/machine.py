"""Machine descriptions: the kinematic chain from workpiece to tool, its axes and travels.

A machine is a serial chain written as in ``shared/spec/formats.md`` section 1, e.g.
``w X Y b Z t``: tokens between ``w`` (workpiece) and ``b`` (base) carry the workpiece,
the token next to ``b`` riding on the base; tokens between ``b`` and ``t`` (tool) carry
the tool the same way. ``X Y Z`` are linear axes along the base's x, y, z; ``A B C`` rotary
axes about x, y, z. Multi-spindle machines add tool branches (``spindles``), each with its
own linear axis along a given unit vector, after the shared chain.

Conventions (pinned by ``tests/test_machine.py`` and ``tests/test_kinematics.py``):

* ISO 841: the tool moves by +q relative to the workpiece when the command q grows,
  whichever side the axis is on. Rotary axes likewise turn the tool by +q about their
  axis relative to the workpiece (right-hand rule).
* The tool points along the negative direction of the last linear axis of its branch:
  on a vertical machine the tool tip is ``tool_length_mm`` below the spindle gauge line.
* Machine coordinates are in mm (linear) and degrees (rotary).
"""

from __future__ import annotations

import ipaddress
import json
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from volumetric.errors import MachineSpecError
from volumetric.model.typenumbers import chain_for_type_numbers
from volumetric.plausible.angles import ROTARY_POSITION, rotary_travel_warning
from volumetric.plausible.files import decode_text, wrong_file
from volumetric.plausible.lengths import (
    LINEAR_POSITION,
    TOOL_LENGTH,
    length_cause,
    linear_travels_problem,
    short_travel_warning,
)

Side = Literal["workpiece", "tool"]
Kind = Literal["linear", "rotary"]

LINEAR_AXES = ("X", "Y", "Z")
ROTARY_AXES = ("A", "B", "C")
_UNIT = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}
_UNIT.update({"A": _UNIT["X"], "B": _UNIT["Y"], "C": _UNIT["Z"]})
_SPINDLE_AXIS = re.compile(r"^[XYZ][0-9]+$")
# Rotary axes need no travel in a description; a full turn either way is the default.
DEFAULT_ROTARY_TRAVEL_DEG = (-180.0, 180.0)


@dataclass(frozen=True)
class Axis:
    """One axis of the chain.

    Attributes
    ----------
    name : str
        ``X``, ``Y``, ``Z``, ``A``, ``B``, ``C`` or a spindle axis such as ``Z1``.
    kind : {"linear", "rotary"}
    side : {"workpiece", "tool"}
        Which side of the base the axis carries.
    direction : tuple of float
        Unit vector of the axis (line of motion or rotation axis) in the base frame at
        zero of all other axes.
    pivot_mm : tuple of float
        A point on the rotation axis (rotary axes), base frame at zero, mm.
    travel : tuple of float
        Lower and upper travel, mm or degrees.
    """

    name: str
    kind: Kind
    side: Side
    direction: tuple[float, float, float]
    pivot_mm: tuple[float, float, float] = (0.0, 0.0, 0.0)
    travel: tuple[float, float] = (0.0, 0.0)

    @property
    def key(self) -> str:
        """The lower-case name used in ``travel_mm`` and coordinate columns."""
        return self.name.lower()


@dataclass(frozen=True)
class ToolBranch:
    """One tool tip: the shared chain plus, for multi-spindle machines, a spindle axis.

    Attributes
    ----------
    name : str
        The spindle name (``"main"`` for single-spindle machines).
    links : tuple of Axis
        The axes from workpiece to tool in chain order (``b`` removed).
    tool_length_mm : float
        Default tool length of this tip.
    tool_direction : tuple of float
        Unit vector from the gauge line towards the tool tip, base frame at zero.
    """

    name: str
    links: tuple[Axis, ...]
    tool_length_mm: float
    tool_direction: tuple[float, float, float]


@dataclass(frozen=True)
class Machine:
    """A machine tool's nominal geometry.

    Attributes
    ----------
    name, controller, ip : str
        Identity; ``controller`` is ``"fanuc"`` or ``"siemens"``.
    chain : str
        The normalised chain string.
    axes : tuple of Axis
        Every axis of the machine: shared ones in chain order, then spindle axes.
    branches : tuple of ToolBranch
        One per tool tip.
    translational_type, rotary_type : int or None
        The generalized model's type numbers when the description gave them.
    """

    name: str
    controller: str
    ip: str
    chain: str
    axes: tuple[Axis, ...]
    branches: tuple[ToolBranch, ...]
    translational_type: int | None = None
    rotary_type: int | None = None
    extra: Mapping[str, Any] = field(default_factory=dict)

    @property
    def axis_names(self) -> tuple[str, ...]:
        return tuple(a.name for a in self.axes)

    def axis(self, name: str) -> Axis:
        for a in self.axes:
            if a.name == name or a.key == name:
                return a
        raise KeyError(f"machine {self.name!r} has no axis {name!r} (it has {self.axis_names})")

    def branch(self, name: str | None = None) -> ToolBranch:
        if name is None or name == "":
            return self.branches[0]
        for b in self.branches:
            if b.name == name:
                return b
        names = [b.name for b in self.branches]
        raise KeyError(f"machine {self.name!r} has no spindle {name!r} (it has {names})")

    @property
    def travel_lo(self) -> NDArray[np.float64]:
        """Lower travel per axis, shape (n_axes,), mm or degrees."""
        return np.array([a.travel[0] for a in self.axes])

    @property
    def travel_hi(self) -> NDArray[np.float64]:
        """Upper travel per axis, shape (n_axes,), mm or degrees."""
        return np.array([a.travel[1] for a in self.axes])


def parse_chain(chain: str) -> tuple[list[str], list[str]]:
    """Split a chain string into its workpiece-side and tool-side axis tokens.

    Parameters
    ----------
    chain : str
        E.g. ``"w X Y b Z t"``.

    Returns
    -------
    workpiece, tool : list of str
        Axis tokens in chain order (from ``w`` to ``b``, and from ``b`` to ``t``).

    Raises
    ------
    MachineSpecError
        On an unknown token, an axis twice, or ``w``/``b``/``t`` missing or misplaced.
    """
    if not isinstance(chain, str) or not chain.strip():
        raise MachineSpecError("chain: empty; expected tokens such as 'w X Y b Z t'")
    tokens = chain.split()
    allowed = {"w", "b", "t", *LINEAR_AXES, *ROTARY_AXES}
    for i, tok in enumerate(tokens):
        if tok not in allowed:
            raise MachineSpecError(
                f"chain {chain!r}: unknown token {tok!r} at position {i + 1}; "
                "allowed are w, b, t and the axes X Y Z A B C"
            )
    for marker in ("w", "b", "t"):
        count = tokens.count(marker)
        if count != 1:
            raise MachineSpecError(
                f"chain {chain!r}: needs exactly one {marker!r} "
                f"({'workpiece' if marker == 'w' else 'base' if marker == 'b' else 'tool'}),"
                f" found {count}"
            )
    if tokens[0] != "w":
        raise MachineSpecError(f"chain {chain!r}: must start with 'w' (the workpiece)")
    if tokens[-1] != "t":
        raise MachineSpecError(f"chain {chain!r}: must end with 't' (the tool)")
    seen: dict[str, int] = {}
    for i, tok in enumerate(tokens):
        if tok in ("w", "b", "t"):
            continue
        if tok in seen:
            raise MachineSpecError(
                f"chain {chain!r}: axis {tok} appears twice (positions {seen[tok] + 1} and {i + 1})"
            )
        seen[tok] = i
    ib = tokens.index("b")
    return tokens[1:ib], tokens[ib + 1 : -1]


def _vector(value: Any, where: str, *, unit: bool) -> tuple[float, float, float]:
    if not isinstance(value, Sequence) or isinstance(value, str) or len(value) != 3:
        raise MachineSpecError(f"{where}: expected a list of three numbers, got {value!r}")
    try:
        v = tuple(float(x) for x in value)
    except (TypeError, ValueError):
        raise MachineSpecError(f"{where}: expected three numbers, got {value!r}") from None
    if not all(math.isfinite(x) for x in v):
        raise MachineSpecError(f"{where}: values must be finite, got {value!r}")
    if unit:
        n = math.sqrt(sum(x * x for x in v))
        if abs(n - 1.0) > 1e-6:
            raise MachineSpecError(f"{where}: must be a unit vector, |v| = {n:.6g}")
    return (v[0], v[1], v[2])


def _travel(
    raw: Mapping[str, Any], key: str, kind: Kind, machine: str
) -> tuple[float, float]:
    if key not in raw:
        if kind == "rotary":
            return DEFAULT_ROTARY_TRAVEL_DEG
        raise MachineSpecError(
            f"machine {machine!r}: travel_mm has no entry for axis {key!r} "
            f"(give it as \"{key}\": [low, high])"
        )
    value = raw[key]
    if not isinstance(value, Sequence) or isinstance(value, str) or len(value) != 2:
        raise MachineSpecError(f"travel_mm.{key}: expected [low, high], got {value!r}")
    try:
        lo, hi = float(value[0]), float(value[1])
    except (TypeError, ValueError):
        raise MachineSpecError(f"travel_mm.{key}: expected two numbers, got {value!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi)) or not lo < hi:
        raise MachineSpecError(f"travel_mm.{key}: need finite low < high, got {value!r}")
    limit, unit = ((MAX_ROTARY_TRAVEL_DEG, "°") if kind == "rotary" else
                   (MAX_LINEAR_TRAVEL_MM, " mm"))
    if max(abs(lo), abs(hi)) > limit:
        cause = length_cause([lo, hi]) if kind == "linear" else None
        raise MachineSpecError(
            f"travel_mm.{key}: [{lo:g}, {hi:g}] reaches beyond ±{limit:g}{unit}, more than "
            f"any {'rotary' if kind == 'rotary' else 'linear'} axis travels; "
            + (cause or "check the unit (travel_mm is in mm, rotary axes in degrees)"))
    return (lo, hi)


MAX_LINEAR_TRAVEL_MM = LINEAR_POSITION.hi
"""Largest |end| of a linear axis's travel, mm: 100 m, beyond the largest gantry. Past it a
description is a unit slip (µm for mm), and the kinematics would work with positions whose
squares overflow the arithmetic a map build does (:mod:`volumetric.plausible.lengths`)."""
MAX_TOOL_LENGTH_MM = TOOL_LENGTH.hi
"""Longest tool, mm (the measurement CSV's ``tool_mm`` has the same limit)."""
MAX_ROTARY_TRAVEL_DEG = ROTARY_POSITION.hi
"""Largest |end| of a rotary axis's travel, degrees: a hundred turns."""


def description_warnings(machine: Machine) -> list[str]:
    """What in an accepted description looks like a unit slip all the same: every linear
    travel within 2 mm, or one under 10 mm (metres?), a rotary one within ±2π (radians?).
    One line each. Warned, not refused: a spindle's thermal test that moves no axis is
    described with travels of 1 mm (the FL data set of tests/data)."""
    out = []
    metres = metres_problem(machine)
    if metres is not None:
        return [f"machine {machine.name!r}: {metres}"]
    for a in machine.axes:
        lo, hi = a.travel
        w = (rotary_travel_warning(a.key, lo, hi) if a.kind == "rotary" else
             short_travel_warning(a.key, lo, hi))
        if w is not None:
            out.append(f"machine {machine.name!r}: {w}")
    return out
PIVOT_MARGIN_MM = 10.0
"""How far inside the linear travels a table's rotary axis must pass when its pivot is
left at the default origin (the smallest R-test ball radius, machine_sim.testprograms)."""


def metres_problem(machine: Machine) -> str | None:
    """Why every linear travel of ``machine`` looks like metres, or None
    (:func:`volumetric.plausible.lengths.linear_travels_problem`)."""
    return linear_travels_problem({a.key: a.travel for a in machine.axes
                                   if a.kind == "linear"})


def missing_pivots(spec: Mapping[str, Any], machine: Machine) -> str | None:
    """Why the description needs ``pivots_mm`` it lacks, or None.

    A rotary axis on the workpiece side (a table) turns about a line in the machine's
    frame; without ``pivots_mm`` that line passes through the origin. When the origin lies
    at the edge of (or outside) the linear travels across the axis, no tool tip can reach
    around the axis: the table's axis is not where the description says, and everything
    computed from it (an R-test, the Abbe arms of its errors) is wrong. Such a description
    must say where its rotary axes are. A pivot given explicitly is taken as given.

    Parameters
    ----------
    spec : mapping
        The description as written (to know which pivots were given).
    machine : Machine
        The parsed description.
    """
    given = spec.get("pivots_mm") or {}
    lo, hi = machine.travel_lo, machine.travel_hi
    linear = {a.key: (lo[i], hi[i]) for i, a in enumerate(machine.axes)
              if a.kind == "linear" and a.key in ("x", "y", "z")}
    lacking = []
    for a in machine.axes:
        if a.kind != "rotary" or a.side != "workpiece" or a.name in given:
            continue
        across = [k for k, d in zip("xyz", a.direction, strict=True)
                  if abs(d) < 0.5 and k in linear]
        if any(not (linear[k][0] + PIVOT_MARGIN_MM <= 0.0 <= linear[k][1] - PIVOT_MARGIN_MM)
               for k in across):
            lacking.append(a.name)
    if not lacking:
        return None
    mid = [(linear[k][0] + linear[k][1]) / 2 if k in linear else 0.0 for k in "xyz"]
    example = ", ".join(f'"{n}": [{mid[0]:g}, {mid[1]:g}, {mid[2]:g}]' for n in lacking)
    return (f"pivots_mm: the rotary {'axis' if len(lacking) == 1 else 'axes'} "
            f"{', '.join(lacking)} of the table need a point on each axis (mm, machine "
            f"coordinates at zero position): without it the axis passes through the origin, at "
            f"the edge of the linear travel; add for example \"pivots_mm\": {{{example}}}")


def _tool_length(value: object, where: str) -> float:
    """A tool length, mm: finite and not negative (the tip is *below* the gauge line; a
    negative length would put it inside the spindle and flip every Abbe arm's sign)."""
    try:
        length = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise MachineSpecError(f"{where}: expected a number, got {value!r}") from None
    if not math.isfinite(length) or length < 0 or length > MAX_TOOL_LENGTH_MM:
        raise MachineSpecError(
            f"{where}: {length:g} mm; a tool length is a finite length from 0 to "
            f"{MAX_TOOL_LENGTH_MM:g} mm from the spindle gauge line to the tool tip")
    return length


def parse_machine(spec: Mapping[str, Any]) -> Machine:
    """Build a :class:`Machine` from a description (formats.md section 1).

    Parameters
    ----------
    spec : mapping
        The parsed JSON. ``chain`` wins over ``translational_type``/``rotary_type``.
        Extensions: ``pivots_mm`` (``{"C": [x, y, z]}``: a point on each rotary axis).

    Raises
    ------
    MachineSpecError
        With a message naming the field and the problem.
    """
    if not isinstance(spec, Mapping):
        raise MachineSpecError(f"machine description must be a JSON object, got {type(spec)}")
    name = str(spec.get("name", "machine"))
    controller = str(spec.get("controller", "fanuc")).lower()
    if controller not in ("fanuc", "siemens"):
        raise MachineSpecError(f"controller: expected 'fanuc' or 'siemens', got {controller!r}")
    ip = str(spec.get("ip", "0.0.0.0"))
    try:
        ipaddress.ip_address(ip)
    except ValueError:
        raise MachineSpecError(f"ip: {ip!r} is not an IPv4 or IPv6 address") from None

    t_type = spec.get("translational_type")
    r_type = spec.get("rotary_type")
    if "chain" in spec and spec["chain"] is not None:
        chain = str(spec["chain"])
    elif t_type is not None:
        chain = chain_for_type_numbers(t_type, r_type if r_type is not None else 0)
    else:
        raise MachineSpecError(
            "machine description needs 'chain' or 'translational_type' (and 'rotary_type')"
        )
    wp_tokens, tool_tokens = parse_chain(chain)

    travel_raw = spec.get("travel_mm", {})
    if not isinstance(travel_raw, Mapping):
        raise MachineSpecError("travel_mm: expected an object such as {\"x\": [0, 500]}")
    pivots_raw = spec.get("pivots_mm", {})
    if not isinstance(pivots_raw, Mapping):
        raise MachineSpecError("pivots_mm: expected an object such as {\"C\": [0, 0, 0]}")

    def make(token: str, side: Side) -> Axis:
        kind: Kind = "linear" if token in LINEAR_AXES else "rotary"
        pivot = (0.0, 0.0, 0.0)
        if kind == "rotary" and token in pivots_raw:
            pivot = _vector(pivots_raw[token], f"pivots_mm.{token}", unit=False)
            if max(abs(c) for c in pivot) > MAX_LINEAR_TRAVEL_MM:
                raise MachineSpecError(f"pivots_mm.{token}: {list(pivot)} lies beyond "
                                       f"±{MAX_LINEAR_TRAVEL_MM:g} mm; check the unit (mm)")
        return Axis(
            name=token,
            kind=kind,
            side=side,
            direction=_UNIT[token],
            pivot_mm=pivot,
            travel=_travel(travel_raw, token.lower(), kind, name),
        )

    shared = [make(t, "workpiece") for t in wp_tokens] + [make(t, "tool") for t in tool_tokens]
    for key in travel_raw:
        known = {a.key for a in shared}
        spindle_keys = {
            str(s.get("axis", "")).lower()
            for s in spec.get("spindles", []) or []
            if isinstance(s, Mapping)
        }
        if key not in known | spindle_keys:
            raise MachineSpecError(
                f"travel_mm.{key}: the machine has no axis {key!r} (chain {chain!r})"
            )
    for key in pivots_raw:
        if key not in {a.name for a in shared if a.kind == "rotary"}:
            raise MachineSpecError(f"pivots_mm.{key}: the machine has no rotary axis {key!r}")

    default_tool = _tool_length(spec.get("tool_length_mm", 0.0), "tool_length_mm")

    spindles = spec.get("spindles") or []
    if not isinstance(spindles, list):
        raise MachineSpecError(
            "spindles: expected a list of {name, axis, direction, tool_length_mm}"
        )
    branches: list[ToolBranch] = []
    all_axes = list(shared)
    if not spindles:
        last_linear = [a for a in shared if a.kind == "linear" and a.side == "tool"]
        tool_dir = _tool_direction(last_linear[-1].direction if last_linear else (0.0, 0.0, 1.0))
        branches.append(ToolBranch("main", tuple(shared), default_tool, tool_dir))
    for i, s in enumerate(spindles):
        where = f"spindles[{i}]"
        if not isinstance(s, Mapping):
            raise MachineSpecError(f"{where}: expected an object")
        axis_name = str(s.get("axis", ""))
        if not _SPINDLE_AXIS.match(axis_name):
            raise MachineSpecError(
                f"{where}.axis: {axis_name!r} is not a spindle axis name such as 'Z1'"
            )
        if axis_name in {a.name for a in all_axes}:
            raise MachineSpecError(f"{where}.axis: axis {axis_name} appears twice")
        direction = _vector(s.get("direction"), f"{where}.direction", unit=True)
        axis = Axis(
            name=axis_name,
            kind="linear",
            side="tool",
            direction=direction,
            travel=_travel(travel_raw, axis_name.lower(), "linear", name),
        )
        all_axes.append(axis)
        tool_len = _tool_length(s.get("tool_length_mm", default_tool), f"{where}.tool_length_mm")
        spindle_name = str(s.get("name", f"S{i + 1}"))
        if spindle_name in {b.name for b in branches}:
            raise MachineSpecError(f"{where}.name: spindle {spindle_name!r} appears twice")
        branches.append(
            ToolBranch(spindle_name, (*shared, axis), tool_len, _tool_direction(direction))
        )
    known_keys = {
        "name", "controller", "ip", "chain", "travel_mm", "tool_length_mm", "spindles",
        "translational_type", "rotary_type", "pivots_mm",
    }
    extra = {k: v for k, v in spec.items() if k not in known_keys}
    return Machine(
        name=name,
        controller=controller,
        ip=ip,
        chain=" ".join(["w", *wp_tokens, "b", *tool_tokens, "t"]),
        axes=tuple(all_axes),
        branches=tuple(branches),
        translational_type=int(t_type) if t_type is not None else None,
        rotary_type=int(r_type) if r_type is not None else None,
        extra=extra,
    )


def _tool_direction(axis_dir: tuple[float, float, float]) -> tuple[float, float, float]:
    # The tool points against its branch's last linear axis (formats.md convention).
    return (-axis_dir[0], -axis_dir[1], -axis_dir[2])


def load_machine(path: str | Path, *, require_pivots: bool = False) -> Machine:
    """Read a machine description JSON file; errors name the file.

    With ``require_pivots``, a table's rotary axis that needs ``pivots_mm`` and lacks it
    is refused too (:func:`missing_pivots`): the commands that compute with the axes ask
    for it; reading the format alone does not.
    """
    p = Path(path)
    try:
        data = p.read_bytes()
    except OSError as exc:
        raise MachineSpecError(f"{p}: cannot read ({exc.strerror or exc})") from None
    other = wrong_file(data[:4096], str(p), "machine")
    if other is not None:
        raise MachineSpecError(other)
    try:
        spec = json.loads(decode_text(data, str(p)))
    except ValueError as exc:
        if not isinstance(exc, json.JSONDecodeError):
            raise MachineSpecError(str(exc)) from None
        raise MachineSpecError(f"{p}: not JSON ({exc.msg} at line {exc.lineno})") from None
    except RecursionError:
        raise MachineSpecError(f"{p}: nested too deeply to be a machine description") from None
    try:
        machine = parse_machine(spec)
        problem = missing_pivots(spec, machine) if require_pivots else None
    except MachineSpecError as exc:
        raise MachineSpecError(f"{p}: {exc}") from None
    if problem is not None:
        raise MachineSpecError(f"{p}: {problem}")
    return machine
