"""Which CEC tables to write when the control has fewer than the model asks for.

Each group of tables (a 1-D table, a product with the tables it needs, a backlash pair)
is judged by what it removes at the tool tip, not by its own size: shares of different
tables onto one axis add and may cancel; a constant over the whole workspace is not
judged (the workpiece zero absorbs it). Three choices are tried and the best kept, judged
by the worst plus the RMS tool-tip error the first-order correction leaves: greedy from
nothing, adding the group that lowers that most per table it costs, or most outright,
until the table count is reached or nothing lowers it; and the groups by the size of their
own share, largest first, each with the tables it needs; and every set of up to three
products, the rest filled greedily. The best of these is then
improved by exchanging one or two of its tables for others while that lowers the score. The
judgement is on random points over the travel with random traversing directions; what is
not chosen is named with its own tool-tip effect.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping, Sequence

import numpy as np
from numpy.typing import NDArray

from volumetric.compensate.cec_plan import CecPlan, sample_points

F64 = NDArray[np.float64]


def group_shares(plan: CecPlan, backlash: Mapping[str, float], n: int = 1500,
                 seed: int = 7) -> tuple[dict[str, F64], F64]:
    """Per group key (``1d:K:d``, ``prod:K:m:d``, ``dir:K``, ``const:d``) its correction
    at random points, (n, n_linear) in mm (degrees onto rotary axes count by their
    tool-tip reach, see :func:`~volumetric.compensate.cec._rotary_um`); and the sum of
    them all, the full first-order correction."""
    m = plan.machine
    q = sample_points(m, n, seed)
    rng = np.random.default_rng(seed + 1)
    direction = rng.choice([-1.0, 1.0], size=q.shape)
    col = {a.name: i for i, a in enumerate(m.axes)}
    outs = list(plan.linear) + sorted({d for (_, d) in plan.one_d if d not in plan.linear})
    oi = {d: i for i, d in enumerate(outs)}
    reach = float(np.sqrt(sum((a.travel[1] - a.travel[0]) ** 2 for a in m.axes
                              if a.kind == "linear"))) * np.pi / 180.0  # mm per degree
    shares: dict[str, F64] = {}
    for (k, d), pieces in plan.one_d.items():
        v = np.zeros((n, len(outs)))
        for p in pieces:
            v[:, oi[d]] += p.fn(q[:, col[k]])
        if d not in plan.linear:
            v *= reach
        shares[f"1d:{k}:{d}"] = v
    for (k, a, d), pieces in plan.factors.items():
        v = np.zeros((n, len(outs)))
        for p in pieces:
            v[:, oi[d]] += p.fn(q[:, col[k]]) * (q[:, col[a]] - plan.centre[a])
        shares[f"prod:{k}:{a}:{d}"] = v
    for k, b in backlash.items():
        if k in plan.linear:
            v = np.zeros((n, len(outs)))
            v[:, oi[k]] = direction[:, col[k]] * b / 2e3
            shares[f"dir:{k}"] = v
    for d, c in plan.constants.items():
        v = np.zeros((n, len(outs)))
        v[:, oi[d]] = c
        shares[f"const:{d}"] = v
    total = np.zeros((n, len(outs)))
    for v in shares.values():
        total = total + v
    return shares, total


def _score(rest: F64) -> float:
    # a constant over the whole workspace is what the workpiece zero absorbs: not judged
    norm = np.linalg.norm(rest - rest.mean(axis=0), axis=1)
    return float(norm.max() + 0.25 * np.sqrt(np.mean(norm * norm)))


def carried_sum(keys: set[str], shares: Mapping[str, F64], total: F64) -> F64:
    """The correction the tables ``keys`` carry at the points (a location constant rides
    on any 1-D table onto its axis)."""
    out = np.zeros_like(total)
    for key, v in shares.items():
        if key.startswith("const:"):
            if any(t.startswith("1d:") and t.endswith(":" + key[6:]) for t in keys):
                out = out + v
        elif key in keys:
            out = out + v
    return out


def select_groups(needs: Mapping[str, Sequence[str]], shares: Mapping[str, F64],
                  total: F64, max_tables: int) -> set[str]:
    """The table keys to write (see module docstring).

    Parameters
    ----------
    needs : mapping of group key to the table keys it needs (itself included)
    shares, total : from :func:`group_shares`
    max_tables : int
    """
    every = {t for ts in needs.values() for t in ts}
    if len(every) <= max_tables:
        return every

    def carried(keys: set[str]) -> F64:
        return carried_sum(keys, shares, total)

    def greedy(per_table: bool) -> set[str]:
        chosen: set[str] = set()
        best = _score(total)
        while True:
            pick: tuple[float, set[str], float] | None = None
            for ts in needs.values():
                new = set(ts) - chosen
                if not new or len(chosen) + len(new) > max_tables:
                    continue
                s = _score(total - carried(chosen | new))
                gain = (best - s) / (len(new) if per_table else 1)
                if gain > 0 and (pick is None or gain > pick[0]):
                    pick = (gain, new, s)
            if pick is None:
                return chosen
            chosen |= pick[1]
            best = pick[2]

    def by_size() -> set[str]:
        # the largest share first, each with what it needs, while the tables last
        chosen: set[str] = set()
        size = {g: float(np.linalg.norm(shares[g], axis=1).max()) for g in needs}
        for g in sorted(needs, key=lambda g: -size[g]):
            new = set(needs[g]) - chosen
            if len(chosen) + len(new) <= max_tables:
                chosen |= new
        return chosen

    def by_products() -> set[str]:
        # every set of up to three products that fits, the rest filled greedily with the
        # other groups: a product costs several tables at once, which a greedy start
        # from nothing rarely pays for
        prods = [g for g in needs if g.startswith("prod:")]
        others = [g for g in needs if not g.startswith("prod:")]
        best_keys: set[str] = set()
        best = math.inf
        for r in range(0, min(3, len(prods)) + 1):
            for combo in itertools.combinations(prods, r):
                chosen = set().union(*(set(needs[g]) for g in combo)) if combo else set()
                if len(chosen) > max_tables:
                    continue
                current = _score(total - carried(chosen))
                while True:
                    pick: tuple[float, set[str]] | None = None
                    for g in others:
                        new = set(needs[g]) - chosen
                        if not new or len(chosen) + len(new) > max_tables:
                            continue
                        sc = _score(total - carried(chosen | new))
                        if sc < current and (pick is None or sc < pick[0]):
                            pick = (sc, new)
                    if pick is None:
                        break
                    current = pick[0]
                    chosen |= pick[1]
                if current < best:
                    best, best_keys = current, chosen
        return best_keys

    options = [greedy(True), greedy(False), by_size(), by_products()]
    start = min(options, key=lambda keys: _score(total - carried(keys)))
    return _improve(start, needs, shares, total, max_tables)


def _improve(start: set[str], needs: Mapping[str, Sequence[str]],
             shares: Mapping[str, F64], total: F64, max_tables: int) -> set[str]:
    """Hill-climb from a choice: exchange one or two tables for as many others (a
    product needs its factor and its arm at once) while that lowers the score."""
    keys = sorted({t for ts in needs.values() for t in ts})
    # a group is carried when every table it needs is written
    carried_by = [(set(ts), shares[g]) for g, ts in needs.items() if g in shares]
    consts = [(k[6:], v) for k, v in shares.items() if k.startswith("const:")]

    def score(state: frozenset[str]) -> float:
        out = np.zeros_like(total)
        for ts, v in carried_by:
            if ts <= state:
                out = out + v
        for d, v in consts:
            if any(t.startswith("1d:") and t.endswith(":" + d) for t in state):
                out = out + v
        return _score(total - out)

    state = frozenset(start)
    best = score(state)
    for _ in range(50):
        outside = [k for k in keys if k not in state]
        moves: list[frozenset[str]] = []
        room = max_tables - len(state)
        moves += [state | {a} for a in outside] if room >= 1 else []
        moves += [state - {r} | {a} for r in state for a in outside]
        found = min(moves, key=score, default=None)
        if found is None or score(found) >= best - 1e-12:
            inside = sorted(state)
            pairs_out = [(inside[i], inside[j]) for i in range(len(inside))
                         for j in range(i + 1, len(inside))]
            pairs_in = [(outside[i], outside[j]) for i in range(len(outside))
                        for j in range(i + 1, len(outside))]
            moves = [state - set(po) | set(pi) for po in pairs_out for pi in pairs_in]
            if room >= 1:
                moves += [state - {r} | set(pi) for r in state for pi in pairs_in]
            found = min(moves, key=score, default=None)
            if found is None or score(found) >= best - 1e-12:
                return set(state)
        state = found
        best = score(found)
    return set(state)


__all__ = ["carried_sum", "group_shares", "select_groups"]
