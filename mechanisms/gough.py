"""6-SPS (Gough-Stewart) platform with linearly related planar base and platform (PMlpp), after
Kong & Gosselin, "Generation of architecturally singular 6-SPS parallel manipulators with linearly
related planar platforms" (``shared/papers/004_407e258733e8e5c8.txt``).

Frames and conventions (paper section 2; SI, radians):
* {B}: origin O = A1, base plane z = 0, A_i = (xA_i, yA_i, 0), i = 2..6. The paper also puts X
  through A2 (yA2 = 0), but its own section 5.4 example has yA2 = -5; nothing below needs it.
* {P}: origin O_P = B1, platform plane z_P = 0. Eq (1): B_i^(P) = (t11 xA_i + t12 yA_i,
  t22 yA_i, 0), t11 t22 != 0 (also true for i = 1: both points at the origin).
* Pose ^B_P T: position p = O_P = B1 = (x, y, z) and R = [i_P j_P k_P] (columns: the platform
  axes in {B}); B_i = p + R B_i^(P). Leg i joins A_i to B_i; the actuated variables are the leg
  lengths l1..l6.
* Passive variables (the Newton unknowns): x, y, z and the Z-Y-X Euler angles alpha, beta, gamma
  of R = Rot_z(alpha) Rot_y(beta) Rot_x(gamma), as everywhere in parakin. The parametrisation is
  singular at beta = +-pi/2 (i_P vertical): there Newton reports a singular Jacobian although the
  platform is not at a type II singularity; the closed form (forward_pose_all) is unaffected.
* Residual: |B_i - A_i| - l_i (metres), one per leg; there is no false closure (alignment 1).
  The legs are S-P-S joint chains (``parakin.generator.joints``): closure, rates, factors,
  inverse and drawing are derived, the closure in this unsquared form (``squared=False``)
  because the polynomial family it gives has its root count (32) proven by the trace test,
  which the squared form's family does not reach at generation.
* Rates: A twist = B l_dot with row i of A the leg line's Pluecker coordinates (d_i ; (A_i - p) x
  d_i), d_i = B_i - A_i (moment about the origin of {P}, since the twist is (v of O_P, w) in {B}),
  and B = diag(l_i). det A = prod(l_i) det J, J the unit-line Pluecker matrix (rows s_i, moments
  about O_P; the same determinant as with moments about O). det A = 0: type II singularity.
* Forward pose (paper section 3 with the procedure of sections 5.1-5.3, u3 known): the linear
  system (8) M u = L in u1..u5 (Cramer: adj(M) L / det M), i_x = -u3 / t11, j_x and j_y affine in
  i_y (eqs 19-22), the quartic (23) in i_y, then i_z = sigma sqrt(1 - i_x^2 - i_y^2) (24) and j_z
  with i_z j_z = -(i_x j_x + i_y j_y) (25, written without the division by i_z), and the position
  from (9), (10), (5) as a line-sphere intersection p = p0 + tau h d (the same equations as (26),
  (27) without Q^-1, which fails when the solution line is parallel to the base). 4 roots x 2 x 2
  = 16 complex candidates; real ones come in mirror pairs through the base plane (at most 8).
* Architecture: det M (eq 14) is a polynomial of degree 8 in the base coordinates, equal to the
  6-point conic determinant with A1 = O; it vanishes iff A1..A6 lie on a conic (eq 15). The
  declared measure is det M normalised (scale-free, |measure| <= 1), singular below the
  architecture tolerance 1e-9 (``parakin.load`` warns). Then
  M u = L has a one-parameter family of solutions and the platform has a self-motion
  (traced generically by ``m.self_motion``; the paper's own analysis is ``examples/gough_architecture.py``); ``forward_pose_all`` reports the degeneracy ``base_points_on_a_conic``.
* Defaults: a usable (not architecturally singular) PMlpp, the general case of section 3 (det M
  != 0, M u = L has one solution): section 5.4's base and platform map with one base joint moved
  off the conic, A4 = (13, 0) instead of (10, 0) (the base hexagon stays convex; the normalised
  conic measure is -6.4e-3, far from the 1e-9 tolerance), i.e. xA2..xA6 = 5, 9, 13, 9, 5,
  yA2..yA6 = -5, -3, 0, 3, 5, t11 = t12 = t22 = 1 (the paper gives no unit: read as metres).
  Home: {x y z alpha beta gamma} = {5, 2, 5, -0.3, -0.5, 0.3} (m, rad, ``HOME_POSE``), the
  platform tilted over the base (every B_i at z > 3.7 m), a regular configuration: closure
  Jacobian pivot ratio 0.14, eight real assembly modes. Level poses (platform parallel to the
  base) are type II singular for linearly related platforms, so the home is tilted about all
  three axes. Section 5.4's own geometry (base on the conic (x - 5)^2 + y^2 = 25: singular at
  every pose, ``parakin.load`` warns) is the named example ``section54_self_motion``
  (``SECTION_54_PARAMETERS``); its walkthrough is ``examples/gough_architecture.py``.
"""

from __future__ import annotations

import sympy as sp
from parakin.generator import joints
from parakin.generator.frames import euler_zyx_rotation, homogeneous
from parakin.generator.model import (
    POSE_POSITION,
    POSE_ROTATION,
    Citation,
    Example,
    ForwardElimination,
    Mechanism,
    ParameterInfo,
)

XA = sp.symbols("xA2:7", real=True)
YA = sp.symbols("yA2:7", real=True)
t11, t12, t22 = sp.symbols("t11 t12 t22", real=True)
lengths = sp.symbols("l1:7", positive=True)
x, y, z = sp.symbols("x y z", real=True)
alpha, beta, gamma = sp.symbols("alpha beta gamma", real=True)
u = sp.symbols("u1:6", real=True)

#: section 5.4 (A2..A6, then t11, t12, t22): on the conic (x - 5)^2 + y^2 = 25, singular
SECTION_54_BASE = [(5.0, -5.0), (9.0, -3.0), (10.0, 0.0), (9.0, 3.0), (5.0, 5.0)]
SECTION_54_T = (1.0, 1.0, 1.0)
#: section 5.4: the locked inputs, printed to two decimals
SECTION_54_LENGTHS = [33.17, 32.02, 35.12, 37.57, 39.01, 38.32]
#: section 5.4 as parameter names -> values (the named example's parameters)
SECTION_54_PARAMETERS = {
    **{f"xA{k + 2}": SECTION_54_BASE[k][0] for k in range(5)},
    **{f"yA{k + 2}": SECTION_54_BASE[k][1] for k in range(5)},
    **dict(zip(("t11", "t12", "t22"), SECTION_54_T, strict=True)),
}
#: a point of section 5.4's self-motion: {x y z alpha beta gamma} (m, rad) of the mode at i_x =
#: 0.044 (the first of its eight, ``examples/gough_architecture.py``) for the compatible lengths
#: nearest the printed ones; its leg lengths are the printed l1..l6 to 4.2e-3 (printed to 0.01)
SECTION_54_POSE = (11.100315736401, 24.869206220077, 18.934814882557, -1.110996974574, -1.471482307985, 0.496304779502)
#: the default geometry (module docstring): section 5.4 with A4 moved off the conic to (13, 0)
DEFAULT_BASE = [(5.0, -5.0), (9.0, -3.0), (13.0, 0.0), (9.0, 3.0), (5.0, 5.0)]
#: home {x y z alpha beta gamma} (m, rad) on the default geometry: regular (module docstring)
HOME_POSE = (5.0, 2.0, 5.0, -0.3, -0.5, 0.3)


def base_points() -> list[sp.Matrix]:
    """A_1..A_6 in {B} (A_1 = O)."""
    return [sp.zeros(3, 1)] + [sp.Matrix([XA[k], YA[k], 0]) for k in range(5)]


def platform_points() -> list[sp.Matrix]:
    """B_1^(P)..B_6^(P) in {P}, eq (1)."""
    return [sp.zeros(3, 1)] + [sp.Matrix([t11 * XA[k] + t12 * YA[k], t22 * YA[k], 0]) for k in range(5)]


def system8_matrix() -> sp.Matrix:
    """The 5x5 coefficient matrix of eq (8): rows [x, y, x^2, y^2, x y] of A_2..A_6."""
    return sp.Matrix([[XA[k], YA[k], XA[k] ** 2, YA[k] ** 2, XA[k] * YA[k]] for k in range(5)])


def base_scale2() -> sp.Expr:
    """The mean square distance of A2..A6 from A1 = O (m^2), the scale of the base (kept positive
    when every point sits at O)."""
    return sp.Max(sum(XA[k] ** 2 + YA[k] ** 2 for k in range(5)) / 5, 1e-300)


def normalised_conic_determinant(det_m: sp.Expr, scale2: sp.Expr) -> sp.Expr:
    """det M (eq 14) made scale-free: with the base coordinates divided by s = sqrt(scale2) (the
    columns x, y of M scale by 1/s, x^2, y^2, xy by 1/s^2: det by 1/s^8 = 1/scale2^4), divided by
    an upper bound of its row norms, sqrt(r^2 / s^2 + r^4 / s^4) >= |row| (r^2 = x^2 + y^2), so that
    |measure| <= 1 (Hadamard), invariant under scaling and rotating the base. Coincident points
    (a zero row) give 0, not 0 / 0."""
    rows = [(XA[k] ** 2 + YA[k] ** 2) / scale2 + (XA[k] ** 2 + YA[k] ** 2) ** 2 / scale2**2 for k in range(5)]
    return det_m / sp.Max(scale2**4 * sp.sqrt(sp.Mul(*rows)), 1e-300)


def system8_rhs() -> sp.Matrix:
    """L_i of eq (7), i = 2..6."""
    rows = []
    for k, b in enumerate(platform_points()[1:]):
        rows.append((lengths[k + 1] ** 2 - b[0] ** 2 - b[1] ** 2 - XA[k] ** 2 - YA[k] ** 2 - lengths[0] ** 2) / 2)
    return sp.Matrix(rows)


def conic_matrix() -> sp.Matrix:
    """Rows [1, x, y, x^2, y^2, x y] of A_1..A_6: det = 0 iff the six base points lie on a conic."""
    points = [(0, 0)] + list(zip(XA, YA, strict=True))
    return sp.Matrix([[1, px, py, px**2, py**2, px * py] for px, py in points])


def leg_vectors(rotation: sp.Matrix, position: sp.Matrix) -> list[sp.Matrix]:
    """d_i = B_i - A_i = p + R B_i^(P) - A_i."""
    return [position + rotation * b - a for a, b in zip(base_points(), platform_points(), strict=True)]


#: the platform's coordinates: the position and Z-Y-X Euler angles read off ^B_P T
MOTION = joints.Platform(
    "transform",
    (x, y, z, alpha, beta, gamma),
    euler_zyx_rotation(alpha, beta, gamma),
    sp.Matrix([x, y, z]),
    read=(
        (x, POSE_POSITION[0]),
        (y, POSE_POSITION[1]),
        (z, POSE_POSITION[2]),
        (alpha, sp.atan2(POSE_ROTATION[1, 0], POSE_ROTATION[0, 0])),
        (beta, sp.atan2(-POSE_ROTATION[2, 0], sp.sqrt(POSE_ROTATION[0, 0] ** 2 + POSE_ROTATION[1, 0] ** 2))),
        (gamma, sp.atan2(POSE_ROTATION[2, 1], POSE_ROTATION[2, 2])),
    ),
    pose=(POSE_ROTATION, POSE_POSITION),
    angular=(alpha, beta, gamma),
)
#: the model: six S-P-S legs from A_i to B_i^(P); closure, rates, the singularity factor, the
#: inverse and the drawing are derived from it (the forward elimination below is the paper's)
MODEL = joints.DistanceMechanism(
    MOTION,
    [
        joints.prismatic_leg(a, b, lengths[k])
        for k, (a, b) in enumerate(zip(base_points(), platform_points(), strict=True))
    ],
)


def forward() -> ForwardElimination:
    matrix, rhs = system8_matrix(), system8_rhs()
    det_m, scale2 = sp.symbols("det_M scale2", real=True)
    big_l = sp.symbols("L2:7", real=True)
    ix, iy, e1, e2, a1, a2 = sp.symbols("i_x i_y e1 e2 a1 a2", real=True)
    adjugate = matrix.adjugate()
    auxiliary: list[tuple[sp.Symbol, sp.Expr]] = [(big_l[k], rhs[k]) for k in range(5)]
    auxiliary.append((det_m, sp.expand(matrix.det(method="berkowitz"))))
    # eq (8) by Cramer's rule
    auxiliary += [(u[j], sum(sp.expand(adjugate[j, k]) * big_l[k] for k in range(5)) / det_m) for j in range(5)]
    auxiliary += [
        (ix, -u[2] / t11),  # eq (11)
        (e1, -t11 / t22),
        (e2, -t12 / t22),
        (a1, -(u[4] + t12 * ix) / t22),  # eq (20): j_x = e1 i_y + a1
        (a2, -u[3] / t22),  # eq (19): j_y = e2 i_y + a2
    ]
    jx, jy = e1 * iy + a1, e2 * iy + a2
    quartic = sp.Poly(sp.expand((1 - ix**2 - iy**2) * (1 - jx**2 - jy**2) - (ix * jx + iy * jy) ** 2), iy)
    coefficients = [quartic.coeff_monomial(iy**k) for k in range(5)]  # eq (23), ascending

    sigma, tau = sp.symbols("sigma tau", real=True)
    names = "j_x j_y w_i w_j i_dot_j s_dot i_z j_z g11 g12 g22 det_G c1 c2 h2"
    jx_s, jy_s, wi, wj, dot, sdot, iz, jz, g11, g12, g22, det_g, c1, c2, h2 = sp.symbols(names, real=True)
    i_p = sp.Matrix([ix, iy, iz])
    j_p = sp.Matrix([jx_s, jy_s, jz])
    n1 = t11 * i_p - sp.Matrix([1, 0, 0])  # eq (9): n1 . p = u1
    n2 = t12 * i_p + t22 * j_p - sp.Matrix([0, 1, 0])  # eq (10): n2 . p = u2
    back = [
        (jx_s, jx),
        (jy_s, jy),
        (wi, 1 - ix**2 - iy**2),
        (wj, 1 - jx_s**2 - jy_s**2),
        (dot, ix * jx_s + iy * jy_s),
        (sdot, dot / sp.Max(sp.Abs(dot), 1e-300)),  # sign(dot); exactly 0 only at i_z = 0 = i.j
        (iz, sigma * sp.sqrt(sp.Max(0, wi))),  # eq (24)
        (jz, -sigma * sdot * sp.sqrt(sp.Max(0, wj))),  # eq (25): i_z j_z = -(i_x j_x + i_y j_y)
        (g11, n1.dot(n1)),
        (g12, n1.dot(n2)),
        (g22, n2.dot(n2)),
        (det_g, sp.Max(g11 * g22 - g12**2, 1e-300)),  # |n1 x n2|^2
        (c1, (g22 * u[0] - g12 * u[1]) / det_g),
        (c2, (g11 * u[1] - g12 * u[0]) / det_g),
    ]
    p0 = c1 * n1 + c2 * n2
    back.append((h2, lengths[0] ** 2 - p0.dot(p0)))  # eq (5) on the line p0 + s (n1 x n2)
    position = p0 + tau * sp.sqrt(sp.Max(0, h2) / det_g) * n1.cross(n2)
    # at a root i_P, j_P are orthonormal; Gram-Schmidt keeps the pose of a near-double root (or of
    # a candidate that is no mode, rejected downstream by its leg residual) a rigid transform
    i_n, j_t, j_n = sp.symbols("i_norm j_tangent j_norm", real=True)
    back += [(i_n, sp.sqrt(sp.Max(i_p.dot(i_p), 1e-300))), (j_t, j_p.dot(i_p) / i_n)]
    j_perp = j_p - j_t * i_p / i_n
    back.append((j_n, sp.sqrt(sp.Max(j_perp.dot(j_perp), 1e-300))))
    i_unit, j_unit = i_p / i_n, j_perp / j_n
    pose = homogeneous(sp.Matrix.hstack(i_unit, j_unit, i_unit.cross(j_unit)), position)
    # normalised det M (the architecture measure, here on the auxiliaries): 0 on a conic
    auxiliary.insert(0, (scale2, base_scale2()))
    degeneracies = {
        "base_points_on_a_conic": normalised_conic_determinant(det_m, scale2),
        "platform_map_singular": t11 * t22,
    }
    return ForwardElimination(iy, coefficients, [sigma, tau], auxiliary, back, pose, degeneracies)


def defaults() -> dict[sp.Symbol, float]:
    """The default geometry: ``DEFAULT_BASE`` and section 5.4's platform map (module docstring)."""
    values: dict[sp.Symbol, float] = {}
    values.update({XA[k]: DEFAULT_BASE[k][0] for k in range(5)})
    values.update({YA[k]: DEFAULT_BASE[k][1] for k in range(5)})
    values.update(dict(zip((t11, t12, t22), SECTION_54_T, strict=True)))
    return values


def xyz_euler_transform(values: tuple[float, ...]) -> sp.Matrix:
    """^B_P T of {x y z alpha beta gamma} (Z-Y-X Euler angles), numerically."""
    rotation = euler_zyx_rotation(*(sp.Float(v, 17) for v in values[3:]))
    return homogeneous(rotation, [sp.Float(v, 17) for v in values[:3]]).evalf(17)


def home() -> dict[sp.Symbol, float]:
    """``HOME_POSE`` with its leg lengths l_i = |p + R B_i^(P) - A_i| on the default geometry."""
    pose = xyz_euler_transform(HOME_POSE)
    legs = leg_vectors(pose[:3, :3], pose[:3, 3])
    values = {lengths[k]: float(sp.sqrt(d.dot(d)).xreplace(defaults())) for k, d in enumerate(legs)}
    values.update(zip((x, y, z, alpha, beta, gamma), HOME_POSE, strict=True))
    return values


def examples() -> list[Example]:
    """Section 5.4: the paper prints the base, the platform map and the locked lengths, and no
    pose. Its geometry is architecturally singular (base on a conic; load warns), and the lengths
    lock a self-motion, not a pose: forward_pose_all raises there (SelfMotionError on compatible
    lengths; the printed ones are compatible only within their rounding, tests/test_gough.py). So
    the example is a pose of the self-motion (``SECTION_54_POSE``) whose inverse pose gives the
    printed l1..l6 to their rounding (tolerance 5e-3 m, half a unit in the last printed digit)."""
    pose = xyz_euler_transform(SECTION_54_POSE)
    return [
        Example(
            name="section54_self_motion",
            description="section 5.4's architecturally singular geometry (base A2..A6 = (5,-5) (9,-3) (10,0) "
            "(9,3) (5,5) on the conic (x - 5)^2 + y^2 = 25, t11 = t12 = t22 = 1; load warns): a pose on the "
            "self-motion of its locked inputs has the printed lengths l1..l6 = 33.17, 32.02, 35.12, 37.57, "
            "39.01, 38.32 to their rounding (5e-3 m); forward_pose_all at these lengths raises (a self-motion, "
            "not isolated modes: examples/gough_architecture.py)",
            pose=[[float(pose[i, j]) for j in range(4)] for i in range(4)],
            parameters=dict(SECTION_54_PARAMETERS),
            expected={"actuated": list(SECTION_54_LENGTHS)},
            tolerance=5e-3,
        )
    ]


def parameter_info() -> dict[sp.Symbol, ParameterInfo]:
    """Section 5.4 prints the base without a unit: read as metres (module docstring)."""
    info = {}
    for k in range(5):
        info[XA[k]] = ParameterInfo("m", f"x of the base joint A{k + 2} in {{B}} (A1 = O), eq (1)")
        info[YA[k]] = ParameterInfo("m", f"y of the base joint A{k + 2} in {{B}} (A1 = O), eq (1)")
    info[t11] = ParameterInfo("", "platform map, eq (1): x_B = t11 x_A + t12 y_A (t11 t22 != 0)", "nonzero")
    info[t12] = ParameterInfo("", "platform map, eq (1): shear term of x_B = t11 x_A + t12 y_A")
    info[t22] = ParameterInfo("", "platform map, eq (1): y_B = t22 y_A (t11 t22 != 0)", "nonzero")
    return info


def build() -> Mechanism:
    return Mechanism(
        name="gough",
        title="6-SPS platform with linearly related planar platforms (Kong & Gosselin)",
        citation=Citation(
            ("X. Kong", "C. M. Gosselin"),
            "Generation of architecturally singular 6-SPS parallel manipulators with linearly related planar platforms",
            2002,
            "Electronic Journal of Computational Kinematics",
        ),
        parameters=defaults(),
        **MODEL.fields() | {"closure": MODEL.closure(squared=False)},
        forward=forward(),
        home=home(),
        limits={length: (0.0, float("inf")) for length in lengths},  # leg lengths
        architecture=architecture(),
        # a normalised measure (|.| <= 1): below this the base lies on a conic (load warns)
        architecture_tolerance=1e-9,
        parameter_info=parameter_info(),
        parameter_groups={"base": sp.Matrix([[XA[k], YA[k]] for k in range(5)])},
        examples=examples(),
    )


def architecture() -> dict[str, sp.Expr]:
    """Eq (14): det M of system (8). It is checked here to be, term by term, the six-point conic
    determinant det[1, x, y, x^2, y^2, x y] of A1..A6 (A1 = O): it vanishes exactly when the base
    points lie on a conic, eq (15). The measure is det M normalised (``normalised_conic_
    determinant``: scale-free, |measure| <= 1), so that ``architecture_tolerance`` decides."""
    det_m = sp.expand(system8_matrix().det(method="berkowitz"))
    if sp.expand(det_m - conic_matrix().det(method="berkowitz")) != 0:
        raise ValueError("det M of system (8) is not the six-point conic determinant")
    return {"normalised_six_point_conic_determinant": normalised_conic_determinant(det_m, base_scale2())}
