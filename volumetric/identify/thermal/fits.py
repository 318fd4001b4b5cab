"""The final least-squares fits of a selected thermal-drift model
(:mod:`volumetric.identify.thermal`, steps 5 and 6): the selected terms alone, or averaged
with the all-sensor part; block-jackknife uncertainties either way.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from volumetric.identify.thermal.blocked_cv import contiguous_blocks
from volumetric.identify.thermal.columns import ThermalTerm
from volumetric.identify.thermal.model import SelectionStep, ThermalDriftModel
from volumetric.model.lag import first_order_lag

F64 = NDArray[np.float64]


def final_fit(terms: list[ThermalTerm], cols: list[F64], y: F64, n_blocks: int, t0: float,
               *, cv_rms: float, baseline: float,
               steps: tuple[SelectionStep, ...]) -> ThermalDriftModel:
    """OLS on all training rows, with block-jackknife standard uncertainties."""
    n = y.shape[0]
    design = np.column_stack([np.ones(n), *cols])
    coef = np.asarray(np.linalg.lstsq(design, y, rcond=None)[0], dtype=np.float64)
    residual = y - design @ coef
    blocks = contiguous_blocks(n, n_blocks)
    leave_out = np.array([np.linalg.lstsq(design[blocks != b], y[blocks != b], rcond=None)[0]
                          for b in range(n_blocks)])
    spread = leave_out - leave_out.mean(axis=0)
    u = np.sqrt((n_blocks - 1) / n_blocks * np.sum(spread**2, axis=0))
    return ThermalDriftModel(
        terms=tuple(terms), intercept_um=float(coef[0]), coef=coef[1:],
        intercept_u_um=float(u[0]), coef_u=u[1:], t0_s=t0,
        train_rms_um=float(np.sqrt(np.mean(residual**2))), cv_rms_um=cv_rms,
        baseline_cv_rms_um=baseline, n_train=n, n_blocks=n_blocks, steps=steps,
        selected=tuple(terms))


def combined_fit(chosen: list[ThermalTerm], cols: list[F64], y: F64, t: F64, temps: F64,
                  names: list[str], train: NDArray[np.bool_], dense_taus: list[float],
                  n_blocks: int, t0: float, *, baseline: float,
                  steps: tuple[SelectionStep, ...]) -> ThermalDriftModel:
    """The selected terms' OLS fit and the all-sensor part's, averaged with equal weights.

    The all-sensor part is, for each τ of ``dense_taus``, the OLS fit of the intercept,
    every temperature and its lag τ (which spans its smoothed rate), averaged over the τ.
    Both parts are fitted on the same training rows; the result is one linear model over
    the union of their columns. Its uncertainties are block-jackknife estimates and its
    ``cv_rms_um`` the blocked CV of the whole procedure with the selected structure fixed.

    Parameters
    ----------
    chosen, cols : the selected terms and their columns over the training rows, (n,) each.
    y : ndarray, shape (n,)
        Training drift (µm).
    t : ndarray, shape (N,)
        All sample times (s); the lags run over the whole series.
    temps : ndarray, shape (N, S)
        The temperatures (°C) over all rows, in the order of ``names``.
    train : ndarray of bool, shape (N,)
    """
    n, n_sel = y.shape[0], len(chosen)
    sparse = np.column_stack([np.ones(n), *cols])
    levels = temps[train]
    denses = [np.column_stack([np.ones(n), levels, first_order_lag(t, temps, tau)[train]])
              for tau in dense_taus]
    terms: dict[ThermalTerm, int] = {term: j for j, term in enumerate(chosen)}
    for name in names:
        terms.setdefault(ThermalTerm("level", name), len(terms))
    for tau in dense_taus:
        for name in names:
            terms.setdefault(ThermalTerm("lag", name, tau), len(terms))
    # where each part's coefficients go in the merged vector (0 is the intercept)
    sparse_at = np.arange(n_sel + 1)
    dense_at = [np.array([0, *(1 + terms[ThermalTerm("level", k)] for k in names),
                          *(1 + terms[ThermalTerm("lag", k, tau)] for k in names)])
                for tau in dense_taus]
    share = 0.5 / len(dense_taus)

    def combined(rows: NDArray[np.bool_]) -> F64:
        out = np.zeros(len(terms) + 1)
        out[sparse_at] += 0.5 * np.linalg.lstsq(sparse[rows], y[rows], rcond=None)[0]
        for at, design in zip(dense_at, denses, strict=True):
            np.add.at(out, at, share * np.linalg.lstsq(design[rows], y[rows], rcond=None)[0])
        return out

    # the merged design from the parts' own columns (where both parts hold a column, e.g.
    # a selected level or the intercept, the two are the same)
    merged = np.empty((n, len(terms) + 1))
    for at, design in zip(dense_at, denses, strict=True):
        merged[:, at] = design
    merged[:, sparse_at] = sparse
    coef = combined(np.ones(n, dtype=bool))
    blocks = contiguous_blocks(n, n_blocks)
    leave_out = np.array([combined(blocks != b) for b in range(n_blocks)])
    cv_sse = sum(float(np.sum((y - merged @ c)[blocks == b] ** 2))
                 for b, c in enumerate(leave_out))
    spread = leave_out - leave_out.mean(axis=0)
    u = np.sqrt((n_blocks - 1) / n_blocks * np.sum(spread**2, axis=0))
    residual = y - merged @ coef
    return ThermalDriftModel(
        terms=tuple(sorted(terms, key=terms.__getitem__)), intercept_um=float(coef[0]),
        coef=coef[1:],
        intercept_u_um=float(u[0]), coef_u=u[1:], t0_s=t0,
        train_rms_um=float(np.sqrt(np.mean(residual**2))),
        cv_rms_um=float(np.sqrt(cv_sse / n)), baseline_cv_rms_um=baseline, n_train=n,
        n_blocks=n_blocks, steps=steps, selected=tuple(chosen),
        dense_taus_s=tuple(dense_taus))
