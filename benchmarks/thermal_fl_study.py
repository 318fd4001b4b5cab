"""Which thermal-drift model predicts a held-out block of a real spindle test?

Data: ``shared/data/fl_thermal_ch3_measurements.csv`` (FL_THERMAL, MIT): a 46 h spindle test,
15 s sampling, drift of channel ch3 along the tool axis (µm), 16 temperatures (°C), spindle
speed. Heat/cool cycles until t = 144 000 s, then a variable-speed block. Every model is fitted
on t < 144 000 s, with every choice (time constants, sensors, penalties, number of terms) made
from those rows alone, and judged once on t >= 144 000 s.

Run: ``.venv/bin/python benchmarks/thermal_fl_study.py`` (about 30 s). Prints one table row per
model: number of columns, training RMS, blocked-CV RMS where the model was chosen by it, and
the held-out RMS; then the automated procedure's path, coefficients and run time.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from volumetric.identify.thermal import (
    DEFAULT_TAUS_S,
    ThermalDriftModel,
    fit_thermal_drift,
    thermal_regressors,
)
from volumetric.measure.measurement import read_measurements

F64 = NDArray[np.float64]
DATA = Path(__file__).resolve().parents[2] / "shared" / "data" / "fl_thermal_ch3_measurements.csv"
SPLIT_S = 144_000.0
N_BLOCKS = 5


def rms(r: F64) -> float:
    return float(np.sqrt(np.mean(r**2)))


def blocks_of(n: int, k: int = N_BLOCKS) -> NDArray[np.intp]:
    return (np.arange(n) * k) // n


def ols(X: F64, y: F64, train: NDArray[np.bool_], intercept: bool = True) -> tuple[F64, F64]:
    """Fitted values over all rows and the coefficients (OLS on the training rows)."""
    A = np.column_stack([np.ones(X.shape[0]), X]) if intercept else X
    c = np.linalg.lstsq(A[train], y[train], rcond=None)[0]
    return A @ c, c


def ridge_predictor(X: F64, y: F64, lam: float) -> Callable[[F64], F64]:
    """Ridge on standardised columns, unpenalised intercept; λ per row (scale-free)."""
    mu, sd = X.mean(axis=0), X.std(axis=0)
    sd[sd == 0] = 1.0
    Z = (X - mu) / sd
    ym = y.mean()
    c = np.linalg.solve(Z.T @ Z + lam * X.shape[0] * np.eye(X.shape[1]), Z.T @ (y - ym))
    return lambda Xn: ym + ((Xn - mu) / sd) @ c


def pls_predictor(X: F64, y: F64, ncomp: int) -> Callable[[F64], F64]:
    """PLS1 (NIPALS) on standardised columns."""
    mu, sd = X.mean(axis=0), X.std(axis=0)
    sd[sd == 0] = 1.0
    Z = (X - mu) / sd
    ym = y.mean()
    r = y - ym
    W, P, q = [], [], []
    for _ in range(ncomp):
        w = Z.T @ r
        w /= np.linalg.norm(w)
        s = Z @ w
        p = Z.T @ s / (s @ s)
        qa = r @ s / (s @ s)
        Z = Z - np.outer(s, p)
        r = r - qa * s
        W.append(w)
        P.append(p)
        q.append(qa)
    Wm, Pm = np.array(W).T, np.array(P).T
    b = Wm @ np.linalg.solve(Pm.T @ Wm, np.array(q))
    return lambda Xn: ym + ((Xn - mu) / sd) @ b


def blocked_cv(fit: Callable[[F64, F64], Callable[[F64], F64]], X: F64, y: F64) -> float:
    """Leave-one-block-out RMS over contiguous blocks of the training rows."""
    blocks = blocks_of(X.shape[0])
    sse = 0.0
    for b in range(N_BLOCKS):
        m = blocks != b
        sse += float(np.sum((y[~m] - fit(X[m], y[m])(X[~m])) ** 2))
    return float(np.sqrt(sse / X.shape[0]))


def sparse_readings(t: F64, temps: dict[str, F64], y: F64) -> None:
    """Held-out RMS when only some readings exist: every k-th row at five phases, and
    random rows (mean spacing 150 s) with three 2 h gaps, as a campaign would give."""
    T = np.column_stack(list(temps.values()))

    def both(rows: NDArray[np.intp]) -> tuple[float, float]:
        ts, ys = t[rows], y[rows]
        sub = {k: v[rows] for k, v in temps.items()}
        train = ts < SPLIT_S
        model = fit_thermal_drift(ts, sub, ys, train)
        static, _ = ols(T[rows], ys, train)
        return (rms((ys - model.predict(ts, sub))[~train]), rms((ys - static)[~train]))

    print("\nsparse readings: held-out RMS (µm), automated dynamic model / static model")
    for k in (20, 40, 80):
        cells = [both(np.arange(phase * k // 5, t.shape[0], k)) for phase in range(5)]
        text = "  ".join(f"{d:5.2f}/{s_:5.2f}" for d, s_ in cells)
        print(f"  every {k:2d}th row ({15 * k // 60:2d} min), 5 phases: {text}")
    cells = []
    for seed in range(5):
        rng = np.random.default_rng(seed)
        keep = rng.random(t.shape[0]) < 0.1
        for start in rng.uniform(0.0, t[-1], 3):
            keep &= ~((t > start) & (t < start + 7200.0))
        cells.append(both(np.flatnonzero(keep)))
    text = "  ".join(f"{d:5.2f}/{s_:5.2f}" for d, s_ in cells)
    print(f"  random 10 % of rows + three 2 h gaps, 5 seeds: {text}")


def main() -> int:
    if not DATA.is_file():
        print(f"missing {DATA}", file=sys.stderr)
        return 2
    m = read_measurements(DATA)
    t, y = m.time_s, m.value
    temps = {col: m.temperatures[s] for s, col in m.temperature_columns.items()}
    rpm = {"spindle_rpm": m.extra["spindle_rpm"]}
    train = t < SPLIT_S
    held = ~train
    T = np.column_stack(list(temps.values()))
    rows: list[tuple[str, int, float, float | None, float]] = []
    chosen: dict[str, str] = {}

    def add(name: str, pred: F64, ncols: int, cv: float | None = None) -> None:
        rows.append((name, ncols, rms((y - pred)[train]), cv, rms((y - pred)[held])))

    # --- baselines of the issue
    add("no thermal model (drift itself)", np.zeros_like(y), 0)
    pred, _ = ols(T, y, train)
    add("static: 16 temperatures + intercept (OLS)", pred, 17)
    pred, _ = ols(T, y, train, intercept=False)
    add("static: 16 absolute temperatures, no intercept", pred, 16)
    pred, _ = ols(T - T[0], y, train, intercept=False)
    add("static: 16 temperature changes, no intercept", pred, 16)

    # --- one lag per sensor with a common τ, OLS (the 'lagged static model')
    for tau in (900.0, 3600.0, 14400.0):
        X, _ = thermal_regressors(t, temps, taus_s=(tau,))
        pred, _ = ols(X, y, train)
        add(f"16 levels + 16 lags τ={tau:.0f} s (OLS)", pred, X.shape[1] + 1)

    # --- everything at once: levels and ten lags of every sensor
    X_all, _ = thermal_regressors(t, temps)
    pred, _ = ols(X_all, y, train)
    add("16 levels + 160 lags (OLS, no selection)", pred, X_all.shape[1] + 1)

    # --- ridge and PLS on everything, penalty / components by blocked CV
    lams = 10.0 ** np.arange(-8.0, 1.0)
    cvs = [blocked_cv(lambda A, b, lam=lam: ridge_predictor(A, b, lam), X_all[train], y[train])
           for lam in lams]
    lam = float(lams[int(np.argmin(cvs))])
    add(f"ridge on all 176, λ={lam:.0e} by blocked CV", ridge_predictor(
        X_all[train], y[train], lam)(X_all), X_all.shape[1] + 1, min(cvs))
    comps = range(1, 13)
    cvs = [blocked_cv(lambda A, b, a=a: pls_predictor(A, b, a), X_all[train], y[train])
           for a in comps]
    a_best = comps[int(np.argmin(cvs))]
    add(f"PLS on all 176, {a_best} components by blocked CV", pls_predictor(
        X_all[train], y[train], a_best)(X_all), a_best + 1, min(cvs))

    # --- forward selection variants
    def fs(name: str, **kw: object) -> ThermalDriftModel:
        model = fit_thermal_drift(t, temps, y, train, **kw)  # type: ignore[arg-type]
        inputs = kw.get("inputs")
        pred = model.predict(t, temps, inputs)  # type: ignore[arg-type]
        add(name, pred, len(model.terms) + 1, model.cv_rms_um)
        chosen[name] = ", ".join(model.names) or "(intercept only)"
        return model

    fs("forward, min-CV stopping", stopping="min-cv")
    fs("forward, 1-SE on absolute block gains", stopping="1se-abs")
    for k in (3, 4, 6, 8, 10):
        fs(f"forward, 1-SE absolute, {k} CV blocks", stopping="1se-abs", n_blocks=k)
    fs("forward, grid τ only (no refinement)", refine_tau=False)
    fs("forward, τ grid 900 s·4^k, no refinement", refine_tau=False,
       taus_s=tuple(900.0 * 4.0**k for k in range(5)))
    fs("forward, τ grid 900 s·4^k, refined", taus_s=tuple(900.0 * 4.0**k for k in range(5)))
    for k in (3, 4, 6, 8, 10):
        fs(f"forward, {k} CV blocks", n_blocks=k)
    fs("forward, spindle_rpm offered", inputs=rpm)
    start = time.perf_counter()
    auto = fs("AUTOMATED (default: 5 blocks, 1-SE + BIC)")
    elapsed = time.perf_counter() - start

    width = max(len(r[0]) for r in rows)
    print(f"fit on t < {SPLIT_S:.0f} s ({int(train.sum())} rows), held out t >= "
          f"{SPLIT_S:.0f} s ({int(held.sum())} rows); RMS in µm")
    print(f"{'model':<{width}}  {'cols':>4}  {'train':>6}  {'CV':>6}  {'held-out':>8}")
    for name, ncols, tr, cv, te in rows:
        cv_text = f"{cv:6.2f}" if cv is not None else "     -"
        print(f"{name:<{width}}  {ncols:4d}  {tr:6.2f}  {cv_text}  {te:8.2f}")
        if name in chosen:
            print(f"    {chosen[name]}")

    print("\nautomated procedure: selection path (CV-MSE gain in µm²; relative gain = mean "
          "over blocks of ln(SSE before/after) ± its standard error)")
    print(f"  intercept only: CV RMS {auto.baseline_cv_rms_um:.2f} µm")
    for step in auto.steps:
        verdict = "joins" if step.accepted else "rejected, stop"
        print(f"  {step.term.name:<26} CV RMS {step.cv_rms_um:6.2f}  gain {step.gain_um2:8.3f}  "
              f"relative {step.log_gain_mean:6.3f} ± {step.log_gain_se:5.3f}  {verdict}")
    print("  coefficients (± block-jackknife standard uncertainty):")
    print(f"    intercept                  {auto.intercept_um:9.2f} ± {auto.intercept_u_um:.2f} µm")
    for term, c, u in zip(auto.terms, auto.coef, auto.coef_u, strict=True):
        unit = {"time": "µm/h", "level": "µm/K", "lag": "µm/K"}[term.kind]
        if term.source not in temps and term.kind != "time":
            unit = f"µm per unit of {term.source}"
        print(f"    {term.name:<26} {c:9.3f} ± {u:.3f} {unit}")
    print(f"  fit + selection time: {elapsed:.2f} s (11 115 rows, 16 sensors, "
          f"{len(DEFAULT_TAUS_S)} time constants)")
    sparse_readings(t, temps, y)
    return 0


if __name__ == "__main__":
    sys.exit(main())
