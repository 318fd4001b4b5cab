"""The real measured data in ``tests/data/``: where it is and how to unpack it."""

from __future__ import annotations

import gzip
import hashlib
import shutil
from pathlib import Path

DATA = Path(__file__).resolve().parents[1] / "data"

# SHA-256 of each file as the tests read it (after unpacking), as in tests/data/README.md:
# a truncated or re-encoded copy fails loudly here instead of as a wrong figure in a test.
SHA256 = {
    "fl_thermal_ch3_measurements.csv":
        "94570ad061e269e2d713d92c6689c4716acba0837be0ec1e73ae3b694318f017",
    "fl_thermal_channels.csv":
        "28bfee77c04bafc135b39d3635c4c4dd9d352119084d08030adb307085a1d788",
    "iso230_2_ecmccfg_mcu1025_axis.csv":
        "bd380e9dcda0bc5a06f2c862e1574a5244998c279debfe62dc40b4ffce624505",
}


class DataFileError(RuntimeError):
    """A data file is missing or not the file tests/data/README.md describes."""


def unpack_real_data(into: Path) -> Path:
    """Put every data file, uncompressed and checked, in ``into``; return ``into``.

    The tests read plain paths (``read_measurements(path)``, ``path.read_text()``), so the
    compressed files are unpacked once per session rather than taught to every reader.
    """
    into.mkdir(parents=True, exist_ok=True)
    for name, want in SHA256.items():
        target = into / name
        packed, plain = DATA / (name + ".gz"), DATA / name
        if packed.is_file():
            with gzip.open(packed, "rb") as src, target.open("wb") as dst:
                shutil.copyfileobj(src, dst)
        elif plain.is_file():
            shutil.copyfile(plain, target)
        else:
            raise DataFileError(f"{name}: neither {packed} nor {plain} exists")
        got = hashlib.sha256(target.read_bytes()).hexdigest()
        if got != want:
            raise DataFileError(f"{name}: SHA-256 {got}, tests/data/README.md says {want}")
    return into


FL_MACHINE: dict[str, object] = {
    "name": "fl", "chain": "w X Y b Z t", "tool_length_mm": 0.0,
    "travel_mm": {"x": [0, 1], "y": [0, 1], "z": [-1, 0]}}
"""The machine of the real 46 h spindle thermal test (a test at one fixed point: only the
offset along z is identifiable); ``benchmarks/thermal_fl_study.py`` uses the same."""
