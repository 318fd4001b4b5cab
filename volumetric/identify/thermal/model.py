"""A fitted thermal-drift model (:class:`ThermalDriftModel`) and the steps of the selection
that chose its terms (:class:`SelectionStep`); :mod:`volumetric.identify.thermal`.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from volumetric.identify.thermal.columns import ThermalTerm, merge_signals
from volumetric.model.lag import _as_time

F64 = NDArray[np.float64]


@dataclass(frozen=True, slots=True)
class SelectionStep:
    """One step of the forward selection.

    Attributes
    ----------
    term : ThermalTerm
        The best candidate of this step (with its refined τ).
    cv_rms_um : float
        Blocked-CV RMS (µm) of the model with this candidate added.
    gain_um2 : float
        Reduction of the blocked-CV mean squared error (µm²) the candidate brings.
    log_gain_mean : float
        Mean over blocks of ``ln(SSE before / SSE after)`` of the held-out squared errors
        (dimensionless; 0.1 is about a 10 % smaller error sum).
    log_gain_se : float
        Standard error of that mean.
    accepted : bool
        Whether the stopping rule let it join (the last step of a selection is the first
        rejected candidate, unless ``max_terms`` stopped it).
    """

    term: ThermalTerm
    cv_rms_um: float
    gain_um2: float
    log_gain_mean: float
    log_gain_se: float
    accepted: bool


@dataclass(frozen=True, eq=False, slots=True)
class ThermalDriftModel:
    """A fitted drift model ``y = intercept + Σ coef_j · column_j``.

    Attributes
    ----------
    terms : tuple of ThermalTerm, length p
        The selected columns.
    intercept_um : float
        Constant term (µm).
    coef : ndarray, shape (p,)
        Coefficients: µm/K for temperature levels and lags, µm/h for the time drift,
        µm per unit for extra inputs.
    intercept_u_um : float
        Standard uncertainty (block jackknife) of the intercept (µm).
    coef_u : ndarray, shape (p,)
        Standard uncertainties (block jackknife) of ``coef``, same units.
    t0_s : float
        Time origin (s) of the time drift term.
    train_rms_um : float
        RMS residual on the training rows (µm).
    cv_rms_um : float
        Blocked-CV RMS of the selected model on the training rows (µm); with the
        all-sensor part, of the whole average with the selected structure fixed.
    baseline_cv_rms_um : float
        Blocked-CV RMS of the intercept-only model (µm): what selection started from.
    n_train : int
        Number of training rows.
    n_blocks : int
        Number of contiguous CV blocks.
    steps : tuple of SelectionStep
        The selection path, for reports.
    selected : tuple of ThermalTerm
        The terms the forward selection chose (``terms`` also holds the all-sensor part's
        levels and lags when it joined).
    dense_taus_s : tuple of float
        Time constants (s) of the all-sensor part; empty when it did not join.
    shrinkage : float
        Ridge penalty λ (per training row, on standardised columns) the coefficients
        were fitted with (:func:`~volumetric.identify.thermal.plain.fit_all_sensors`);
        0 for ordinary least squares.
    """

    terms: tuple[ThermalTerm, ...]
    intercept_um: float
    coef: F64
    intercept_u_um: float
    coef_u: F64
    t0_s: float
    train_rms_um: float
    cv_rms_um: float
    baseline_cv_rms_um: float
    n_train: int
    n_blocks: int
    steps: tuple[SelectionStep, ...]
    selected: tuple[ThermalTerm, ...] = ()
    dense_taus_s: tuple[float, ...] = ()
    shrinkage: float = 0.0

    @property
    def names(self) -> list[str]:
        """Column names of the selected terms."""
        return [term.name for term in self.terms]

    def design(self, t_s: ArrayLike, temps: Mapping[str, ArrayLike],
               inputs: Mapping[str, ArrayLike] | None = None) -> F64:
        """The selected columns over a time series, shape (N, p).

        Lags start at rest at ``t_s[0]``, so pass the history that precedes the rows of
        interest (the same series the model was fitted on, extended), not a lone excerpt.
        """
        signals = merge_signals(temps, inputs)
        t = _as_time(t_s)
        if not self.terms:
            return np.zeros((t.shape[0], 0))
        return np.column_stack([term.column(t, signals, self.t0_s) for term in self.terms])

    def predict(self, t_s: ArrayLike, temps: Mapping[str, ArrayLike],
                inputs: Mapping[str, ArrayLike] | None = None) -> F64:
        """Predicted drift (µm), shape (N,), over the series ``t_s`` (s) with temperatures
        ``temps`` (°C, each shape (N,)) and the extra ``inputs`` the model uses, if any."""
        return self.intercept_um + self.design(t_s, temps, inputs) @ self.coef
