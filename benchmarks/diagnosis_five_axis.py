"""The diagnosis on random five-axis campaigns: hit rate per family, false alarms,
estimate errors, compensation of cyclic errors and CPU per diagnosis (issue 27, item 3).

Run::

    .venv/bin/python benchmarks/diagnosis_five_axis.py [--campaigns 50] [--first 0]
        [--jobs 1] [--verbose] [--log results.jsonl]
    .venv/bin/python benchmarks/diagnosis_five_axis.py --from-log results.jsonl

Every campaign draws from its seed (``--first`` + i) a machine of one of the 12 five-axis
types (:func:`tests.support.five_axis.five_axis_machine`: translational type 1-4 x rotary
type 1-3, C a full turn, A and B ±110°; a random rigid geometry whose rotary components
carry harmonics up to 4 per turn, :func:`machine_sim.truth.random_geometry`) and what it
hides:

* ``null`` (three in ten): nothing; any answer but ``none`` is a false alarm
  (``unexplained`` included), and a ``rotary_periodic`` anywhere in ``effects`` is
  counted on its own;
* ``single`` (four in ten): one effect: a cyclic error of 6 to 18 per turn on a random
  rotary axis (:func:`machine_sim.truth.cyclic_error`: indexing 8 to 30 µrad, radial 1 to
  4 µm), a reversal error of 10 to 40 µrad of a rotary axis whose angle the tool tip
  feels (:class:`machine_sim.effects.RotaryBacklash`; not a tool-side C, which turns the
  tool about its own axis), or one of the three-axis families (backlash, periodic, thermal_drift,
  thermal_expansion on a random linear axis, as ``benchmarks/diagnosis_hit_rate.py``
  draws them: sensors of formats.md, the spindle's among them); a hit names it first with
  its axis (and for a cyclic error its order and, within 30 %, the amplitude of the
  largest component the readings sense: the indexing error of a table; on a tool-side C,
  which turns the tool about its own axis, a tilt or a radial motion), sensor and size
  within 30 %;
* ``pair`` (three in ten): a cyclic error or a rotary reversal error with one of the
  three-axis families, or two three-axis families; a hit lists both.

With ``--cyclic`` the campaigns are those of the issue's target instead: the demo's
``5ax-04`` (``w C A X b Y Z t``) whose C and A carry once- and twice-per-turn error
motions (:func:`machine_sim.truth.rotary_error_motions`), measured by the standard
campaign plus R-tests at four balls per rotary axis read every 5°
(:func:`tests.support.five_axis.rich_campaign_04`); one in four hides nothing more, the
others a cyclic error of 6 to 18 per turn on C or on A (indexing 8 to 30 µrad, radial 1
to 4 µm). A hit names ``rotary_periodic`` on the right axis with the right order (and,
for a null, no ``rotary_periodic`` at all).

The campaign is the standard one (one positioning block) plus the standard R-test
set-ups read every 5° (:func:`tests.support.five_axis.five_axis_campaign`, which resolve
cyclic errors up to 35 per turn), instruments' noise 0.25 µm and 0.25 µrad. For every
cyclic error (``--compensation``, always with ``--cyclic``) the worst tool-tip error over
2000 random poses (up to a constant offset) is computed uncompensated and with the
corrections of the diagnosis's saved model and of the plain ``ednc fit`` model. Only the
diagnosis is timed (BLAS on one thread).
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")

import argparse
import json
import multiprocessing
import sys
import time
from collections import Counter, defaultdict
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from diagnosis_hit_rate import FAMILIES, matches, one_effect

from machine_sim.effects import Effects, Noise, RotaryBacklash
from machine_sim.instruments import SimulatedMachine
from machine_sim.truth import cyclic_error, random_geometry, rotary_error_motions
from tests.support.five_axis import (
    FIVE_AX_04,
    TYPES,
    five_axis_campaign,
    five_axis_machine,
    rich_campaign_04,
)
from volumetric.compensate.solver import compensate
from volumetric.diagnose.diagnosis import diagnose
from volumetric.identify.fit import fit
from volumetric.model.components import Fourier, GeometricErrors, Sum
from volumetric.model.kinematics import tool_pose
from volumetric.model.machine import Machine, parse_machine

TOLERANCE = 0.3
STEP_DEG = 5.0
NOISE = Noise(0.25, 0.25)


def category(seed: int) -> str:
    return ["null", "single", "single", "pair", "null", "single", "single", "pair", "null",
            "pair"][seed % 10]


def worst_um(machine: Machine, truth: GeometricErrors, model: GeometricErrors | None,
             q: np.ndarray) -> float:
    nominal, _ = tool_pose(machine, q, orientation=False)
    dq = 0.0 if model is None else compensate(machine, model, q).dq
    actual, _ = tool_pose(machine, q + dq, truth, orientation=False)
    e = actual - nominal
    return float(np.linalg.norm(e - e.mean(axis=0), axis=1).max()) * 1e3


def judge(seed: int) -> dict[str, Any]:
    rng = np.random.default_rng(27_000 + seed)
    t, r = TYPES[seed % len(TYPES)]
    machine = five_axis_machine(t, r)
    truth = random_geometry(machine, rng)
    cat = category(seed)
    hidden: list[dict[str, Any]] = []
    parts: list[Effects] = []
    kinds: list[str] = []
    if cat == "single":
        u = rng.uniform()
        kinds = ["rotary_periodic" if u < 0.3 else "rotary_backlash" if u < 0.45
                 else str(rng.choice(FAMILIES))]
    elif cat == "pair":
        u = rng.uniform()
        kinds = ([str(k) for k in rng.choice(FAMILIES, 2, replace=False)] if u < 0.35
                 else ["rotary_periodic" if u < 0.8 else "rotary_backlash",
                       str(rng.choice(FAMILIES))])
    for k in kinds:
        if k == "rotary_backlash":
            # a tool-side C turns the tool about its own axis: no reading of the tool tip
            # sees its angle, so its reversal is not drawn
            seen = [a for a in machine.axes if a.kind == "rotary"
                    and (a.name != "C" or a.side == "workpiece")]
            axis = seen[int(rng.integers(len(seen)))]
            b = float(rng.uniform(10, 40))
            hidden.append({"effect": k, "axis": axis.key, "sensor": None,
                           "size": {"reversal_urad": b}})
            parts.append(Effects(rotary_backlash=(RotaryBacklash(axis.key, b),)))
            continue
        if k == "rotary_periodic":
            rot = [a for a in machine.axes if a.kind == "rotary"]
            axis = rot[int(rng.integers(len(rot)))]
            order = int(rng.integers(6, 19))
            angular, radial = float(rng.uniform(8, 30)), float(rng.uniform(1, 4))
            truth = cyclic_error(machine, truth, axis.key, order, radial, angular, rng)
            hidden.append({"effect": k, "axis": axis.key, "sensor": None,
                           "size": {"order": order, "angular_urad": angular,
                                    "radial_um": radial},
                           "components": true_amplitudes(truth, axis.name, order)})
        else:
            avoid = {h["sensor"][2:-2] for h in hidden if h["sensor"]}
            h, e = one_effect(k, machine, rng, avoid)
            hidden.append({"effect": h.effect, "axis": h.axis, "sensor": h.sensor,
                           "size": h.size})
            parts.append(e)
    eff = Effects(expansion=sum((p.expansion for p in parts), ()),
                  drift=sum((p.drift for p in parts), ()),
                  backlash=sum((p.backlash for p in parts), ()),
                  periodic=sum((p.periodic for p in parts), ()), noise=NOISE,
                  rotary_backlash=sum((p.rotary_backlash for p in parts), ()))
    sim = SimulatedMachine(machine, truth, eff, seed=seed)
    m = five_axis_campaign(sim, rng, step_deg=STEP_DEG, runs=1)
    t0, c0 = time.perf_counter(), time.process_time()
    d = diagnose(machine, m)
    out: dict[str, Any] = {"seed": seed, "type": [t, r], "category": cat, "hidden": hidden,
                           "n": len(m), "seconds": time.perf_counter() - t0,
                           "cpu_seconds": time.process_time() - c0}
    effects = d.to_json()["effects"]
    out["said"] = [(e["effect"], e["axis"], e["sensor"]) for e in effects]
    out["rotary_periodic_said"] = sum(e["effect"] == "rotary_periodic" for e in effects)
    out["found"], out["errors"] = [], {}
    if cat == "null":
        out["hit"] = d.effect == "none"
    else:
        pool = effects[:1] if cat == "single" else effects
        for h in hidden:
            ok = False
            for e in pool:
                good, errs = match(h, e)
                if errs:
                    out["errors"][h["effect"]] = errs
                ok |= good
            out["found"].append(ok)
        out["hit"] = all(out["found"])
        named = [e for e in effects if e["effect"] != "unexplained"]
        out["extra"] = max(len(named) - len(hidden), 0)
    if (any(h["effect"] == "rotary_periodic" for h in hidden)
            and os.environ.get("EDNC_BENCH_COMPENSATION") == "1"):
        q = np.column_stack([np.random.default_rng(seed).uniform(a.travel[0], a.travel[1],
                                                                  2000)
                             for a in machine.axes])
        before = worst_um(machine, truth, None, q)
        out["worst_before_um"] = before
        out["worst_saved_um"] = worst_um(machine, truth, d.model.geometry, q)
        out["worst_fit_um"] = worst_um(machine, truth, fit(machine, m).model.geometry, q)
    return out


def judge_cyclic(seed: int) -> dict[str, Any]:
    """One ``--cyclic`` campaign (module docstring)."""
    rng = np.random.default_rng(47_000 + seed)
    machine = parse_machine(FIVE_AX_04)
    base = random_geometry(machine, rng)
    truth = GeometricErrors({**base.components, **rotary_error_motions(machine, rng)},
                            base.locations)
    hidden: list[dict[str, Any]] = []
    if seed % 4:
        axis = "c" if rng.uniform() < 0.5 else "a"
        order = int(rng.integers(6, 19))
        angular, radial = float(rng.uniform(8, 30)), float(rng.uniform(1, 4))
        truth = cyclic_error(machine, truth, axis, order, radial, angular, rng)
        hidden.append({"effect": "rotary_periodic", "axis": axis, "sensor": None,
                       "size": {"order": order, "angular_urad": angular,
                                "radial_um": radial},
                       "components": true_amplitudes(truth, axis.upper(), order)})
    sim = SimulatedMachine(machine, truth, Effects(noise=NOISE), seed=seed)
    m = rich_campaign_04(sim, rng, step_deg=STEP_DEG, runs=1)
    t0, c0 = time.perf_counter(), time.process_time()
    d = diagnose(machine, m)
    out: dict[str, Any] = {"seed": seed, "type": "5ax-04",
                           "category": "single" if hidden else "null",
                           "hidden": hidden, "n": len(m),
                           "seconds": time.perf_counter() - t0,
                           "cpu_seconds": time.process_time() - c0}
    effects = d.to_json()["effects"]
    out["said"] = [(e["effect"], e["axis"], e["sensor"]) for e in effects]
    out["rotary_periodic_said"] = sum(e["effect"] == "rotary_periodic" for e in effects)
    out["found"], out["errors"] = [], {}
    if not hidden:
        out["hit"] = out["rotary_periodic_said"] == 0 and d.effect == "none"
    else:
        ok = False
        for e in effects:
            good, errs = match(hidden[0], e)
            if errs:
                out["errors"]["rotary_periodic"] = errs
            ok |= good
        out["found"] = [ok]
        out["hit"] = ok
        q = np.column_stack([np.random.default_rng(seed).uniform(a.travel[0], a.travel[1],
                                                                  2000)
                             for a in machine.axes])
        out["worst_before_um"] = worst_um(machine, truth, None, q)
        out["worst_saved_um"] = worst_um(machine, truth, d.model.geometry, q)
        out["worst_fit_um"] = worst_um(machine, truth, fit(machine, m).model.geometry, q)
    return out


def true_amplitudes(truth: GeometricErrors, axis: str, order: int) -> dict[str, float]:
    """The amplitude of the harmonic of ``order`` per turn that ``cyclic_error`` added to
    each component of rotary axis ``axis`` (its last term), µm or µrad."""
    out: dict[str, float] = {}
    for c in "XYZABC":
        comp = truth.components[f"E{c}{axis}"]
        last = comp.terms[-1] if isinstance(comp, Sum) else comp
        assert isinstance(last, Fourier)
        out[f"E{c}{axis}"] = last.harmonic(order)
    return out


def match(h: dict[str, Any], e: dict[str, Any]) -> tuple[bool, list[float]]:
    """Whether entry ``e`` names hidden effect ``h``, and the relative size errors."""
    if h["effect"] == "rotary_backlash":
        if (e["effect"], e["axis"]) != (h["effect"], h["axis"]):
            return False, []
        err = abs(e["estimate"]["reversal_urad"] - h["size"]["reversal_urad"]) / h["size"][
            "reversal_urad"]
        # the simulated axis lags behind its motion (machine_sim.effects.RotaryBacklash)
        return err <= TOLERANCE and e["estimate"]["sign"] == "lags behind the motion", [err]
    if h["effect"] != "rotary_periodic":
        return matches(h, e)
    if (e["effect"], e["axis"]) != ("rotary_periodic", h["axis"]):
        return False, []
    est = e["estimate"]
    if est["order"] != h["size"]["order"]:
        return False, []
    # the largest true amplitude among the components the readings sense (the estimate
    # lists those): the indexing error on a table, a tilt or a radial motion on a
    # tool-side C, whose indexing no tool-tip reading sees
    order = str(h["size"]["order"])
    seen = {c: v[order] for c, v in est["components"].items() if order in v}
    if not seen:
        return False, []
    comp = max(seen, key=lambda c: h["components"][c])
    true = h["components"][comp]
    err = abs(seen[comp] - true) / true
    return err <= TOLERANCE, [err]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--campaigns", type=int, default=50)
    ap.add_argument("--first", type=int, default=0, help="first seed")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--verbose", action="store_true")
    ap.add_argument("--cyclic", action="store_true",
                    help="5ax-04 with periodic rotary error motions, rich R-tests")
    ap.add_argument("--compensation", action="store_true",
                    help="also the worst tool-tip error of every cyclic campaign (always "
                         "with --cyclic)")
    ap.add_argument("--log", type=Path, help="append each campaign's result (JSON line)")
    ap.add_argument("--from-log", type=Path, nargs="*", help="only the table of --log files")
    args = ap.parse_args()
    if args.from_log:
        rows = [json.loads(line) for p in args.from_log for line in p.read_text().splitlines()
                if line]
        report(rows, float("nan"))
        return
    if args.compensation:
        os.environ["EDNC_BENCH_COMPENSATION"] = "1"  # the spawned workers inherit it
    t_start = time.perf_counter()
    results: list[dict[str, Any]] = []
    seeds = range(args.first, args.first + args.campaigns)
    with multiprocessing.get_context("spawn").Pool(args.jobs) as pool:
        for res in pool.imap_unordered(judge_cyclic if args.cyclic else judge, seeds):
            results.append(res)
            if args.log is not None:
                with args.log.open("a") as f:
                    f.write(json.dumps(res) + "\n")
            if args.verbose or not res["hit"]:
                print(f"{'ok  ' if res['hit'] else 'MISS'} seed {res['seed']} type "
                      f"{res['type']} {res['category']}: hid "
                      f"{[(h['effect'], h['axis'], h['sensor']) for h in res['hidden']]}; "
                      f"said {res['said']} ({res['cpu_seconds']:.1f} s CPU)", flush=True)
    report(results, time.perf_counter() - t_start)


def report(results: list[dict[str, Any]], wall: float) -> None:
    by_cat: Counter[str] = Counter()
    hit_cat: Counter[str] = Counter()
    fam_total: Counter[tuple[str, str]] = Counter()
    fam_hit: Counter[tuple[str, str]] = Counter()
    errors: dict[str, list[float]] = defaultdict(list)
    by_type: Counter[str] = Counter()
    hit_type: Counter[str] = Counter()
    for r in results:
        by_cat[r["category"]] += 1
        hit_cat[r["category"]] += r["hit"]
        key = (f"type {r['type'][0]}/{r['type'][1]}" if isinstance(r["type"], list)
               else str(r["type"]))
        by_type[key] += 1
        hit_type[key] += r["hit"]
        for h, ok in zip(r["hidden"], r["found"], strict=False):
            fam_total[(r["category"], h["effect"])] += 1
            fam_hit[(r["category"], h["effect"])] += ok
        for fam, errs in r["errors"].items():
            errors[fam] += errs
    seeds = sorted(r["seed"] for r in results)
    print(f"\n{len(results)} five-axis campaigns, seeds {seeds[0]}..{seeds[-1]}, "
          f"{wall / 60:.1f} min wall")
    labels = {"single": "single effect (named first)", "pair": "pairs (both named)",
              "null": "null (said none)"}
    for cat in ("single", "pair", "null"):
        if by_cat[cat]:
            print(f"{labels[cat]:34s} {hit_cat[cat]:4d}/{by_cat[cat]:<4d} "
                  f"{100 * hit_cat[cat] / by_cat[cat]:5.1f} %")
    nulls = [r for r in results if r["category"] == "null"]
    print(f"{'false alarms on null':34s} {sum(not r['hit'] for r in nulls):4d}")
    print(f"{'rotary_periodic said on null':34s} "
          f"{sum(r['rotary_periodic_said'] for r in nulls):4d}")
    print(f"{'extra effects named (single/pair)':34s} "
          f"{sum(r.get('extra', 0) for r in results):4d}")
    print(f"\n{'family':20s} {'single':>9s} {'in pairs':>9s}  "
          "estimate error median / 95 % / worst")
    for fam in ["rotary_periodic", "rotary_backlash", *FAMILIES]:
        if not (fam_total[("single", fam)] or fam_total[("pair", fam)]):
            continue
        errs = np.array(errors.get(fam) or [np.inf])
        s = f"{fam_hit[('single', fam)]}/{fam_total[('single', fam)]}"
        p = f"{fam_hit[('pair', fam)]}/{fam_total[('pair', fam)]}"
        print(f"{fam:20s} {s:>9s} {p:>9s}  {100 * np.median(errs):8.1f} % / "
              f"{100 * np.percentile(errs, 95):5.1f} % / {100 * errs.max():5.1f} %")
    cyc = [r for r in results if "worst_before_um" in r]
    if cyc:
        saved = np.array([1 - r["worst_saved_um"] / r["worst_before_um"] for r in cyc])
        plain = np.array([1 - r["worst_fit_um"] / r["worst_before_um"] for r in cyc])
        print(f"\ncyclic errors: worst tool-tip error better by, saved model: min "
              f"{100 * saved.min():.1f} %, median {100 * np.median(saved):.1f} %; "
              f"plain ednc fit: min {100 * plain.min():.1f} %, median "
              f"{100 * np.median(plain):.1f} % ({len(cyc)} campaigns)")
    print(f"\n{'machine type':14s} {'hits':>9s}")
    for key in sorted(by_type):
        print(f"{key:14s} {hit_type[key]:4d}/{by_type[key]:<4d}")
    cpu = np.array([r["cpu_seconds"] for r in results])
    n = np.array([r["n"] for r in results])
    print(f"\nreadings per campaign: median {int(np.median(n))}, max {int(n.max())}")
    print(f"diagnosis CPU time (one core): median {np.median(cpu):.1f} s, "
          f"95 % {np.percentile(cpu, 95):.1f} s, worst {cpu.max():.1f} s")


if __name__ == "__main__":
    main()
