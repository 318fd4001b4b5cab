"""No import circle in the house, counting every import (issue 27, item 5).

``tests/test_layout.py`` looks for circles among the imports that run. This test is
stricter: an import under ``if TYPE_CHECKING:`` counts as well, as does one inside a
function. A circle that only the type checker sees still means that neither module can be
read, typed or moved without the other (``server.center`` -> ``server.intake`` ->
``server.feed`` -> ``server.center`` was one, its first edge typing-only). The graph is
read from the source with ``ast`` (:mod:`tests.support.imports`); nothing is imported.
"""

from __future__ import annotations

from pathlib import Path

from tests.support.imports import PACKAGES, Edge, cycles, edges, modules


def full_graph(es: list[Edge]) -> dict[str, set[str]]:
    """Module -> the modules it imports, typing-only and function-level imports included."""
    graph: dict[str, set[str]] = {}
    for e in es:
        graph.setdefault(e.source, set()).add(e.target)
    return graph


def describe(es: list[Edge], circle: list[str]) -> str:
    """The edges inside one circle, as ``path:line imports module`` lines."""
    inside = set(circle)
    lines = {f"  {e}{'' if e.runtime else ' (TYPE_CHECKING)'}"
             for e in es if e.source in inside and e.target in inside}
    return "\n".join(sorted(lines))


def test_the_house_has_no_import_circle() -> None:
    known = modules(PACKAGES)
    assert {name.split(".")[0] for name in known} == set(PACKAGES)
    es = edges(known)
    assert len(es) > 500  # the project's own imports, not an empty parse
    found = cycles(full_graph(es))
    assert not found, "import circles:\n" + "\n".join(
        " <-> ".join(c) + "\n" + describe(es, c) for c in found)


# -- the check can fail: on small trees with each kind of circle


def _tree(tmp_path: Path, files: dict[str, str]) -> list[list[str]]:
    for name, text in files.items():
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return cycles(full_graph(edges(modules(sorted({n.split("/")[0] for n in files}),
                                           root=tmp_path))))


def test_a_circle_closed_by_a_typing_only_import_is_found(tmp_path: Path) -> None:
    found = _tree(tmp_path, {
        "server/__init__.py": "",
        "server/center.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                            "    from server.intake import Intake\n",
        "server/intake.py": "from server.center import Center\nfrom server import feed\n",
        "server/feed.py": "from server.center import Center\n",
    })
    assert found == [["server.center", "server.feed", "server.intake"]]


def test_a_circle_through_a_function_level_import_is_found(tmp_path: Path) -> None:
    found = _tree(tmp_path, {
        "machine_sim/__init__.py": "",
        "machine_sim/campaign.py": "from .instruments import SimulatedMachine\n",
        "machine_sim/instruments.py": "def run():\n    from .campaign import run_campaign\n",
    })
    assert found == [["machine_sim.campaign", "machine_sim.instruments"]]


def test_imports_without_a_circle_give_none(tmp_path: Path) -> None:
    found = _tree(tmp_path, {
        "server/__init__.py": "",
        "server/center.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n"
                            "    from server.intake import Intake\n",
        "server/intake.py": "from server import feed\n",
        "server/feed.py": "import server.events\n",
        "server/events.py": "",
    })
    assert found == []
