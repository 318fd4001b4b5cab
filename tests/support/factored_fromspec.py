"""A factored map (format version 5) and an int32 grid map (versions 1 and 3) evaluated
from protocol/README.md section 6 alone: the byte layout parsed with ``struct``, the
arithmetic in plain Python integers, one point at a time, as a PLC programmer would write
it from the page. Nothing here imports the project's decoders or evaluators, so that a
test comparing this with ``ednc lookup`` checks the page, not the code against itself.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass
from fractions import Fraction


def r_shift(x: int, s: int) -> int:
    """R(x, s) of section 6: x / 2^s, halves up; a left shift for s < 0."""
    if s > 0:
        return (x + (1 << (s - 1))) >> s
    if s < 0:
        return x << -s
    return x


def half_up(v: Fraction) -> int:
    return (v + Fraction(1, 2)).__floor__()


def position_counts(q: float, per_unit: int) -> int:
    """A position in mm (degrees) as counts: floor(q · P + 0.5) in double precision."""
    import math
    return math.floor(q * per_unit + 0.5)


def millicelsius(celsius: float) -> int:
    return half_up(Fraction(celsius) * 1000)


@dataclass
class Table:
    start: int
    shift: int
    values: list[int]

    def look_up(self, q: int) -> int:
        """Step 1: the interpolated value times 2^15."""
        v, n, k = self.values, len(self.values), self.shift
        if n == 1:
            return v[0] * (1 << 15)
        x = min(max(q - self.start, 0), (n - 1) * (1 << k))
        i = min(x >> k, n - 2)
        r = x - i * (1 << k)
        return v[i] * (1 << 15) + r_shift((v[i + 1] - v[i]) * r, k - 15)


@dataclass
class Record:
    sensor: str
    axis: int
    kind: int
    coefficient: int
    t_ref: int
    q_min: int


@dataclass
class Factored:
    per_unit: int
    names: list[str]
    rotary: list[bool]
    reversal: list[int]
    limit: list[int]
    bases: list[tuple[int, Table]]
    terms: list[tuple[int, int, int, list[int], Table]]  # field, axis, e, factors, table
    records: list[Record]


def _name(raw: bytes) -> str:
    return raw.split(b"\0", 1)[0].decode("ascii")


def parse_factored(data: bytes) -> Factored:
    """The layout table of section 6.5."""
    assert data[:4] == b"EDMP" and struct.unpack_from("<H", data, 4)[0] == 5
    d, b_count, h_count = data[7], data[8], data[9]
    (t_count,) = struct.unpack_from("<H", data, 10)
    (per_unit,) = struct.unpack_from("<I", data, 12)
    at = 64
    names, rotary, reversal, limit, grids = [], [], [], [], []
    for _ in range(d):
        name = _name(data[at:at + 4])
        flags, shift, nodes = data[at + 4], data[at + 5], struct.unpack_from("<H", data,
                                                                            at + 6)[0]
        start, rev, lim = struct.unpack_from("<iii", data, at + 8)
        names.append(name)
        rotary.append(bool(flags & 1))
        reversal.append(rev if flags & 2 else 0)
        limit.append(lim)
        grids.append((start, shift, nodes))
        at += 20
    bases = []
    for _ in range(b_count):
        axis, shift = data[at], data[at + 1]
        (n,) = struct.unpack_from("<H", data, at + 2)
        (start,) = struct.unpack_from("<i", data, at + 4)
        values = list(struct.unpack_from(f"<{n}h", data, at + 8))
        bases.append((axis, Table(start, shift, values)))
        at += 8 + 2 * n
    terms = []
    for _ in range(t_count):
        field, axis = data[at], data[at + 1]
        (e,) = struct.unpack_from("<b", data, at + 2)
        m = data[at + 3]
        factors = list(data[at + 4:at + 4 + (m & 7)])
        start, shift, nodes = grids[axis]
        n = 1 if m & 0x80 else nodes
        values = list(struct.unpack_from(f"<{n}h", data, at + 8))
        terms.append((field, axis, e, factors, Table(start, shift, values)))
        at += 8 + 2 * n
    records = []
    for _ in range(h_count):
        sensor = _name(data[at:at + 16])
        axis, kind = data[at + 16], data[at + 17]
        coef, t_ref, q_min = struct.unpack_from("<iii", data, at + 20)
        records.append(Record(sensor, axis, kind, coef, t_ref, q_min))
        at += 32
    assert at == len(data)
    return Factored(per_unit, names, rotary, reversal, limit, bases, terms, records)


def thermal_constants(records: list[Record], n_axes: int,
                      readings: dict[str, int]) -> tuple[list[int], list[int]]:
    """c0 (2^-16 counts) and c1 (2^-32 counts per count) per axis, section 6's rule."""
    c0, c1 = [0] * n_axes, [0] * n_axes
    for rec in records:
        if rec.sensor not in readings:
            continue
        dt = min(max(readings[rec.sensor] - rec.t_ref, -(1 << 17)), 1 << 17)
        if rec.kind == 1:
            c0[rec.axis] -= r_shift(rec.coefficient * dt, 16)
        else:
            s = r_shift(rec.coefficient * dt, 16)
            c1[rec.axis] -= s
            c0[rec.axis] += r_shift(s * rec.q_min, 16)
    return c0, c1


def factored_counts(m: Factored, q: list[int], readings: dict[str, int],
                    negative: list[bool] | None = None) -> list[int]:
    """Steps 1-6 of section 6.5 at positions q (counts); ``negative[d]``: axis d last
    moved in the negative direction."""
    d = len(m.names)
    rot = [i for i in range(d) if m.rotary[i]]
    lin = [i for i in range(d) if not m.rotary[i]]
    n_fields = d + len(lin) * len(rot)
    acc = [0] * n_fields
    basis = [t.look_up(q[axis]) for axis, t in m.bases]
    for field, axis, e, factors, table in m.terms:
        p = table.look_up(q[axis])
        for b in factors:
            p = r_shift(p * basis[b], 29)
        acc[field] += r_shift(p, -(e + 1))
    c0, c1 = thermal_constants(m.records, d, readings)
    c = []
    for k in range(d):
        v = acc[k] + c0[k] + r_shift(c1[k] * q[k], 16)
        c.append(min(max(v, -m.limit[k] * 65536), m.limit[k] * 65536))
    if not rot or not lin:
        n = [r_shift(v, 16) for v in c]
    else:
        near = {r: r_shift(c[r], 16) for r in rot}
        far = {r: near[r] - 1 if near[r] * 65536 > c[r] else near[r] + 1 for r in rot}
        best: list[int] | None = None
        best_cost = 0
        for choice in range(1 << len(rot)):
            n = [0] * d
            moved = {}
            for j, r in enumerate(rot):
                n[r] = far[r] if (choice >> (len(rot) - 1 - j)) & 1 else near[r]
                moved[r] = n[r] * 65536 - c[r]
            cost = 0
            for li, ax in enumerate(lin):
                w = c[ax] + r_shift(sum(acc[d + li * len(rot) + j] * moved[r]
                                        for j, r in enumerate(rot)), 16)
                n[ax] = r_shift(w, 16)
                cost += (w - n[ax] * 65536) ** 2
            if best is None or cost < best_cost:
                best, best_cost = n, cost
        assert best is not None
        n = best
    if negative is not None:  # step 6: the reversal, then the clamp
        n = [v + (m.reversal[k] if negative[k] else 0) for k, v in enumerate(n)]
    return [min(max(v, -m.limit[k]), m.limit[k]) for k, v in enumerate(n)]


@dataclass
class Grid:
    per_unit: int
    grid: list[tuple[str, int, int, int]]  # name, count, start counts, step counts
    outputs: list[tuple[str, int]]  # name, reversal counts
    values: list[int]
    records: list[Record]


def parse_grid(data: bytes) -> Grid:
    """Sections 6.1 and 6.4 (int32 encoding), f64 fields converted once at load."""
    assert data[:4] == b"EDMP"
    (version,) = struct.unpack_from("<H", data, 4)
    assert version in (1, 3) and data[6] == 1
    d, k = data[7], data[8]
    (inc,) = struct.unpack_from("<d", data, 56)
    per_unit = half_up(1 / Fraction(inc))
    at = 64
    grid = []
    for _ in range(d):
        name = _name(data[at:at + 4])
        count, start, step = struct.unpack_from("<Idd", data, at + 4)
        grid.append((name, count, half_up(Fraction(start) * per_unit),
                     half_up(Fraction(step) * per_unit)))
        at += 24
    outputs = []
    for _ in range(k):
        name = _name(data[at:at + 4])
        flags = data[at + 4]
        (rev,) = struct.unpack_from("<i", data, at + 8)
        outputs.append((name, rev if flags & 1 else 0))
        at += 12
    n = 1
    for _, count, _, _ in grid:
        n *= count
    values = list(struct.unpack_from(f"<{n * k}i", data, at))
    at += 4 * n * k
    records = []
    if version == 3:
        (h,) = struct.unpack_from("<I", data, at)
        at += 4
        for _ in range(h):
            sensor = _name(data[at:at + 16])
            axis = _name(data[at + 16:at + 20])
            kind = data[at + 20]
            coef, t_ref, q_min = struct.unpack_from("<ddd", data, at + 24)
            if kind == 1:
                c = half_up(Fraction(coef) * per_unit / 10**6 * 2**32)
                qm = 0
            else:
                c = half_up(Fraction(coef) / 10**9 * 2**48)
                qm = half_up(Fraction(q_min) * per_unit)
            out_index = [o for o, _ in outputs].index(axis)
            records.append(Record(sensor, out_index, kind, c,
                                  half_up(Fraction(t_ref) * 1000), qm))
            at += 48
    assert at == len(data)
    return Grid(per_unit, grid, outputs, values, records)


def grid_counts(g: Grid, q: dict[str, int], readings: dict[str, int],
                negative: dict[str, bool] | None = None) -> list[int]:
    """Section 6.1's integer rule at positions q (counts by axis name)."""
    d, k = len(g.grid), len(g.outputs)
    idx, frac = [], []
    for name, count, start, step in g.grid:
        x = min(max(q[name] - start, 0), (count - 1) * step)
        i = min(x // step, count - 2)
        idx.append(i)
        frac.append(((x - i * step) * 65536) // step)
    strides = [1] * d
    for j in range(d - 2, -1, -1):
        strides[j] = strides[j + 1] * g.grid[j + 1][1]
    c0, c1 = thermal_constants(g.records, k, readings)
    out = []
    for o in range(k):
        vals = []
        for corner in range(1 << d):
            node = sum((idx[j] + ((corner >> (d - 1 - j)) & 1)) * strides[j]
                       for j in range(d))
            vals.append(g.values[node * k + o] * 65536)
        for j in range(d - 1, -1, -1):
            vals = [a + r_shift((b - a) * frac[j], 16)
                    for a, b in zip(vals[0::2], vals[1::2], strict=True)]
        name = g.outputs[o][0]
        pos = q.get(name, 0)
        n = r_shift(vals[0] + c0[o] + r_shift(c1[o] * pos, 16), 16)
        if negative is not None and negative.get(name):
            n += g.outputs[o][1]
        out.append(n)
    return out
