"""Hypothesis strategies the fuzz tests share: numbers and text a user might type, garbage
CSV readings, JSON trees and one-entry mutations of a valid document."""

from __future__ import annotations

import string
from collections.abc import Callable
from typing import Any

from hypothesis import strategies as st

HEADER = ["test", "run", "time_s", "x_mm", "y_mm", "z_mm", "dir_x", "dir_y", "dir_z",
          "tool_mm", "quantity", "ux", "uy", "uz", "value"]
GOOD_ROW = ["X-positioning", "1", "0", "100", "300", "-250", "1", "0", "0", "100",
            "displacement", "1", "0", "0", "1.5"]

# the CLI fuzz's cases per kind (the entry-point fuzz adds its own to reach 10,000)
CASES = {"csv": 1100, "json": 1300, "options": 2000, "files": 800}


NUMBERS = st.one_of(
    st.integers(-10**6, 10**6).map(str),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(["1e300", "-1e300", "1e9", "nan", "inf", "-inf", "0", "-0", "1e-320",
                     "0x10", "1_000", " 3 ", "+1", ".", "-", "1e", "２"]),
)
TEXT = st.text(alphabet=string.printable + "µ°é\u200b\x00", max_size=12)
CELL = st.one_of(NUMBERS, TEXT, st.sampled_from(["", '"', '""', "displacement", "angle",
                                                 "X-positioning", "-1", "1"]))


@st.composite
def readings_csv(draw: st.DrawFn) -> str:
    """A small CSV: the format's header (sometimes shuffled, cut or with extra columns)
    and rows of good cells with some replaced by garbage."""
    header = list(HEADER)
    if draw(st.booleans()):
        header = draw(st.permutations(header))
    if draw(st.integers(0, 9)) == 0:
        header = header[:draw(st.integers(0, len(header)))]
    header += draw(st.lists(st.sampled_from(["a_deg", "c_deg", "T_s_C", "spindle", "x_mm",
                                             "extra", ""]), max_size=2))
    rows = []
    for _ in range(draw(st.integers(0, 6))):
        row = [dict(zip(HEADER, GOOD_ROW, strict=True)).get(h, "20") for h in header]
        for _ in range(draw(st.integers(0, 3))):
            if row:
                row[draw(st.integers(0, len(row) - 1))] = draw(CELL)
        if draw(st.integers(0, 9)) == 0:
            row = row[:draw(st.integers(0, len(row)))]
        rows.append(row)
    sep = draw(st.sampled_from([",", ",", ",", ";", "\t"]))
    lines = [sep.join(header)] + [sep.join(r) for r in rows]
    end = draw(st.sampled_from(["\n", "\r\n", "\n\n", ""]))
    return "\n".join(lines) + end


JSON = st.recursive(
    st.one_of(st.none(), st.booleans(), st.integers(-10**12, 10**12),
              st.floats(allow_nan=False, allow_infinity=False), TEXT),
    lambda inner: st.one_of(st.lists(inner, max_size=4),
                            st.dictionaries(TEXT, inner, max_size=4)),
    max_leaves=12)


def mutate(base: Any, draw: Callable[[Any], Any]) -> Any:
    """``base`` with one entry, somewhere in its tree, replaced, removed or added."""
    if isinstance(base, dict) and base and draw(st.integers(0, 3)):
        key = draw(st.sampled_from(sorted(base)))
        out = dict(base)
        action = draw(st.integers(0, 2))
        if action == 0:
            out.pop(key)
        elif action == 1:
            out[key] = mutate(base[key], draw)
        else:
            out[draw(TEXT)] = draw(JSON)
        return out
    if isinstance(base, list) and base and draw(st.booleans()):
        i = draw(st.integers(0, len(base) - 1))
        return [mutate(v, draw) if k == i else v for k, v in enumerate(base)]
    return draw(st.one_of(JSON, st.sampled_from([1e300, -1e9, 0, -1, "", [], {}])))
