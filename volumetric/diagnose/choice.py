"""Which model of a thermal drift a forward split saves (issue 33): a richer model only
when it wins on every forward split, never one that predicts the future worse than the
plain static model on every sensor (step 4 of :mod:`volumetric.diagnose`).

A saved model is applied to everything after the campaign, so the models are compared on
splits that look like that use: for every judged block ``k`` of the forward split, the
model fitted on the blocks before ``k`` predicts *every* later block, not ``k`` alone
(:func:`future_rms`; each model selected again from that split's training readings,
as in the split itself). The pooled held-out RMS of the next block alone let one block
carry the choice: a ridge model on every sensor's level and lag that fits a heat cycle's
shape closely won it by a wide margin on two blocks and lost the last, and after the cut
predicted worse than the simpler model (the real 46 h test cut at 60 %, ch3: 6.31
against 3.42 µm). The rule, from the simplest model up:

1. the *simple* model: the one-sensor static drift or its lagged refinement (a few
   selected terms, :func:`volumetric.diagnose.lagged.dynamic_drift`), whichever predicts
   the future splits better on average; each judged as it would be chosen, in every
   split from that split's training readings alone (the refinement's terms; the static
   drift's sensor, :func:`static_future`: the best of sixteen sensors by a figure over
   the judged readings is a choice made on them, and flatters it);
2. the plain least squares on every sensor's level (the reference every thermal model
   must not lose to, :func:`volumetric.identify.thermal.plain.fit_all_sensors`) instead
   when it predicts the future splits better on average;
3. a richer model (every sensor with their rates, or shrunk by ridge) replaces it only
   when it predicts better in *every* future split and by ``RICHER_MARGIN`` on average;
   of several that do, the best on average.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from volumetric.diagnose.candidates import Candidate
from volumetric.diagnose.gates import Scored
from volumetric.diagnose.splits import BaseGrams, Judge, rms_of, solve_normal

F64 = NDArray[np.float64]

RICHER_MARGIN = 0.10
"""Relative RMS, averaged over the future splits, by which a richer model must beat the
simple one (beside beating it in every future split)."""


@dataclass(frozen=True)
class Future:
    """A thermal model and its RMS (µm) over each future split, shape (B,)."""

    scored: Scored
    rms_um: F64

    @property
    def mean(self) -> float:
        return float(self.rms_um.mean())


def future_masks(judge: Judge) -> list[tuple[NDArray[np.bool_], NDArray[np.bool_]]]:
    """(fitted, judged) readings of every future split: the fold's training readings, and
    every judged reading from the fold's block on."""
    sp = judge.split
    out = []
    for (tr, te), k in zip(judge.fits, sp.fold_ids, strict=True):
        later = sp.judge & (sp.folds >= k) if sp.name == "forward" else te & sp.judge
        out.append((tr, later))
    return out


def future_rms(c: Candidate, judge: Judge) -> F64:
    """RMS (µm) of ``c`` (with its columns of each fold, when selected per fold) over each
    future split of ``judge``'s forward split, shape (B,)."""
    sp = judge.split
    out = []
    for f, (tr, later) in enumerate(future_masks(judge)):
        grams = BaseGrams(judge.a0, judge.y, judge.w, [(tr, later)], sp.folds)
        r = grams.heldout([c.in_fold(f)])
        out.append(rms_of(r[later]))
    return np.array(out)


def static_future(drifts: list[Candidate], judge: Judge) -> F64:
    """RMS (µm) over each future split of the one-sensor static drift with its sensor
    chosen in every split from its training readings alone (the sensor whose column,
    beside the base design, fits them best: least weighted residual sum of squares),
    shape (B,)."""
    a0, y, w = judge.a0, judge.y, judge.w
    out = []
    for tr, later in future_masks(judge):
        best: tuple[float, float] | None = None
        for c in drifts:
            a = np.column_stack((a0, c.columns))
            at, wt = a[tr], w[tr]
            x = solve_normal(at.T @ (at * wt[:, None]), (at * wt[:, None]).T @ y[tr])
            res = y - a @ x
            rss = float(np.sum(wt * res[tr] ** 2))
            if best is None or rss < best[0]:
                best = (rss, rms_of(res[later]))
        assert best is not None
        out.append(best[1])
    return np.array(out)


def forward_choice(simple: list[Future], plain: Future | None,
                   richer: list[Future]) -> Future:
    """The model a forward split saves (module docstring, steps 1-3).

    Parameters
    ----------
    simple : list of Future
        The one-sensor static drift and its lagged refinement (those available).
    plain : Future or None
        The plain least squares on every sensor's level.
    richer : list of Future
        The models on every sensor (``plain`` among them or not).
    """
    pool = list(simple) or ([plain] if plain is not None else [])
    if not pool:
        raise ValueError("no model to choose from")
    base = min(pool, key=lambda s: s.mean)
    if plain is not None and plain.mean < base.mean:
        base = plain
    wins = [r for r in richer if r is not base and r is not plain
            and bool(np.all(r.rms_um < base.rms_um))
            and r.mean <= (1.0 - RICHER_MARGIN) * base.mean]
    return min(wins, key=lambda s: s.mean) if wins else base
