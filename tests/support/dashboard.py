"""What the dashboard tests show: more machines, an example error map per encoding, ISO 230-6
diagonal readings and a stored diagnosis."""

from __future__ import annotations

import numpy as np

from protocol.codes import MapEncoding
from protocol.mapformat import ErrorMapPayload, GridAxis, OutputAxis, encode_map
from tests.support.api import CSV_HEADER, VMC

SIEMENS = {**VMC, "name": "dmu-02", "controller": "siemens", "ip": "10.0.0.22"}


OTHER = {**VMC, "name": "vmc-03", "ip": "10.0.0.23"}


GRID = (GridAxis("X", 0.0, 50.0, 11), GridAxis("Y", 0.0, 50.0, 7), GridAxis("Z", -300.0, 100.0, 4))


def correction_um(output: int, x: float, y: float, z: float) -> float:
    """The example map's correction (whole µm, so int32 counts of 1 µm hold it exactly)."""
    return float([x / 50 + 2 * y / 50, -x / 25 + z / 100, 3 + y / 50][output])


def example_map(machine: str, version: int, encoding: MapEncoding) -> bytes:
    """An encoded map over X, Y, Z holding :func:`correction_um` for outputs X, Y, Z."""
    nodes = np.stack(np.meshgrid(*[g.start + g.step * np.arange(g.count) for g in GRID],
                                 indexing="ij"), axis=-1)
    um = np.stack([np.vectorize(lambda x, y, z, k=k: correction_um(k, x, y, z))(
        nodes[..., 0], nodes[..., 1], nodes[..., 2]) for k in range(3)], axis=-1)
    if encoding is MapEncoding.INT32_INCREMENTS:
        values = np.round(um).astype("<i4").tobytes()
        outputs = (OutputAxis("X", 4), OutputAxis("Y"), OutputAxis("Z"))
        increment = 0.001
    else:
        values = (um / 1000.0).astype("<f4").tobytes()
        outputs = (OutputAxis("X", 0.004), OutputAxis("Y"), OutputAxis("Z"))
        increment = 0.0
    return encode_map(ErrorMapPayload(machine, version, encoding, GRID, outputs, values,
                                      increment_mm=increment))


def diagonal_error_um(label_index: int, t: float, scale: float) -> float:
    """Error along diagonal ``label_index`` at fraction ``t`` of its length (µm)."""
    return scale * (np.sin(np.pi * t) * (label_index + 1) + 2.0 * t)


def diagonals_csv(scale: float, points: int = 11) -> str:
    """The four body diagonals of VMC (10 mm margin), two runs each."""
    from volumetric.verify.iso230_6 import diagonal_targets, diagonal_unit_vectors

    travel = {k: tuple(v) for k, v in VMC["travel_mm"].items()}  # type: ignore[attr-defined]
    targets = diagonal_targets(travel, points)
    units = diagonal_unit_vectors(travel)
    lines = [CSV_HEADER]
    for i, (label, xyz) in enumerate(targets.items()):
        u = units[label]
        for run in (1, 2):
            for j, p in enumerate(xyz):
                value = diagonal_error_um(i, j / (points - 1), scale) + 0.1 * (run - 1.5)
                lines.append(f"{label},{run},{j},{p[0]},{p[1]},{p[2]},1,1,1,100,displacement,"
                             f"{u[0]},{u[1]},{u[2]},{value}")
    return "\n".join(lines) + "\n"


DIAGNOSIS = {"effect": "backlash", "axis": "x", "sensor": None,
             "estimate": {"reversal_um": 9.8}, "rms_before_um": 2.9, "rms_after_um": 0.27}


MODEL = {"format": "ednc-model/1", "machine": "vmc-01",
         "components": {"EXX": {"type": "polynomial", "coefficients": [0.0, 4.0, 1.5],
                                "origin": 250.0, "scale": 250.0}},
         "locations": {"EC0Y": 12.0}, "terms": [], "info": {}}
"""A small model of the test machine vmc-01 (an x scale error and a y-x squareness)."""
