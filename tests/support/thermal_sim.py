"""A simulated spindle whose growth is a known lagged function of its temperatures: the
truth against which the dynamic thermal model and the saved model's forward prediction are
checked (tests/test_predict.py, tests/test_thermal_fl.py)."""

from __future__ import annotations

import numpy as np

from volumetric.measure.measurement import Measurements
from volumetric.model.lag import first_order_lag

NOISE_UM = 0.3
"""Standard deviation of the simulated readings' noise (µm)."""
TRUE_LAGS = {"T_a_C": (3000.0, -5.0), "T_d_C": (20_000.0, 3.0)}
"""The growth's true terms: sensor column -> (time constant s, coefficient µm/K)."""


def lagged_spindle(seed: int) -> Measurements:
    """40 h of a simulated spindle at a fixed point, read every minute along z (µm).

    Heat cycles of random power (3 h on, 3 h off) reach sensors a, b and c through lags of
    0.5 h, 2 h and 10 min; d follows the ambient's daily swing; every sensor has 0.02 K of
    noise. The growth follows a through a 3000 s lag (-5 µm/K) and d through a 20 000 s lag
    (+3 µm/K) (:data:`TRUE_LAGS`), zero at the start, plus :data:`NOISE_UM` of noise.
    """
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 40 * 3600.0, 60.0)
    power = np.zeros(t.size)
    for start in range(0, t.size, 360):
        if (start // 360) % 2 == 0:
            power[start:start + 180] = rng.uniform(0.3, 1.0)
    ambient = 0.5 * np.sin(2 * np.pi * t / 86_400.0 + rng.uniform(0.0, 6.0))
    temps = {"a": 22 + ambient + 6 * first_order_lag(t, power, 1800.0),
             "b": 22 + ambient + 3 * first_order_lag(t, power, 7200.0),
             "c": 22 + ambient + 0.5 * first_order_lag(t, power, 600.0),
             "d": 22 + 1.2 * ambient}
    temps = {k: v + rng.normal(0.0, 0.02, t.size) for k, v in temps.items()}
    growth = sum(coef * first_order_lag(t, temps[col[2:-2]], tau)
                 for col, (tau, coef) in TRUE_LAGS.items())
    n = t.size
    return Measurements(
        test=np.full(n, "spindle-thermal"), run=np.zeros(n, np.int64), time_s=t,
        q=np.zeros((n, 6)), direction=np.zeros((n, 3), np.int8), tool_mm=np.zeros(n),
        is_angle=np.zeros(n, bool), u=np.tile([0.0, 0.0, 1.0], (n, 1)),
        value=growth - growth[0] + rng.normal(0.0, NOISE_UM, n),
        temperatures=temps, temperature_columns={k: f"T_{k}_C" for k in temps})
