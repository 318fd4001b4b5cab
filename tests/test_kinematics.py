"""The volumetric error model against an independent oracle, physics and the seed's Eq. 17."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from tests.support.kinematics import arch, machine, naive_pose, random_errors, random_q
from volumetric.errors import ComponentErrorSpecError
from volumetric.model.components import (
    GeometricErrors,
    Polynomial,
    Table,
)
from volumetric.model.exact import volumetric_error
from volumetric.model.linear import linear_volumetric_error

# --- the oracle: one 4x4 product per point, written from the link table, scipy rotations ---


CHAINS = [
    "w X Y b Z t",
    "w b Y X Z t",
    "w Y b X Z t",
    "w C A X Y b Z t",
    "w C Y b X Z B t",
    "w b X Y Z C A t",
    "w Z b X Y A t",
]


@pytest.mark.parametrize("chain", CHAINS)
@pytest.mark.parametrize("size", [3.0, 3000.0])
def test_exact_error_matches_naive_product_per_point(chain: str, size: float) -> None:
    # size 3000 µm/µrad per coefficient: far outside first order, so only an exact model agrees
    rng = np.random.default_rng(7)
    m = machine(chain, pivots_mm={k: [20.0, -15.0, 40.0] for k in "ABC" if k in chain})
    e = random_errors(m, rng, size)
    q = random_q(m, rng, 40)
    got = volumetric_error(m, e, q)
    assert got.orientation_urad is not None
    for i in range(len(q)):
        act = naive_pose(m, e, q[i])
        nom = naive_pose(m, None, q[i])
        want_p = (act[:3, 3] - nom[:3, 3]) * 1e3
        want_w = Rotation.from_matrix(act[:3, :3] @ nom[:3, :3].T).as_rotvec() * 1e6
        np.testing.assert_allclose(got.position_um[i], want_p, atol=1e-7 * max(1, size))
        np.testing.assert_allclose(got.orientation_urad[i], want_w, atol=1e-7 * max(1, size))


@pytest.mark.parametrize("spindle", ["S1", "S2"])
def test_arch_machine_matches_naive_product(spindle: str) -> None:
    rng = np.random.default_rng(3)
    m = arch(5.0, 30.0)
    e = random_errors(m, rng, 5.0)
    q = random_q(m, rng, 30)
    got = volumetric_error(m, e, q, spindle=spindle).position_um
    for i in range(len(q)):
        want = (naive_pose(m, e, q[i], spindle)[:3, 3] - naive_pose(m, None, q[i], spindle)[:3, 3])
        np.testing.assert_allclose(got[i], want * 1e3, atol=1e-8)


@pytest.mark.parametrize("chain", CHAINS)
def test_first_order_form_agrees_with_exact_for_small_errors(chain: str) -> None:
    rng = np.random.default_rng(11)
    m = machine(chain, pivots_mm={k: [20.0, -15.0, 40.0] for k in "ABC" if k in chain})
    e = random_errors(m, rng, 10.0)  # tens of µm and µrad: realistic
    q = random_q(m, rng, 500)
    exact = volumetric_error(m, e, q)
    lin = linear_volumetric_error(m, e, q)
    assert np.abs(exact.position_um).max() > 20.0  # the errors are not trivially small
    # second-order terms: ε² × arm ≈ (1e-4)² × 1e3 mm ≈ 1e-5 mm = 0.01 µm at most
    np.testing.assert_allclose(lin.position_um, exact.position_um, atol=0.02)
    assert lin.orientation_urad is not None and exact.orientation_urad is not None
    np.testing.assert_allclose(lin.orientation_urad, exact.orientation_urad, atol=0.02)
    # and the difference really is second order: 10x smaller errors, 100x smaller gap
    e10 = GeometricErrors(
        {k: Polynomial(tuple(c / 10 for c in v.coefficients), v.origin, v.scale)
         for k, v in e.components.items() if isinstance(v, Polynomial)},
        {k: v / 10 for k, v in e.locations.items()},
    )
    gap = np.abs(lin.position_um - exact.position_um).max()
    gap10 = np.abs(linear_volumetric_error(m, e10, q).position_um
                   - volumetric_error(m, e10, q).position_um).max()
    assert gap10 < gap / 50


@pytest.mark.parametrize("chain", [*CHAINS, "w b X Y Z t"])
def test_zero_errors_give_zero_error(chain: str) -> None:
    m = machine(chain)
    q = random_q(m, np.random.default_rng(0), 100)
    v = volumetric_error(m, GeometricErrors(), q)
    assert np.abs(v.position_um).max() < 1e-9
    assert v.orientation_urad is not None and np.abs(v.orientation_urad).max() < 1e-9


@pytest.mark.parametrize("chain", ["w X Y b Z t", "w b X Y Z t", "w Y b X Z t"])
def test_positioning_error_reads_the_same_on_either_side_of_the_base(chain: str) -> None:
    # EXX is the tool's error relative to the workpiece, whichever side X is on
    m = machine(chain)
    e = GeometricErrors({"EXX": Polynomial((0.0, 0.01))})  # 10 µm per metre of x
    q = random_q(m, np.random.default_rng(1), 50)
    v = volumetric_error(m, e, q).position_um
    x = q[:, m.axis_names.index("X")]
    np.testing.assert_allclose(v[:, 0], 0.01 * x, atol=1e-9)
    np.testing.assert_allclose(v[:, 1:], 0.0, atol=1e-9)


@pytest.mark.parametrize("chain", ["w X Y b Z t", "w b Y X Z t"])
def test_pure_squareness_gives_the_documented_linear_field(chain: str) -> None:
    m = machine(chain)
    rng = np.random.default_rng(2)
    q = random_q(m, rng, 200)
    y, z = q[:, m.axis_names.index("Y")], q[:, m.axis_names.index("Z")]
    cases = {
        "EC0Y": (0, -y),  # +y move pushes the tool to -x: angle X^Y above 90°
        "EB0Z": (0, z),
        "EA0Z": (1, -z),
    }
    for name, (component, field) in cases.items():
        v = volumetric_error(m, GeometricErrors(locations={name: 50.0}), q).position_um
        want = 50.0e-6 * field * 1e3
        np.testing.assert_allclose(v[:, component], want, atol=2e-6, err_msg=name)
        others = [i for i in range(3) if i != component]
        # only cosine terms elsewhere: travel × ε²/2 ≈ 300 mm × 1.3e-9 = 4e-4 µm
        assert np.abs(v[:, others]).max() < 1e-3, name


def test_pitch_of_the_workpiece_axis_has_the_tool_position_as_abbe_arm() -> None:
    m = machine("w X Y b Z t")  # tool length 100 mm: the tip is 100 mm below the gauge line
    q = np.array([[100.0, 50.0, -50.0], [400.0, 250.0, -250.0]])
    v = volumetric_error(m, GeometricErrors({"EBX": Polynomial((20.0,))}), q).position_um
    # ε_y × r with r = (x, y, z - L): Δx = ε (z - L), Δz = -ε x
    # (second-order terms are below 1e-4 µm here)
    np.testing.assert_allclose(v[:, 0], 20e-3 * (q[:, 2] - 100.0), atol=1e-4)
    np.testing.assert_allclose(v[:, 2], -20e-3 * q[:, 0], atol=1e-4)


def test_pitch_of_the_spindle_axis_has_only_the_tool_length_as_arm() -> None:
    m = machine("w X Y b Z t")
    q = random_q(m, np.random.default_rng(4), 20)
    v = volumetric_error(m, GeometricErrors({"EBZ": Polynomial((20.0,))}), q).position_um
    np.testing.assert_allclose(v[:, 0], 20e-3 * -100.0, rtol=1e-6)


def test_roll_gives_the_same_orientation_error_on_both_sides() -> None:
    for chain in ("w X Y b Z t", "w b X Y Z t"):
        m = machine(chain)
        q = random_q(m, np.random.default_rng(5), 10)
        v = volumetric_error(m, GeometricErrors({"EAX": Polynomial((30.0,))}), q)
        assert v.orientation_urad is not None
        np.testing.assert_allclose(v.orientation_urad, [[30.0, 0.0, 0.0]] * 10, atol=1e-6)


def test_table_components_interpolate_and_hold_their_ends() -> None:
    m = machine("w X Y b Z t")
    e = GeometricErrors({"EXX": Table((0.0, 100.0, 500.0), (0.0, 4.0, -4.0))})
    q = np.array([[50.0, 0, 0], [300.0, 0, 0], [-10.0, 0, 0], [600.0, 0, 0]])
    v = volumetric_error(m, e, q).position_um[:, 0]
    np.testing.assert_allclose(v, [2.0, 0.0, 0.0, -4.0], atol=1e-9)


def test_rotary_table_offset_rotates_with_the_table() -> None:
    # the C axis line is 10 µm off in x: a point on the workpiece sees the tool displaced by
    # (I - R(c)) · offset when the table has turned by c
    m = machine("w C X Y b Z t")
    q = np.zeros((4, 4))
    q[:, 0] = [0.0, 90.0, 180.0, 270.0]
    v = volumetric_error(m, GeometricErrors(locations={"EX0C": 10.0}), q).position_um
    np.testing.assert_allclose(v[:, 0], [0.0, 10.0, 20.0, 10.0], atol=1e-6)
    np.testing.assert_allclose(v[:, 1], [0.0, -10.0, 0.0, 10.0], atol=1e-6)


# --- the first seed's arch machine: Eq. 17 to first order ---

def test_arch_machine_px1_agrees_with_seed_eq17_to_first_order() -> None:
    """Eq. 17 of Ahn, Min and Pasek (2006), first-order terms.

    The seed's table moves +x under a fixed tool and its P is the workpiece point's
    displacement minus the tool's; this project's component errors are the tool's error
    relative to the workpiece. So: EXX = -δxx, ..., ECX = -εzx for the table (x), the
    column (y) and spindle (z1) errors carry over with their sign, EC0Y = S_xy,
    EB0Z1 = -S_xz1, EA0Z1 = S_y1z1, the seed's tool dimension Z4 = -tool length (our tool
    points against its axis), and P_x1 = -(our x error).
    """
    theta1 = 20.0
    m = arch(theta1, 35.0)
    th = np.deg2rad(theta1)
    rng = np.random.default_rng(17)
    s = {k: float(rng.normal(0, 10)) for k in [
        "dxx", "dyx", "dzx", "exx", "eyx", "ezx", "dxy", "dyy", "dzy", "exy", "eyy", "ezy",
        "dxz1", "dy1z1", "dz1z1", "exz1", "ey1z1", "ez1z1", "Sxy", "Sxz1", "Sy1z1"]}
    const = Polynomial
    e = GeometricErrors(
        {
            "EXX": const((-s["dxx"],)), "EYX": const((-s["dyx"],)), "EZX": const((-s["dzx"],)),
            "EAX": const((-s["exx"],)), "EBX": const((-s["eyx"],)), "ECX": const((-s["ezx"],)),
            "EXY": const((s["dxy"],)), "EYY": const((s["dyy"],)), "EZY": const((s["dzy"],)),
            "EAY": const((s["exy"],)), "EBY": const((s["eyy"],)), "ECY": const((s["ezy"],)),
            "EXZ1": const((s["dxz1"],)), "EYZ1": const((s["dy1z1"],)),
            "EZZ1": const((s["dz1z1"],)), "EAZ1": const((s["exz1"],)),
            "EBZ1": const((s["ey1z1"],)), "ECZ1": const((s["ez1z1"],)),
        },
        {"EC0Y": s["Sxy"], "EB0Z1": -s["Sxz1"], "EA0Z1": s["Sy1z1"]},
    )
    q = random_q(m, rng, 50)  # columns x, y, z1, z2
    y, z1 = q[:, 1], q[:, 2]
    z4 = -m.branch("S1").tool_length_mm
    um = 1e-3  # µrad × mm → µm
    px1 = (
        s["dxx"] - y * s["ezx"] * um - s["dxy"] - s["dxz1"] - z4 * s["ey1z1"] * um
        + y * s["Sxy"] * um + z1 * s["Sxz1"] * um
        + (z1 + z4) * (s["eyx"] * np.cos(th) + s["ezx"] * np.sin(th)) * um
        - (z1 + z4) * (s["eyy"] * np.cos(th) + s["ezy"] * np.sin(th)) * um
    )
    lin = linear_volumetric_error(m, e, q, spindle="S1").position_um[:, 0]
    np.testing.assert_allclose(-lin, px1, atol=1e-9)
    exact = volumetric_error(m, e, q, spindle="S1").position_um[:, 0]
    np.testing.assert_allclose(-exact, px1, atol=5e-3)  # the seed's second-order terms


# --- bad input ---

def test_component_for_an_axis_the_machine_lacks_is_refused_by_name() -> None:
    m = machine("w X Y b Z t")
    with pytest.raises(ComponentErrorSpecError, match=r"EXC.*no axis C"):
        volumetric_error(m, GeometricErrors({"EXC": Polynomial((1.0,))}), np.zeros((1, 3)))
    with pytest.raises(ComponentErrorSpecError, match="EA0Y"):
        volumetric_error(m, GeometricErrors(locations={"EA0Y": 1.0}), np.zeros((1, 3)))
    with pytest.raises(ComponentErrorSpecError, match="not an ISO 230-1 error name"):
        GeometricErrors.from_json({"components": {"EQX": {"coefficients": [1]}}})


def test_nan_in_a_table_is_refused_with_its_entry() -> None:
    with pytest.raises(ComponentErrorSpecError, match="entry 1"):
        Table((0.0, 1.0, 2.0), (0.0, float("nan"), 1.0))


def test_positions_with_wrong_shape_or_nan_are_refused() -> None:
    m = machine("w X Y b Z t")
    with pytest.raises(ValueError, match=r"shape \(N, 3\)"):
        volumetric_error(m, GeometricErrors(), np.zeros((5, 4)))
    with pytest.raises(ValueError, match="NaN"):
        volumetric_error(m, GeometricErrors(), np.full((1, 3), np.nan))


def test_tool_pose_of_the_nominal_gantry_is_command_minus_tool_length() -> None:
    from volumetric.model.kinematics import tool_pose

    m = machine("w b Y X Z t")
    q = random_q(m, np.random.default_rng(9), 10)
    p, r = tool_pose(m, q)
    xyz = q[:, [m.axis_names.index(a) for a in "XYZ"]]
    np.testing.assert_allclose(p, xyz - [0.0, 0.0, 100.0], atol=1e-12)
    assert r is not None
    np.testing.assert_allclose(r, np.broadcast_to(np.eye(3), r.shape), atol=1e-15)
