"""The tables evaluation of ``plc/ednc_tables.st`` on its own, compiled by MATIEC and gcc:
a small PROGRAM that decodes a payload placed in a working copy (as the window protocol
leaves it after its checks) and runs ``FB_TablesEval`` once per scan, with the held
readings given per temperature slot. The tests of ``tests/test_plc_st_tables.py`` and
``benchmarks/plc_scan.py`` drive it."""

from __future__ import annotations

import ctypes
import tempfile
from collections.abc import Sequence
from pathlib import Path

from machine_sim.iec import StProgram, StVar, build_program
from machine_sim.stplc import ST_SOURCES

__all__ = ["NO_READING", "TablesHarness"]

NO_READING = -(1 << 31)
"""A slot without a reading (m°C)."""

HARNESS = """
PROGRAM PRG_Tables
VAR
  copy : T_Copy;
  size : DINT;
  load : BOOL;
  code : INT;
  loadFailed : BOOL;
  machine : T_Name32;
  nAxes : INT := 3;
  axisName : T_Name32;
  countsPerUnit : DINT := 1000;
  channelLimit : DINT := 500;
  q : T_AxisDint;
  temps : T_Slots;
  counts : T_AxisDint;
  outLimit : T_AxisDint;
  reversal : T_AxisDint;
  axis : T_AxisDint;
  nOut : INT;
  steps : INT;
  sweeps : INT;
  oneStep : BOOL;
  cfg : ST_Config;
  map : ST_Map;
  tm : ST_TablesMap;
  held : ST_Held;
  ev : FB_TablesEval;
  qL : T_AxisLint;
  k : INT;
END_VAR
IF load THEN
  cfg.machine := machine;
  cfg.nAxes := nAxes;
  cfg.axisName := axisName;
  cfg.countsPerUnit := countsPerUnit;
  cfg.channelLimit := channelLimit;
  code := F_DecodeTables(copy, map, tm, cfg, size);
  loadFailed := map.loadFailed;
  nOut := map.nAxes;
  FOR k := 0 TO 7 DO
    outLimit[k] := map.limit[k];
    reversal[k] := map.reversal[k];
    axis[k] := INT_TO_DINT(map.axis[k]);
  END_FOR;
  ev.map := tm;
  load := FALSE;
END_IF;
FOR k := 0 TO 31 DO
  held.valid[k] := temps[k] <> DINT#-2147483648;
  held.value[k] := temps[k];
END_FOR;
FOR k := 0 TO 7 DO
  qL[k] := DINT_TO_LINT(q[k]);
END_FOR;
IF code = 0 AND NOT loadFailed THEN
  ev(q := qL, held := held, oneStep := oneStep);
  FOR k := 0 TO 7 DO
    counts[k] := LINT_TO_DINT(ev.counts[k]);
  END_FOR;
  steps := ev.steps;
  sweeps := ev.sweeps;
END_IF;
END_PROGRAM
"""

VARIABLES = (
    StVar("copy", ctypes.c_uint8, 16416),
    StVar("size", ctypes.c_int32),
    StVar("load", ctypes.c_uint8),
    StVar("code", ctypes.c_int16),
    StVar("loadFailed", ctypes.c_uint8),
    StVar("machine", ctypes.c_uint8, 32),
    StVar("nAxes", ctypes.c_int16),
    StVar("axisName", ctypes.c_uint8, 32),
    StVar("countsPerUnit", ctypes.c_int32),
    StVar("channelLimit", ctypes.c_int32),
    StVar("q", ctypes.c_int32, 8),
    StVar("temps", ctypes.c_int32, 32),
    StVar("counts", ctypes.c_int32, 8),
    StVar("outLimit", ctypes.c_int32, 8),
    StVar("reversal", ctypes.c_int32, 8),
    StVar("axis", ctypes.c_int32, 8),
    StVar("nOut", ctypes.c_int16),
    StVar("steps", ctypes.c_int16),
    StVar("sweeps", ctypes.c_int16),
    StVar("oneStep", ctypes.c_uint8),
)


def harness_library(sources: Sequence[Path] | None = None) -> Path:
    """The program's sources (ednc_tables.st among them) and the harness, compiled."""
    srcs = list(sources if sources is not None else ST_SOURCES)
    srcs = [s for s in srcs if s.name != "ednc_program.st"]
    tables = srcs[0].parent / "ednc_tables.st"
    if tables not in srcs:
        srcs.insert(len(srcs) - 1, tables)  # before the window, which uses it
    with tempfile.TemporaryDirectory() as tmp:
        harness = Path(tmp) / "harness.st"
        harness.write_text(HARNESS)
        return build_program([*srcs, harness], "PRG_Tables", VARIABLES)


def _name(text: str, size: int) -> list[int]:
    raw = text.encode("ascii")
    return list(raw + bytes(size - len(raw)))


class TablesHarness:
    """One compiled harness: :meth:`load` a payload, :meth:`counts` at positions."""

    def __init__(self, machine: str, axes: Sequence[str], *, counts_per_unit: int = 1000,
                 channel_limit: int = (1 << 30) - 1, library: Path | None = None) -> None:
        self.axes = tuple(a.upper() for a in axes)
        self.program = StProgram(library or harness_library(), VARIABLES)
        self.program.init()
        p = self.program
        p.var("machine")[:] = _name(machine, 32)
        p.var("nAxes")[0] = len(self.axes)
        p.var("axisName")[:] = _name("".join(a.ljust(4, "\0") for a in self.axes), 32)
        p.var("countsPerUnit")[0] = counts_per_unit
        p.var("channelLimit")[0] = channel_limit

    def load(self, payload: bytes) -> tuple[int, bool]:
        """Decode ``payload``; returns (code, load failed)."""
        p = self.program
        copy = p.var("copy")
        copy[32:32 + len(payload)] = list(payload)
        p.var("size")[0] = len(payload)
        p.var("load")[0] = 1
        p.scan()
        return int(p.var("code")[0]), bool(p.var("loadFailed")[0])

    def set_readings(self, slots_mC: Sequence[int]) -> None:
        t = self.program.var("temps")
        for k in range(32):
            t[k] = int(slots_mC[k]) if k < len(slots_mC) else NO_READING

    def counts(self, q_counts: Sequence[int]) -> list[int]:
        """One scan at q (counts, the program's axis order): counts per output."""
        p = self.program
        qv = p.var("q")
        for k, v in enumerate(q_counts):
            qv[k] = int(v)
        p.scan()
        return list(p.var("counts")[:int(p.var("nOut")[0])])


def int32_tables(built: bytes, *, limit_mm: float | None = None,
                 increment_mm: float = 0.001) -> bytes:
    """A tables map as the center builds it (float32 encoding) re-encoded in int32 counts
    of ``increment_mm`` (reversals in whole counts), optionally with another limit: what
    a PLC writing counts to its NC takes."""
    from dataclasses import replace

    from protocol import MapEncoding, OutputAxis
    from protocol.maptables import decode_tables, encode_tables
    p = decode_tables(built)
    p = replace(p, encoding=MapEncoding.INT32_INCREMENTS, increment_mm=increment_mm,
                outputs=tuple(OutputAxis(o.name, None if o.reversal is None
                                         else round(o.reversal / increment_mm))
                              for o in p.outputs))
    if limit_mm is not None:
        p = replace(p, limit_mm=limit_mm)
    return encode_tables(p)


def center_tables(description: dict[str, object], seed: int, *,
                  backlash: dict[str, float], formats: object = None) -> bytes:
    """The center's tables map (float32) of a machine description with random component
    errors, a spindle drift on Z, an X screw expansion and backlash terms."""
    import numpy as np

    from benchmarks.map_build import errors
    from protocol import MapEncoding
    from server.mapcodec import build_for, encode
    from volumetric.model.machine import parse_machine
    from volumetric.model.model import BacklashTerm, MachineModel, ThermalTerm
    m = parse_machine({**description, "controller": "fanuc"})
    geo = errors(m, np.random.default_rng(seed), 5.0)
    thermal = [ThermalTerm("thermal_drift", "z", "T_spindle_C", -2.5, 20.0),
               ThermalTerm("thermal_expansion", "x", "T_x_screw_C", 11.5, 20.0, 0.0)]
    lash = [BacklashTerm(a, v) for a, v in backlash.items()]
    model = MachineModel(m.name, geo, (*thermal, *lash))
    return encode(build_for(m, model, None, kind="tables", tolerance_um=0.5,
                            formats=formats if formats is not None
                            else MapEncoding.FLOAT32_MM | MapEncoding.TABLES))
