"""Big measurement files (issue 14, item 2): read block by block, identified from normal
equations accumulated block by block, with the same answers and the same one-line errors
as a file read whole. Small blocks (a few kB) stand in for the real ones (8 MB) so that a
file of a few hundred readings spans many of them."""

from __future__ import annotations

import csv
import dataclasses
import io
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from rich.console import Console

from ednc.progress import CommandProgress, wanted
from volumetric.identify.fit import FitError, fit, fit_blocks
from volumetric.measure import csvblocks
from volumetric.measure.measurement import (
    MeasurementFormatError,
    Measurements,
    read_measurement_blocks,
    read_measurements,
    subsample,
    write_measurements,
)
from volumetric.model.components import GeometricErrors, Polynomial, component_names
from volumetric.model.exact import volumetric_error
from volumetric.model.machine import Machine, parse_machine

EDNC = str(Path(sys.executable).parent / "ednc")
VMC = {"name": "vmc", "chain": "w X Y b Z t", "tool_length_mm": 100.0,
       "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}}


@pytest.fixture
def small_blocks(monkeypatch: pytest.MonkeyPatch) -> int:
    size = 4096
    monkeypatch.setattr(csvblocks, "BLOCK_BYTES", size)
    return size


def campaign(n: int, seed: int = 0) -> tuple[Machine, Measurements]:
    """Readings of a 3-axis machine with cubic component errors, 0.3 µm/µrad noise."""
    rng = np.random.default_rng(seed)
    m = parse_machine(VMC)
    comps = {}
    for a in m.axes:
        for name in component_names(a):
            c = rng.normal(0, 4 if name[1] in "XYZ" else 8, 4)
            c[0] = 0
            comps[name] = Polynomial(tuple(c), a.travel[0], a.travel[1] - a.travel[0])
    truth = GeometricErrors(comps, {})
    q = np.column_stack([rng.uniform(a.travel[0], a.travel[1], n) for a in m.axes])
    tool = rng.choice(np.array([0.0, 150.0]), n)
    u = rng.normal(size=(n, 3))
    u /= np.linalg.norm(u, axis=1)[:, None]
    ang = rng.random(n) < 0.2
    ve = volumetric_error(m, truth, q, tool_mm=tool)
    assert ve.orientation_urad is not None
    val = np.where(ang, np.einsum("ni,ni->n", u, ve.orientation_urad),
                   np.einsum("ni,ni->n", u, ve.position_um)) + rng.normal(0, 0.3, n)
    labels = np.array([f"probe-{k // 100}" for k in range(n)])
    meas = Measurements(
        test=labels, run=(np.arange(n) // 25 % 4).astype(np.int64),
        time_s=np.arange(n, dtype=float), q=np.column_stack([q, np.zeros((n, 3))]),
        direction=rng.choice(np.array([-1, 1], np.int8), (n, 3)), tool_mm=tool,
        is_angle=ang, u=u, value=val,
        temperatures={"t1": 20 + rng.normal(0, 0.1, n)},
        temperature_columns={"t1": "T_t1_C"},
        extra={"spindle_rpm": rng.choice(np.array([0.0, 8000.0]), n)})
    return m, meas


def csv_text(m: Measurements) -> str:
    buf = io.StringIO()
    write_measurements(buf, m)
    return buf.getvalue()


def same(a: Measurements, b: Measurements) -> None:
    for name in ("test", "run", "time_s", "q", "direction", "tool_mm", "is_angle", "u",
                 "value"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert a.temperature_columns == b.temperature_columns
    for s in a.temperatures:
        np.testing.assert_array_equal(a.temperatures[s], b.temperatures[s])
    assert list(a.extra) == list(b.extra)
    for c in a.extra:
        assert a.extra[c].dtype.kind == b.extra[c].dtype.kind, c
        np.testing.assert_array_equal(a.extra[c], b.extra[c])


def test_blocks_join_to_the_file_and_to_the_careful_parse(tmp_path: Path,
                                                          small_blocks: int) -> None:
    _, meas = campaign(600)
    path = tmp_path / "m.csv"
    write_measurements(path, meas)
    assert path.stat().st_size > 20 * small_blocks  # many blocks
    blocks = list(read_measurement_blocks(path))
    assert len(blocks) > 20
    whole = read_measurements(path)
    same(meas, whole)
    same(whole, Measurements.concat(blocks))
    # every label quoted: the csv-module path, block by block, reads the same
    head, _, body = path.read_text().partition("\n")
    quoted = re.sub(r"^(probe-\d+),", r'"\1",', body, flags=re.MULTILINE)
    assert quoted.count('"') == 2 * len(meas)
    careful = read_measurements(io.StringIO(head + "\n" + quoted))
    same(whole, careful)


def test_progress_reports_every_byte(tmp_path: Path, small_blocks: int) -> None:
    _, meas = campaign(300)
    path = tmp_path / "m.csv"
    write_measurements(path, meas)
    seen: list[int] = []
    read_measurements(path, progress=seen.append)
    assert len(seen) > 5 and seen == sorted(seen)
    assert seen[-1] == path.stat().st_size


@pytest.mark.parametrize("row", [5, 170, 299])
@pytest.mark.parametrize(("column", "cell", "what"), [
    ("value", "abc", "not a number"),
    ("value", "nan", "not a finite number"),
    ("dir_x", "2", "direction must be -1, 0 or +1"),
    ("quantity", "force", "quantity must be"),
])
def test_a_bad_cell_in_any_block_names_its_line(
        tmp_path: Path, small_blocks: int, row: int, column: str, cell: str, what: str
) -> None:
    _, meas = campaign(300)
    lines = csv_text(meas).split("\n")
    header = lines[0].split(",")
    cells = lines[row + 1].split(",")
    cells[header.index(column)] = cell
    lines[row + 1] = ",".join(cells)
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(lines))
    for read in (read_measurements, lambda p: list(read_measurement_blocks(p))):
        with pytest.raises(MeasurementFormatError) as info:
            read(path)
        assert (info.value.line, info.value.column) == (row + 2, column)
        assert what in str(info.value) and f"line {row + 2}," in str(info.value)


def test_structure_errors_across_block_boundaries(tmp_path: Path, small_blocks: int) -> None:
    _, meas = campaign(300)
    lines = csv_text(meas).rstrip("\n").split("\n")
    path = tmp_path / "bad.csv"
    # a blank line a few blocks in, readings after it
    at = next(k for k in range(1, len(lines))
              if sum(len(x) + 1 for x in lines[:k]) > 2 * small_blocks)
    path.write_text("\n".join([*lines[:at], "", *lines[at:]]) + "\n")
    with pytest.raises(MeasurementFormatError, match="blank line between readings") as info:
        read_measurements(path)
    assert info.value.line == at + 1
    # a short row far into the file
    short = list(lines)
    short[250] = short[250].rsplit(",", 1)[0]
    path.write_text("\n".join(short) + "\n")
    with pytest.raises(MeasurementFormatError, match="row has 16 cells, the header has 17") as info:
        list(read_measurement_blocks(path))
    assert info.value.line == 251
    # trailing blank lines end the file harmlessly, CR LF line breaks too
    path.write_bytes(("\r\n".join(lines) + "\r\n\r\n\n").encode())
    assert len(read_measurements(path)) == 300


def test_a_quoted_line_break_stays_in_its_block(tmp_path: Path, small_blocks: int) -> None:
    _, meas = campaign(200)
    note = np.array(["plain"] * 200, dtype=object)
    note[120] = "two\nlines, quoted"
    meas = Measurements(**{**{f: getattr(meas, f) for f in (
        "test", "run", "time_s", "q", "direction", "tool_mm", "is_angle", "u", "value",
        "temperatures", "temperature_columns")}, "extra": {"note": note.astype(str)}})
    path = tmp_path / "q.csv"
    write_measurements(path, meas)
    back = read_measurements(path)
    assert back.extra["note"][120] == "two\nlines, quoted"
    assert back.extra["note"][119] == "plain" and len(back) == 200


def test_an_extra_column_is_judged_over_the_whole_file(tmp_path: Path,
                                                       small_blocks: int) -> None:
    _, meas = campaign(300)
    text = csv_text(meas).rstrip("\n").split("\n")
    header = text[0].split(",")
    k = header.index("spindle_rpm")
    cells = text[-1].split(",")
    cells[k] = "idle"  # numbers in every earlier block, a word in the last one
    text[-1] = ",".join(cells)
    path = tmp_path / "m.csv"
    path.write_text("\n".join(text) + "\n")
    rpm = read_measurements(path).extra["spindle_rpm"]
    assert rpm.dtype.kind == "U"
    assert rpm[-1] == "idle" and rpm[0] == next(csv.reader([text[1]]))[k]


def test_fit_from_blocks_is_the_fit_of_the_whole(tmp_path: Path) -> None:
    machine, meas = campaign(4000, seed=3)
    whole = fit(machine, meas)
    parts = [meas.select(np.arange(s, min(s + 700, len(meas)))) for s in range(0, 4000, 700)]
    streamed = fit_blocks(machine, iter(parts))
    assert [p.name for p in streamed.params] == [p.name for p in whole.params]
    np.testing.assert_allclose(streamed.values, whole.values, rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(streamed.std, whole.std, rtol=1e-8)
    assert streamed.residual is None and whole.residual is not None
    # the RMS from the normal equations is the RMS of the residuals themselves
    for key, mask in (("displacement_um", ~meas.is_angle), ("angle_urad", meas.is_angle)):
        direct = float(np.sqrt(np.mean(whole.residual[mask] ** 2)))
        assert abs(streamed.rms[key] - direct) < 1e-9 * direct
    assert abs(streamed.rms["displacement_um"] - 0.3) < 0.03  # the noise
    # read from a file block by block: the same model
    path = tmp_path / "m.csv"
    write_measurements(path, meas)
    from_file = fit_blocks(machine, read_measurement_blocks(path))
    np.testing.assert_allclose(from_file.values, whole.values, rtol=1e-8, atol=1e-9)


def test_fit_blocks_refuses_what_fit_refuses() -> None:
    machine, meas = campaign(50)
    with pytest.raises(FitError, match="no readings"):
        fit_blocks(machine, iter([]))
    with pytest.raises(FitError, match="cannot identify"):
        fit_blocks(machine, iter([meas.select(np.arange(20)), meas.select(np.arange(20, 40))]))


def test_progress_is_drawn_on_a_terminal_only(monkeypatch: pytest.MonkeyPatch) -> None:
    out = io.StringIO()
    console = Console(file=out, force_terminal=True, width=100)
    with CommandProgress(True, console=console) as progress:
        advance = progress.reading("reading big.csv", 1000)
        advance(500)
        progress.stage("identifying")
    assert "reading big.csv" in out.getvalue()
    quiet = io.StringIO()
    with CommandProgress(False, console=Console(file=quiet, force_terminal=True)) as progress:
        progress.reading("reading big.csv", 1000)(1000)
        progress.stage("identifying")
    assert quiet.getvalue() == ""
    monkeypatch.setattr(sys.stdout, "isatty", lambda: True)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    assert wanted(False) and not wanted(True)
    monkeypatch.setattr(sys.stderr, "isatty", lambda: False)
    assert not wanted(False)


def test_cli_fit_reads_in_blocks_and_keeps_one_line_errors(tmp_path: Path) -> None:
    machine_file = tmp_path / "m.json"
    machine_file.write_text(__import__("json").dumps(VMC))
    _, meas = campaign(3000, seed=5)
    path = tmp_path / "d.csv"
    write_measurements(path, meas)
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1"}
    ok = subprocess.run([EDNC, "fit", "--machine", str(machine_file), "--data", str(path)],
                        capture_output=True, text=True, env=env, timeout=300)
    assert ok.returncode == 0, ok.stderr
    assert "readings: 3000" in ok.stdout and ok.stderr == ""  # no bar off a terminal
    lines = path.read_text().split("\n")
    lines[2900] = lines[2900].replace("displacement", "force").replace("angle", "force")
    path.write_text("\n".join(lines))
    bad = subprocess.run([EDNC, "fit", "--machine", str(machine_file), "--data", str(path),
                          "--json"], capture_output=True, text=True, env=env, timeout=300)
    assert bad.returncode == 2 and bad.stdout == ""
    assert bad.stderr.count("\n") == 1 and "line 2901, column 'quantity'" in bad.stderr


def test_subsample_keeps_every_test_its_share_and_is_repeatable() -> None:
    _, meas = campaign(3000)
    # two long tests and a short one of 100 readings
    labels = np.where(np.arange(3000) < 1500, "long-a", "long-b")
    labels[2900:] = "short"
    many = dataclasses.replace(meas, test=labels)
    sub = subsample(many, 600, per_test=50)
    assert sub is not many and 550 <= len(sub) <= 700
    assert np.all(np.diff(sub.time_s) > 0)  # file order kept
    labels, counts = np.unique(sub.test, return_counts=True)
    assert set(labels.tolist()) == set(np.unique(many.test).tolist())
    assert counts[labels.tolist().index("short")] == 50  # a short test keeps per_test
    assert abs(counts[labels.tolist().index("long-a")] - 300) <= 1  # the others their share
    again = subsample(many, 600, per_test=50)
    np.testing.assert_array_equal(sub.time_s, again.time_s)
    # each kept reading is the file's own, with its temperature and run
    idx = np.searchsorted(many.time_s, sub.time_s)
    np.testing.assert_array_equal(many.value[idx], sub.value)
    np.testing.assert_array_equal(many.temperatures["t1"][idx], sub.temperatures["t1"])
    assert subsample(many, len(many)) is many and subsample(many, 0) is many
