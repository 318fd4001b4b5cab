"""The weighted compensation solver against the first seed (Eq. 24a, Tables 1 and 2)."""

from __future__ import annotations

import numpy as np
import pytest
from numpy.typing import NDArray

from tests.support.compensate import realistic_arch_errors
from tests.support.kinematics import arch, machine, random_errors, random_q
from volumetric.compensate.solver import Compensation, CompensationError, Weights, compensate
from volumetric.model.components import GeometricErrors, Polynomial
from volumetric.model.exact import volumetric_error
from volumetric.model.linear import jacobian
from volumetric.model.machine import Machine

F64 = NDArray[np.float64]


def workspace_grid(m: Machine, n: int = 7) -> F64:
    """The seed's measured workspace, x 10..500, y 10..290, z1 = z2 -300..-10 (the two
    spindles move together here, as the seed evaluates both tips at one z)."""
    x, y, z = np.meshgrid(np.linspace(10, 500, n), np.linspace(10, 290, n),
                          np.linspace(-300, -10, n), indexing="ij")
    return np.column_stack([x.ravel(), y.ravel(), z.ravel(), z.ravel()])


# --- reduction to the textbook cases ---

def test_three_axis_machine_reduces_to_minus_the_error() -> None:
    m = machine("w X Y b Z t")
    rng = np.random.default_rng(5)
    e = random_errors(m, rng, 10.0)
    q = random_q(m, rng, 300)
    c = compensate(m, e, q)
    assert c, c.message
    # the fixed point: the correction is minus the error at the compensated command
    at_corrected = volumetric_error(m, e, q + c.dq).position_um
    np.testing.assert_allclose(c.dq, -at_corrected / 1e3, atol=1e-9)
    assert np.abs(c.residual_um).max() < 1e-6
    assert (c.rank == 3).all()
    # and minus the error at the command itself, up to a second-order gap (e's slope
    # times dq): half the errors, a quarter of the gap
    before = volumetric_error(m, e, q).position_um
    assert np.abs(before).max() > 20.0
    gap = np.abs(c.dq + before / 1e3).max()
    half = scaled(e, 0.5)
    c2 = compensate(m, half, q)
    gap2 = np.abs(c2.dq + volumetric_error(m, half, q).position_um / 1e3).max()
    assert 3.0 < gap / gap2 < 5.0


def scaled(e: GeometricErrors, k: float) -> GeometricErrors:
    comps = {}
    for name, f in e.components.items():
        assert isinstance(f, Polynomial)
        comps[name] = Polynomial(tuple(k * c for c in f.coefficients), f.origin, f.scale)
    return GeometricErrors(comps, {n: k * v for n, v in e.locations.items()})


def test_unobservable_axis_gets_zero_not_nan() -> None:
    # spindle 2 weighs nothing: z2 moves only tool 2, so its column of W½J is zero
    m = arch(0.0, 30.0)
    rng = np.random.default_rng(8)
    e = realistic_arch_errors(m, rng)
    q = random_q(m, rng, 200)
    c = compensate(m, e, q, weights=Weights.parse(m, [1, 1, 1, 0, 0, 0]))
    assert c, c.message
    assert np.all(np.isfinite(c.dq))
    assert np.all(c.dq[:, 3] == 0.0)
    assert (c.rank == 3).all()
    assert np.abs(c.residual_um[0]).max() < 1e-6  # spindle 1 alone is fully correctable


# --- the seed's Eq. 24a, typed in from Eq. 23 ---

def seed_eq24a(theta1_deg: float, theta2_deg: float, w: F64, p: F64) -> F64:
    """C_act = (Tᵀ W T)⁻¹ Tᵀ W C_ref with C_ref = -P, one point at a time.

    ``p`` (N, 6) is P of Eq. 19, ``[Px1 Py1 Pz1 Px2 Py2 Pz2]`` in µm, in this project's
    sign convention (the tool's error relative to the workpiece: see the docstring of
    ``test_arch_machine_px1_agrees_with_seed_eq17_to_first_order``); the result is in µm
    of actuator motion, columns ``x, y, z1, z2``.
    """
    s1, c1 = np.sin(np.deg2rad(theta1_deg)), np.cos(np.deg2rad(theta1_deg))
    s2, c2 = np.sin(np.deg2rad(theta2_deg)), np.cos(np.deg2rad(theta2_deg))
    t = np.array([  # Eq. 23
        [1, 0, 0, 0],
        [0, 1, -s1, 0],
        [0, 0, c1, 0],
        [1, 0, 0, 0],
        [0, 1, 0, -s2],
        [0, 0, 0, c2],
    ])
    wm = np.diag(w)  # Eq. 24b
    out = np.empty((p.shape[0], 4))
    for i, row in enumerate(p):
        c_ref = -row  # Eq. 20
        out[i] = np.linalg.solve(t.T @ wm @ t, t.T @ wm @ c_ref)  # Eq. 24a
    return out


@pytest.mark.parametrize("weights", [
    [1, 1, 1, 1, 1, 1], [10, 10, 10, 1, 1, 1], [1, 1, 1, 10, 10, 10], [3, 0.5, 2, 1, 7, 0.2],
])
def test_arch_machine_agrees_with_seed_eq24a(weights: list[float]) -> None:
    theta1, theta2 = 10.0, 35.0
    m = arch(theta1, theta2)
    rng = np.random.default_rng(24)
    e = realistic_arch_errors(m, rng)
    q = random_q(m, rng, 60)
    w = Weights.parse(m, weights)
    p = np.hstack([volumetric_error(m, e, q, spindle=s).position_um for s in ("S1", "S2")])
    want_um = seed_eq24a(theta1, theta2, np.array(weights, dtype=float), p)
    # one solve is Eq. 24a exactly
    first = compensate(m, e, q, weights=w, max_iterations=1)
    np.testing.assert_allclose(first.dq * 1e3, want_um, atol=1e-9)
    # the refinement at q + dq moves it only by the error's change over dq (≲ 0.01 µm)
    refined = compensate(m, e, q, weights=w)
    assert refined, refined.message
    assert 2 <= refined.iterations <= 4
    gap = np.abs(refined.dq * 1e3 - want_um).max()
    assert 0.0 < gap < 0.05
    assert np.abs(want_um).max() > 10.0  # the corrections themselves are tens of µm


# --- the seed's Tables 1 and 2: coupling and the weights that share it ---

def max_abs(c: Compensation) -> F64:
    return c.max_residual_um()


def test_arch_machine_reproduces_the_behaviour_of_tables_1_and_2() -> None:
    m = arch(0.0, 30.0)  # θ1 = 0 as in the seed's model
    e = realistic_arch_errors(m, np.random.default_rng(2006))
    q = workspace_grid(m)
    cases = {
        "S1 only": [1, 1, 1, 0, 0, 0],
        "S2 only": [0, 0, 0, 1, 1, 1],
        "equal": [1, 1, 1, 1, 1, 1],
        "S1 x10": [10, 10, 10, 1, 1, 1],
        "S2 x10": [1, 1, 1, 10, 10, 10],
    }
    res = {k: compensate(m, e, q, weights=Weights.parse(m, w)) for k, w in cases.items()}
    for k, c in res.items():
        assert c, f"{k}: {c.message}"
    before = res["equal"].max_error_um()
    lines = ["max |error| µm (x, y, z)      spindle 1               spindle 2",
             f"{'before':<22} {_fmt(before[0])}   {_fmt(before[1])}"]
    lines += [f"{k:<22} {_fmt(max_abs(c)[0])}   {_fmt(max_abs(c)[1])}" for k, c in res.items()]
    print("\n" + "\n".join(lines))
    assert before.max() > 30.0

    worst = {k: max_abs(c).max(axis=1) for k, c in res.items()}  # per spindle, over x y z
    # Table 1: compensating one spindle alone leaves the other large
    assert worst["S1 only"][1] >= 5 * worst["S1 only"][0]
    assert worst["S2 only"][0] >= 5 * worst["S2 only"][1]
    assert worst["S1 only"][1] > 10.0 and worst["S2 only"][0] > 10.0
    # the shared x axis cannot serve both: their x errors end up equal and opposite
    c = res["equal"]
    np.testing.assert_allclose(c.residual_um[0, :, 0], -c.residual_um[1, :, 0], atol=1e-6)
    # Table 2, case 1: equal weights balance both spindles, each better than uncompensated
    assert 0.5 < worst["equal"][0] / worst["equal"][1] < 2.0
    assert np.all(worst["equal"] < before.max(axis=1))
    # and minimise the total squared residual among all weightings
    total = {k: float((c.residual_um**2).sum()) for k, c in res.items()}
    assert all(total["equal"] <= t * (1 + 1e-9) for t in total.values())
    # cases 2 and 3: ten times the weight shifts the residual to the other spindle
    assert worst["S1 x10"][0] < 0.5 * worst["equal"][0]
    assert worst["S1 x10"][1] > worst["equal"][1]
    assert worst["S1 x10"][0] < worst["S1 x10"][1]
    assert worst["S2 x10"][1] < 0.5 * worst["equal"][1]
    assert worst["S2 x10"][0] > worst["equal"][0]
    assert worst["S2 x10"][1] < worst["S2 x10"][0]


def _fmt(v: F64) -> str:
    return " ".join(f"{x:7.2f}" for x in v)


# --- orientation rows ---

def test_orientation_weights_let_rotary_axes_fix_the_tool_orientation() -> None:
    m = machine("w C A X Y b Z t", pivots_mm={"A": [0.0, 0.0, 50.0]})
    rng = np.random.default_rng(12)
    e = random_errors(m, rng, 10.0)
    q = random_q(m, rng, 400)
    pos_only = compensate(m, e, q, weights=Weights.parse(m, [1, 1, 1]))
    both = compensate(m, e, q, weights=Weights.parse(m, [1, 1, 1, 1, 1, 1]))
    assert pos_only and both
    assert np.abs(pos_only.residual_um).max() < 1e-5
    assert np.abs(both.residual_um).max() < 1e-5  # X Y Z still fix the position
    assert both.residual_urad is not None and both.error_urad is not None
    before = np.linalg.norm(both.error_urad, axis=2)
    after = np.linalg.norm(both.residual_urad, axis=2)
    assert np.all(after <= before + 1e-6)
    assert (after < before - 1.0).mean() > 0.9
    # five axes fix at most two of three orientation components (rank 5 of 6 rows); what
    # is left is orthogonal to what the rotary axes can turn (the normal equations)
    assert (both.rank == 5).all()
    turn = jacobian(m, q)[:, 3:, :2]  # orientation µrad per degree of C and A
    dots = np.einsum("ni,nik->nk", both.residual_urad[0], turn)
    scale = np.linalg.norm(turn, axis=1) * after[0][:, None]
    assert np.all(np.abs(dots) <= 1e-6 * scale + 1e-9)


# --- bad input and non-convergence ---

def test_weights_of_the_wrong_length_are_refused_with_what_is_expected() -> None:
    m = arch()
    with pytest.raises(CompensationError, match=r"2 tool tip\(s\) \(S1 S2\); give 6 .* or 12"):
        Weights.parse(m, [1, 1, 1, 10])
    with pytest.raises(CompensationError, match=r"value 2 \(-1.0\)"):
        Weights.parse(m, [1, -1, 1, 1, 1, 1])
    with pytest.raises(CompensationError, match="finite"):
        Weights.parse(m, [1, float("nan"), 1, 1, 1, 1])
    with pytest.raises(CompensationError, match="all weights are zero"):
        Weights.parse(m, [0] * 6)
    with pytest.raises(CompensationError, match="for 1 tool tips"):
        compensate(m, GeometricErrors(), np.zeros((1, 4)),
                   weights=Weights.parse(machine("w X Y b Z t"), [1, 1, 1]))


def test_a_refinement_cut_short_is_falsy_with_a_message() -> None:
    m = machine("w X Y b Z t")
    e = GeometricErrors({"EXX": Polynomial((5.0, 0.02))})
    c = compensate(m, e, random_q(m, np.random.default_rng(0), 10), max_iterations=1)
    assert not c
    assert "not converged" in c.message
