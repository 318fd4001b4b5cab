"""Translational and rotary type numbers of the generalized kinematic model.

The EDNC seed paper builds one model for 4 three-axis and 12 five-axis machine types,
chosen by a translational type number (which linear axes carry the workpiece and which
the tool) and a rotary type number (where the two rotary axes sit). Its figures did not
survive extraction, so the numbering below is this project's, documented here and pinned
by tests; every combination maps to a chain string (``formats.md`` section 1).

Translational types (three linear axes):

====  =======================  ==========================================================
type  chain                    machine
====  =======================  ==========================================================
1     ``w b Y X Z t``          workpiece fixed; gantry/bridge: Y on the base, X on Y, Z on X
2     ``w X Y b Z t``          cross table (X on Y) under a fixed column with a Z slide
3     ``w X b Y Z t``          table in X; column in Y carrying the Z slide
4     ``w Y b X Z t``          table in Y; travelling column in X carrying the Z slide
====  =======================  ==========================================================

Rotary types (0 = three-axis machine):

====  =======================  ==========================================================
type  rotary axes              where they go in the chain
====  =======================  ==========================================================
0     none                     three-axis machine
1     table-tilting: C on A    ``w C A`` at the workpiece end (trunnion table)
2     spindle-tilting: C, A    ``C A t`` at the tool end (fork head: C on Z, A on C)
3     table C, spindle B       ``w C`` at the workpiece end and ``B t`` at the tool end
====  =======================  ==========================================================

Five-axis types are the 12 combinations of translational type 1-4 with rotary type 1-3.
"""

from __future__ import annotations

from typing import Any

from volumetric.errors import MachineSpecError

TRANSLATIONAL_CHAINS: dict[int, tuple[tuple[str, ...], tuple[str, ...]]] = {
    1: ((), ("Y", "X", "Z")),
    2: (("X", "Y"), ("Z",)),
    3: (("X",), ("Y", "Z")),
    4: (("Y",), ("X", "Z")),
}

# (axes added at the workpiece end, axes added at the tool end), in chain order.
ROTARY_PLACEMENT: dict[int, tuple[tuple[str, ...], tuple[str, ...]]] = {
    0: ((), ()),
    1: (("C", "A"), ()),
    2: ((), ("C", "A")),
    3: (("C",), ("B",)),
}


def chain_for_type_numbers(translational_type: Any, rotary_type: Any = 0) -> str:
    """The chain string of a generalized-model type.

    Parameters
    ----------
    translational_type : int
        1 to 4.
    rotary_type : int
        0 (three-axis) or 1 to 3.

    Returns
    -------
    str
        E.g. ``chain_for_type_numbers(2, 0) == "w X Y b Z t"``.

    Raises
    ------
    MachineSpecError
        For numbers outside the table (the message lists the valid ones).
    """
    try:
        t = int(translational_type)
        r = int(rotary_type)
    except (TypeError, ValueError):
        raise MachineSpecError(
            f"type numbers must be integers, got {translational_type!r}, {rotary_type!r}"
        ) from None
    if t not in TRANSLATIONAL_CHAINS:
        raise MachineSpecError(
            f"translational_type {t} is not in the table (valid: {sorted(TRANSLATIONAL_CHAINS)})"
        )
    if r not in ROTARY_PLACEMENT:
        raise MachineSpecError(
            f"rotary_type {r} is not in the table (valid: {sorted(ROTARY_PLACEMENT)})"
        )
    wp, tool = TRANSLATIONAL_CHAINS[t]
    rwp, rtool = ROTARY_PLACEMENT[r]
    return " ".join(["w", *rwp, *wp, "b", *tool, *rtool, "t"])


def all_types() -> list[tuple[int, int]]:
    """Every documented (translational, rotary) pair: 4 three-axis and 12 five-axis."""
    return [(t, r) for r in sorted(ROTARY_PLACEMENT) for t in sorted(TRANSLATIONAL_CHAINS)]
