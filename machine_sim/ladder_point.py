"""The ladder's factored-map arithmetic at one point, on Python ints (a PMC scan's case).

:func:`machine_sim.ladder.factored_counts` evaluates N points with int64 arrays; a PMC
scans one point per scan, where each of its ~40 array operations on one element costs a
microsecond or more of NumPy call overhead (1.3 ms a scan for a 3-axis map of 21 tables,
most of a simulated PMC's CPU). :class:`FactoredPoint` does the same steps of §6.5 on
Python ints, with the tables' values loaded once as tuples and each axis's table interval
found once per scan (every term table of an axis shares its start, spacing and nodes).

Same results, bit for bit: NumPy's int64 ``+ - * <<`` equal exact integer arithmetic
modulo 2^64, and so does their Python-int counterpart read modulo 2^64; only the
operations that are not modular (``>>``, clip, min/max, comparisons) could tell an exact
value from a wrapped one. Every value that enters one of them is checked to be an int64
here; one that is not (a map whose products overflow, which the spec's ranges exclude)
raises :class:`Wide`, and the caller evaluates that point with the array code, which
wraps as before. Nothing here touches a float (``tests/test_factored_ladder.py`` checks
this module's source as it does :mod:`machine_sim.ladder`'s).
"""

from __future__ import annotations

from collections.abc import Sequence

from .ladder import FactoredProgram

__all__ = ["FactoredPoint", "Wide"]

_LO = -(1 << 63)
_HI = (1 << 63) - 1


class Wide(ArithmeticError):
    """An intermediate left int64: the array code (which wraps) must decide."""


def _shift_half_up(x: int, s: int) -> int:
    """:func:`machine_sim.ladder.half_up_shift` of one int; ``x`` checked when shifted
    right."""
    if s > 0:
        if not _LO <= x <= _HI:
            raise Wide
        return (x + (1 << (s - 1))) >> s
    if s < 0:
        return x << -s
    return x


class FactoredPoint:
    """A factored program's per-scan evaluation at one point (module docstring).

    Parameters
    ----------
    prog : FactoredProgram
        The map's integer tables (:func:`machine_sim.ladder.factored_program`).
    """

    def __init__(self, prog: FactoredProgram) -> None:
        self.d = len(prog.axes)
        # the interval grids: one per distinct (axis, start, shift, nodes) of the tables
        grids: list[tuple[int, int, int, int]] = []

        def grid_of(axis: int, start: int, shift: int, n: int) -> int:
            key = (axis, start, shift, n)
            if key not in grids:
                grids.append(key)
            return grids.index(key)

        # a table: (grid index or -1 for one node, values, s = shift - 15); its value at
        # the interval (i, r) is (v[i] << 15) + half_up_shift((v[i+1] - v[i]) · r, s)
        Table = tuple[int, tuple[int, ...], int]

        def table(axis: int, start: int, shift: int, values: Sequence[int]) -> Table:
            vals = tuple(map(int, values))
            if len(vals) == 1:
                return -1, vals, 0
            return grid_of(axis, int(start), int(shift), len(vals)), vals, int(shift) - 15

        self.bases = [table(axis, t.start, t.shift, t.values.tolist()) for axis, t in prog.bases]
        self.terms = [(table(t.axis, t.table.start, t.table.shift, t.table.values.tolist()),
                       t.field, t.factors, -(t.exponent + 1)) for t in prog.terms]
        self.grids = [(axis, start, shift, (n - 1) << shift, n - 2)
                      for axis, start, shift, n in grids]
        self.n_fields = prog.n_fields
        # the bounds the array code clips to, as it computes them (int64, wrapped)
        self.lim = [int(v) for v in prog.limit.tolist()]
        self.lim16 = [int(v) for v in (prog.limit << 16).tolist()]
        self.neg_lim16 = [int(v) for v in (-(prog.limit << 16)).tolist()]
        self.neg_lim = [int(v) for v in (-prog.limit).tolist()]
        self.reversal = [int(v) for v in prog.reversal.tolist()]
        self.rot = list(prog.rotary)
        self.lin = list(prog.linear)
        # a grid whose top does not fit int64 is the array code's (it clips to a wrap)
        self.usable = all(_LO <= g[3] <= _HI and _LO <= g[1] <= _HI for g in self.grids)

    def fields(self, q: Sequence[int]) -> list[int]:
        """§6.5 steps 1-2 at positions q (D,) counts: every field, 2^-16 counts (or counts
        per count), as :func:`machine_sim.ladder.factored_fields` (n_fields,)."""
        if not self.usable:
            raise Wide
        lo, hi = _LO, _HI
        at: list[tuple[int, int]] = []
        for axis, start, shift, top, last in self.grids:
            x = q[axis] - start
            if not lo <= x <= hi:
                raise Wide
            x = 0 if x < 0 else (top if x > top else x)
            i = x >> shift
            if i > last:
                i = last
            at.append((i, x - (i << shift)))
        # one table's value at its interval (i, r): (v[i] << 15) + half_up_shift((v[i+1] -
        # v[i]) · r, s), written out (a call per table costs more than its arithmetic)
        basis = []
        for g, v, s in self.bases:
            if g < 0:
                basis.append(v[0] << 15)
                continue
            i, r = at[g]
            d = (v[i + 1] - v[i]) * r
            if s > 0:
                if not lo <= d <= hi:
                    raise Wide
                d = (d + (1 << (s - 1))) >> s
            elif s < 0:
                d <<= -s
            basis.append((v[i] << 15) + d)
        acc = [0] * self.n_fields
        for (g, v, s), field, factors, out in self.terms:
            if g < 0:
                p = v[0] << 15
            else:
                i, r = at[g]
                d = (v[i + 1] - v[i]) * r
                if s > 0:
                    if not lo <= d <= hi:
                        raise Wide
                    d = (d + (1 << (s - 1))) >> s
                elif s < 0:
                    d <<= -s
                p = (v[i] << 15) + d
            for b in factors:
                p *= basis[b]
                if not lo <= p <= hi:
                    raise Wide
                p = (p + (1 << 28)) >> 29
            if out > 0:
                if not lo <= p <= hi:
                    raise Wide
                p = (p + (1 << (out - 1))) >> out
            elif out < 0:
                p <<= -out
            acc[field] += p
        return acc

    def counts(self, q: Sequence[int], c0: Sequence[int], c1: Sequence[int],
               negative: Sequence[bool] | None = None) -> list[int]:
        """§6.5 at positions q (D,) counts with thermal constants c0, c1 (D,): the counts
        the ladder writes (D,), as :func:`machine_sim.ladder.factored_counts` of one point;
        ``negative`` (D,): the axes approaching negatively (their reversal goes in before
        the final clamp). Raises :class:`Wide` where only the array code can answer."""
        d = self.d
        if len(q) != d:
            raise ValueError(f"expected {d} positions, got {len(q)}")
        acc = self.fields(q)
        c = []
        for k in range(d):
            v = acc[k] + c0[k] + _shift_half_up(c1[k] * q[k], 16)
            if not _LO <= v <= _HI:
                raise Wide
            lo, hi = self.neg_lim16[k], self.lim16[k]
            c.append(min(max(v, lo), hi))
        rev = ([0] * d if negative is None
               else [r if n else 0 for r, n in zip(self.reversal, negative, strict=True)])
        rot, lin = self.rot, self.lin
        if not rot or not lin:
            out = [_shift_half_up(c[k], 16) + rev[k] for k in range(d)]
            return self._clamp(out)
        nr = len(rot)
        sens = [[acc[d + li * nr + ri] for ri in range(nr)] for li in range(len(lin))]
        cr = [c[k] for k in rot]
        near = [_shift_half_up(x, 16) for x in cr]
        far = []
        for n_, x in zip(near, cr, strict=True):
            up = n_ << 16
            if not _LO <= up <= _HI:
                raise Wide
            far.append(n_ - 1 if up > x else n_ + 1)
        best = [0] * d
        best_cost = 0
        for choice in range(1 << nr):
            r_counts = [far[j] if (choice >> (nr - 1 - j)) & 1 else near[j] for j in range(nr)]
            moved = [(rc << 16) - x for rc, x in zip(r_counts, cr, strict=True)]
            l_counts = []
            cost = 0
            for li, k in enumerate(lin):
                srow = sens[li]
                want = c[k] + _shift_half_up(sum(srow[j] * moved[j] for j in range(nr)), 16)
                lc = _shift_half_up(want, 16)
                resid = want - (lc << 16)
                cost += resid * resid
                l_counts.append(lc)
            if not _LO <= cost <= _HI:
                raise Wide
            if choice == 0 or cost < best_cost:
                best_cost = cost
                for j, k in enumerate(rot):
                    best[k] = r_counts[j]
                for li, k in enumerate(lin):
                    best[k] = l_counts[li]
        return self._clamp([best[k] + rev[k] for k in range(d)])

    def _clamp(self, values: list[int]) -> list[int]:
        out = []
        for k, v in enumerate(values):
            if not _LO <= v <= _HI:
                raise Wide
            out.append(min(max(v, self.neg_lim[k]), self.lim[k]))
        return out
