"""A thermal drift and a thermal expansion on one axis (issue 33): both named with their
own sensors and sizes, estimated jointly, the correlation of the two estimates reported.

The cases are simulated campaigns (standard campaign, noise twice the usual) whose pair
main before issue 33 got wrong: the sensors swapped between the two effects (a drift on
the y screw and an expansion on the column came out as an expansion on the y screw and
a drift on the column, each with the other's size), and a drift on the y screw beside
a column expansion named on the spindle's sensor at a fifth of its size, the expansion
left out; a drift and an expansion of opposite signs, which cancel over the middle of
the travel, named as nothing at all; a drift on the x screw beside an expansion of the y
screw named as a drift and an expansion both on the y screw (issue 33's fix, the pair on
two sensors kept within the tie). ``benchmarks/diagnosis_hit_rate.py --thermal-pairs``
runs such pairs by the dozen.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from machine_sim.campaign import standard_campaign
from machine_sim.effects import Effects, Noise, ThermalDrift, ThermalExpansion
from machine_sim.instruments import SimulatedMachine
from machine_sim.truth import random_geometry
from volumetric.diagnose.candidates import Candidate
from volumetric.diagnose.diagnosis import diagnose
from volumetric.diagnose.gates import TIE
from volumetric.diagnose.joint import best_pair, joint_fit
from volumetric.diagnose.text import effects_text
from volumetric.model.machine import Machine, parse_machine
from volumetric.model.model import ThermalTerm

CASES = {
    # seed: chain, axis, drift (sensor, µm/K), expansion (sensor, µm/(m K))
    1: ("w b Y X Z t", "y", ("y_screw", 2.1), ("column", 6.5)),
    11: ("w X b Y Z t", "y", ("y_screw", -1.6), ("column", 7.0)),
    # opposite signs: over the middle of the travel they cancel, neither passes alone
    26: ("w X b Y Z t", "x", ("z_screw", -3.0), ("y_screw", 7.5)),
    # two screws that follow the same air: the pair on the expansion's sensor alone won by
    # the sensors' reading noise and named the drift on the y screw too (before best_pair)
    41: ("w Y b X Z t", "z", ("x_screw", -1.0), ("y_screw", 6.0)),
}


def machine_for(chain: str) -> Machine:
    return parse_machine({"name": "m", "chain": chain, "tool_length_mm": 100.0,
                          "travel_mm": {"x": [0, 800], "y": [0, 600], "z": [-500, 0]}})


def entry(effects: list[dict[str, Any]], effect: str, axis: str) -> dict[str, Any]:
    found = [e for e in effects if (e["effect"], e["axis"]) == (effect, axis)]
    assert len(found) == 1, effects
    return found[0]


@pytest.mark.parametrize("seed", sorted(CASES))
def test_a_drift_and_an_expansion_on_one_axis_each_get_their_own_size(seed: int) -> None:
    chain, axis, (ds, k), (es, alpha) = CASES[seed]
    m = machine_for(chain)
    rng = np.random.default_rng(8300 + seed)
    eff = Effects(drift=(ThermalDrift(axis, ds, k),),
                  expansion=(ThermalExpansion(axis, es, alpha),), noise=Noise(0.5, 0.8))
    sim = SimulatedMachine(m, random_geometry(m, rng), eff, seed=seed)
    d = diagnose(m, standard_campaign(sim, rng))
    effects = d.to_json()["effects"]
    drift = entry(effects, "thermal_drift", axis)
    expansion = entry(effects, "thermal_expansion", axis)
    assert drift["sensor"] == f"T_{ds}_C" and expansion["sensor"] == f"T_{es}_C"
    assert drift["estimate"]["um_per_K"] == pytest.approx(k, rel=0.3)
    assert expansion["estimate"]["um_per_m_K"] == pytest.approx(alpha, rel=0.3)
    # the joint fit's correlation of the two estimates, reported both ways
    r = drift["correlation"][0]["r"]
    assert drift["correlation"] == [{"effect": "thermal_expansion", "axis": axis,
                                     "sensor": f"T_{es}_C", "r": r}]
    assert expansion["correlation"][0]["r"] == r and -1.0 < r < 1.0
    said = "\n".join(effects_text(d))
    assert f"estimated jointly with thermal_expansion {axis} T_{es}_C" in said
    # the saved model carries both terms with the reported sizes
    terms = {(t.kind, t.sensor): t for t in d.model.terms if isinstance(t, ThermalTerm)}
    assert terms[("thermal_drift", f"T_{ds}_C")].coefficient == pytest.approx(
        drift["estimate"]["um_per_K"])
    assert terms[("thermal_expansion", f"T_{es}_C")].coefficient == pytest.approx(
        expansion["estimate"]["um_per_m_K"])


def test_joint_fit_gives_the_least_squares_covariance_and_correlation() -> None:
    """Two extension columns beside a base: the coefficients and their correlation are
    those of ``(AᵀWA)⁻¹`` scaled by the residual variance."""
    rng = np.random.default_rng(0)
    n = 400
    a0 = np.column_stack((np.ones(n), rng.normal(size=n)))
    t = rng.normal(size=n)
    q = rng.uniform(0, 1, n)
    c1 = Candidate("thermal_drift", "x", "T_a_C", t[:, None])
    c2 = Candidate("thermal_expansion", "x", "T_a_C", (t * q)[:, None])
    y = a0 @ [1.0, 2.0] + 3.0 * t + 5.0 * t * q + rng.normal(scale=0.1, size=n)
    w = np.full(n, 4.0)
    train = np.ones(n, dtype=bool)
    fit = joint_fit(a0, w, y, train, [c1, c2])
    a = np.column_stack((a0, t, t * q))
    g = a.T @ (a * w[:, None])
    x = np.linalg.solve(g, (a * w[:, None]).T @ y)
    r = y - a @ x
    cov = np.linalg.inv(g) * float(np.sum(w * r * r) / (n - 4))
    assert fit.coef(0) == pytest.approx(x[2:3]) and fit.coef(1) == pytest.approx(x[3:4])
    assert fit.std(1) == pytest.approx(np.sqrt(cov[3:4, 3]))
    assert fit.correlation(0, 1) == pytest.approx(cov[2, 3] / np.sqrt(cov[2, 2] * cov[3, 3]))
    assert fit.correlation(0, 1) < -0.5  # t and t·q overlap by q's mean


def test_a_pair_on_one_sensor_gives_way_to_two_sensors_within_the_tie() -> None:
    """A drift and an expansion read from one sensor are one body's growth about another
    fixed point: a pair on two sensors within ``TIE`` of it is judged instead; one that
    beats every two-sensor pair by more than the tie is kept."""
    col = np.zeros((4, 1))
    r = np.zeros(4)

    def cand(effect: str, sensor: str) -> Candidate:
        return Candidate(effect, "z", f"T_{sensor}_C", col)

    d_y, d_x = cand("thermal_drift", "y_screw"), cand("thermal_drift", "x_screw")
    e_y, e_x = cand("thermal_expansion", "y_screw"), cand("thermal_expansion", "x_screw")
    near = [(0.2938, d_y, e_y, r), (0.2953, d_x, e_y, r)]
    assert best_pair(near)[1] is d_x
    far = [(0.2938, d_y, e_y, r), (0.2938 * (1 + TIE) * 1.01, d_x, e_y, r)]
    assert best_pair(far)[1] is d_y
    # only pairs on one sensor: the best of them
    assert best_pair([(0.5, d_x, e_x, r), (0.3, d_y, e_y, r)])[0] == 0.3
