"""The whole diagnosis on random simulated campaigns: hit rate per family, false alarms,
estimate errors and time per diagnosis (issue 15, item 7).

Run::

    .venv/bin/python benchmarks/diagnosis_hit_rate.py [--campaigns 200] [--jobs 2]
        [--first 0] [--verbose] [--log results.jsonl]
    .venv/bin/python benchmarks/diagnosis_hit_rate.py --thermal-pairs [--campaigns 45]
    .venv/bin/python benchmarks/diagnosis_hit_rate.py --from-log results.jsonl

Every campaign draws from its seed (``--first`` + i) what it hides:

* ``null`` (a fifth): no effect; any answer but ``none`` is a false alarm (``unexplained``
  included);
* ``single`` (two fifths): one effect of the library (backlash, periodic, thermal_drift,
  thermal_expansion) on a random linear axis, sensor and size in the realistic ranges of
  :mod:`machine_sim.effects`; a hit names it first with its axis, sensor and size within
  30 %; a backlash also in its sense (the simulated one lags behind the motion);
* ``pair`` (the rest but one in ten): two effects of different families; a hit lists both
  in ``effects`` (each as above). The table counts pairs by families and by same or two
  axes, and the misses whose only fault is a sensor the data cannot tell from the true
  one (the entry lists the true sensor among its ``alternatives``; still a miss);
* ``outside`` (one in ten): an effect no library holds, a step of 2 to 6 µm along a linear
  axis at a random place of its travel (a scale joint); a hit says ``unexplained`` with
  ``position`` of that axis among the correlates.

With ``--thermal-pairs`` every campaign hides a same-axis thermal pair instead (issue 33):
a thermal drift and a thermal expansion on one axis, x, y and z in turn by seed, their
sensors different and drawn as above; a hit lists both in ``effects`` with the right
sensors and each estimate within 30 % (category ``thermal_pair``). A position-dependent
and a position-independent effect on one axis share variance: the pair tells whether the
diagnosis gives each its own size.

Each family runs on a three-axis machine (one of four chains, 800 x 600 x 500 mm) or, one
campaign in four, the five-axis machine of the demo's ``5ax-04`` chain (smooth rotary
components: the benchmark of periodic rotary error motions is
``benchmarks/diagnosis_rotary.py``), with the instruments' noise of the usual range (0.1 to
0.4 µm, 0.2 to 0.6 µrad) or twice it. The standard campaign measures it
(:func:`machine_sim.campaign.standard_campaign`) and
:func:`volumetric.diagnose.diagnosis.diagnose` judges it; only the diagnosis is timed (one
process per job, BLAS on one thread, so a job is one core's figure).
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import argparse
import dataclasses
import functools
import json
import multiprocessing
import sys
import time
from collections import Counter, defaultdict
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from machine_sim.campaign import standard_campaign
from machine_sim.effects import Backlash, Effects, Noise, Periodic, ThermalDrift, ThermalExpansion
from machine_sim.instruments import SimulatedMachine
from machine_sim.thermal import default_thermal
from machine_sim.truth import random_geometry
from volumetric.diagnose.diagnosis import diagnose
from volumetric.identify.design import axis_positions
from volumetric.measure.measurement import Measurements
from volumetric.model.components import Component, GeometricErrors, Polynomial
from volumetric.model.machine import Machine, parse_machine

CHAINS = ["w X Y b Z t", "w b Y X Z t", "w X b Y Z t", "w Y b X Z t"]
FIVE_AXIS: dict[str, Any] = {"name": "5ax", "chain": "w C A X b Y Z t",
             "travel_mm": {"x": [0, 500], "y": [0, 400], "z": [-400, 0], "a": [-110, 110],
                           "c": [-180, 180]},
             "pivots_mm": {"A": [0.0, 300.0, -150.0], "C": [400.0, 300.0, -100.0]},
             "tool_length_mm": 100.0}
FAMILIES = ["backlash", "periodic", "thermal_drift", "thermal_expansion"]
TOLERANCE = 0.3


def machine_for(chain: str) -> Machine:
    if chain == FIVE_AXIS["chain"]:
        return parse_machine(FIVE_AXIS)
    return parse_machine({"name": "m", "chain": chain, "tool_length_mm": 100.0,
                          "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}})


def smooth_geometry(machine: Machine, rng: np.random.Generator) -> GeometricErrors:
    """A random rigid geometry whose rotary components are smooth: a cubic of the angle
    on an axis of limited travel, none on a full turn (where a cubic would not close)."""
    g = random_geometry(machine, rng)
    comps: dict[str, Component] = dict(g.components)
    for a in machine.axes:
        if a.kind == "rotary":
            full = a.travel[1] - a.travel[0] >= 359.0
            for c in "XYZABC":
                size = 3.0 if c in "XYZ" else 15.0
                coef = (0.0,) if full else (0.0, *(rng.uniform(-1, 1, 3) * size))
                comps[f"E{c}{a.name}"] = Polynomial(coef, 0.0, 180.0)
    return GeometricErrors(comps, g.locations)


@dataclasses.dataclass(frozen=True)
class Hidden:
    effect: str
    axis: str
    sensor: str | None
    size: dict[str, float]


def one_effect(kind: str, machine: Machine, rng: np.random.Generator, avoid: set[str],
               axis: str | None = None) -> tuple[Hidden, Effects]:
    drawn = str(rng.choice(["x", "y", "z"]))
    axis = drawn if axis is None else axis
    sensors = [s for s in default_thermal(machine).names if s not in avoid]
    if kind == "backlash":
        b = float(rng.uniform(2, 15))
        return Hidden(kind, axis, None, {"reversal_um": b}), Effects(
            backlash=(Backlash(axis, b),))
    if kind == "periodic":
        a, p = float(rng.uniform(0.8, 5)), float(rng.uniform(5, 25))
        return Hidden(kind, axis, None, {"amplitude_um": a, "period_mm": p}), Effects(
            periodic=(Periodic(axis, a, p, float(rng.uniform(0, 6.28))),))
    if kind == "thermal_drift":
        s = str(rng.choice([x for x in sensors if x != "air"]))
        k = float(rng.uniform(0.5, 5)) * float(rng.choice([-1, 1]))
        return Hidden(kind, axis, f"T_{s}_C", {"um_per_K": k}), Effects(
            drift=(ThermalDrift(axis, s, k),))
    s = str(rng.choice([x for x in sensors if x.endswith("screw") or x == "column"]))
    alpha = float(rng.uniform(2, 12))
    return Hidden(kind, axis, f"T_{s}_C", {"um_per_m_K": alpha}), Effects(
        expansion=(ThermalExpansion(axis, s, alpha),))


def category(seed: int) -> str:
    return ["null", "single", "single", "pair", "pair", "null", "single", "single", "pair",
            "outside"][seed % 10]


THERMAL_PAIR_SEED = 30_000
"""Offset of the random streams of the ``--thermal-pairs`` family (its campaigns are not
those of the mixed family's seeds)."""


def make_campaign(seed: int, thermal_pairs: bool = False
                  ) -> tuple[dict[str, Any], Machine, Measurements]:
    """What the campaign of ``seed`` hides (a description) and its readings; with
    ``thermal_pairs``, a thermal drift and a thermal expansion on axis ``xyz[seed % 3]``."""
    rng = np.random.default_rng((THERMAL_PAIR_SEED if thermal_pairs else 20_000) + seed)
    chain = FIVE_AXIS["chain"] if rng.uniform() < 0.25 else CHAINS[int(rng.integers(4))]
    machine = machine_for(chain)
    noise_x = 2 if rng.uniform() < 0.5 else 1
    noise = Noise(noise_x * float(rng.uniform(0.1, 0.4)), noise_x * float(rng.uniform(0.2, 0.6)))
    cat = "thermal_pair" if thermal_pairs else category(seed)
    hidden: list[Hidden] = []
    eff = Effects(noise=noise)
    if cat == "thermal_pair":
        axis = "xyz"[seed % 3]
        h1, e1 = one_effect("thermal_drift", machine, rng, set(), axis)
        assert h1.sensor is not None
        h2, e2 = one_effect("thermal_expansion", machine, rng, {h1.sensor[2:-2]}, axis)
        hidden = [h1, h2]
        eff = Effects(expansion=e2.expansion, drift=e1.drift, noise=noise)
    elif cat in ("single", "pair"):
        kinds = [str(k) for k in rng.choice(FAMILIES, 1 if cat == "single" else 2,
                                            replace=False)]
        parts = []
        for k in kinds:
            h, e = one_effect(k, machine, rng, {x.sensor[2:-2] for x in hidden if x.sensor})
            hidden.append(h)
            parts.append(e)
        eff = Effects(expansion=sum((p.expansion for p in parts), ()),
                      drift=sum((p.drift for p in parts), ()),
                      backlash=sum((p.backlash for p in parts), ()),
                      periodic=sum((p.periodic for p in parts), ()), noise=noise)
    step: dict[str, float] = {}
    if cat == "outside":
        axis = str(rng.choice(["x", "y", "z"]))
        lo, hi = machine.axis(axis).travel
        step = {"axis": "xyz".index(axis), "at": float(lo + rng.uniform(0.25, 0.75) * (hi - lo)),
                "um": float(rng.uniform(2, 6)) * float(rng.choice([-1, 1]))}
        hidden.append(Hidden("unexplained", axis, None, {}))
    sim = SimulatedMachine(machine, smooth_geometry(machine, rng), eff, seed=seed)
    m = standard_campaign(sim, rng)
    if step:
        m = add_step(machine, m, int(step["axis"]), step["at"], step["um"])
    desc = {"seed": seed, "category": cat, "chain": chain, "noise": noise_x,
            "hidden": [dataclasses.asdict(h) for h in hidden]}
    return desc, machine, m


def add_step(machine: Machine, m: Measurements, k: int, at: float, um: float) -> Measurements:
    """The readings of a machine whose axis k (0, 1, 2: x, y, z) is ``um`` further along
    itself beyond ``at`` (mm): a joint of two scale segments, which no smooth component and
    no effect of the library holds."""
    q = axis_positions(machine, m)
    j = machine.axis_names.index("XYZ"[k])
    shift = np.where(q[:, j] >= at, um, 0.0)
    add = np.where(m.is_angle, 0.0, m.u[:, k] * shift)
    return dataclasses.replace(m, value=m.value + add)


def matches(h: dict[str, Any], e: dict[str, Any]) -> tuple[bool, list[float]]:
    """Whether entry ``e`` names hidden effect ``h`` (effect, axis, sensor, sizes within
    TOLERANCE), and the relative errors of its sizes."""
    if (e["effect"], e["axis"]) != (h["effect"], h["axis"]):
        return False, []
    if h["sensor"] is not None and e["sensor"] != h["sensor"]:
        return False, []
    if h["effect"] == "backlash" and e["estimate"].get("sign") != "lags behind the motion":
        # the simulated backlash lags (machine_sim.effects); the size alone would pass a
        # reversal of the wrong sense, which a compensation would double
        return False, []
    errs = []
    for k, v in h["size"].items():
        true = abs(v) if k in ("reversal_um", "amplitude_um") else v
        errs.append(abs(float(e["estimate"][k]) - true) / abs(true))
    return all(x <= TOLERANCE for x in errs), errs


def judge(seed: int, thermal_pairs: bool = False) -> dict[str, Any]:
    desc, machine, m = make_campaign(seed, thermal_pairs)
    t0, c0 = time.perf_counter(), time.process_time()
    d = diagnose(machine, m)
    desc["seconds"] = time.perf_counter() - t0
    desc["cpu_seconds"] = time.process_time() - c0
    effects = d.to_json()["effects"]
    desc["said"] = [(e["effect"], e["axis"], e["sensor"]) for e in effects]
    cat = desc["category"]
    hidden = desc["hidden"]
    desc["found"] = []
    desc["errors"] = {}
    if cat == "null":
        desc["hit"] = d.effect == "none"
    elif cat == "outside":
        # the step shows as structure along its axis: position (or a period) of that axis
        axis = hidden[0]["axis"]
        corr = [c["correlate"] for e in effects if e["effect"] == "unexplained"
                for c in e["estimate"]["correlates"]]
        desc["hit"] = any(c == f"position {axis}" or c.endswith(f" along {axis}")
                          for c in corr)
    else:
        for h in hidden:
            ok = False
            pool = effects[:1] if cat == "single" else effects
            for e in pool:
                good, errs = matches(h, e)
                if errs:
                    desc["errors"][h["effect"]] = errs
                ok |= good
            desc["found"].append(ok)
        desc["hit"] = all(desc["found"])
        # a miss on the sensor alone, the true one listed as one the data cannot tell apart
        desc["tied"] = [not ok and any(
            (e["effect"], e["axis"]) == (h["effect"], h["axis"])
            and h["sensor"] in e.get("alternatives", []) for e in effects)
            for h, ok in zip(hidden, desc["found"], strict=True)]
        named = [e for e in effects if e["effect"] != "unexplained"]
        desc["extra"] = max(len(named) - len(hidden), 0)
        desc["unexplained"] = len(named) < len(effects)
    return desc


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--campaigns", type=int, default=200)
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--first", type=int, default=0, help="first seed")
    ap.add_argument("--thermal-pairs", action="store_true",
                    help="every campaign a thermal drift and expansion on one axis")
    ap.add_argument("--verbose", action="store_true", help="one line per campaign")
    ap.add_argument("--log", type=Path, help="append each campaign's result (JSON line)")
    ap.add_argument("--from-log", type=Path, help="only print the table of a --log file "
                                                   "(a run stopped early)")
    args = ap.parse_args()
    if args.from_log is not None:
        rows = [json.loads(line) for line in args.from_log.read_text().splitlines() if line]
        args.first = min((r["seed"] for r in rows), default=0)
        report(rows, float("nan"), args)
        return
    seeds = range(args.first, args.first + args.campaigns)
    t_start = time.perf_counter()
    results: list[dict[str, Any]] = []
    with multiprocessing.get_context("spawn").Pool(args.jobs) as pool:
        for r in pool.imap_unordered(functools.partial(judge, thermal_pairs=args.thermal_pairs),
                                     seeds):
            results.append(r)
            if args.log is not None:
                with args.log.open("a") as f:
                    f.write(json.dumps(r) + "\n")
            if args.verbose or not r["hit"]:
                hid = "; ".join(f"{h['effect']} {h['axis']} {h['sensor'] or ''} "
                                f"{ {k: round(v, 3) for k, v in h['size'].items()} }"
                                for h in r["hidden"]) or "nothing"
                print(f"{'ok  ' if r['hit'] else 'MISS'} seed {r['seed']} {r['category']} "
                      f"{r['chain']} noise x{r['noise']}: hid {hid}; said {r['said']} "
                      f"({r['seconds']:.1f} s)", flush=True)
    wall = time.perf_counter() - t_start
    report(results, wall, args)


def report(results: list[dict[str, Any]], wall: float, args: argparse.Namespace) -> None:
    by_cat: Counter[str] = Counter()
    hit_cat: Counter[str] = Counter()
    fam_total: Counter[tuple[str, str]] = Counter()
    fam_hit: Counter[tuple[str, str]] = Counter()
    errors: dict[str, list[float]] = defaultdict(list)
    by_kind: Counter[str] = Counter()
    hit_kind: Counter[str] = Counter()
    extra = 0
    unexplained = 0
    for r in results:
        by_cat[r["category"]] += 1
        hit_cat[r["category"]] += r["hit"]
        kind = f"{'5-axis' if r['chain'] == FIVE_AXIS['chain'] else '3-axis'} noise x{r['noise']}"
        by_kind[kind] += 1
        hit_kind[kind] += r["hit"]
        extra += r.get("extra", 0)
        unexplained += r.get("unexplained", False)
        for h, ok in zip(r["hidden"], r["found"], strict=False):
            fam_total[(r["category"], h["effect"])] += 1
            fam_hit[(r["category"], h["effect"])] += ok
        for fam, errs in r["errors"].items():
            errors[fam] += errs
    secs = np.array([r["seconds"] for r in results])
    cpu = np.array([r["cpu_seconds"] for r in results])
    print(f"\n{len(results)} campaigns, seeds {args.first}..{args.first + len(results) - 1}, "
          f"{args.jobs} job(s), {wall / 60:.1f} min wall")
    print(f"{'what':34s} {'hits':>9s}  {'rate':>6s}")
    labels = {"single": "single effect (named first)", "pair": "pairs (both named)",
              "null": "null (said none; else false alarm)",
              "outside": "outside the library (unexplained)",
              "thermal_pair": "same-axis drift + expansion"}
    for cat in ("single", "pair", "thermal_pair", "null", "outside"):
        if by_cat[cat]:
            print(f"{labels[cat]:34s} {hit_cat[cat]:4d}/{by_cat[cat]:<4d}  "
                  f"{100 * hit_cat[cat] / by_cat[cat]:5.1f} %")
    print(f"{'false alarms on null':34s} {by_cat['null'] - hit_cat['null']:4d}")
    print(f"{'extra effects named (single/pair)':34s} {extra:4d}")
    print(f"{'unexplained also said (single/pair)':34s} {unexplained:4d}")
    tied = sum(any(r.get("tied", [])) for r in results)
    print(f"{'misses, true sensor in alternatives':34s} {tied:4d}")
    head = "estimate error median / 95 %"
    pair_cat = "thermal_pair" if by_cat["thermal_pair"] else "pair"
    print(f"\n{'family':20s} {'single':>9s} {'in pairs':>9s}  {head:>30s}")
    for fam in FAMILIES:
        if not (fam_total[("single", fam)] or fam_total[(pair_cat, fam)]):
            continue
        errs = np.array(errors.get(fam) or [np.inf])
        s = f"{fam_hit[('single', fam)]}/{fam_total[('single', fam)]}"
        p = f"{fam_hit[(pair_cat, fam)]}/{fam_total[(pair_cat, fam)]}"
        print(f"{fam:20s} {s:>9s} {p:>9s}  {100 * np.median(errs):12.1f} % / "
              f"{100 * np.percentile(errs, 95):5.1f} %")
    pair_total: Counter[str] = Counter()
    pair_hit: Counter[str] = Counter()
    for r in results:
        if r["category"] not in ("pair", "thermal_pair"):
            continue
        h = r["hidden"]
        where = "same axis" if h[0]["axis"] == h[1]["axis"] else "two axes"
        if r["category"] == "thermal_pair":
            where = f"same axis {h[0]['axis']}"
        for key in (" + ".join(sorted(x["effect"] for x in h)), where):
            pair_total[key] += 1
            pair_hit[key] += r["hit"]
    if pair_total:
        print(f"\n{'pairs by families, by axes':42s} {'hits':>9s}")
        for key in sorted(pair_total, key=lambda k: (" + " not in k, k)):
            print(f"{key:42s} {pair_hit[key]:4d}/{pair_total[key]:<4d}")
    print(f"\n{'machine, noise':20s} {'hits':>9s}")
    for kind in sorted(by_kind):
        print(f"{kind:20s} {hit_kind[kind]:4d}/{by_kind[kind]:<4d}")
    print(f"\ndiagnosis time: median {np.median(secs):.1f} s, "
          f"95 % {np.percentile(secs, 95):.1f} s, worst {secs.max():.1f} s "
          "wall (load shared)")
    print(f"diagnosis CPU time (one core): median {np.median(cpu):.1f} s, "
          f"95 % {np.percentile(cpu, 95):.1f} s, worst {cpu.max():.1f} s")


if __name__ == "__main__":
    main()
