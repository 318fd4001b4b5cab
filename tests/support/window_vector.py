"""Running ``tests/vectors/window.json`` (protocol/README.md §13.3, the PLC's side of the
window) on a PLC program: the center's writes of each step put into the window, then
scans, then the status compared with the step's expectation.

Two programs take it: the Python PLC of the simulated Fanuc machine
(:class:`machine_sim.plcmap.PlcMapProgram` over :class:`machine_sim.fanuc.FanucPMC`)
and the compiled Structured Text program (:class:`machine_sim.stplc.StPlc`).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from machine_sim.fanuc import FanucPMC
from machine_sim.plcmap import PlcMapProgram
from machine_sim.stplc import StPlc
from protocol.ctrlmem import STATUS_AT, STATUS_SIZE, Layout, decode_status

__all__ = ["FIELDS", "load", "observed", "run_python", "run_st"]

VECTOR = Path(__file__).resolve().parents[1] / "vectors" / "window.json"
FIELDS = ("ack_seq", "ack_code", "active", "applied_version", "temp_ack", "temp_refused",
          "map_in_use")


def load() -> dict[str, Any]:
    body: dict[str, Any] = json.loads(VECTOR.read_text())
    return body


def observed(window: bytes | bytearray | memoryview) -> dict[str, int]:
    """The status fields a step's ``expect`` names."""
    st = decode_status(bytes(window[STATUS_AT:STATUS_AT + STATUS_SIZE]))
    return {"ack_seq": st.ack_seq, "ack_code": st.ack_code, "active": st.active,
            "applied_version": st.applied_version, "temp_ack": st.temp_ack,
            "temp_refused": st.temp_refused, "map_in_use": st.state & 1}


def _run(vector: dict[str, Any], window: Callable[[], bytearray | memoryview],
         scan: Callable[[], None], restart: Callable[[], None]) -> list[dict[str, int]]:
    out = []
    for step in vector["steps"]:
        w = window()
        for write in step.get("writes", []):
            data = bytes.fromhex(write["hex"])
            w[write["offset"]:write["offset"] + len(data)] = data
        if step.get("restart"):  # after the writes: the window is nonvolatile
            restart()
        for _ in range(int(step.get("scans", 2))):
            scan()
        out.append(observed(window()))
    return out


def run_python(vector: dict[str, Any]) -> list[dict[str, int]]:
    """The Python PLC (scans at positions 0), one status per step."""
    layout = Layout(vector["capacity"])
    window = bytearray(layout.size)
    axes = tuple(vector["axes"])
    state: dict[str, Any] = {}

    def boot() -> None:
        pmc = FanucPMC(vector["machine"], axes)
        plc = PlcMapProgram(window, layout, pmc, formats=pmc.store.assembler.accepted)
        plc.boot(0.0, vector["machine"])
        state.update(pmc=pmc, plc=plc, now=0.0)

    def scan() -> None:
        state["now"] += 0.008
        applied = state["pmc"].scan(state["now"], np.zeros(len(axes)))
        state["plc"].scan(state["now"], np.zeros(len(axes)),
                          np.asarray(applied, dtype=np.float64) * 0.001)

    boot()
    return _run(vector, lambda: window, scan, boot)


def run_st(vector: dict[str, Any]) -> list[dict[str, int]]:
    """The compiled Structured Text program (scans at positions 0)."""
    axes = tuple(vector["axes"])
    plc = StPlc(vector["machine"], axes)
    if plc.layout.capacity != vector["capacity"]:
        raise ValueError(f"the ST program's window has capacity {plc.layout.capacity}, the "
                         f"vector {vector['capacity']}")
    plc.scan([0] * len(axes))

    def scan() -> None:
        plc.scan([0] * len(axes))

    return _run(vector, lambda: plc.window, scan, plc.restart)
