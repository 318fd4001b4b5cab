"""The text of a CEC export: a part program (MPF) or an initialisation file (INI) that a
SINUMERIK loads as is.

Layout (the K3 manual's example, section 4.4.4, with the header of an NC file)::

    %_N_<NAME>_MPF                      or  %_N_NC_CEC_INI
    ;$PATH=/_N_MPF_DIR                      CHANDATA(1)
    ; what the file carries, at the tool tip; activation and memory settings
    $AN_CEC_INPUT_AXIS[t]=(Y1)
    $AN_CEC_OUTPUT_AXIS[t]=(X1)
    $AN_CEC_STEP[t]=10  $AN_CEC_MIN[t]=0  $AN_CEC_MAX[t]=500 (one per line)
    $AN_CEC_DIRECTION[t]=0  $AN_CEC_MULT_BY_TABLE[t]=0  $AN_CEC_IS_MODULO[t]=0
    $AN_CEC[t,0]=0.0012 ...
    M30                                 or  M17

The file is plain ASCII. Numbers are written in plain decimals, 6 places at most (1 nm,
1e-6 degree), trailing zeros dropped and never ``-0``; ``STEP·(points - 1) = MAX - MIN``
holds exactly in the
decimals written.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass

from volumetric.compensate.cec import CecExport, CecTable
from volumetric.compensate.cec_check import LONGER_MM, ToolTip

_NAME = re.compile(r"^[A-Z][A-Z0-9_]{0,23}$")


@dataclass(frozen=True)
class CecFile:
    """How to write the file.

    Attributes
    ----------
    layout : {"mpf", "ini"}
    name : str
        Program name (``EDNC_CEC`` → ``%_N_EDNC_CEC_MPF``); ignored for INI.
    axis_names : mapping of model axis (``X``) to control axis (``X1``, ``AX1``)
    first_table : int
        Index of the first table written (an OEM's own tables below it stay).
    """

    layout: str = "mpf"
    name: str = "EDNC_CEC"
    axis_names: Mapping[str, str] | None = None
    first_table: int = 0

    def axis(self, name: str) -> str:
        return (self.axis_names or {}).get(name, f"{name}1")


def number(v: float) -> str:
    """Plain decimal, at most 6 places, no trailing zeros, no ``-0``."""
    s = f"{v:.6f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "", "-") else s


def program_name(stem: str) -> str:
    """An NC program name from a file stem: upper case, letters, digits and ``_``."""
    name = re.sub(r"[^A-Z0-9_]", "_", stem.upper()) or "EDNC_CEC"
    if not name[0].isalpha():
        name = "N" + name
    return name[:24]


def _describe(t: CecTable, i: int, f: CecFile) -> str:
    what = {"table": "carries", "factor": "factor of a product, carries",
            "arm": "arm of products (its own value is cancelled in the table of the same "
                   "input and output)"}[t.role]
    covers = ", ".join(dict.fromkeys(c for c in t.covers))
    if t.role == "arm":
        covers = ""
    extra = ""
    if t.role == "factor" and t.mult_by is not None:
        extra = (f"; multiplied by table {f.first_table + t.mult_by} "
                 f"(number {f.first_table + t.mult_by + 1}); its own value is cancelled "
                 "in the table of the same input and output")
    d = {1: "; positive direction only", -1: "; negative direction only"}.get(t.direction, "")
    return (f"; table {i}: input {f.axis(t.input)}, output {f.axis(t.output)}, "
            f"{t.values.size} points: {what} {covers}{extra}{d}").rstrip(", ")


def cec_text(e: CecExport, figures: ToolTip, *, machine_name: str, model_note: str,
             f: CecFile, offsets_um: Mapping[str, float] | None = None) -> str:
    """The whole file (module docstring); ``offsets_um`` are the fit's constant tool-tip
    offsets (the readings' zero), named in the header as not in the tables."""
    n_used = len(e.tables)
    last = f.first_table + n_used - 1
    lines: list[str] = []
    if f.layout == "ini":
        lines += ["%_N_NC_CEC_INI", "CHANDATA(1)"]
    else:
        if not _NAME.match(f.name):
            raise ValueError(f"program name {f.name!r}: letters, digits and _ only, at "
                             "most 24, starting with a letter")
        lines += [f"%_N_{f.name}_MPF", ";$PATH=/_N_MPF_DIR"]
    lines += [
        f"; CEC compensation (sag compensation, multi-dimensional) of {machine_name}, "
        f"{model_note}",
        "; written by ednc export --format cec; how the tables combine: SINUMERIK function "
        "manual K3, 4.4.4",
        "; values: corrections in mm (degrees onto a rotary axis) = -error; a product "
        "of two tables is added as mm",
        f"; tool tip ({e.tool_mm:g} mm tool), worst / RMS over {figures.points} random "
        "points and directions:",
        f";   model without these tables {figures.worst_before_um:.2f} / "
        f"{figures.rms_before_um:.2f} um",
        f";   with these tables          {figures.worst_after_um:.2f} / "
        f"{figures.rms_after_um:.2f} um",
    ]
    lines.append(f";   worst with each axis's mean removed (the workpiece zero absorbs it): "
                 f"{figures.worst_before_zeroed_um:.2f} -> {figures.worst_after_zeroed_um:.2f}"
                 " um")
    lines.append(f";   with a tool {LONGER_MM:g} mm longer (same tables) "
                 f"{figures.worst_after_longer_tool_um:.2f} / "
                 f"{figures.rms_after_longer_tool_um:.2f} um")
    if offsets_um:
        lines.append("; the fit's constant tool-tip offsets (the readings' zero: "
                     + ", ".join(f"{k} {v:.2f}" for k, v in sorted(offsets_um.items()))
                     + " um) are not in the tables, as in the center's maps: the workpiece "
                     "zero absorbs them")
    if figures.worst_after_lec_um is not None:
        lines.append(f";   with the positioning errors also in the LEC tables "
                     f"{figures.worst_after_lec_um:.2f} / {figures.rms_after_lec_um:.2f} um")
    if e.left_out:
        lines.append("; not carried (tool-tip effect, why):")
        lines += [f";   {x.error}: "
                  + ("" if x.effect_um is None else f"{x.effect_um:.2f} um, ") + x.reason
                  for x in e.left_out]
    used_axes = sorted({f.axis(t.output) for t in e.tables})
    lines += [
        f"; {n_used} tables, numbers {f.first_table}..{last} ({e.control}: at most "
        f"{e.max_tables} tables of {e.max_points} points)",
        "; activation (load with the compensation off, MD32710 $MA_CEC_ENABLE=0 on the "
        "output axes):",
        f";   SD41300 $SN_CEC_TABLE_ENABLE[t]=1 for t = {f.first_table}..{last} (every "
        "table, factors and arms included)",
        f";   MD32710 $MA_CEC_ENABLE=1 on {', '.join(used_axes)}; NEWCONF or reset",
        ";   MD32720 $MA_CEC_MAX_SUM above the largest total correction: "
        + ", ".join(f"{f.axis(k)} {number(v)}" for k, v in sorted(figures.max_total.items())),
    ]
    if e.control == "840d":
        pts = ", ".join(f"[{f.first_table + i}]={t.values.size}"
                        for i, t in enumerate(e.tables))
        lines.append(f";   memory: MD18342 $MN_MM_CEC_MAX_POINTS{pts} (power on to format)")
    else:
        lines.append(";   memory: an 828D has its 8 tables of 200 points once the option is "
                     "set (no MD18342)")
    if e.positioning:
        lines.append("; the positioning errors (EXX, EYY, ...) are in tables of an axis onto "
                     "itself: if the leadscrew (LEC) tables already carry them, export "
                     "with --lec")
    for i, t in enumerate(e.tables):
        k = f.first_table + i
        mult = 0 if t.mult_by is None else f.first_table + t.mult_by + 1
        lines += [
            _describe(t, k, f),
            f"$AN_CEC_INPUT_AXIS[{k}]=({f.axis(t.input)})",
            f"$AN_CEC_OUTPUT_AXIS[{k}]=({f.axis(t.output)})",
            f"$AN_CEC_STEP[{k}]={number(t.step)}",
            f"$AN_CEC_MIN[{k}]={number(t.start)}",
            f"$AN_CEC_MAX[{k}]={number(t.stop)}",
            f"$AN_CEC_DIRECTION[{k}]={t.direction}",
            f"$AN_CEC_MULT_BY_TABLE[{k}]={mult}",
            f"$AN_CEC_IS_MODULO[{k}]={int(t.modulo)}",
        ]
        lines += [f"$AN_CEC[{k},{n}]={number(v)}" for n, v in enumerate(t.values)]
    lines.append("M17" if f.layout == "ini" else "M30")
    return ascii_text("\n".join(lines) + "\n")


_ASCII = {"×": "x", "µ": "u", "·": "*", "°": " deg", "±": "+-", "−": "-", "→": "->",
          "²": "^2", "³": "^3", "≤": "<=", "≥": ">="}


def ascii_text(text: str) -> str:
    """The file in plain ASCII (an NC reads part programs as 7-bit text): the few signs
    the comments use spelled out, anything else replaced by ``?``."""
    for a, b in _ASCII.items():
        text = text.replace(a, b)
    return text.encode("ascii", "replace").decode("ascii")


__all__ = ["CecFile", "ascii_text", "cec_text", "number", "program_name"]
