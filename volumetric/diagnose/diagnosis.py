"""Diagnosis: what the rigid model gets wrong, its physical cause, and the gain of extending it.

Procedure (``ednc diagnose``):

1. **Base model.** The rigid model (21 errors, smooth polynomial components on every
   axis, rotary ones included, :mod:`volumetric.identify.fit` with ``fourier=False``) is
   identified on the readings; its column set (degrees, identifiable parameters) and
   weights are then kept fixed. When effects are named (steps 4-6), the degrees are
   chosen again on the readings with those effects taken out and the whole diagnosis
   runs again on that base, up to ``REFITS`` times (:func:`_base_without`): with a
   12 µm backlash in the readings, BIC takes a cubic straightness for noise, and what
   the too-smooth base leaves decides between sensors that follow the same shop air.
2. **Held-out readings**, the split chosen from the data alone, the same way every time
   (the JSON's ``split``):

   * ``forward`` when the readings are time-ordered (every test spans at least
     ``TIME_ORDERED_SPAN`` of the campaign, :func:`time_ordered`: a thermal test, a
     long-term run): ``FORWARD_BLOCKS`` contiguous blocks of equal counts in time; each
     block from ``FIRST_JUDGED`` on is predicted by a model fitted on all blocks before
     it, never on anything later. ``blocks`` reports each judged block, their mean and
     the worst;
   * ``runs`` otherwise, in ``K = 5`` folds: a test with several runs gives whole runs
     to a fold (so repeated readings of one point never sit on both sides, and a
     time-dependent effect shows as a run that disagrees with the others); a test with
     one run gives contiguous stretches of it;
   * ``chronological`` with ``holdout_after`` (expert option): fit before, judge after.

   In every split, a lagged thermal model's sensors and time constants are selected again
   in every fold from that fold's training readings (``Candidate.per_fold``), wherever it
   is judged: alone, with further effects beside it, or when those are chosen again.
   Selected once on every reading, only its coefficients refitted per fold, it would
   carry the held-out readings' shape into their prediction. (A lagged model that does not
   beat the best candidate even judged that way, which favours it, is dropped unjudged:
   it could only matter as the best.)
3. **Candidates** (:mod:`volumetric.diagnose.candidates`), each a few extra columns of
   the same least-squares problem, all along one machine axis ``k`` (``u_k`` is what the
   reading senses of 1 µm along axis k's own line of motion,
   :func:`~volumetric.diagnose.candidates.along_axes`: its component along k, turned by
   the rotary axes between the reading's frame and the axis, as on an R-test of a
   rotary table):

   ===================  =========================================  ======================
   effect               extra column(s)                            estimate
   ===================  =========================================  ======================
   thermal_expansion    ``u_k (T_s − T̄_s)(q_k − q_min) / 1000``    α, ``um_per_m_K``
   thermal_drift        ``u_k (T_s − T̄_s)``; refined by lagged      k, ``um_per_K``
                        temperatures: the selection, averaged
                        with an all-sensor part (its prediction
                        as it comes, ``Candidate.fixed``) when
                        a map can carry the
                        model's records (``MAP_THERMAL_RECORDS``;
                        :mod:`volumetric.identify.thermal`, its
                        step 6)
   backlash             ``−u_k d_k / 2`` (d_k approach direction)  B, ``reversal_um``
   periodic             ``u_k sin(2π q_k/P)``, ``u_k cos(2π q_k/P)``  A, P
                        with P from the base residual's spectrum
   time_drift           ``u_k (t − t̄) / 3600``                     ``um_per_h``
   rotary_periodic      the rigid model refitted with a rotary     ``order``,
                        axis's components in harmonics of the      ``radial_um``,
                        angle (orders by BIC), replacing its       ``angular_urad``
                        polynomials (axes of >= 180° travel)
   ===================  =========================================  ======================

4. **Ranking and significance.** Candidates are ranked by held-out RMS of the displacement
   readings. The best (and only the best) is named when its gain is significant: it must
   reduce the held-out RMS of all displacement readings by at least ``MIN_GAIN``; over
   the readings it touches, the held-out squared errors of base and candidate, compared
   in contiguous chunks (so that correlated neighbours count once), must show a mean
   gain of ``Z_MIN`` standard errors; and its coefficient must stand ``T_MIN`` standard
   uncertainties clear of zero. Otherwise the answer is ``none``: a false alarm on clean
   data is as wrong as a miss. On clean simulated campaigns the best spurious candidate
   gains well under 1 %; a real effect of the smallest realistic size gains tens of per
   cent. Sensors whose temperatures move together cannot be told apart by any data: the
   runners-up of the same effect and axis within ``TIE`` of the best are listed as
   ``alternatives``.
5. **Estimate.** The named effect is fitted together with the base model on all readings;
   its coefficient and standard uncertainty are reported in physical units, and it becomes
   a term of the machine's :class:`~volumetric.model.model.MachineModel` (a lagged
   thermal drift as a ``thermal_dynamic`` term with its time constants and end states,
   every term of the average with the coefficient and block-jackknife uncertainty of
   its own fit, only the rigid part fitted beside it; the fit's
   tool-tip offsets in ``info["offsets_um"]``), so that the saved model applied
   forward (``ednc predict``) reproduces the figure. Its estimate's ``dynamic`` gives
   ``steady_um_per_K``: what each sensor 1 K off moves the drift by at steady state
   (sensors that move together can carry large coefficients of opposite signs; the
   largest is what a faulty sensor would cost).
6. **Further effects** (``effects``): forward selection. With the effects found so far in
   the model, every candidate of another effect or axis is judged again against that
   model's held-out residuals and the best is added when it passes the same three tests
   (``MIN_GAIN`` of the remaining RMS, ``Z_MIN``, ``T_MIN``), up to ``MAX_EFFECTS``. A
   null campaign cannot pass: the gates are those that keep single effects free of false
   alarms. Each entry's ``rms_after_um`` counts the effects up to it; the top-level
   ``rms_after_um`` is the last one's. A rotary axis's harmonics replace the base
   columns, so at most one ``rotary_periodic`` is named (the saved model still takes the
   Fourier basis on every rotary axis whose harmonics are significant on their own).
   When two or more effects are named, each thermal or time effect is chosen again among
   the thermal and time candidates of its axis with every other effect in the model
   (:func:`_refine`): forward selection picked it while another effect on that axis still
   distorted the comparison of sensors that move alike. A time drift gives way to a
   thermal candidate of its axis within ``TIME_TIE`` (:func:`_prefer_physical`). Each
   named thermal effect lists in its entry the ``alternatives``: sensors of its effect and
   axis within ``TIE`` of it with every other named effect in the model
   (:func:`_list_alternatives`).
7. **Unexplained structure** (:mod:`volumetric.diagnose.unexplained`): the final held-out
   residuals are searched for what they still follow (position, a period along an axis,
   approach direction, time, a temperature). Structure there is reported as an
   ``unexplained`` entry of ``effects`` (``estimate``: ``correlates_with``, the strongest
   correlate, ``structure_um``, every ``correlates`` with its F-test figures). A named
   effect whose own correlate (its sensor; its axis's position for a periodic error or an
   expansion; its axis's direction for a backlash) still carries structure of at least
   ``DEMOTE_RATIO`` of what the effect explained was the nearest
   candidate, not the cause: it moves into the entry's ``nearest`` list and the
   ``unexplained`` entry takes its place (the top-level ``effect`` when it was the first).
   The saved model keeps every term selected (each made a held-out gain). A periodic
   error's period is found again, in :func:`_refine`, from the residual of the model
   with the other effects in.

Candidates that the data cannot support are not guessed at: they are listed in
``not_assessed`` with the reason (no temperature columns, one approach direction only,
an axis never sensed).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from volumetric.diagnose.candidates import Candidate, RotaryFits, candidates, periodic_again
from volumetric.diagnose.candidates import temperature_columns as _temperature_columns
from volumetric.diagnose.unexplained import (
    DEMOTE_RATIO,
    Structure,
    correlate_key,
    own_correlates,
    residual_structure,
)
from volumetric.identify.design import Param, build_design
from volumetric.identify.fit import FitError, FitResult, fit, model_from_parameters
from volumetric.identify.thermal import DENSE_TAUS_S, fit_thermal_drift
from volumetric.identify.thermal import ThermalTerm as ThermalColumn
from volumetric.measure.measurement import Measurements
from volumetric.model.machine import Machine
from volumetric.model.model import (
    BacklashTerm,
    DynamicThermalTerm,
    LagColumn,
    MachineModel,
    PeriodicTerm,
    Term,
    ThermalTerm,
)

F64 = NDArray[np.float64]
K_FOLDS = 5
Z_MIN = 1.0
"""Significance of the held-out gain, in standard errors of the chunk-mean gain."""
MIN_GAIN = 0.05
"""Smallest relative reduction of the held-out RMS that names an effect."""
T_MIN = 5.0
"""Coefficient over its standard uncertainty that a named effect must reach."""
N_CHUNKS = 30
TIE = 0.05
"""Relative held-out RMS within which another sensor is reported as an alternative."""
MIN_READINGS = 50
MAX_EFFECTS = 3
"""Most effects one diagnosis names (forward selection)."""
MAP_THERMAL_RECORDS = 32
"""Thermal records one map carries (``protocol.mapformat.MAX_THERMAL``): a lagged model is
applied live as one record per sensor level and per time constant of its lags
(:mod:`volumetric.model.live`), beside one for each other thermal effect named."""
SELECTED_TERMS = 3
"""Most terms the lagged model's selection takes (``fit_thermal_drift``'s ``max_terms``)."""
REFITS = 2
"""Most times the rigid model's degrees are chosen again with the named effects taken out
(:func:`_base_without`); each time the diagnosis runs again on the new base."""


class DiagnosisError(ValueError):
    """The readings cannot support a diagnosis; the message says what is missing."""


@dataclass(frozen=True)
class Scored:
    candidate: Candidate
    heldout: F64  # (N,) held-out residuals
    rms_after_um: float
    z: float
    gain: float


@dataclass(frozen=True)
class Diagnosis:
    """The answer of :func:`diagnose` (formats.md section 3 plus extensions)."""

    effect: str
    axis: str | None
    sensor: str | None
    estimate: dict[str, Any]
    rms_before_um: float
    rms_after_um: float
    candidates: list[dict[str, Any]]
    not_assessed: dict[str, str]
    model: MachineModel
    details: dict[str, Any] = field(default_factory=dict)
    residual_before: F64 = field(default_factory=lambda: np.zeros(0), repr=False)
    residual_after: F64 = field(default_factory=lambda: np.zeros(0), repr=False)
    judged: NDArray[np.bool_] = field(default_factory=lambda: np.zeros(0, bool), repr=False)

    def to_json(self) -> dict[str, Any]:
        return {
            "effect": self.effect,
            "axis": self.axis,
            "sensor": self.sensor,
            "estimate": self.estimate,
            "rms_before_um": round(self.rms_before_um, 4),
            "rms_after_um": round(self.rms_after_um, 4),
            "candidates": self.candidates,
            "not_assessed": self.not_assessed,
            **self.details,
        }


def fold_labels(m: Measurements, k: int = K_FOLDS) -> NDArray[np.intp]:
    """Fold of each reading (see module docstring, step 2)."""
    folds = np.zeros(len(m), dtype=np.intp)
    for label in np.unique(m.test):
        rows = np.flatnonzero(m.test == label)
        runs = np.unique(m.run[rows])
        if runs.size >= 2:
            # whole runs to folds, in time order of the runs
            starts = [float(m.time_s[rows[m.run[rows] == r]].min()) for r in runs]
            order = runs[np.argsort(starts)]
            fold_of = {int(r): i % k for i, r in enumerate(order)}
            folds[rows] = [fold_of[int(r)] for r in m.run[rows]]
        else:
            by_time = rows[np.argsort(m.time_s[rows], kind="stable")]
            folds[by_time] = (np.arange(by_time.size) * k) // max(by_time.size, 1)
    return folds


def heldout_residuals(a: F64, y: F64, w: F64, folds: NDArray[np.intp]) -> F64:
    """Residual of every reading predicted by a weighted fit on the other folds.

    Rank-deficient training sets (a column unobserved without the fold) are solved in the
    minimum-norm sense with a stated eigenvalue cut (1e-10 of the largest).
    """
    aw = a * w[:, None]
    g_all = a.T @ aw
    b_all = aw.T @ y
    r = np.empty_like(y)
    for f in np.unique(folds):
        rows = folds == f
        g = g_all - a[rows].T @ aw[rows]
        b = b_all - aw[rows].T @ y[rows]
        x = _pinv_solve(g, b)
        r[rows] = y[rows] - a[rows] @ x
    return r


def _pinv_solve(g: F64, b: F64) -> F64:
    d = np.sqrt(np.clip(np.diag(g), 0, None))
    d[d == 0] = 1.0
    lam, vec = np.linalg.eigh(g / np.outer(d, d))
    keep = lam > 1e-10 * max(float(lam.max(initial=0.0)), 1e-300)
    z = vec[:, keep].T @ (b / d)
    out: F64 = (vec[:, keep] @ (z / lam[keep])) / d
    return out


def _rms(r: F64) -> float:
    return float(np.sqrt(np.mean(r * r))) if r.size else float("nan")


def _significance(base: F64, cand: F64, order: NDArray[np.intp], touched: NDArray[np.bool_]
                  ) -> float:
    """Chunk-mean gain of squared held-out errors over its standard error.

    ``order`` lists the judged readings in time order; only those the candidate touches
    count, so an effect confined to one axis is not diluted by the others' readings.
    """
    rows = order[touched[order]]
    gain = (base * base - cand * cand)[rows]
    chunks = np.array_split(gain, min(N_CHUNKS, max(gain.size // 5, 2)))
    sums = np.array([c.mean() for c in chunks if c.size])
    if sums.size < 2:
        return 0.0
    se = float(sums.std(ddof=1) / math.sqrt(sums.size))
    return float(sums.mean() / se) if se > 0 else (math.inf if sums.mean() > 0 else 0.0)


FORWARD_BLOCKS = 6
"""Contiguous time blocks of forward chaining (equal counts of readings in time order)."""
FIRST_JUDGED = FORWARD_BLOCKS // 2
"""The first block judged: every judged block is predicted by a model fitted on all the
blocks before it, at least half of the campaign (a thermal model fitted on a sixth of a
heat cycle says little of the next one, and would make the figure a measure of how soon
the campaign started to repeat itself)."""
TIME_ORDERED_SPAN = 0.5
"""A campaign is time-ordered when every test's readings span at least this fraction of
the campaign's duration: the same tests repeat over time, so the past predicts the future."""


def time_ordered(m: Measurements) -> bool:
    """True when the readings are one long time series of repeated tests (see
    :data:`TIME_ORDERED_SPAN`): a thermal test, a long-term drift run. A campaign of
    different tests one after the other is not: a later block would hold tests no earlier
    block saw."""
    span = float(np.ptp(m.time_s)) if len(m) else 0.0
    if span <= 0:
        return False
    for label in np.unique(m.test):
        t = m.time_s[m.test == label]
        if float(np.ptp(t)) < TIME_ORDERED_SPAN * span:
            return False
    return True


def forward_blocks(m: Measurements, k: int = FORWARD_BLOCKS) -> NDArray[np.intp]:
    """Block (0 .. k-1) of each reading: equal counts of readings in time order."""
    order = np.argsort(m.time_s, kind="stable")
    blocks = np.empty(len(m), dtype=np.intp)
    blocks[order] = (np.arange(len(m)) * k) // max(len(m), 1)
    return blocks


def forward_residuals(a: F64, y: F64, w: F64, blocks: NDArray[np.intp]) -> F64:
    """Residual of every reading of blocks ``FIRST_JUDGED`` .. predicted by a weighted fit
    on the blocks before its own (NaN in the earlier blocks, which only train)."""
    r = np.full(len(y), np.nan)
    for k in range(FIRST_JUDGED, int(blocks.max(initial=0)) + 1):
        tr = blocks < k
        rows = blocks == k
        x = _pinv_solve(a[tr].T @ (a[tr] * w[tr, None]), (a[tr] * w[tr, None]).T @ y[tr])
        r[rows] = y[rows] - a[rows] @ x
    return r


Fits = list[tuple[NDArray[np.bool_], NDArray[np.bool_]]]
"""The (fitted, judged) readings of every fold of a split, as boolean masks of shape (N,)."""


def fold_fits(split: str, folds: NDArray[np.intp], train: NDArray[np.bool_]) -> Fits:
    """The fitted and judged readings of every fold of ``split`` (step 2), in the order of
    a candidate's ``per_fold`` columns."""
    if split == "chronological":
        return [(train, ~train)]
    if split == "forward":
        return [(folds < k, folds == k)
                for k in range(FIRST_JUDGED, int(folds.max(initial=0)) + 1)]
    return [(folds != f, folds == f) for f in np.unique(folds)]


def heldout_per_fold(a0: F64, cands: list[Candidate], y: F64, w: F64, fits: Fits,
                     cells: NDArray[np.intp]) -> F64:
    """Held-out residuals of the base design extended by ``cands``, each fold fitted with
    every candidate's columns of that fold (NaN where no fold judges); ``cells`` as for
    :class:`BaseGrams`, whose base here is ``a0`` with the candidates that serve every
    fold (a replacing one included)."""
    serve_all = [c for c in cands if not c.per_fold]
    return BaseGrams(_combined(a0, serve_all), y - _known(len(y), serve_all), w, fits,
                     cells).heldout([c for c in cands if c.per_fold])


class BaseGrams:
    """The base design's weighted normal equations summed over each fold's fitted readings,
    computed once per diagnosis: a candidate judged adds only its own columns' rows and
    cross terms, O(N·P·k) per fold for k extra columns instead of O(N·P²) for the whole
    design again (the base design holds a hundred columns; a candidate one to a few).

    Parameters
    ----------
    a0 : ndarray, shape (N, P)
    y, w : ndarray, shape (N,)
        Readings and their weights.
    fits : Fits
    cells : ndarray of int, shape (N,)
        Labels such that every fold's fitted readings are a union of cells.
    """

    def __init__(self, a0: F64, y: F64, w: F64, fits: Fits, cells: NDArray[np.intp]) -> None:
        self.a0, self.y, self.w, self.fits = a0, y, w, fits
        aw = a0 * w[:, None]
        labels = [int(c) for c in np.unique(cells)]
        g_cell = {c: aw[cells == c].T @ a0[cells == c] for c in labels}
        b_cell = {c: aw[cells == c].T @ y[cells == c] for c in labels}
        p = a0.shape[1]
        self.g: list[F64] = []
        self.b: list[F64] = []
        for tr, _ in fits:
            inside = [int(c) for c in np.unique(cells[tr])]
            if not np.array_equal(np.isin(cells, inside), tr):
                raise ValueError("the fitted readings of a fold are not a union of cells")
            self.g.append(sum((g_cell[c] for c in inside), np.zeros((p, p))))
            self.b.append(sum((b_cell[c] for c in inside), np.zeros(p)))

    def heldout(self, cands: list[Candidate]) -> F64:
        """Held-out residuals of the base extended by ``cands`` (none replacing base
        columns), each fold with every candidate's columns of that fold (a fixed one's
        taken off the readings)."""
        w = self.w
        p = self.a0.shape[1]
        r = np.full(len(self.y), np.nan)
        free = [c for c in cands if not c.fixed]
        for f, (tr, te) in enumerate(self.fits):
            e = (np.column_stack([c.in_fold(f).columns for c in free]) if free
                 else np.zeros((len(self.y), 0)))
            known = _known(len(self.y), cands, f)
            y = self.y - known
            # the fold's fitted rows only, weighted; no copy of the (N, P) base
            ew = e * (w * tr)[:, None]
            g_be = self.a0.T @ ew
            g = np.block([[self.g[f], g_be], [g_be.T, ew.T @ e]])
            b = self.b[f] - self.a0.T @ (w * tr * known) if known.any() else self.b[f]
            x = _pinv_solve(g, np.concatenate((b, ew.T @ y)))
            r[te] = (y - self.a0 @ x[:p] - e @ x[p:])[te]
        return r


def _per_fold_dynamic(m: Measurements, static: Candidate, full: Candidate, grams: BaseGrams,
                      train: NDArray[np.bool_], order: NDArray[np.intp]) -> Candidate:
    """``full``, the lagged drift selected on all training readings, with its terms selected
    again in every fold from that fold's training readings alone, on the residual of the
    base fitted there (lags over the whole series use only the inputs; a fold that selects
    nothing gets no columns). Which sensors and time constants is part of what a fold
    judges: selected on every reading, they would carry the held-out readings' shape into
    the fold, which only refits their coefficients. The base's fit in each fold comes from
    ``grams``, the normal equations the fold's judging uses."""
    per = []
    for f, (tr, _) in enumerate(grams.fits):
        if np.array_equal(tr, train):
            per.append(full.columns)  # the chronological split: the fold is the whole fit
            continue
        x0 = _pinv_solve(grams.g[f], grams.b[f])
        dyn = _dynamic_drift(m, static, grams.y - grams.a0 @ x0, tr, order)
        per.append(np.zeros((len(m), 0)) if dyn is None else dyn.columns)
    return replace(full, per_fold=tuple(per))


def _block_table(blocks: NDArray[np.intp], judge: NDArray[np.bool_], before: F64,
                 ids: list[int], after: F64 | None = None) -> dict[str, Any]:
    """Per judged block: held-out RMS before (and after) the extension; mean and worst."""
    rows = []
    for k in ids:
        sel = judge & (blocks == k)
        item = {"block": k, "n": int(sel.sum()), "rms_before_um": round(_rms(before[sel]), 4)}
        if after is not None:
            item["rms_after_um"] = round(_rms(after[sel]), 4)
        rows.append(item)
    key = "rms_after_um" if after is not None else "rms_before_um"
    values = [float(r[key]) for r in rows]
    return {"per_block": rows, "mean_rms_um": round(float(np.mean(values)), 4),
            "worst_rms_um": round(float(np.max(values)), 4)}


def _offsets(params: list[Param], values: F64) -> dict[str, float]:
    """The tool-tip offsets (``OFFSET_X`` ...) of a solution, µm."""
    return {p.name: float(v) for p, v in zip(params, values, strict=True)
            if p.component == "OFFSET"}


def _dynamic_term(m: Measurements, a0: F64, w: F64, y: F64, train: NDArray[np.bool_],
                  c: Candidate, order: NDArray[np.intp]
                  ) -> tuple[DynamicThermalTerm, F64, float]:
    """The lagged drift fitted jointly with the base model on the training readings: its
    model term (coefficients with standard uncertainties, lag states at the last training
    reading, centred on the training readings), the base parameters of the joint fit and
    the level (µm) moved from the term's mean into the offset along its axis. An averaged
    model (fixed) keeps its own coefficients; only the base is fitted beside it."""
    a = c.design(a0)
    at, wt, yt = a[train], w[train], (y - c.known())[train]
    g = at.T @ (at * wt[:, None])
    x = _pinv_solve(g, (at * wt[:, None]).T @ yt)
    r = yt - at @ x
    s2 = float(np.sum(wt * r * r) / max(int(train.sum()) - a.shape[1], 1))
    std = np.sqrt(np.clip(np.diag(np.linalg.pinv(g)), 0, None) * s2)
    terms: list[ThermalColumn] = c.extra["terms"]
    kx = 0 if c.fixed else c.columns.shape[1]  # one column per term when fitted here
    temps = _temperature_columns(m)
    last = int(order[train[order]][-1])  # the last training reading in time
    t_all = m.time_s[order]
    sig = {s: v[order] for s, v in temps.items()}
    cols = []
    described = c.extra["description"]["terms"]
    for j, term in enumerate(terms):
        # the block-jackknife uncertainty of the drift model: the residuals of a thermal
        # test are strongly autocorrelated, which the least-squares formula ignores
        if c.fixed:
            coef = float(described[j]["um_per_K"])
            u = float(described[j]["um_per_K_std"])
        else:
            coef = float(x[a.shape[1] - kx + j])
            u = max(float(std[a.shape[1] - kx + j]), float(described[j]["um_per_K_std"]))
        if term.kind == "time":
            cols.append(LagColumn("time", "", 0.0, coef, u))
            continue
        state = None
        inp = float(temps[term.source][last])
        if term.kind == "lag":
            series = term.column(t_all, sig, c.extra["t0_s"])
            state = float(series[int(np.flatnonzero(order == last)[0])])
        cols.append(LagColumn(term.kind, term.source, float(term.tau_s), coef, u, state, inp))
    # centre the term on the training readings so that the rigid part's offset along the
    # axis stays the readings' zero, not the thermal level (the sum is unchanged)
    drift_sorted = np.zeros(len(m))
    for col, term in zip(cols, terms, strict=True):
        drift_sorted += col.coefficient * term.column(t_all, sig, c.extra["t0_s"])
    drift = np.empty(len(m))
    drift[order] = drift_sorted
    level = float(drift[train].mean())
    dyn = DynamicThermalTerm(c.axis, -level, tuple(cols), float(c.extra["t0_s"]),
                             float(m.time_s[last]))
    return dyn, x[: a.shape[1] - kx], level


def diagnose(
    machine: Machine,
    m: Measurements,
    *,
    holdout_after: float | None = None,
    base: FitResult | None = None,
    refits: int = REFITS,
) -> Diagnosis:
    """Find what the rigid model misses (see the module docstring).

    Parameters
    ----------
    machine : Machine
    m : Measurements
    holdout_after : float, optional
        Judge on readings with ``time_s >= holdout_after`` after fitting on the earlier
        ones, instead of the default folds.
    base : FitResult, optional
        The rigid model to extend (its parameters and weights; fitted on the training
        readings, polynomials on every axis). By default identified here by BIC.
    refits : int
        How many times the rigid model's degrees may be chosen again on the readings with
        the named effects taken out (step 1; :func:`_base_without`), the diagnosis then
        run again on that base. 0 keeps the first choice.

    Raises
    ------
    DiagnosisError
        Too few readings, or no displacement readings.
    """
    return _diagnose(machine, m, holdout_after, base, refits, {})


def _diagnose(machine: Machine, m: Measurements, holdout_after: float | None,
              base: FitResult | None, refits: int, rotary_fits: RotaryFits) -> Diagnosis:
    """:func:`diagnose`, with the rotary candidates' rigid fits kept for its refits (same
    readings, same training rows: only the base differs)."""
    if len(m) < MIN_READINGS:
        raise DiagnosisError(f"too few readings for a diagnosis: {len(m)} (need at least "
                             f"{MIN_READINGS})")
    disp = ~m.is_angle
    if not disp.any():
        raise DiagnosisError("no displacement readings: the diagnosis judges displacements")
    order = np.argsort(m.time_s, kind="stable")
    if holdout_after is not None:
        folds = (m.time_s >= holdout_after).astype(np.intp)
        if folds.all() or not folds.any():
            raise DiagnosisError(f"holdout_after={holdout_after} s leaves no readings on one "
                                 "side of the split")
        train = folds == 0
        judge = ~train & disp
        fold_ids: list[int] = [1]
    elif time_ordered(m):
        # forward chaining: block k is judged by a model fitted on blocks 0 .. k-1 only
        folds = forward_blocks(m)
        train = np.ones(len(m), dtype=bool)
        judge = disp & (folds >= FIRST_JUDGED)
        fold_ids = sorted(int(f) for f in np.unique(folds) if f >= FIRST_JUDGED)
    else:
        folds = fold_labels(m)
        train = np.ones(len(m), dtype=bool)
        judge = disp
        fold_ids = sorted(int(f) for f in np.unique(folds))
    split = ("chronological" if holdout_after is not None
             else "forward" if judge.sum() < disp.sum() else "runs")

    try:
        # the smooth model (polynomials on every axis): a periodic rotary error motion is
        # one of the candidates, named when its harmonics make the held-out gain
        base_fit = base if base is not None else fit(machine, m.select(train), fourier=False)
    except FitError as exc:
        raise DiagnosisError(f"the rigid model cannot be identified: {exc}") from None
    design = build_design(machine, m, fourier=False)
    names = [p.name for p in base_fit.params]
    a0 = design.matrix[:, design.columns(names)]
    trained = m.select(train)
    wd = base_fit.weights[~trained.is_angle]
    wa = base_fit.weights[trained.is_angle]
    w = np.where(m.is_angle, float(wa[0]) if wa.size else 1.0, float(wd[0]) if wd.size else 1.0)
    y = m.value

    def heldout(a: F64, y: F64 = y) -> F64:
        if split == "forward":
            return forward_residuals(a, y, w, folds)
        if holdout_after is not None:
            r = np.full(len(m), np.nan)
            x = _pinv_solve(a[train].T @ (a[train] * w[train, None]),
                            (a[train] * w[train, None]).T @ y[train])
            r[~train] = y[~train] - a[~train] @ x
            return r
        return heldout_residuals(a, y, w, folds)

    fits = fold_fits(split, folds, train)
    grams = BaseGrams(a0, y, w, fits, folds)

    def heldout_of(cands: list[Candidate]) -> F64:
        # a candidate selected again per fold is judged fold by fold with those columns;
        # one that replaces base columns (a rotary axis's harmonics) changes the base
        if any(c.drop for c in cands):
            if any(c.per_fold for c in cands):
                return heldout_per_fold(a0, cands, y, w, fits, folds)
            return heldout(_combined(a0, cands), y - _known(len(y), cands))
        return grams.heldout(cands)

    base_heldout = heldout(a0)
    rms_before = _rms(base_heldout[judge])
    full_base_resid = y - a0 @ _pinv_solve(a0[train].T @ (a0[train] * w[train, None]),
                                           (a0[train] * w[train, None]).T @ y[train])
    cands, missing = candidates(machine, m, full_base_resid, train, base_fit.params,
                                rotary_fits)
    order_judge = order[judge[order]]
    scored: list[Scored] = []
    for c in cands:
        r = heldout_of([c])
        rms = _rms(r[judge])
        z = _significance(base_heldout, r, order_judge, np.any(c.columns != 0, axis=1))
        scored.append(Scored(c, r, rms, z, (rms_before - rms) / rms_before))
    # a dynamic (lagged) refinement of the best thermal drift
    drift = [s for s in scored if s.candidate.effect == "thermal_drift"]
    if drift:
        best_drift = min(drift, key=lambda s: s.rms_after_um)
        dyn = _dynamic_drift(m, best_drift.candidate, full_base_resid, train, order)
        if (dyn is not None and split != "chronological"
                and _rms(heldout(_combined(a0, [dyn]), y - dyn.known())[judge])
                >= min(s.rms_after_um for s in scored)):
            # screening: judged with its lags and sensors chosen on every reading, which
            # favours it, it does not beat the best candidate; chosen again per fold (the
            # costly honest figure, five or three more selections) it would not either
            dyn = None
        if dyn is not None:
            # the lags and sensors are chosen again in every fold from its training readings
            dyn = _per_fold_dynamic(m, best_drift.candidate, dyn, grams, train, order)
            r = heldout_of([dyn])
            rms = _rms(r[judge])
            z = _significance(base_heldout, r, order_judge, np.any(dyn.columns != 0, axis=1))
            scored.append(Scored(dyn, r, rms, z, (rms_before - rms) / rms_before))
    scored.sort(key=lambda s: s.rms_after_um)
    table = [{"effect": s.candidate.effect, "axis": s.candidate.axis,
              "sensor": s.candidate.sensor, "rms_after_um": round(s.rms_after_um, 4),
              "gain": round(s.gain, 4), "z": round(s.z, 2),
              **({"model": "lagged"} if "lagged" in s.candidate.extra else {})}
             for s in scored]
    details: dict[str, Any] = {"n_readings": len(m), "folds": len(fold_ids), "split": split}
    if split == "forward":
        details["blocks"] = _block_table(folds, judge, base_heldout, fold_ids)
    pick = _prefer_physical(scored) if scored else None
    best = pick if pick is not None and pick.z >= Z_MIN and pick.gain >= MIN_GAIN else None
    if best is not None:
        static = best.candidate
        if "lagged" in static.extra:
            static = min((s for s in scored if s.candidate.effect == "thermal_drift"
                          and "lagged" not in s.candidate.extra), key=lambda s: s.rms_after_um
                         ).candidate
        estimate, term, joint = _estimate(machine, m, a0, w, y, train, static)
        details["t"] = round(estimate.pop("_t"), 2)
        if details["t"] < T_MIN:
            best = None
    if best is None:
        none_model = MachineModel(machine.name, base_fit.model.geometry, (),
                                  {**base_fit.model.info,
                                   "offsets_um": _offsets(base_fit.params, base_fit.values)})
        details["effects"] = []
        left = residual_structure(machine, m, base_heldout, judge, base_fit.degrees)
        if left:
            # structure no candidate explains: say so rather than "none"
            entry = _unexplained_entry(left, [], rms_before)
            details["effects"] = [entry]
            return Diagnosis("unexplained", entry["axis"], entry["sensor"], entry["estimate"],
                             rms_before, rms_before, table, missing, none_model, details,
                             base_heldout, base_heldout, judge)
        return Diagnosis("none", None, None, {}, rms_before, rms_before, table, missing,
                         none_model, details, base_heldout, base_heldout, judge)
    c = best.candidate
    if "lagged" in c.extra:
        # the static family names the effect; the dynamic model is its refinement
        estimate["dynamic"] = c.extra.get("description", {})
    effect, axis, sensor = static.effect, static.axis, static.sensor
    if effect == "rotary_periodic":
        # the extension is the rigid model itself in the Fourier basis: what `ednc fit` gives
        # every rotary axis whose harmonics make a significant gain on their own
        axes = frozenset(machine.axis(s.candidate.axis).name for s in scored
                         if s.candidate.effect == "rotary_periodic"
                         and s.z >= Z_MIN and s.gain >= MIN_GAIN)
        periodic_fit = fit(machine, m.select(train), fourier=axes | {machine.axis(axis).name})
        model = MachineModel(machine.name, periodic_fit.model.geometry, (),
                             {**periodic_fit.model.info, "extended_with": effect})
    elif "lagged" in c.extra:
        # the dynamic model behind the figure is what is saved: its lags with their time
        # constants and end states, and the offsets of the same joint fit
        term_d, joint_d, level = _dynamic_term(m, a0, w, y, train, c, order)
        # what one sensor off by 1 K does to the drift at steady state: sensors that move
        # together can carry large coefficients of opposite signs that cancel while they
        # do, and the worst of them is what a faulty sensor would cost
        steady = term_d.steady_um_per_K()
        estimate["dynamic"] = {**estimate["dynamic"], "steady_um_per_K": {
            s: round(v, 3) for s, v in sorted(steady.items(), key=lambda kv: -abs(kv[1]))}}
        geometry = model_from_parameters(machine, base_fit.params, joint_d).geometry
        offsets = _offsets(base_fit.params, joint_d)
        along = f"OFFSET_{c.axis.upper()}"
        if along in offsets:
            offsets[along] += level
        model = MachineModel(machine.name, geometry, (term_d,),
                             {**base_fit.model.info, "extended_with": "thermal_dynamic",
                              "offsets_um": offsets})
    else:
        # the rigid part refitted together with the effect, so it no longer carries a
        # share of it (a drift seen as straightness, a backlash as positioning error)
        geometry = model_from_parameters(machine, base_fit.params, joint).geometry
        model = MachineModel(machine.name, geometry, (term,) if term is not None else (),
                             {**base_fit.model.info, "extended_with": effect,
                              "offsets_um": _offsets(base_fit.params, joint)})
    alternatives = sorted({s.candidate.sensor for s in scored
                           if s.candidate.effect == effect and s.candidate.axis == axis
                           and s.candidate.sensor not in (None, sensor)
                           and s.rms_after_um <= best.rms_after_um * (1 + TIE)} - {None})
    if alternatives:
        details["alternatives"] = alternatives
    # further effects: forward selection, each judged against the model with the effects
    # already found and held to the same three tests as the first
    effects: list[dict[str, Any]] = [{"effect": effect, "axis": axis, "sensor": sensor,
                                      "estimate": estimate,
                                      "rms_after_um": round(best.rms_after_um, 4)}]
    effect_terms: list[Term | None] = [model.terms[0] if model.terms else None]
    chosen = [best.candidate]
    current = best
    while len(chosen) < MAX_EFFECTS:
        nxt = _next_effect(machine, m, a0, w, y, train, judge, order_judge, heldout_of,
                           scored, chosen, current)
        if nxt is None:
            break
        found, est2, term2 = nxt
        chosen.append(found.candidate)
        current = found
        effects.append({"effect": found.candidate.effect, "axis": found.candidate.axis,
                        "sensor": found.candidate.sensor, "estimate": est2,
                        "rms_after_um": round(found.rms_after_um, 4)})
        effect_terms.append(term2)
        if term2 is not None:
            model = model.with_terms(term2)
        if found.candidate.effect == "rotary_periodic":
            # the rigid part in the Fourier basis of that axis, as for a first effect
            rotary_axis = machine.axis(found.candidate.axis).name
            periodic = fit(machine, m.select(train), fourier=frozenset({rotary_axis}))
            model = MachineModel(machine.name, periodic.model.geometry, model.terms,
                                 {**model.info, "fourier_axes": [rotary_axis]})
    if len(chosen) > 1:
        swapped = _refine(machine, m, chosen, scored, a0, y, w, train, judge, heldout_of)
        if any(a is not b for a, b in zip(swapped, chosen, strict=True)):
            # a sensor (or time) chosen before another effect on its axis was in the model
            # gives way to the alias that explains more with all the effects in; a period
            # taken from a residual that still held a drift, to the one without it
            chosen = swapped
            for i, c_i in enumerate(chosen):
                r_i = heldout_of(chosen[: i + 1])
                effects[i].update(effect=c_i.effect, axis=c_i.axis, sensor=c_i.sensor,
                                  rms_after_um=round(_rms(r_i[judge]), 4))
            current = Scored(chosen[-1], r_i, _rms(r_i[judge]), current.z, current.gain)
            effect, axis, sensor = chosen[0].effect, chosen[0].axis, chosen[0].sensor
    if len(chosen) > 1:
        # each estimate again with every other effect in the model: effects on one axis
        # (a drift and an expansion) share variance that the first fit gave to one alone
        for i, c_i in enumerate(chosen):
            if c_i.drop or "lagged" in c_i.extra:
                continue  # a replacing or dynamic model keeps its own fit
            rest = [c for j, c in enumerate(chosen) if j != i]
            est_i, term_i, _ = _estimate(machine, m, _combined(a0, rest), w,
                                         y - _known(len(y), rest), train, c_i)
            est_i.pop("_t")
            effects[i]["estimate"] = est_i
            effect_terms[i] = term_i
        model = MachineModel(model.machine, model.geometry,
                             tuple(t for t in effect_terms if t is not None), model.info)
        estimate = effects[0]["estimate"]
    left = residual_structure(machine, m, current.heldout, judge, base_fit.degrees)
    if left:
        # structure left that the named effects do not explain; an effect whose own
        # correlate (its sensor, its axis's position or direction) still carries it was
        # the nearest candidate, not the cause: it gives way to "unexplained"
        strength = {correlate_key(s): s.rms_um for s in left}
        nearest = []
        before_i = rms_before
        for e in effects:
            # what this effect explained: the held-out RMS it removed (in quadrature)
            explained = math.sqrt(max(before_i ** 2 - float(e["rms_after_um"]) ** 2, 0.0))
            before_i = float(e["rms_after_um"])
            own = own_correlates(e["effect"], e["axis"], e["sensor"])
            if any(strength.get(k, 0.0) >= DEMOTE_RATIO * explained for k in own):
                nearest.append(e)
        kept = [e for e in effects if e not in nearest]
        entry = _unexplained_entry(left, nearest, current.rms_after_um)
        effects = [entry, *kept] if nearest and nearest[0] is effects[0] else [*kept, entry]
        first = effects[0]
        effect, axis, sensor, estimate = (first["effect"], first["axis"], first["sensor"],
                                          first["estimate"])
    details["effects"] = effects
    if split == "forward":
        details["blocks"] = _block_table(folds, judge, base_heldout, fold_ids, current.heldout)
    if refits > 0:
        # the base's degrees were chosen with these effects still in the readings, which
        # made them look like noise: chosen again without them, and everything judged
        # again on that base when it differs
        again = _base_without(machine, m, train, a0, w, chosen, base_fit)
        if again is not None:
            return _diagnose(machine, m, holdout_after, again, refits - 1, rotary_fits)
    _list_alternatives(chosen, effects, details, scored, judge, heldout_of)
    return Diagnosis(effect, axis, sensor, estimate, rms_before, current.rms_after_um, table,
                     missing, model, details, base_heldout, current.heldout, judge)


def _base_without(
    machine: Machine, m: Measurements, train: NDArray[np.bool_], a0: F64, w: F64,
    chosen: list[Candidate], base_fit: FitResult,
) -> FitResult | None:
    """The rigid model identified again on the training readings minus the named effects,
    or None when it keeps the same parameters.

    The base's degrees are chosen by BIC on readings that still hold the effects: a
    12 µm backlash or a drift of several µm is residual variance no polynomial
    explains, so the criterion takes the higher degrees' gain for noise and keeps
    components too smooth. Their leftover shape then decides between candidates that
    differ by less (screw sensors that follow the same shop air: a wrong one that fits
    a straightness component's leftover wins). The effects' fitted contribution (joint
    fit with the base, training readings) is taken out, the degrees chosen again, and
    the parameters' values fitted on the readings as they are (the effects beside them
    are the diagnosis's job).

    Parameters
    ----------
    machine : Machine
    m : Measurements
    train : ndarray of bool, shape (N,)
    a0 : ndarray, shape (N, P)
        The current base design.
    w : ndarray, shape (N,)
        Weights of the readings.
    chosen : list of Candidate
        The effects named; a replacing candidate (a rotary axis's harmonics) is fitted
        but not taken out (the base it replaces is what is chosen again).
    base_fit : FitResult
        The current base.

    Returns
    -------
    FitResult or None
    """
    extra = [c for c in chosen if not c.drop and not c.fixed]
    k = sum(c.columns.shape[1] for c in extra)
    known = _known(len(m), chosen)
    if k == 0 and not known.any():
        return None
    a = _combined(a0, chosen)
    y = m.value - known
    x = _pinv_solve(a[train].T @ (a[train] * w[train, None]),
                    (a[train] * w[train, None]).T @ y[train])
    effect = known + (np.column_stack([c.columns for c in extra]) @ x[a.shape[1] - k:]
                      if k else 0.0)
    trained = m.select(train)
    cleaned = replace(trained, value=trained.value - effect[train])
    try:
        again = fit(machine, cleaned, fourier=False)
    except FitError:
        return None
    if [p.name for p in again.params] == [p.name for p in base_fit.params]:
        return None
    # the values on the readings as they are, with the weights found without the effects
    design = build_design(machine, trained, fourier=False)
    at = design.matrix[:, design.columns([p.name for p in again.params])]
    wt = again.weights
    values = _pinv_solve(at.T @ (at * wt[:, None]), (at * wt[:, None]).T @ trained.value)
    resid = trained.value - at @ values
    rms = {label: _rms(resid[sel]) for label, sel in
           (("displacement_um", ~trained.is_angle), ("angle_urad", trained.is_angle))
           if sel.any()}
    info = {**again.model.info, "rms": rms, "offsets_um": _offsets(again.params, values),
            "parameters": [{**p, "value": float(v)} for p, v in
                           zip(again.model.info["parameters"], values, strict=True)]}
    model = MachineModel(machine.name, model_from_parameters(machine, again.params,
                                                             values).geometry, (), info)
    return replace(again, values=values, model=model, rms=rms,
                               residual=resid)


def _list_alternatives(
    chosen: list[Candidate], effects: list[dict[str, Any]], details: dict[str, Any],
    scored: list[Scored], judge: NDArray[np.bool_],
    heldout_of: Callable[[list[Candidate]], F64],
) -> None:
    """Each named thermal effect's ``alternatives`` in its ``effects`` entry: the other
    sensors of its effect and axis whose held-out RMS, with every other named effect in
    the model, is within ``TIE`` of its own. Screw sensors that follow the same shop air
    differ by tenths of a kelvin over a campaign; with a second effect beside a small
    drift the data may not tell them apart, and the entry says so instead of leaving
    the user to trust a coin toss. With one effect this is the top level's list; with
    several, the top level's list is the first entry's (all others in)."""
    if len(chosen) == 1:
        if "alternatives" in details and effects and effects[0]["effect"] == chosen[0].effect:
            effects[0]["alternatives"] = details["alternatives"]
        return
    for i, c_i in enumerate(chosen):
        if c_i.sensor is None or c_i.drop or "lagged" in c_i.extra:
            continue
        others = [c for j, c in enumerate(chosen) if j != i]
        own = _rms(heldout_of([*others, c_i])[judge])
        alt = sorted({s.candidate.sensor for s in scored
                      if (s.candidate.effect, s.candidate.axis) == (c_i.effect, c_i.axis)
                      and s.candidate.sensor not in (None, c_i.sensor)
                      and not s.candidate.drop and "lagged" not in s.candidate.extra
                      and _rms(heldout_of([*others, s.candidate])[judge]) <= own * (1 + TIE)}
                     - {None})
        entry = next((e for e in effects
                      if (e["effect"], e["axis"], e["sensor"]) == (c_i.effect, c_i.axis,
                                                                   c_i.sensor)), None)
        if entry is None:
            continue
        if alt:
            entry["alternatives"] = alt
        if entry is effects[0]:
            if alt:
                details["alternatives"] = alt
            else:
                details.pop("alternatives", None)


def _unexplained_entry(left: list[Structure], nearest: list[dict[str, Any]],
                       rms_after: float) -> dict[str, Any]:
    """The ``effects`` entry of structure no candidate explains: the strongest correlate
    names it (axis or sensor when it has one), every correlate found is listed, and the
    named effects it displaced (``nearest``) keep their estimates there."""
    top = left[0]
    estimate: dict[str, Any] = {"correlates_with": top.label, "structure_um": round(top.rms_um, 4),
                                "correlates": [s.to_json() for s in left]}
    if nearest:
        estimate["nearest"] = [{k: e[k] for k in ("effect", "axis", "sensor", "estimate")}
                               for e in nearest]
    return {"effect": "unexplained", "axis": top.axis, "sensor": top.sensor,
            "estimate": estimate, "rms_after_um": round(rms_after, 4)}


THERMAL_FAMILY = ("thermal_drift", "thermal_expansion", "time_drift")
"""Effects that follow a slow signal (a sensor or the clock): over one campaign several of
them can look alike, so which one is named is settled with every other effect in."""
TIME_TIE = 0.02
"""A time drift is named over a thermal candidate of its axis only when it explains the
held-out readings more than this much better: a slowly warming structure and the clock
are aliases over one campaign, and the sensor is the physical cause that can be
compensated."""


def _prefer_physical(ranked: list[Scored]) -> Scored:
    """The first of ``ranked`` (sorted by held-out RMS), unless it is a time drift and a
    thermal candidate of the same axis is within ``TIME_TIE`` of it."""
    top = ranked[0]
    if top.candidate.effect != "time_drift":
        return top
    for s in ranked[1:]:
        if s.rms_after_um > top.rms_after_um * (1 + TIME_TIE):
            break
        c = s.candidate
        if (c.effect in THERMAL_FAMILY[:2] and c.axis == top.candidate.axis
                and "lagged" not in c.extra):
            return s
    return top


def _refine(machine: Machine, m: Measurements, chosen: list[Candidate], scored: list[Scored],
            a0: F64, y: F64, w: F64, train: NDArray[np.bool_], judge: NDArray[np.bool_],
            heldout_of: Callable[[list[Candidate]], F64]) -> list[Candidate]:
    """Each thermal or time effect of ``chosen`` chosen again among the thermal and time
    candidates of its axis, with every other chosen effect in the model (forward selection
    picked it before the others were in, when a backlash or a drift on the same axis
    still distorted the comparison of sensors that move alike); each periodic error's
    period found again from the residual of the model with the others in (the base
    residual it was first taken from still held them, and a drift of several µm moves
    the periodogram's peak)."""
    out = list(chosen)
    for i, c_i in enumerate(out):
        if c_i.effect == "periodic":
            others = [c for j, c in enumerate(out) if j != i]
            base = _combined(a0, others)
            y_o = y - _known(len(y), others)
            x = _pinv_solve(base[train].T @ (base[train] * w[train, None]),
                            (base[train] * w[train, None]).T @ y_o[train])
            again = periodic_again(machine, m, c_i, y_o - base @ x, train)
            if again is not None:
                r_old = heldout_of([*others, c_i])
                r_new = heldout_of([*others, again])
                if _rms(r_new[judge]) < _rms(r_old[judge]):
                    out[i] = again
            continue
        if c_i.effect not in THERMAL_FAMILY or c_i.drop or "lagged" in c_i.extra:
            continue
        others = [c for j, c in enumerate(out) if j != i]
        taken = {(c.effect, c.axis) for c in others}
        tried = []
        for s in scored:
            c = s.candidate
            if (c.effect in THERMAL_FAMILY and c.axis == c_i.axis and not c.drop
                    and "lagged" not in c.extra and (c.effect, c.axis) not in taken):
                r = heldout_of([*others, c])
                tried.append(Scored(c, r, _rms(r[judge]), 0.0, 0.0))
        if tried:
            tried.sort(key=lambda t: t.rms_after_um)
            out[i] = _prefer_physical(tried).candidate
    return out


def _combined(a0: F64, cands: list[Candidate]) -> F64:
    """The base design extended by several candidates (a replacing one, a rotary axis's
    harmonics, first; at most one of those); a fixed one adds no column (its prediction,
    :func:`_known`, is taken off the readings)."""
    replacing = [c for c in cands if c.drop]
    a = replacing[0].design(a0) if replacing else a0
    extra = [c.columns for c in cands if not c.drop and not c.fixed]
    return np.column_stack((a, *extra)) if extra else a


def _known(n: int, cands: list[Candidate], f: int | None = None) -> F64:
    """What the fixed candidates among ``cands`` predict (µm), shape (n,), their columns
    of fold ``f`` when given: the readings less this are what the others are fitted to."""
    out = np.zeros(n)
    for c in cands:
        if c.fixed:
            out += c.known(f)
    return out


def _next_effect(
    machine: Machine, m: Measurements, a0: F64, w: F64, y: F64, train: NDArray[np.bool_],
    judge: NDArray[np.bool_], order_judge: NDArray[np.intp],
    heldout_of: Callable[[list[Candidate]], F64], scored: list[Scored],
    chosen: list[Candidate],
    current: Scored,
) -> tuple[Scored, dict[str, Any], Term | None] | None:
    """The strongest further effect given those ``chosen``, or None when none passes.

    Candidates of an effect and axis already chosen (other sensors of the same drift),
    lagged refinements and a second replacing candidate are not tried; the gain is
    measured against the held-out residuals of the model with the chosen effects.
    """
    taken = {(c.effect, c.axis) for c in chosen}
    replacing = any(c.drop for c in chosen)
    rms0 = _rms(current.heldout[judge])
    base = _combined(a0, chosen)
    y = y - _known(len(y), chosen)  # what the chosen effects' fitted columns and base face
    tried: list[Scored] = []
    # a periodic error's period taken again from the residual of the model with the
    # effects found so far: the base residual it came from still held them (a drift of
    # several µm moves the periodogram's peak off a 1 µm pitch error)
    x_now = _pinv_solve(base[train].T @ (base[train] * w[train, None]),
                        (base[train] * w[train, None]).T @ y[train])
    resid_now = y - base @ x_now
    for s in scored:
        c = s.candidate
        if (c.effect, c.axis) in taken or "lagged" in c.extra or (c.drop and replacing):
            continue
        if c.effect == "periodic":
            c = periodic_again(machine, m, c, resid_now, train) or c
        r = heldout_of([*chosen, c])
        rms = _rms(r[judge])
        tried.append(Scored(c, r, rms, 0.0, (rms0 - rms) / rms0))
    if not tried:
        return None
    tried.sort(key=lambda t: t.rms_after_um)
    pick = _prefer_physical(tried)
    z = _significance(current.heldout, pick.heldout, order_judge,
                      np.any(pick.candidate.columns != 0, axis=1))
    best = Scored(pick.candidate, pick.heldout, pick.rms_after_um, z, pick.gain)
    if best.z < Z_MIN or best.gain < MIN_GAIN:
        return None
    est, term, _ = _estimate(machine, m, base, w, y, train, best.candidate)
    if est.pop("_t") < T_MIN:
        return None
    return best, est, term


def _estimate(
    machine: Machine, m: Measurements, a0: F64, w: F64, y: F64,
    train: NDArray[np.bool_], c: Candidate,
) -> tuple[dict[str, Any], Term | None, F64]:
    """Fit base + candidate on the training readings: the effect in physical units, its
    model term, and the rigid parameters of the joint fit."""
    if c.fixed:
        raise ValueError(f"{c.label} is a fixed prediction: it has no coefficient to estimate")
    a = c.design(a0)
    at, wt, yt = a[train], w[train], y[train]
    g = at.T @ (at * wt[:, None])
    x = _pinv_solve(g, (at * wt[:, None]).T @ yt)
    r = yt - at @ x
    dof = max(int(train.sum()) - a.shape[1], 1)
    s2 = float(np.sum(wt * r * r) / dof)
    cov = np.linalg.pinv(g) * s2
    kx = c.columns.shape[1]
    coef = x[-kx:]
    std = np.sqrt(np.clip(np.diag(cov)[-kx:], 0, None))
    axis = machine.axis(c.axis)
    temps = _temperature_columns(m)
    est, term = _physical(c, coef, std, axis.travel[0], temps, train)
    est["_t"] = float(np.linalg.norm(coef) / max(float(np.linalg.norm(std)), 1e-300))
    return est, term, x[:-kx]


def _physical(
    c: Candidate, coef: F64, std: F64, q_min: float, temps: dict[str, F64],
    train: NDArray[np.bool_],
) -> tuple[dict[str, Any], Term | None]:
    if c.effect == "thermal_expansion":
        assert c.sensor is not None
        tref = float(temps[c.sensor][train].mean())
        return ({"um_per_m_K": float(coef[0]), "um_per_m_K_std": float(std[0])},
                ThermalTerm("thermal_expansion", c.axis, c.sensor, float(coef[0]), tref,
                            q_min))
    if c.effect == "thermal_drift":
        assert c.sensor is not None
        tref = float(temps[c.sensor][train].mean())
        return ({"um_per_K": float(coef[0]), "um_per_K_std": float(std[0])},
                ThermalTerm("thermal_drift", c.axis, c.sensor, float(coef[0]), tref))
    if c.effect == "backlash":
        return ({"reversal_um": abs(float(coef[0])), "reversal_um_std": float(std[0]),
                 "sign": "lags behind the motion" if coef[0] >= 0 else "leads the motion"},
                BacklashTerm(c.axis, abs(float(coef[0]))))
    if c.effect == "periodic":
        a_s, a_c = float(coef[0]), float(coef[1])
        amp = math.hypot(a_s, a_c)
        amp_std = float(math.sqrt((a_s * std[0]) ** 2 + (a_c * std[1]) ** 2) / max(amp, 1e-12))
        phase = math.atan2(a_c, a_s)
        period = c.extra["period_mm"]
        return ({"amplitude_um": amp, "period_mm": period, "amplitude_um_std": amp_std,
                 "phase_rad": phase},
                PeriodicTerm(c.axis, amp, period, phase))
    if c.effect == "time_drift":
        return ({"um_per_h": float(coef[0]), "um_per_h_std": float(std[0])}, None)
    if c.effect == "rotary_periodic":
        return _rotary_estimate(c.extra["params"], coef, std), None
    raise ValueError(f"unknown effect {c.effect}")


def _rotary_estimate(params: list[Param], coef: F64, std: F64) -> dict[str, Any]:
    """Harmonic amplitudes of a rotary axis's components: the strongest order per turn,
    its largest radial/axial (µm) and angular (µrad) amplitude, and every component's
    amplitudes by order (with standard uncertainties, first order propagated).

    ``params`` are all the candidate's parameters; only the harmonics count."""
    amp: dict[str, dict[int, tuple[float, float]]] = {}
    parts: dict[tuple[str, int], list[tuple[float, float]]] = {}
    for p, v, u in zip(params, coef, std, strict=True):
        if p.basis != "fourier":
            continue
        parts.setdefault((p.component, (p.degree + 1) // 2), []).append((float(v), float(u)))
    for (comp, k), vu in parts.items():
        a = math.hypot(*(v for v, _ in vu))
        ua = math.sqrt(sum((v * u) ** 2 for v, u in vu)) / max(a, 1e-12)
        amp.setdefault(comp, {})[k] = (a, ua)
    # the order whose harmonics, in units of their own uncertainty, stand out most
    score: dict[int, float] = {}
    for by_k in amp.values():
        for k, (a, ua) in by_k.items():
            score[k] = score.get(k, 0.0) + (a / max(ua, 1e-12)) ** 2
    order = max(score, key=lambda k: score[k])
    radial = [(a, ua) for comp, by_k in amp.items() if comp[1] in "XYZ"
              for k, (a, ua) in by_k.items() if k == order]
    angular = [(a, ua) for comp, by_k in amp.items() if comp[1] in "ABC"
               for k, (a, ua) in by_k.items() if k == order]
    best_r = max(radial, default=(0.0, 0.0))
    best_a = max(angular, default=(0.0, 0.0))
    return {"order": order, "radial_um": best_r[0], "radial_um_std": best_r[1],
            "angular_urad": best_a[0], "angular_urad_std": best_a[1],
            "components": {comp: {str(k): round(a, 3) for k, (a, _) in sorted(by_k.items())}
                           for comp, by_k in sorted(amp.items())}}


def _dynamic_drift(
    m: Measurements, static: Candidate, resid: F64, train: NDArray[np.bool_],
    order: NDArray[np.intp],
) -> Candidate | None:
    """Lagged-temperature drift along the static candidate's axis (volumetric.identify.thermal),
    sensed as the static candidate senses it (:func:`~volumetric.diagnose.candidates.along_axes`:
    on an R-test the axis's direction turns with the table)."""
    k = "xyz".index(static.axis)
    along = static.extra.get("along")
    uk = np.where(m.is_angle, 0.0, m.u[:, k] if along is None else along)
    rows = order[np.abs(uk[order]) > 0.5]
    if rows.size < 50:
        return None
    temps = _temperature_columns(m)
    t = m.time_s[rows]
    y = resid[rows] / uk[rows]
    # the all-sensor part joins only when the model it makes can be applied live: one
    # record per sensor level and one per time constant (its lags over every sensor are
    # one lag of their weighted sum, volumetric.model.live), beside the selection's and
    # the other effects', within what a map carries (sixteen sensors: 26 of 32)
    records = len(temps) + len(DENSE_TAUS_S) + SELECTED_TERMS + MAX_EFFECTS - 1
    dense = DENSE_TAUS_S if records <= MAP_THERMAL_RECORDS else ()
    try:
        model = fit_thermal_drift(t, {c: v[rows] for c, v in temps.items()}, y,
                                  train[rows], time_drift=False, max_terms=SELECTED_TERMS,
                                  dense_taus_s=dense)
    except ValueError:
        return None
    if not model.terms:
        return None
    # columns over every reading: the lags run over the time-ordered series of all rows
    t_all = m.time_s[order]
    sig = {c: v[order] for c, v in temps.items()}
    cols_sorted = np.column_stack([term.column(t_all, sig, model.t0_s) for term in model.terms])
    cols = np.empty_like(cols_sorted)
    cols[order] = cols_sorted
    # each term also as fields (kind, sensor, time constant), not only as its name's text
    desc: dict[str, Any] = {
        "terms": [{"name": term.name, "kind": term.kind, "sensor": term.source or None,
                   "tau_s": float(term.tau_s), "um_per_K": float(cf), "um_per_K_std": float(cu)}
                  for term, cf, cu in zip(model.terms, model.coef, model.coef_u, strict=True)]}
    averaged = bool(model.dense_taus_s)
    if averaged:
        # the selection averaged with the all-sensor part (volumetric.identify.thermal,
        # step 6) is one model, its prediction fixed by that fit, shape and scale: term
        # by term, the joint fit with the rigid model would undo the average with a
        # hundred free coefficients, and even one free scale undoes part of it. Fitted on
        # the readings the average came from, that scale is never below 1: the average
        # of projections P_i y has <y, Σ a_i P_i y> = Σ a_i |P_i y|² >= |Σ a_i P_i y|²
        # (a_i >= 0 summing to 1; P_i holds the constant). Measured on all five channels
        # of the real test (three splits each, module docstring of thermal.py) it came
        # out 1.002-1.17, and the free scale predicted worse in 7 of the 11 splits where
        # the average joins (by up to 0.55 µm), better in 4 (by up to 0.16 µm).
        desc["selected"] = [term.name for term in model.selected]
        desc["all_sensor_taus_s"] = [float(tau) for tau in model.dense_taus_s]
        cols = cols @ model.coef[:, None]
    return Candidate("thermal_drift", static.axis, static.sensor, uk[:, None] * cols,
                     {"lagged": True, "description": desc, "terms": list(model.terms),
                      "t0_s": float(model.t0_s)}, fixed=averaged)
