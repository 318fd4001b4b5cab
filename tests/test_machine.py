"""Machine descriptions: chains, type numbers, spindles, and errors that say what and where."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from volumetric.errors import MachineSpecError
from volumetric.model.machine import load_machine, parse_chain, parse_machine
from volumetric.model.typenumbers import all_types, chain_for_type_numbers

TRAVEL = {"x": [0, 500], "y": [0, 300], "z": [-300, 0]}


def test_formats_example_parses_with_the_documented_sides() -> None:
    m = parse_machine({"name": "vmc-01", "controller": "fanuc", "ip": "10.0.0.21",
                       "chain": "w X Y b Z t", "travel_mm": TRAVEL, "tool_length_mm": 100.0})
    assert m.axis_names == ("X", "Y", "Z")
    assert [a.side for a in m.axes] == ["workpiece", "workpiece", "tool"]
    assert m.branch().tool_direction == (-0.0, -0.0, -1.0)
    assert m.axis("x").travel == (0.0, 500.0)


def test_gantry_has_every_axis_on_the_tool_side() -> None:
    wp, tool = parse_chain("w b Y X Z t")
    assert wp == [] and tool == ["Y", "X", "Z"]


def test_every_documented_type_number_builds() -> None:
    types = all_types()
    assert len([t for t in types if t[1] == 0]) == 4
    assert len([t for t in types if t[1] != 0]) == 12
    chains = set()
    for t, r in types:
        m = parse_machine({"translational_type": t, "rotary_type": r, "travel_mm": TRAVEL})
        n_rot = sum(a.kind == "rotary" for a in m.axes)
        assert n_rot == (0 if r == 0 else 2)
        assert {a.name for a in m.axes} >= {"X", "Y", "Z"}
        chains.add(m.chain)
    assert len(chains) == 16  # every type is a different machine


def test_type_numbers_map_to_the_documented_chains() -> None:
    assert chain_for_type_numbers(2, 0) == "w X Y b Z t"
    assert chain_for_type_numbers(1, 0) == "w b Y X Z t"
    assert chain_for_type_numbers(3, 1) == "w C A X b Y Z t"
    assert chain_for_type_numbers(4, 2) == "w Y b X Z C A t"
    assert chain_for_type_numbers(2, 3) == "w C X Y b Z B t"


def test_chain_wins_over_type_numbers() -> None:
    m = parse_machine({"chain": "w b X Y Z t", "translational_type": 2, "travel_mm": TRAVEL})
    assert m.chain == "w b X Y Z t"


def test_arch_machine_has_two_tool_branches_sharing_x_and_y() -> None:
    m = parse_machine({
        "chain": "w X b Y t",
        "travel_mm": {"x": [10, 500], "y": [10, 290], "z1": [-300, -10], "z2": [-300, -10]},
        "spindles": [
            {"name": "S1", "axis": "Z1", "direction": [0, 0, 1], "tool_length_mm": 50},
            {"name": "S2", "axis": "Z2", "direction": [0, -0.5, 0.8660254037844386]},
        ],
    })
    assert m.axis_names == ("X", "Y", "Z1", "Z2")
    assert [a.name for a in m.branch("S2").links] == ["X", "Y", "Z2"]
    assert m.branch("S2").tool_direction == (-0.0, 0.5, -0.8660254037844386)


@pytest.mark.parametrize(
    ("spec", "message"),
    [
        ({"chain": "w X Q b Z t"}, r"unknown token 'Q' at position 3"),
        ({"chain": "w X X b Z t"}, r"axis X appears twice \(positions 2 and 3\)"),
        ({"chain": "w X Y Z t"}, r"exactly one 'b'"),
        ({"chain": "X w Y b Z t"}, r"must start with 'w'"),
        ({"chain": "w X Y b t Z"}, r"must end with 't'"),
        ({"chain": "w X Y b Z"}, r"exactly one 't'"),
        ({"chain": "w X Y b Z t", "travel_mm": {"x": [0, 1], "y": [0, 1]}},
         r"no entry for axis 'z'"),
        ({"chain": "w X Y b Z t", "travel_mm": {**TRAVEL, "c": [0, 360]}},
         r"travel_mm.c: the machine has no axis"),
        ({"chain": "w X Y b Z t", "travel_mm": {**TRAVEL, "x": [5, 1]}}, r"low < high"),
        ({"translational_type": 7}, r"translational_type 7 is not in the table"),
        ({"translational_type": 2, "rotary_type": 5}, r"rotary_type 5"),
        ({}, r"needs 'chain' or 'translational_type'"),
        ({"chain": "w X Y b Z t", "travel_mm": TRAVEL, "ip": "10.0.0.999"}, r"not an IPv4"),
        ({"chain": "w X Y b Z t", "travel_mm": TRAVEL, "controller": "heidenhain"}, r"fanuc"),
        ({"chain": "w X b Y t", "travel_mm": {"x": [0, 1], "y": [0, 1], "z1": [0, 1]},
          "spindles": [{"axis": "Z1", "direction": [0, 0, 2]}]}, r"unit vector"),
        ({"chain": "w X b Y t", "travel_mm": {"x": [0, 1], "y": [0, 1]},
          "spindles": [{"axis": "Q1", "direction": [0, 0, 1]}]}, r"not a spindle axis name"),
    ],
)
def test_bad_descriptions_get_errors_that_say_what_and_where(
    spec: dict[str, object], message: str
) -> None:
    spec.setdefault("travel_mm", TRAVEL)
    with pytest.raises(MachineSpecError, match=message):
        parse_machine(spec)


def test_load_machine_names_the_file(tmp_path: Path) -> None:
    p = tmp_path / "m.json"
    p.write_text("{not json")
    with pytest.raises(MachineSpecError, match=r"m.json: not JSON"):
        load_machine(p)
    p.write_text(json.dumps({"chain": "w X Y b Z t", "travel_mm": TRAVEL}))
    assert load_machine(p).axis_names == ("X", "Y", "Z")
