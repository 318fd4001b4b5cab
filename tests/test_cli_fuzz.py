"""Garbage in, one line out: hypothesis feeds random CSVs, JSON files, binary files and
option values to every offline command, in-process through typer's CliRunner, and no
input may end in a traceback (issue 25: ">= 10,000 cases, no traceback").

A run is fine when it succeeds (exit 0), when typer refuses the options (a usage error,
exit 2), or when the command raises the project's :class:`~ednc.cli.UserError` with one
line (which ``ednc`` prints as ``ednc: error: ...``, exit 2). Anything else escaping is a
traceback a user would see.

Cases per run (derandomised, so CI sees the same ones): readings CSVs 1,100, JSON files
(machine and model, mutated and random) 1,300, options 2,000, binary and text garbage
as map, point, machine, model and data files 800: 5,200 (``CASES``), with the 5,000 of
``tests/test_entry_fuzz.py`` (REST uploads, MQTT temperatures, fleet files) over 10,000
across the entry points; marked slow. A command that refuses its input leaves no output
file behind (checked where the fuzz names one).
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
import typer
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from ednc.cli import UserError, _load_commands, app, error_line
from tests.support.fuzz import CASES, JSON, NUMBERS, TEXT, mutate, readings_csv

pytestmark = pytest.mark.slow

VMC = {"name": "vmc", "controller": "siemens", "chain": "w X Y b Z t",
       "tool_length_mm": 100.0,
       "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}}
"""The CLI's share of the >= 10,000 cases; tests/test_entry_fuzz.py has the rest (REST,
MQTT, fleet files), in about the time this file alone took before."""

_load_commands()
RUNNER = CliRunner()
COMMAND: Any = typer.main.get_command(app)  # built once: typer rebuilds it per invoke
SETTINGS = dict(deadline=None, derandomize=True, database=None,
                suppress_health_check=[HealthCheck.too_slow,
                                       HealthCheck.function_scoped_fixture,
                                       HealthCheck.data_too_large])


def run(args: list[str], outputs: tuple[Path, ...] = ()) -> None:
    """Invoke ``ednc ARGS`` in-process; fail on anything but exit 0, a usage error or one
    UserError line, and on a refusal that leaves one of ``outputs`` behind."""
    for out in outputs:
        if out.is_dir():
            shutil.rmtree(out)
        out.unlink(missing_ok=True)
    r = RUNNER.invoke(COMMAND, args, catch_exceptions=True)
    exc = r.exception
    if exc is None or isinstance(exc, SystemExit):
        assert r.exit_code in (0, 1, 2), (args, r.exit_code, r.output)
        if r.exit_code == 1:  # typer's own aborts; anything else exiting 1 is a crash
            raise AssertionError((args, r.output))
        if r.exit_code == 2:
            assert not [o for o in outputs if o.exists()], (args, "left", outputs)
        return
    if isinstance(exc, UserError):
        assert error_line(exc), args  # what ednc prints: one line, never empty
        assert not [o for o in outputs if o.exists()], (args, "left", outputs)
        return
    raise AssertionError(f"ednc {' '.join(args)!r} raised {type(exc).__name__}: {exc}"
                         ) from exc


@pytest.fixture(scope="module")
def files(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A valid machine, model and map: the fixed parts the garbage is combined with."""
    d = tmp_path_factory.mktemp("fuzz")
    (d / "vmc.json").write_text(json.dumps(VMC))
    run(["sim", "--campaign", str(d / "c.csv"), "--machine", str(d / "vmc.json"),
         "--effect", "noise:0.3"])
    run(["fit", "--machine", str(d / "vmc.json"), "--data", str(d / "c.csv"),
         "--out", str(d / "model.json")])
    run(["map", "--machine", str(d / "vmc.json"), "--model", str(d / "model.json"),
         "--out", str(d / "map.bin"), "--tolerance-um", "5"])
    for name in ("model.json", "map.bin"):
        assert (d / name).exists(), name
    (d / "points.csv").write_text("x,y,z\n400,300,-250\n")
    return {"dir": d, "machine": d / "vmc.json", "model": d / "model.json",
            "map": d / "map.bin", "points": d / "points.csv", "data": d / "c.csv"}


# -- the tests


@settings(max_examples=CASES["csv"], **SETTINGS)  # type: ignore[arg-type]
@given(data=st.data())
def test_garbage_readings(files: dict[str, Path], data: st.DataObject) -> None:
    text = data.draw(readings_csv())
    path = files["dir"] / "garbage.csv"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    command = data.draw(st.sampled_from(["fit", "diagnose", "predict", "iso230-2"]))
    args = {"fit": ["fit", "--machine", str(files["machine"])],
            "diagnose": ["diagnose", "--machine", str(files["machine"]), "--json"],
            "predict": ["predict", "--machine", str(files["machine"]), "--model",
                        str(files["model"])],
            "iso230-2": ["iso230-2", "--json"]}[command]
    run([*args, "--data", str(path)])


@settings(max_examples=CASES["json"], **SETTINGS)  # type: ignore[arg-type]
@given(data=st.data())
def test_garbage_machine_and_model_files(files: dict[str, Path], data: st.DataObject) -> None:
    model = json.loads(files["model"].read_text())
    which = data.draw(st.sampled_from(["machine", "model"]))
    base = VMC if which == "machine" else model
    body = mutate(base, data.draw) if data.draw(st.integers(0, 3)) else data.draw(JSON)
    path = files["dir"] / f"garbage-{which}.json"
    path.write_text(json.dumps(body))
    machine = str(path if which == "machine" else files["machine"])
    model_path = str(path if which == "model" else files["model"])
    command = data.draw(st.sampled_from(["compensate", "predict", "fit", "tables"]))
    args = {
        "compensate": ["compensate", "--machine", machine, "--model", model_path,
                       "--point", "400,300,-250", "--json"],
        "predict": ["predict", "--machine", machine, "--model", model_path, "--data",
                    str(files["points"])],
        "fit": ["fit", "--machine", machine, "--data", str(files["points"])],
        "tables": ["tables", "export", "--machine", machine, "--model", model_path,
                   "--out", str(files["dir"] / "tables-out")],
    }[command]
    run(args, outputs=(files["dir"] / "tables-out",))


OPTION = st.one_of(NUMBERS, TEXT, st.sampled_from(["x=1", "1,2", "T=1", "+", "-", "=",
                                                   "fanuc", "grid", "auto"]))


def options(files: dict[str, Path]) -> dict[str, Callable[[Callable[[Any], Any]], list[str]]]:
    m, model, mp = str(files["machine"]), str(files["model"]), str(files["map"])
    out = str(files["dir"] / "o")
    return {
        "map": lambda draw: ["map", "--machine", m, "--model", model, "--out", out + ".bin",
                             draw(st.sampled_from(["--tolerance-um", "--increment",
                                                   "--limit-mm", "--limit-deg", "--version",
                                                   "--kind", "--controller",
                                                   "--temperature", "--weights"])),
                             draw(OPTION), "--tolerance-um", "50"],
        "compensate": lambda draw: ["compensate", "--machine", m, "--model", model,
                                    "--point", draw(OPTION),
                                    draw(st.sampled_from(["--approach", "--weights",
                                                          "--temperature", "--point"])),
                                    draw(OPTION)],
        "lookup": lambda draw: ["lookup", "--map", mp, "--points", str(files["points"]),
                                "--temperature", draw(OPTION)],
        "diagnose": lambda draw: ["diagnose", "--machine", m, "--data", str(files["points"]),
                                  draw(st.sampled_from(["--max-readings",
                                                        "--holdout-after"])),
                                  draw(OPTION)],
        "sim": lambda draw: ["sim", "--campaign", out + ".csv", "--machine",
                             str(files["dir"] / "missing.json"),
                             draw(st.sampled_from(["--seed", "--effect", "--cycle-ms",
                                                   "--duration", "--controller"])),
                             draw(OPTION)],
        "fit": lambda draw: ["fit", "--machine", m, "--data", str(files["points"]), "--out",
                             draw(st.sampled_from(["/missing/dir/x.json", "/", "",
                                                   str(files["dir"])]))],
        "predict": lambda draw: ["predict", "--machine", m, "--model", model, "--data",
                                 draw(OPTION)],
    }


@settings(max_examples=CASES["options"], **SETTINGS)  # type: ignore[arg-type]
@given(data=st.data())
def test_garbage_options(files: dict[str, Path], data: st.DataObject) -> None:
    table = options(files)
    name = data.draw(st.sampled_from(sorted(table)))
    out = files["dir"] / "o"
    run(table[name](data.draw), outputs=(out.with_suffix(".bin"), out.with_suffix(".csv")))


@settings(max_examples=CASES["files"], **SETTINGS)  # type: ignore[arg-type]
@given(data=st.data())
def test_garbage_files_where_maps_and_points_belong(files: dict[str, Path],
                                                    data: st.DataObject) -> None:
    good = files["map"].read_bytes()
    blob = data.draw(st.one_of(
        st.binary(max_size=200),
        st.builds(lambda i, b: good[:i] + b + good[i + len(b):],
                  st.integers(0, len(good)), st.binary(min_size=1, max_size=8)),
        st.builds(lambda i: good[:i], st.integers(0, len(good))),
        readings_csv().map(lambda t: t.encode("utf-8", "surrogatepass"))))
    path = files["dir"] / "garbage.bin"
    path.write_bytes(blob)
    where = data.draw(st.sampled_from(["map", "points", "machine", "model", "data"]))
    args = {
        "map": ["lookup", "--map", str(path), "--points", str(files["points"])],
        "points": ["lookup", "--map", str(files["map"]), "--points", str(path)],
        "machine": ["compensate", "--machine", str(path), "--model", str(files["model"]),
                    "--point", "1,2,3"],
        "model": ["compensate", "--machine", str(files["machine"]), "--model", str(path),
                  "--points", str(files["points"])],
        "data": ["fit", "--machine", str(files["machine"]), "--data", str(path)],
    }[where]
    run(args)
