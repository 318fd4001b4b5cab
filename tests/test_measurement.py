"""The measurement CSV (formats.md section 2): reading, writing, and every bad input."""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from volumetric.measure.measurement import (
    MeasurementFormatError,
    Measurements,
    read_measurements,
    write_measurements,
)

HEADER = ("test,run,time_s,x_mm,y_mm,z_mm,dir_x,dir_y,dir_z,tool_mm,quantity,ux,uy,uz,value,"
          "T_spindle_C,feed_mm_min")
ROWS = (
    "X-positioning,1,0.5,10,0,0,1,0,0,100,displacement,1,0,0,1.25,20.5,1000",
    "X-positioning,1,1.5,20,0,0,1,0,0,100,displacement,1,0,0,-2.5,20.6,1000",
    "X-positioning,2,2.5,20,0,0,-1,0,0,100,angle,0,0,1,3.0,20.7,1000",
)


def text(*rows: str, header: str = HEADER) -> str:
    return "\n".join([header, *rows]) + "\n"


def quoted(csv_text: str) -> str:
    """The same table with every cell quoted: forces the careful (csv module) path."""
    out = io.StringIO()
    writer = csv.writer(out, quoting=csv.QUOTE_ALL, lineterminator="\n")
    for line in csv_text.split("\n"):
        writer.writerow(line.split(",") if line else [])
    return out.getvalue()[:-1]  # the final empty line would add one newline too many


def read_text(csv_text: str) -> Measurements:
    return read_measurements(io.StringIO(csv_text))


@pytest.fixture(params=["plain", "quoted"])
def style(request: pytest.FixtureRequest) -> str:
    return str(request.param)


def as_style(csv_text: str, style: str) -> str:
    return quoted(csv_text) if style == "quoted" else csv_text


def test_reads_every_column(style: str) -> None:
    m = read_text(as_style(text(*ROWS), style))
    assert len(m) == 3
    assert m.test.tolist() == ["X-positioning"] * 3
    assert m.run.dtype == np.int64 and m.run.tolist() == [1, 1, 2]
    assert m.time_s.tolist() == [0.5, 1.5, 2.5]
    assert m.q.shape == (3, 6)
    assert m.q[:, 0].tolist() == [10.0, 20.0, 20.0]
    assert not m.q[:, 3:].any() and m.has_rotary == (False, False, False)
    assert m.direction.dtype == np.int8 and m.direction[:, 0].tolist() == [1, 1, -1]
    assert m.is_angle.tolist() == [False, False, True]
    assert m.u.tolist() == [[1, 0, 0], [1, 0, 0], [0, 0, 1]]
    assert m.value.tolist() == [1.25, -2.5, 3.0]
    assert m.tool_mm.tolist() == [100.0] * 3
    assert list(m.temperatures) == ["spindle"]
    assert m.temperature_columns == {"spindle": "T_spindle_C"}
    assert m.temperatures["spindle"].tolist() == [20.5, 20.6, 20.7]
    assert m.spindle is None
    assert list(m.extra) == ["feed_mm_min"] and m.extra["feed_mm_min"].dtype == np.float64


def test_rotary_spindle_and_text_extras(style: str) -> None:
    header = HEADER + ",b_deg,c_deg,spindle,operator"
    rows = [r + f",{b},{c},S{k},ann" for k, (r, b, c) in
            enumerate(zip(ROWS, (0, 45, -30), (90, 0, 10.5), strict=True))]
    m = read_text(as_style(text(*rows, header=header), style))
    assert m.has_rotary == (False, True, True)
    assert m.q[:, 4].tolist() == [0, 45, -30] and m.q[:, 5].tolist() == [90, 0, 10.5]
    assert m.q[:, 3].tolist() == [0, 0, 0]
    assert m.spindle is not None and m.spindle.tolist() == ["S0", "S1", "S2"]
    assert m.extra["operator"].tolist() == ["ann"] * 3


def test_trailing_blank_lines_are_not_readings(style: str) -> None:
    m = read_text(as_style(text(*ROWS), style) + "\n\n")
    assert len(m) == 3


def test_real_thermal_file_matches_an_independent_parse(real_data: Path) -> None:
    path = real_data / "fl_thermal_ch3_measurements.csv"
    m = read_measurements(path)
    with path.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert len(m) == len(rows)
    assert sorted(m.temperature_columns.values()) == sorted(
        c for c in rows[0] if c.startswith("T_"))
    for i in (0, 1, len(rows) // 2, len(rows) - 1):
        row = rows[i]
        assert m.time_s[i] == float(row["time_s"])
        assert m.value[i] == float(row["value"])
        assert m.temperatures["t7"][i] == float(row["T_t7_C"])
        assert m.extra["spindle_rpm"][i] == float(row["spindle_rpm"])
        assert m.u[i].tolist() == [float(row["ux"]), float(row["uy"]), float(row["uz"])]


def test_careful_path_agrees_with_the_fast_path(real_data: Path) -> None:
    """Quoting the test labels sends the same file down the csv-module path."""
    path = real_data / "fl_thermal_ch3_measurements.csv"
    plain = path.read_text()
    head, _, body = plain.partition("\n")
    body = body.replace("spindle-thermal,", '"spindle-thermal",')
    fast = read_measurements(path)
    careful = read_text(head + "\n" + body)
    assert_same(fast, careful)


def assert_same(a: Measurements, b: Measurements) -> None:
    for name in ("test", "run", "time_s", "q", "direction", "tool_mm", "is_angle", "u",
                 "value"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert a.has_rotary == b.has_rotary
    assert a.temperature_columns == b.temperature_columns
    for s in a.temperatures:
        np.testing.assert_array_equal(a.temperatures[s], b.temperatures[s], err_msg=s)
    assert list(a.extra) == list(b.extra)
    for c in a.extra:
        assert a.extra[c].dtype.kind == b.extra[c].dtype.kind
        np.testing.assert_array_equal(a.extra[c], b.extra[c], err_msg=c)
    if a.spindle is None:
        assert b.spindle is None
    else:
        assert b.spindle is not None
        np.testing.assert_array_equal(a.spindle, b.spindle)


def test_round_trip_is_exact(tmp_path: Path) -> None:
    rng = np.random.default_rng(7)
    n = 50
    u = rng.normal(size=(n, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    q = rng.uniform(-500, 500, size=(n, 6))
    q[:, 3] = 0.0  # no a column: q must say 0 there for the round trip to hold
    m = Measurements(
        test=np.array(["diag-PPP", "diag-NPP"] * (n // 2)),
        run=rng.integers(0, 5, n).astype(np.int64),
        time_s=rng.uniform(0, 1e5, n), q=q,
        direction=rng.integers(-1, 2, size=(n, 3)).astype(np.int8),
        tool_mm=np.full(n, 123.456), is_angle=rng.random(n) < 0.3, u=u,
        value=rng.normal(scale=10, size=n), has_rotary=(False, True, True),
        temperatures={"bed": rng.uniform(18, 25, n), "t 2": rng.uniform(18, 25, n)},
        temperature_columns={"bed": "T_bed_C", "t 2": "T_t 2_C"},
        spindle=np.array(["1", "2"] * (n // 2)),
        extra={"spindle_rpm": rng.uniform(0, 8000, n),
               "note": np.array(["a,b", 'say "hi"'] * (n // 2))},
    )
    path = tmp_path / "m.csv"
    write_measurements(path, m)
    assert_same(m, read_measurements(path))
    buf = io.StringIO()
    write_measurements(buf, m)
    buf.seek(0)
    assert_same(m, read_measurements(buf))


def test_select_and_concat() -> None:
    m = read_text(text(*ROWS))
    first_two = m.select(np.array([True, True, False]))
    last = m.select([2])
    assert first_two.value.tolist() == [1.25, -2.5]
    assert last.is_angle.tolist() == [True]
    assert len(m.select([])) == 0
    joined = Measurements.concat([last, first_two])
    assert joined.value.tolist() == [3.0, 1.25, -2.5]
    assert joined.temperatures["spindle"].tolist() == [20.7, 20.5, 20.6]
    assert joined.extra["feed_mm_min"].tolist() == [1000.0] * 3
    with pytest.raises(ValueError, match="mask has shape"):
        m.select(np.array([True, False]))


def test_concat_refuses_parts_that_differ() -> None:
    a = read_text(text(*ROWS))
    b = read_text(text(*(r.rsplit(",", 1)[0] for r in ROWS), header=HEADER.rsplit(",", 1)[0]))
    with pytest.raises(ValueError, match="extra columns"):
        Measurements.concat([a, b])
    with pytest.raises(ValueError, match="at least one"):
        Measurements.concat([])


def test_container_checks_shapes() -> None:
    m = read_text(text(*ROWS))
    with pytest.raises(ValueError, match=r"Measurements.value has shape \(2,\)"):
        Measurements(test=m.test, run=m.run, time_s=m.time_s, q=m.q, direction=m.direction,
                     tool_mm=m.tool_mm, is_angle=m.is_angle, u=m.u, value=m.value[:2])


def replace_cell(row: str, column: str, value: str) -> str:
    cells = row.split(",")
    cells[HEADER.split(",").index(column)] = value
    return ",".join(cells)


BAD_CELLS = [
    ("value", "abc", "not a number"),
    ("value", "", "not a number"),
    ("value", "nan", "not a finite number"),
    ("time_s", "inf", "not a finite number"),
    ("x_mm", "-Infinity", "not a finite number"),
    ("T_spindle_C", "NaN", "not a finite number"),
    ("dir_y", "2", "direction must be -1, 0 or +1"),
    ("dir_x", "0.5", "direction must be -1, 0 or +1"),
    ("run", "1.5", "run must be an integer"),
    ("quantity", "force", "quantity must be 'displacement' or 'angle'"),
    ("test", "", "the test label is empty"),
]


@pytest.mark.parametrize(("column", "cell", "what"), BAD_CELLS)
def test_bad_cell_names_line_and_column(style: str, column: str, cell: str, what: str
                                        ) -> None:
    rows = list(ROWS)
    rows[1] = replace_cell(rows[1], column, cell)
    with pytest.raises(MeasurementFormatError) as info:
        read_text(as_style(text(*rows), style))
    err = info.value
    assert (err.line, err.column) == (3, column)
    assert what in str(err) and "line 3" in str(err) and repr(column) in str(err)


def test_u_that_is_not_a_unit_vector(style: str) -> None:
    rows = list(ROWS)
    rows[2] = replace_cell(rows[2], "uz", "0.99")  # 1e-2 short: clearly not unit
    with pytest.raises(MeasurementFormatError, match=r"line 4.*not a unit vector") as info:
        read_text(as_style(text(*rows), style))
    assert info.value.line == 4
    rows[2] = replace_cell(rows[2], "uz", "0.9995")  # within the documented 1e-3
    assert read_text(as_style(text(*rows), style)).u[2, 2] == 0.9995
    diagonal = "0.5774"  # 1/sqrt(3) to four decimals
    for col in ("ux", "uy", "uz"):
        rows[2] = replace_cell(rows[2], col, diagonal)
    assert math.isclose(np.linalg.norm(read_text(text(*rows)).u[2]), 1.0, abs_tol=1e-3)


@pytest.mark.parametrize("missing", ["test", "run", "dir_z", "tool_mm", "value", "uy"])
def test_missing_required_column(missing: str) -> None:
    cols = HEADER.split(",")
    keep = [k for k, c in enumerate(cols) if c != missing]
    rows = [",".join(r.split(",")[k] for k in keep) for r in ROWS]
    with pytest.raises(MeasurementFormatError, match="required column is missing") as info:
        read_text(text(*rows, header=",".join(cols[k] for k in keep)))
    assert (info.value.line, info.value.column) == (1, missing)


def test_duplicate_and_empty_column_names() -> None:
    with pytest.raises(MeasurementFormatError, match="duplicate column") as info:
        read_text(text(*(r + ",1" for r in ROWS), header=HEADER + ",value"))
    assert (info.value.line, info.value.column) == (1, "value")
    with pytest.raises(MeasurementFormatError, match="header cell 18 is empty"):
        read_text(text(*(r + ",1" for r in ROWS), header=HEADER + ","))


@pytest.mark.parametrize(("content", "what", "line"), [
    ("", "empty file", None),
    ("\n \n", "empty file", None),
    (HEADER + "\n", "header but no readings", 2),
    ("\n" + text(*ROWS), "blank line before the header", 1),
    (text(ROWS[0], "", ROWS[1]), "blank line between readings", 3),
    (text(ROWS[0], ROWS[1] + ",extra"), "row has 18 cells, the header has 17", 3),
    (text(ROWS[0], ROWS[1].rsplit(",", 1)[0]), "row has 16 cells", 3),
])
def test_bad_file_structure(content: str, what: str, line: int | None) -> None:
    with pytest.raises(MeasurementFormatError, match=what) as info:
        read_text(content)
    assert info.value.line == line


def test_error_names_the_file(tmp_path: Path) -> None:
    path = tmp_path / "bad.csv"
    path.write_text(text(replace_cell(ROWS[0], "value", "x")))
    with pytest.raises(MeasurementFormatError, match=r"bad\.csv, line 2, column 'value'"):
        read_measurements(path)


CSV_CHARS = st.sampled_from([*',"\n\r -+.0123456789eE', "nan", "inf", "angle",
                             "displacement", "X", "\t"])


@given(st.lists(CSV_CHARS, max_size=200).map("".join), st.booleans())
@settings(max_examples=300, deadline=None)
def test_any_text_is_read_or_refused_never_crashes(tail: str, with_header: bool) -> None:
    content = (HEADER + "\n" + tail) if with_header else tail
    try:
        m = read_text(content)
    except MeasurementFormatError as exc:
        assert str(exc).startswith("<stream>")
    else:
        assert len(m) >= 1 and np.isfinite(m.value).all()


@given(st.lists(st.tuples(st.integers(min_value=0, max_value=10_000), CSV_CHARS,
                          st.integers(min_value=0, max_value=2)), min_size=1, max_size=6))
@settings(max_examples=400, deadline=None)
def test_a_damaged_file_is_read_or_refused_never_crashes(
        edits: list[tuple[int, str, int]]) -> None:
    content = text(*ROWS)
    for at, chars, drop in edits:  # replace `drop` characters at `at` with `chars`
        k = at % (len(content) + 1)
        content = content[:k] + chars + content[k + drop:]
    try:
        m = read_text(content)
    except MeasurementFormatError as exc:
        assert exc.line is None or exc.line >= 1
    else:
        assert np.isfinite(m.value).all() and set(np.unique(m.direction)) <= {-1, 0, 1}
