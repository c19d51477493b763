"""3-PRS (mechanisms/prs3.py) against references independent of parakin's solvers.

The references are written here:
* geometry in NumPy: rails A_i = r_b e_i, sliders S_i = A_i + d_i k, platform joints
  C_i = R c_i + p, and a reachable pose from Z-Y-Z Euler angles (alpha, beta, -alpha) with the
  parasitic centre x = r_p (cos beta - 1) cos(2 alpha) / 2, y = r_p (1 - cos beta) sin(2 alpha) / 2
  (the form of Carretero et al. 2000 for this architecture; ``tilt`` below writes the same set
  in the tilt vector n, rationally, the hand reference for the reading the generator derives);
* the assembly modes of given strokes by an exact elimination: each link turns in its plane,
  C_i = S_i + L (cos t_i e_i + sin t_i k), and the platform triangle |C_i - C_j|^2 = 3 r_p^2
  gives three polynomials of bidegree (2, 2) in the half-angle tangents tau_i, tau_j. Two
  resultants (exact rational arithmetic, SymPy) leave one polynomial in tau_2 of degree 16 (the
  generic number of modes); its real roots are isolated exactly, tau_3 and tau_1 follow from the
  quadratics, a real triple that closes all three equations is a real mode, polished by Newton
  in the angles. A dense multistart of scipy's least squares in the angles must find the same
  modes. The pose of a mode is the rigid motion taking c_i to C_i (Kabsch).
"""

from __future__ import annotations

import functools
import warnings

import numpy as np
import pytest
import sympy as sp
from parakin.mechanisms import prs3
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

import parakin

R_B, R_P, L = (prs3.DEFAULTS[s] for s in (prs3.r_b, prs3.r_p, prs3.L))
ANGLES = np.radians([0.0, 120.0, 240.0])
RADIAL = np.stack([np.cos(ANGLES), np.sin(ANGLES), np.zeros(3)], 1)
TANGENT = np.stack([-np.sin(ANGLES), np.cos(ANGLES), np.zeros(3)], 1)
K = np.array([0.0, 0.0, 1.0])
VERTICAL = sp.Matrix([0, 0, 1])


def tilt(n: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """The 3-PRS's reachable set by hand (Carretero et al.'s form, rationally; derivation:
    docs/derivations/prs3.md), the reference the generator's derived reading is compared with.

    Parameters
    ----------
    n : sympy.Matrix, shape (3, 1)
        A unit vector, the tilt n = R^T k of the platform (dimensionless).

    Returns
    -------
    rotation : sympy.Matrix, shape (3, 3)
        The tilt R0 about a horizontal axis with R0^T k = n: R0 = I + [v]x + [v]x^2 / (1 + n_z),
        v = n x k.
    q : sympy.Matrix, shape (4, 1)
        Its unit quaternion (scalar first, q0 > 0): (1 + n_z, n x k) / sqrt(2 (1 + n_z)).
    centre : sympy.Matrix, shape (3, 1)
        The platform centre (x0, y0, 0) in metres that the leg planes force at R0 (platform joints
        on the circle of radius r_p, the mechanism's symbol).
    """
    v = n.cross(VERTICAL)
    skew = sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    rotation = sp.eye(3) + skew + (v * v.T - v.dot(v) * sp.eye(3)) / (1 + n[2])
    root = sp.sqrt(2 * (1 + n[2]))
    q = sp.Matrix([(1 + n[2]) / root, v[0] / root, v[1] / root, 0])
    r_p = prs3.r_p
    centre = sp.Matrix([-r_p * (n[0] ** 2 - n[1] ** 2) / (2 * (1 + n[2])), r_p * n[0] * n[1] / (1 + n[2]), 0])
    return rotation, q, centre


@pytest.fixture(scope="module", params=["numpy", "compiled"])
def m(request):
    return parakin.load("prs3", backend=request.param)


# ------------------------------------------------------------------ geometry
def rot_z(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_y(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def transform(rotation: np.ndarray, position) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = rotation, position
    return pose


def euler_pose(alpha: float, beta: float, height: float, r_p: float = R_P) -> np.ndarray:
    """The reachable pose with Z-Y-Z Euler angles (alpha, beta, -alpha) at ``height``."""
    x = r_p * (np.cos(beta) - 1) * np.cos(2 * alpha) / 2
    y = r_p * (1 - np.cos(beta)) * np.sin(2 * alpha) / 2
    return transform(rot_z(alpha) @ rot_y(beta) @ rot_z(-alpha), [x, y, height])


def platform_joints(pose: np.ndarray, r_p: float = R_P) -> np.ndarray:
    """C_i = R c_i + p, one row per leg."""
    return (r_p * RADIAL) @ pose[:3, :3].T + pose[:3, 3]


def sliders(strokes, r_b: float = R_B) -> np.ndarray:
    return r_b * RADIAL + np.asarray(strokes, dtype=float)[:, None] * K


def leg_strokes(pose: np.ndarray, signs, r_b: float = R_B, r_p: float = R_P, length: float = L) -> np.ndarray:
    """d_i = C_i,z - sign_i sqrt(L^2 - horizontal distance^2 from the rail)."""
    joints = platform_joints(pose, r_p)
    horizontal = joints[:, :2] - r_b * RADIAL[:, :2]
    return joints[:, 2] - np.asarray(signs) * np.sqrt(length**2 - (horizontal**2).sum(-1))


def quaternion(rotation: np.ndarray) -> np.ndarray:
    """The unit quaternion (scalar first) of R, from the eigenvector of Bar-Itzhack's K matrix."""
    r = rotation
    k = np.array(
        [
            [r[0, 0] - r[1, 1] - r[2, 2], r[1, 0] + r[0, 1], r[2, 0] + r[0, 2], r[2, 1] - r[1, 2]],
            [r[1, 0] + r[0, 1], r[1, 1] - r[0, 0] - r[2, 2], r[2, 1] + r[1, 2], r[0, 2] - r[2, 0]],
            [r[2, 0] + r[0, 2], r[2, 1] + r[1, 2], r[2, 2] - r[0, 0] - r[1, 1], r[1, 0] - r[0, 1]],
            [r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1], r[0, 0] + r[1, 1] + r[2, 2]],
        ]
    )
    _, vectors = np.linalg.eigh(k / 3)
    vector = vectors[:, -1]
    q = np.array([vector[3], vector[0], vector[1], vector[2]])
    return q if q[0] >= 0 else -q


def passive_of(pose: np.ndarray) -> np.ndarray:
    return np.concatenate([pose[:3, 3], quaternion(pose[:3, :3])])


def constraint_residuals(pose: np.ndarray, strokes) -> np.ndarray:
    """(C_i - A_i) . u_i and |C_i - S_i| - L, computed here."""
    joints = platform_joints(pose)
    planes = ((joints - R_B * RADIAL) * TANGENT).sum(-1)
    links = np.linalg.norm(joints - sliders(strokes), axis=1) - L
    return np.concatenate([planes, links])


# ------------------------------------------------------------------ the forward oracle
def link_joints(angles, strokes) -> np.ndarray:
    """C_i = S_i + L (cos t_i e_i + sin t_i k)."""
    angles = np.asarray(angles, dtype=float)
    return sliders(strokes) + L * (np.cos(angles)[:, None] * RADIAL + np.sin(angles)[:, None] * K)


def triangle(angles, strokes) -> np.ndarray:
    """|C_i - C_j|^2 - 3 r_p^2 for (i, j) = (1, 2), (2, 3), (3, 1)."""
    c = link_joints(angles, strokes)
    sides = c - np.roll(c, -1, axis=0)
    return (sides**2).sum(-1) - 3 * R_P**2


def pose_of(angles, strokes) -> np.ndarray:
    """The rigid motion taking c_i to C_i (Kabsch; the triangles are congruent)."""
    joints = link_joints(angles, strokes)
    centre = joints.mean(0)
    h = (R_P * RADIAL).T @ (joints - centre)
    u, _, vt = np.linalg.svd(h)
    flip = np.diag([1.0, 1.0, np.sign(np.linalg.det(vt.T @ u.T))])
    return transform(vt.T @ flip @ u.T, centre)


def polish(angles, strokes) -> np.ndarray:
    solution = least_squares(triangle, angles, args=(strokes,), xtol=1e-15, ftol=1e-15, gtol=1e-15)
    return np.mod(solution.x + np.pi, 2 * np.pi) - np.pi


def distinct(found: list[np.ndarray], tolerance: float = 1e-7) -> list[np.ndarray]:
    unique: list[np.ndarray] = []
    for angles in found:
        if all(np.abs(np.mod(angles - other + np.pi, 2 * np.pi) - np.pi).max() > tolerance for other in unique):
            unique.append(angles)
    return unique


def elimination(strokes):
    """(P(tau2), [G12, G23, G31], taus) in exact rationals: G_ij = (1 + tau_i^2)(1 + tau_j^2)
    (|C_i - C_j|^2 - 3 r_p^2), with |C_i - C_j|^2 = rho_i^2 + rho_j^2 + rho_i rho_j + (h_i - h_j)^2
    (e_i . e_j = -1/2), rho_i = r_b + L cos t_i, h_i = d_i + L sin t_i; rho_i^2 + h_i^2 is affine
    in (cos t_i, sin t_i), so each G_ij has bidegree (2, 2)."""
    taus = sp.symbols("tau1:4")
    d = [sp.Rational(repr(float(v))) for v in strokes]
    r_b, r_p, length = (sp.Rational(repr(v)) for v in (R_B, R_P, L))

    def parts(i):
        t = taus[i]
        w, c, s = 1 + t**2, 1 - t**2, 2 * t  # (1, cos, sin) times w
        return (
            w,
            r_b * w + length * c,
            d[i] * w + length * s,
            (r_b**2 + length**2 + d[i] ** 2) * w + 2 * length * (r_b * c + d[i] * s),
        )

    def side(i, j):
        wi, rho_i, h_i, square_i = parts(i)
        wj, rho_j, h_j, square_j = parts(j)
        return sp.expand(square_i * wj + square_j * wi + rho_i * rho_j - 2 * h_i * h_j - 3 * r_p**2 * wi * wj)

    g12, g23, g31 = side(0, 1), side(1, 2), side(2, 0)
    h = sp.resultant(g12, g31, taus[0])  # (tau2, tau3)
    p = sp.resultant(sp.Poly(h, taus[2]), sp.Poly(g23, taus[2]))
    return sp.Poly(p.as_expr(), taus[1]), (g12, g23, g31), taus


def quadratic_roots(expr: sp.Expr, unknown: sp.Symbol) -> np.ndarray:
    coefficients = [complex(c) for c in sp.Poly(expr, unknown).all_coeffs()]
    return np.roots(coefficients)


def oracle_modes(strokes) -> tuple[int, list[np.ndarray]]:
    """(degree of the elimination polynomial, link angles of every real mode)."""
    return _oracle_modes(tuple(float(v) for v in strokes))


@functools.cache
def _oracle_modes(strokes: tuple[float, ...]) -> tuple[int, list[np.ndarray]]:
    p, (g12, g23, g31), taus = elimination(strokes)
    assert sp.degree(sp.gcd(p, p.diff()), taus[1]) == 0, "the elimination polynomial has a multiple root"
    found = []
    for root in p.real_roots():
        tau2 = sp.Float(root.evalf(30), 30)
        for tau3 in quadratic_roots(g23.subs(taus[1], tau2), taus[2]):
            for tau1 in quadratic_roots(g12.subs(taus[1], tau2), taus[0]):
                if abs(tau3.imag) > 1e-6 or abs(tau1.imag) > 1e-6:
                    continue
                angles = polish(2 * np.arctan([tau1.real, float(tau2), tau3.real]), strokes)
                if np.abs(triangle(angles, strokes)).max() < 1e-13:
                    found.append(angles)
    return p.degree(), distinct(found)


@functools.cache
def _multistart_modes(strokes: tuple[float, ...], starts: int, seed: int) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    found = []
    for _ in range(starts):
        angles = polish(rng.uniform(-np.pi, np.pi, 3), strokes)
        if np.abs(triangle(angles, strokes)).max() < 1e-13:
            found.append(angles)
    return distinct(found)


def multistart_modes(strokes, starts: int = 1500, seed: int = 3) -> list[np.ndarray]:
    """Link angles of every real mode that least squares reaches from ``starts`` random angles."""
    return _multistart_modes(tuple(float(v) for v in strokes), starts, seed)


# ------------------------------------------------------------------ loop closure and inverse
def test_the_tilt_and_its_half_turn_keep_the_joints_in_their_leg_planes_symbolically():
    """tilt(n) (this file's hand form) for a unit n (n_z = sqrt(1 - n_x^2 - n_y^2)): R0 is a
    rotation with R0^T k = n, its quaternion gives R0, and (C_i - A_i) . u_i = 0 for i = 1..3 both
    at R0 with the centre (x0, y0) and at Rot_z(pi) R0 with (-x0, -y0), for every height z
    (exactly)."""
    nx, ny, height = sp.symbols("n_x n_y z", real=True)
    nz = sp.sqrt(1 - nx**2 - ny**2)
    rotation, q, centre = tilt(sp.Matrix([nx, ny, nz]))
    assert sp.simplify(rotation.T * rotation - sp.eye(3)) == sp.zeros(3, 3)
    assert sp.simplify(rotation.T * VERTICAL - sp.Matrix([nx, ny, nz])) == sp.zeros(3, 1)
    unit = q / sp.sqrt(q.dot(q))
    w, v = unit[0], unit[1:, 0]
    skew = sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    assert sp.simplify(sp.eye(3) + 2 * w * skew + 2 * skew * skew - rotation) == sp.zeros(3, 3)
    half_turn = sp.diag(-1, -1, 1)
    for turn in (sp.eye(3), half_turn):
        position = turn * (centre + height * VERTICAL)
        for e, u in zip(prs3.RADIAL, prs3.TANGENT, strict=True):
            joint = turn * rotation * (prs3.r_p * e) + position
            assert sp.simplify((joint - prs3.r_b * e).dot(u)) == 0


def test_the_generators_reading_is_the_hand_tilt_and_centre():
    """The inverse's reading that the generator derives from the three leg planes (no hand reading
    in the model) is this file's tilt: n = (r31, r32, r33), the rotation diag(turn, turn, 1) R0, the
    centre turn (x0, y0, z) and the quaternion of R0 or of its half-turn, for turn = +-1 (exactly)."""
    steps = dict(prs3.MODEL.inverse().steps)
    nx, ny, nz = sp.symbols("n_x n_y n_z", real=True)
    rotation, q, centre = tilt(sp.Matrix([nx, ny, nz]))
    names = sp.symbols("tilt11 tilt12 tilt13 tilt21 tilt22 tilt23 tilt31 tilt32 tilt33", real=True)
    hand = dict(zip(names, rotation, strict=True))
    assert [steps[s] for s in (nx, ny, nz)] == list(sp.symbols("r31 r32 r33", real=True))
    assert all(sp.simplify(steps[s] - v) == 0 for s, v in hand.items())
    x, y, z = sp.symbols("x y z", real=True)
    turned = {1: list(q), -1: [0, -q[2], q[1], q[0]]}
    for turn in (1, -1):
        at = {**hand, sp.Symbol("turn", real=True): turn}
        assert sp.simplify(steps[x].xreplace(at) - turn * centre[0]) == 0
        assert sp.simplify(steps[y].xreplace(at) - turn * centre[1]) == 0
        for k in range(4):
            assert sp.simplify(steps[sp.Symbol(f"q{k}", real=True)].xreplace(at) - turned[turn][k]) == 0
    assert steps[z] == sp.Symbol("pz", real=True)


def branch_signs(m) -> np.ndarray:
    return np.array(m.capabilities.inverse.combinations, dtype=float)


def test_loop_closure_is_the_leg_planes_the_link_lengths_and_the_unit_quaternion(m):
    """At random (not closed) states: residual = ((C_i - A_i) . u_i, (|C_i - S_i|^2 - L^2) / (2 L),
    (q . q - 1) / 2) computed here from R(q) = rotation of q / |q| (1e-12)."""
    rng = np.random.default_rng(1)
    for _ in range(20):
        strokes = rng.uniform(0.0, 1.0, 3)
        position = rng.normal(scale=0.3, size=3)
        q = rng.normal(size=4)
        unit = q / np.linalg.norm(q)
        w, v = unit[0], unit[1:]
        skew = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
        rotation = np.eye(3) + 2 * w * skew + 2 * skew @ skew
        joints = platform_joints(transform(rotation, position))
        planes = ((joints - R_B * RADIAL) * TANGENT).sum(-1)
        links = (((joints - sliders(strokes)) ** 2).sum(-1) - L**2) / (2 * L)
        expected = np.concatenate([planes, links, [(q @ q - 1) / 2]])
        residual = m.loop_closure(strokes, np.concatenate([position, q]))["residual"]
        assert np.abs(residual - expected).max() < 1e-12, f"closure off by {np.abs(residual - expected).max():.3g}"


def test_euler_poses_with_the_parasitic_centre_are_reachable_and_inverted_exactly(m):
    """Carretero et al.'s form: R = Rz(alpha) Ry(beta) Rz(-alpha) at x = r_p (cos beta - 1)
    cos(2 alpha) / 2, y = r_p (1 - cos beta) sin(2 alpha) / 2 keeps every C_i in its leg plane
    (1e-15). inverse_pose of such a pose: the passive values are the pose (1e-12), and branch k's
    strokes are C_i,z - sigma_i sqrt(L^2 - |h_i|^2) with the signs of combination k (1e-12),
    valid where the discriminant is positive; platform_pose gives the pose back (1e-12)."""
    rng = np.random.default_rng(2)
    signs = branch_signs(m)
    checked = 0
    for _ in range(40):
        pose = euler_pose(rng.uniform(-np.pi, np.pi), rng.uniform(0, 1.2), rng.uniform(0.3, 0.8))
        planes = constraint_residuals(pose, np.zeros(3))[:3]
        assert np.abs(planes).max() < 1e-15
        ik = m.inverse_pose(pose, strict=False)
        joints = platform_joints(pose)
        discriminant = L**2 - ((joints[:, :2] - R_B * RADIAL[:, :2]) ** 2).sum(-1)
        for k in range(len(signs)):
            if ik.valid[k]:
                assert np.abs(ik.actuated[k] - leg_strokes(pose, signs[k])).max() < 1e-12
                assert np.abs(ik.passive[k] - passive_of(pose)).max() < 1e-12
                assert np.abs(m.platform_pose(ik.actuated[k], ik.passive[k]) - pose).max() < 1e-12
                checked += 1
            else:  # invalid only where a link cannot reach or an actuator leaves its rail
                strokes = leg_strokes(pose, signs[k]) if discriminant.min() > 0 else None
                assert strokes is None or ((strokes < 0) | (strokes > prs3.RAIL_LENGTH)).any()
    assert checked >= 100


def test_the_half_turned_pose_is_reachable_and_the_inverse_reads_the_half_turn(m):
    """Rot_z(pi) R0 at (-x0, -y0, z) also keeps every C_i in its leg plane (each joint on the far
    side of the centre); inverse_pose returns that pose (q0 = 0), not R0's, with its strokes."""
    rng = np.random.default_rng(3)
    signs = branch_signs(m)
    for _ in range(20):
        pose = euler_pose(rng.uniform(-np.pi, np.pi), rng.uniform(0, 0.6), rng.uniform(0.3, 0.8))
        turned = transform(rot_z(np.pi) @ pose[:3, :3], [-pose[0, 3], -pose[1, 3], pose[2, 3]])
        assert np.abs(constraint_residuals(turned, np.zeros(3))[:3]).max() < 1e-15
        ik = m.inverse_pose(turned, strict=False)
        assert ik.valid.any(), "the half-turned pose is reachable with L = 0.35 > r_b + r_p"
        for k in np.flatnonzero(ik.valid):
            assert abs(ik.passive[k, 3]) < 1e-15, "q0 of the half-turn"
            assert np.abs(m.platform_pose(ik.actuated[k], ik.passive[k]) - turned).max() < 1e-12
            assert np.abs(ik.actuated[k] - leg_strokes(turned, signs[k])).max() < 1e-12


def test_inverse_reads_height_and_tilt_only(m):
    """A pose off the reachable set (moved horizontally, turned about the vertical of {B} by
    less than 90 deg): inverse_pose returns the reachable pose with its height and tilt
    n = R^T k, the same as for the reachable pose itself."""
    rng = np.random.default_rng(4)
    for _ in range(20):
        pose = euler_pose(rng.uniform(-np.pi, np.pi), rng.uniform(0, 0.6), rng.uniform(0.3, 0.8))
        off = transform(rot_z(rng.uniform(-1.5, 1.5)) @ pose[:3, :3], pose[:3, 3] + [*rng.normal(scale=0.1, size=2), 0])
        ours, theirs = m.inverse_pose(off, strict=False), m.inverse_pose(pose, strict=False)
        assert (ours.valid == theirs.valid).all()
        assert np.abs(ours.actuated[ours.valid] - theirs.actuated[theirs.valid]).max() < 1e-12
        assert np.abs(ours.passive[ours.valid] - passive_of(pose)).max() < 1e-12


def test_link_horizontal_factor_squared_is_the_reach_validity(m):
    """leg<i>_link_horizontal = (C_i - S_i) . k = sigma_i sqrt(L^2 - |h_i|^2) (metres, the slider
    leg's serial factor d . k): its square over L^2 is the validity leg<i>_reachable and its sign
    the branch sign (1e-12)."""
    rng = np.random.default_rng(5)
    signs = branch_signs(m)
    for _ in range(10):
        pose = euler_pose(rng.uniform(-np.pi, np.pi), rng.uniform(0, 0.6), rng.uniform(0.3, 0.8))
        ik = m.inverse_pose(pose, strict=False)
        joints = platform_joints(pose)
        validity = (L**2 - ((joints[:, :2] - R_B * RADIAL[:, :2]) ** 2).sum(-1)) / L**2
        for k in np.flatnonzero(ik.valid):
            factors = m.singularities(parakin.Configuration(ik.actuated[k], ik.passive[k], pose))
            horizontal = np.array([factors[f"leg{i}_link_horizontal"] for i in (1, 2, 3)]) / L
            assert np.abs(horizontal**2 - validity).max() < 1e-12
            assert (np.sign(horizontal) == signs[k]).all()


def closure_conditioning(m, actuated, passive) -> float:
    values = np.linalg.svd(m.loop_closure(actuated, passive)["jacobian"], compute_uv=False)
    return float(values[-1] / values[0])


def test_type_ii_factor_vanishes_where_the_closure_jacobian_is_singular(m):
    """Tilting the platform (alpha = 0.5 rad, z = 0.6 m, links rising) the factor
    platform_moves_with_sliders_locked changes sign between beta = 60 and 80 deg; at its root
    (bisection to 1e-13 rad) the loop-closure Jacobian's smallest singular value is below 1e-9 of
    its largest, while at beta = 30 deg it is above 1e-3."""

    def state(beta):
        pose = euler_pose(0.5, beta, 0.6)
        ik = m.inverse_pose(pose, strict=False)
        assert ik.valid[0]
        return ik.actuated[0], ik.passive[0], pose

    def factor(beta):
        actuated, passive, pose = state(beta)
        return float(
            m.singularities(parakin.Configuration(actuated, passive, pose))["platform_moves_with_sliders_locked"]
        )

    low, high = np.radians(60.0), np.radians(80.0)
    assert factor(low) * factor(high) < 0
    while high - low > 1e-13:
        middle = (low + high) / 2
        low, high = (middle, high) if factor(low) * factor(middle) > 0 else (low, middle)
    assert closure_conditioning(m, *state(low)[:2]) < 1e-9
    assert closure_conditioning(m, *state(np.radians(30.0))[:2]) > 1e-3


# ------------------------------------------------------------------ assembly modes
@pytest.mark.parametrize("name", sorted(prs3.MODE_COUNTS))
def test_real_mode_counts_by_an_independent_elimination(m, name):
    """MODE_COUNTS[name]: the elimination polynomial has degree 16 (the generic number of modes)
    and no multiple root; its real modes number as printed, a multistart of least squares in the
    link angles finds the same modes (1e-7 rad); every mode keeps its joints in the leg planes
    with links of length L (1e-12), closes prs3's loop closure (1e-9) with q0 = 0 or q3 = 0 (R0
    or its half-turn), is given back by inverse_pose on a valid branch (strokes to 1e-9, pose to
    1e-9) and is where prs3's Newton returns from a guess 1e-3 away."""
    strokes, count = prs3.MODE_COUNTS[name]
    assert all(0.0 <= d <= prs3.RAIL_LENGTH for d in strokes)
    degree, modes = oracle_modes(strokes)
    assert degree == 16
    assert len(modes) == count, f"{name}: the elimination finds {len(modes)} real modes, printed {count}"
    others = multistart_modes(strokes)
    assert len(distinct([*modes, *others])) == count, f"{name}: the multistart finds {len(others)} modes"
    rng = np.random.default_rng(6)
    for angles in modes:
        pose = pose_of(angles, strokes)
        assert np.abs(constraint_residuals(pose, strokes)).max() < 1e-12
        passive = passive_of(pose)
        assert min(abs(passive[3]), abs(passive[6])) < 1e-12
        residual = np.abs(m.loop_closure(strokes, passive)["residual"]).max()
        assert residual < 1e-9, f"{name}: a mode leaves prs3's closure residual {residual:.3g}"
        ik = m.inverse_pose(pose, strict=False)
        mismatch = np.where(ik.valid, np.abs(ik.actuated - strokes).max(-1), np.inf)
        k = int(np.argmin(mismatch))
        assert mismatch[k] < 1e-9, f"{name}: no valid inverse branch gives the strokes back ({mismatch[k]:.3g})"
        assert np.abs(m.platform_pose(ik.actuated[k], ik.passive[k]) - pose).max() < 1e-9
        guess = passive + 1e-3 * rng.normal(size=7)
        fk = m.forward_pose(strokes, guess=guess, strict=False)
        assert fk.converged and np.abs(fk.pose - pose).max() < 1e-9
    # the generated all-modes solver (no forward model written) against the elimination
    found = m.forward_pose_all(strokes)
    assert int(found.count) == count
    expected = np.array([pose_of(angles, strokes) for angles in modes])
    apart = np.abs(found.poses[found.valid][:, None] - expected[None]).max(axis=(-2, -1))
    assert apart.min(1).max() < 1e-9 and apart.min(0).max() < 1e-9


def test_the_constructed_input_has_its_pose_and_the_example_modes_among_its_modes():
    """CONSTRUCTED_STROKES are the strokes of the Euler pose (30, 10, -30) deg at 0.55 m on
    branch 0 by this file's geometry (1e-15), and that pose, LINKS_DOWN_MODE and HALF_TURN_MODE
    are among the elimination's 16 real modes for them (1e-12), 8 with q3 = 0 (tilts) and 8 with
    q0 = 0 (half-turned tilts)."""
    alpha, beta, height = prs3.CONSTRUCTED_EULER
    pose = euler_pose(alpha, beta, height)
    strokes = np.array(prs3.CONSTRUCTED_STROKES)
    assert np.abs(leg_strokes(pose, [1, 1, 1]) - strokes).max() < 1e-15
    _, modes = oracle_modes(strokes)
    poses = np.array([pose_of(angles, strokes) for angles in modes])
    for printed in (pose, np.array(prs3.LINKS_DOWN_MODE), np.array(prs3.HALF_TURN_MODE)):
        assert np.abs(poses - printed).max(axis=(1, 2)).min() < 1e-12
    quaternions = np.array([quaternion(p[:3, :3]) for p in poses])
    assert (np.abs(quaternions[:, 3]) < 1e-12).sum() == 8 and (np.abs(quaternions[:, 0]) < 1e-12).sum() == 8


def test_every_mode_and_the_rate_model_are_derived():
    """No forward model and no rate model are written: forward_pose_all comes from the
    generator's polynomial form (method "automatic"; the mode counts against the independent
    elimination are tested above and in test_automatic_forward.py), the rate model with its three
    constraint wrenches from the P-R-S legs."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        m = parakin.load("prs3", backend="numpy")
    assert set(m.capabilities.forward_methods) == {"automatic"}
    assert m.capabilities.rates is not None and m.capabilities.rates.constraints == 3
    assert int(m.forward_pose_all(m.home_actuated).count) >= 1


def test_passive_rates_follow_finite_differences_of_newton(m):
    """passive_rates (from the loop closure) along slider rates: central differences of Newton
    (1e-6 relative), the parasitic x, y rates among them."""
    rng = np.random.default_rng(7)
    state = m.forward_pose(np.array(prs3.CONSTRUCTED_STROKES), guess=passive_of(euler_pose(*prs3.CONSTRUCTED_EULER)))
    rates = rng.normal(size=3)
    step = 1e-5
    ends = [m.forward_pose(state.actuated + s * step * rates, guess=state, tolerance=1e-13).passive for s in (-1, 1)]
    numeric = (ends[1] - ends[0]) / (2 * step)
    ours = m.passive_rates(state, rates)
    assert np.abs(ours - numeric).max() < 1e-6 * np.abs(numeric).max()
    assert np.abs(numeric[:2]).max() > 1e-3 * np.abs(numeric).max(), "the parasitic x, y move"


def test_drawing_has_base_sliders_and_platform(m):
    state = m.forward_pose(m.home_actuated)
    points = m.drawing(state)
    assert np.abs(points["base"].T - R_B * RADIAL).max() < 1e-15
    assert np.abs(points["elbow"].T - sliders(m.home_actuated)).max() < 1e-15
    assert np.abs(points["platform"].T - platform_joints(state.pose)).max() < 1e-12
    assert set(m.capabilities.drawing.polylines) == {"leg1", "leg2", "leg3", "base", "platform"}


def twist_between(before: np.ndarray, after: np.ndarray, step: float) -> np.ndarray:
    """(v of the origin of {P}, w) in {B} by central differences of two poses 2 step apart."""
    velocity = (after[:3, 3] - before[:3, 3]) / (2 * step)
    spin = after[:3, :3] @ before[:3, :3].T
    omega = np.array([spin[2, 1] - spin[1, 2], spin[0, 2] - spin[2, 0], spin[1, 0] - spin[0, 1]]) / (4 * step)
    return np.concatenate([velocity, omega])


def test_lower_mobility_rates_and_statics_match_finite_differences_and_virtual_work(m):
    """At 6 closed configurations near home: forward_rate of slider rates is the twist of the
    central differences of Newton's poses, all six components (the parasitic vx, vy, wz move:
    > 1e-3 of the twist), 1e-6 relative; inverse_rate of the tilt-and-height part of a motion
    (feasible: built by the constraint wrenches' null space from an independent NumPy geometry)
    gives the central differences of inverse_pose along it; a twist against the constraint
    wrenches raises BadInputError; and the actuator and constraint forces hold a random wrench:
    the virtual work tau . d_dot + w . twist vanishes for every feasible motion, and the
    platform's equilibrium w + A^T phi + C^T lambda = 0 (1e-9)."""
    rng = np.random.default_rng(8)
    step, parasitic, checked = 1e-6, 0.0, 0
    for _ in range(6):
        state = m.forward_pose(m.home_actuated + rng.normal(scale=0.02, size=3), guess=m.home_passive)
        rates = rng.normal(size=3)
        ends = [m.forward_pose(state.actuated + s * step * rates, guess=state, tolerance=1e-13).pose for s in (-1, 1)]
        twist = twist_between(ends[0], ends[1], step)
        ours = m.forward_rate(state, rates)
        assert np.abs(ours - twist).max() < 1e-6 * np.abs(twist).max()
        parasitic = max(parasitic, np.abs(twist[[0, 1, 5]]).max() / np.abs(twist).max())
        # constraint wrenches of this test's own geometry: the force along u_i through C_i
        joints = platform_joints(state.pose)
        wrenches = np.array([[*u, *np.cross(c - state.pose[:3, 3], u)] for c, u in zip(joints, TANGENT, strict=True)])
        assert np.abs(wrenches @ ours).max() < 1e-9 * np.abs(ours).max()
        # a feasible motion: any twist projected on the null space of the constraint wrenches
        null = np.linalg.svd(wrenches)[2][3:]
        motion = null.T @ rng.normal(size=3)
        moved = [
            transform(Rotation.from_rotvec(s * step * motion[3:]).as_matrix() @ state.pose[:3, :3],
                      state.pose[:3, 3] + s * step * motion[:3])
            for s in (-1, 1)
        ]  # fmt: skip
        ik = m.inverse_pose(np.stack(moved), strict=False)
        numeric = (ik.actuated[1, 0] - ik.actuated[0, 0]) / (2 * step)
        back = m.inverse_rate(state, motion).actuated
        assert np.abs(back - numeric).max() < 1e-6 * np.abs(numeric).max()
        with pytest.raises(parakin.BadInputError, match="constraint wrenches"):
            m.inverse_rate(state, motion + 1e-3 * np.abs(motion).max() * wrenches[0] / np.linalg.norm(wrenches[0]))
        # statics: the efforts hold a wrench on every feasible motion (virtual work)
        wrench = rng.normal(size=6)
        tau = m.actuator_forces(state, wrench)
        reactions = m.constraint_forces(state, wrench)
        jacobians = m.rate_jacobians(state)
        phi = np.linalg.solve(jacobians["b"].T, tau)
        balance = wrench + jacobians["a"].T @ phi + jacobians["constraints"].T @ reactions
        assert np.abs(balance).max() < 1e-9 * np.abs(wrench).max()
        for _ in range(3):
            slider_rates = rng.normal(size=3)
            work = tau @ slider_rates + wrench @ m.forward_rate(state, slider_rates)
            assert abs(work) < 1e-9 * np.abs(tau).max() * np.abs(slider_rates).max()
            checked += 1
    assert parasitic > 1e-3 and checked == 18
