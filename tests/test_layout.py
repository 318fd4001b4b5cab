"""The layout keeps its promises (issue 14, "a layout that shows the flow"): read from the
source with ``ast``, the imports have no circle, no package imports a layer above it, the
numeric core's stages import only earlier stages, and no test imports another test module.

Layers, lowest first (a package may import the ones before it, never after):

    volumetric, protocol  ->  machine_sim  ->  server  ->  ednc

``volumetric`` (the numeric core) and ``protocol`` (the wire) stand alone: neither imports
the other or anything above. ``machine_sim`` and ``server`` are peers that share
``protocol`` and never import each other. Inside ``volumetric`` the stages follow the flow
of the data: model -> measure -> identify -> verify, diagnose -> compensate.

A violation owned by someone else is listed below with what it is, so the test stays
green for everyone while it is fixed and fails on any new one. Remove an entry when it is
fixed (the lists only shrink; they are allowances, so a stale one fails nothing).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from tests.support.imports import PACKAGES, Edge, cycles, edges, module_path, modules

# Which project packages each package must not import (all imports, typing ones too: a
# layer that needs a type from above is still upside down).
FORBIDDEN = {
    "volumetric": {"protocol", "machine_sim", "server", "ednc"},
    "protocol": {"volumetric", "machine_sim", "server", "ednc"},
    "machine_sim": {"server", "ednc"},
    "server": {"machine_sim", "ednc"},
}

# Stages of volumetric/ in the order the data flows; equal numbers may not import each
# other either (verify and diagnose are two views of one identified model). plausible holds
# the limits every stage checks its inputs against, so it comes first.
STAGES = {"errors": -1, "plausible": -2, "model": 0, "measure": 1, "identify": 2, "verify": 3,
          "diagnose": 3, "compensate": 4}

# Known, reported, owned elsewhere: (importing module, imported module).
KNOWN_CIRCLES: set[frozenset[str]] = set()  # none since SimulatedMachine.run_campaign went
KNOWN_STAGE_BREAKS: set[tuple[str, str]] = set()  # none since first_order_lag moved to model/

ALL = modules(PACKAGES)
EDGES = edges(ALL)


def runtime_graph(es: list[Edge]) -> dict[str, set[str]]:
    graph: dict[str, set[str]] = {}
    for e in es:
        if e.runtime:
            graph.setdefault(e.source, set()).add(e.target)
    return graph


def upward(es: list[Edge]) -> list[Edge]:
    return [e for e in es
            if e.target.split(".")[0] in FORBIDDEN.get(e.source.split(".")[0], set())]


def stage_breaks(es: list[Edge]) -> list[Edge]:
    out = []
    for e in es:
        s, t = e.source.split("."), e.target.split(".")
        if (s[0] == t[0] == "volumetric" and len(s) > 1 and len(t) > 1 and s[1] != t[1]
                and STAGES.get(t[1], 99) >= STAGES.get(s[1], 99)):
            out.append(e)
    return out


# The sans-I/O wire protocol and the pure, synchronous numeric core do no I/O of their own
# (style.md, habits 1 and 4): the event loop calls them, never the other way round.
NO_IO = {"protocol": {"asyncio", "socket", "selectors", "ssl", "threading"},
         "volumetric": {"asyncio", "socket", "selectors", "ssl"}}


def io_imports(known: dict[str, Path]) -> list[str]:
    """``path:line imports x`` for each I/O module a NO_IO package imports."""
    bad = []
    for name, path in known.items():
        banned = NO_IO.get(name.split(".")[0], set())
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            roots = ([a.name for a in node.names] if isinstance(node, ast.Import) else
                     [node.module or ""] if isinstance(node, ast.ImportFrom) and not node.level
                     else [])
            bad += [f"{module_path(name)}:{node.lineno} imports {r}" for r in roots
                    if r.split(".")[0] in banned]
    return bad


def test_protocol_and_numeric_core_do_no_io() -> None:
    bad = io_imports(ALL)
    assert not bad, "\n".join(bad)


def test_the_graph_is_read_from_every_package() -> None:
    assert {name.split(".")[0] for name in ALL} == set(PACKAGES)
    assert len(EDGES) > 500  # the project's own imports, not an empty parse


def test_no_import_circles() -> None:
    found = {frozenset(c) for c in cycles(runtime_graph(EDGES))}
    new = found - KNOWN_CIRCLES
    assert not new, "import circles: " + "; ".join(" <-> ".join(sorted(c)) for c in new)


def test_no_package_imports_a_layer_above_it() -> None:
    bad = upward(EDGES)
    assert not bad, "imports against the layers:\n" + "\n".join(map(str, bad))


def test_numeric_stages_import_only_earlier_stages() -> None:
    found = stage_breaks(EDGES)
    new = [e for e in found if (e.source, e.target) not in KNOWN_STAGE_BREAKS]
    assert not new, "a stage imports a later one:\n" + "\n".join(map(str, new))


def test_every_volumetric_stage_is_known() -> None:
    stages = {name.split(".")[1] for name in ALL if name.startswith("volumetric.")}
    assert stages <= set(STAGES), f"a new stage needs its place in STAGES: {stages - set(STAGES)}"


def imports_of_test_modules(es: list[Edge]) -> list[Edge]:
    """Imports of a test module or of conftest (pytest's, not a library)."""
    return [e for e in es if e.target.split(".")[-1].startswith(("test_", "conftest"))]


def test_no_test_imports_another_test_module() -> None:
    bad = imports_of_test_modules(edges(modules(["tests", "benchmarks"])))
    assert not bad, ("shared test code goes to tests/support/:\n"
                     + "\n".join(map(str, bad)))


# -- the checks can fail: each on a small tree with the fault


def _tree(tmp_path: Path, files: dict[str, str]) -> dict[str, Path]:
    for name, text in files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return modules(sorted({n.split("/")[0] for n in files}), root=tmp_path)


def test_a_circle_through_a_function_level_import_is_found(tmp_path: Path) -> None:
    known = _tree(tmp_path, {
        "machine_sim/__init__.py": "",
        "machine_sim/a.py": "from .b import f\n",
        "machine_sim/b.py": "def f():\n    from machine_sim.a import g\n",
    })
    assert cycles(runtime_graph(edges(known))) == [["machine_sim.a", "machine_sim.b"]]


def test_a_typing_only_import_makes_no_circle_but_counts_for_layers(tmp_path: Path) -> None:
    known = _tree(tmp_path, {
        "server/__init__.py": "",
        "server/a.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                       "    from ednc import x\n    from server import b\n",
        "server/b.py": "import server.a\n",
        "ednc/__init__.py": "from server import a\n",
    })
    es = edges(known)
    assert cycles(runtime_graph(es)) == []
    assert [(e.source, e.target, e.line) for e in upward(es)] == [("server.a", "ednc", 3)]


def test_a_stage_importing_a_later_one_is_found(tmp_path: Path) -> None:
    known = _tree(tmp_path, {
        "volumetric/__init__.py": "",
        "volumetric/model/__init__.py": "",
        "volumetric/model/m.py": "from ..compensate import solver\n",
        "volumetric/compensate/__init__.py": "",
        "volumetric/compensate/solver.py": "from volumetric.model.m import x\n",
    })
    assert [(e.source, e.target) for e in stage_breaks(edges(known))] == [
        ("volumetric.model.m", "volumetric.compensate.solver")]


def test_an_io_import_in_the_protocol_is_found(tmp_path: Path) -> None:
    known = _tree(tmp_path, {"protocol/__init__.py": "",
                             "protocol/codec.py": "import zlib\nfrom asyncio import sleep\n"})
    assert io_imports(known) == ["protocol/codec.py:2 imports asyncio"]


@pytest.mark.parametrize("line", ["from tests.test_x import helper",
                                  "from tests import test_x", "import tests.conftest"])
def test_a_test_importing_a_test_module_is_found(tmp_path: Path, line: str) -> None:
    known = _tree(tmp_path, {"tests/__init__.py": "", "tests/conftest.py": "",
                             "tests/test_x.py": "", "tests/test_y.py": line + "\n"})
    assert [e.source for e in imports_of_test_modules(edges(known))] == ["tests.test_y"]
