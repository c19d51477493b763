"""Accelerator of ``sps.py`` (optional): the paper's closure (eq 7) and the forward pose eliminated
by hand in the angles on the cones of legs 1 and 2, a degree-8 polynomial (eqs 2-6), with the
drawing's centre spokes. Without it the generator derives the closure from the joints and finds
the forward pose by its automatic homotopy. Derivation: ``docs/derivations/sps.md``.
"""

from __future__ import annotations

import sympy as sp
from parakin.generator.elimination import biquadratic_resultant, half_angle_grid
from parakin.generator.frames import homogeneous
from parakin.generator.model import ClosureModel, Drawing, ForwardElimination

NEWTON_STEPS = 6  # Cayley-Newton steps of the back substitution
NEWTON_REACH = sp.Rational(1, 5)  # rad: how far from a closure those steps reach (see _cayley_newton)
T_HALF = sp.Symbol("t", real=True)
Q12 = sp.Symbol("q12", real=True)
COSINES = sp.symbols("c12 s12 p1 p2 p3 rho1 rho2 e1 e2 e3 k1 k2 k3", real=True)
PLATFORM = [sp.Matrix(sp.symbols(f"b{i}p_x b{i}p_y b{i}p_z", real=True)) for i in (1, 2, 3)]


def closure(
    base: list[sp.Matrix], platform: list[sp.Matrix], lengths: tuple[sp.Symbol, ...], rotation: sp.Matrix
) -> ClosureModel:
    """The paper's closure g_i = a_i^2 + b_i^2 - 2 a_i . R b_ip - d_i^2 = 0 (eq 7), as written (its
    Jacobians are eqs 11a and 12); R is always a proper rotation, so the alignment is 1."""
    rows = [
        a.dot(a) + bp.dot(bp) - 2 * a.dot(rotation * bp) - lengths[i] ** 2
        for i, (a, bp) in enumerate(zip(base, platform, strict=True))
    ]
    return ClosureModel(sp.Matrix(rows), sp.Matrix([sp.Integer(1)]), homogeneous(rotation, [0, 0, 0]))


def drawing(parts: Drawing) -> Drawing:
    """The model's parts (base points A_i, platform points B_i = R b_ip, the legs A_i -> B_i, the
    base and platform triangles) with the centre Q on both bodies and the spokes from Q to the
    points of each body (the central spherical joint)."""
    centre = sp.zeros(3, 1)
    spokes = [0, 3, 1, 3, 2]  # A1 (B1) -> Q -> A2 (B2) -> Q -> A3 (B3)
    points = {name: sp.Matrix.hstack(parts.points[name], centre) for name in ("base", "platform")}
    polylines = parts.polylines | {
        "base_spokes": [("base", i) for i in spokes],
        "platform_spokes": [("platform", i) for i in spokes],
    }
    return Drawing(points=points, polylines=polylines)


def cone_grids() -> tuple[sp.Matrix, sp.Matrix]:
    """The closure as two equations bilinear in f(phi) = (1, cos phi, sin phi) and f(psi), in the
    canonical base frame a1o = (1, 0, 0), a2o = (c12, s12, 0), a3o = (e1, e2, e3): b1o = p1 a1o +
    rho1 (cos phi y_b + sin phi z_b) on the cone of leg 1 (eq 1b), b2o = p2 a2o + rho2 (cos psi n2 +
    sin psi z_b) on the cone of leg 2 (n2 = z_b x a2o), rho_i = sqrt(1 - p_i^2); E1 = b1o . b2o -
    q12 (eq 4) and E2 = a3o . b3o - p3 (eq 6) with b3o = k1 b1o + k2 b2o + k3 b1o x b2o (eq 5; k1,
    k2, k3 are platform constants). Entry [j, k] multiplies f_j(phi) f_k(psi)."""
    c12, s12, p1, p2, p3, rho1, rho2, e1, e2, e3, k1, k2, k3 = COSINES
    a1o, a2o, a3o = sp.Matrix([1, 0, 0]), sp.Matrix([c12, s12, 0]), sp.Matrix([e1, e2, e3])
    z = sp.Matrix([0, 0, 1])
    leg1 = [p1 * a1o, rho1 * sp.Matrix([0, 1, 0]), rho1 * z]
    leg2 = [p2 * a2o, rho2 * z.cross(a2o), rho2 * z]
    first, second = sp.zeros(3, 3), sp.zeros(3, 3)
    for j in range(3):
        for k in range(3):
            first[j, k] = leg1[j].dot(leg2[k])
            second[j, k] = k3 * a3o.dot(leg1[j].cross(leg2[k]))
            if k == 0:
                second[j, k] += k1 * a3o.dot(leg1[j])
            if j == 0:
                second[j, k] += k2 * a3o.dot(leg2[k])
    first[0, 0] -= Q12
    second[0, 0] -= p3
    return first.applyfunc(sp.expand), second.applyfunc(sp.expand)


def _cayley_newton(
    base: list[sp.Matrix], radii: tuple[sp.Symbol, ...], rotation: sp.Matrix, step: int
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], sp.Matrix]:
    """One Newton step on a_i . R b_ip = |a_i| b_i p_i (the leg equations), R <- Cay(w) R.

    The step is gated, w / (1 + (|w| / NEWTON_REACH)^4): a candidate within a few hundredths of
    a radian of a closure (a root near a branch point) converges, one further away (the wrong
    branch tau) stays put and is rejected by the runtime, instead of drifting into another mode.
    It is regularised where the Jacobian (rows R b_ip x a_i) is singular. Platform points come
    from the symbols ``PLATFORM`` (assigned in the auxiliaries)."""
    assignments: list[tuple[sp.Symbol, sp.Expr]] = []
    c12, s12, p1, p2, p3, *_ = COSINES
    targets = [p1, p2, p3]
    jacobian = sp.Matrix(3, 3, sp.symbols(f"newton{step}_J1:10", real=True))
    residual = sp.Matrix(sp.symbols(f"newton{step}_g1:4", real=True))
    for i, (a, bp) in enumerate(zip(base, PLATFORM, strict=True)):
        point = rotation * bp
        value = a.dot(point) - sp.sqrt(a.dot(a)) * radii[i] * targets[i]
        row = point.cross(a)
        assignments.append((residual[i], value))
        assignments += [(jacobian[i, k], row[k]) for k in range(3)]
    det = sp.Symbol(f"newton{step}_det", real=True)
    w = sp.Matrix(sp.symbols(f"newton{step}_w1:4", real=True))
    gate = sp.Symbol(f"newton{step}_gate", real=True)
    raw = -(jacobian.adjugate() * residual)
    assignments.append((det, jacobian.det()))
    assignments += [(w[k], raw[k] * det / (det**2 + sp.Float(1e-24))) for k in range(3)]
    assignments.append((gate, 1 / (1 + (w.dot(w) / NEWTON_REACH**2) ** 2)))
    u = w * gate / 2
    skew = sp.Matrix([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    cayley = sp.eye(3) + 2 / (1 + u.dot(u)) * (skew + skew * skew)
    names = " ".join(f"R{step}_{j}{k}" for j in (1, 2, 3) for k in (1, 2, 3))
    updated = sp.Matrix(3, 3, sp.symbols(names, real=True))
    product = cayley * rotation
    assignments += [(updated[j, k], product[j, k]) for j in range(3) for k in range(3)]
    return assignments, updated


def forward(
    base: list[sp.Matrix],
    platform: list[sp.Matrix],
    lengths: tuple[sp.Symbol, ...],
    radii: tuple[sp.Symbol, ...],
    cosines: tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr],
    chi: sp.Symbol,
) -> ForwardElimination:
    """The forward elimination of a 3(SPS)-S with base points ``base`` (A1 on x_b, A2 in the x_b
    y_b plane), platform points ``platform`` at distances ``radii`` from Q, leg lengths ``lengths``,
    the platform's cosines q12, q13, q23 and Gram determinant D3 (``cosines``, eqs 1c and 5) and
    its handedness ``chi``: the degree-8 resultant in t = tan(phi / 2), branch tau the zero of psi."""
    c12, s12, p1, p2, p3, rho1, rho2, e1, e2, e3, k1, k2, k3 = COSINES
    a = base
    q12e, q13e, q23e, d3e = cosines
    a2n, a3n = sp.sqrt(a[1].dot(a[1])), sp.sqrt(a[2].dot(a[2]))
    q13, q23, s3 = sp.symbols("q13 q23 s3", real=True)
    auxiliary: list[tuple[sp.Symbol, sp.Expr]] = [
        (c12, a[1][0] / a2n),
        (s12, a[1][1] / a2n),
        (e1, a[2][0] / a3n),
        (e2, a[2][1] / a3n),
        (e3, a[2][2] / a3n),
        (Q12, q12e),
        (q13, q13e),
        (q23, q23e),
        (s3, chi * sp.sqrt(sp.Max(0, d3e))),
        # b3o = k1 b1o + k2 b2o + k3 b1o x b2o (eq 5)
        (k1, (q13 - Q12 * q23) / (1 - Q12**2)),
        (k2, (q23 - Q12 * q13) / (1 - Q12**2)),
        (k3, s3 / (1 - Q12**2)),
    ]
    for symbols, point in zip(PLATFORM, platform, strict=True):
        auxiliary += [(symbols[k], point[k]) for k in range(3)]
    for i, (p, bi) in enumerate(zip((p1, p2, p3), radii, strict=True)):
        norm = sp.sqrt(a[i].dot(a[i]))
        auxiliary.append((p, (norm**2 + bi**2 - lengths[i] ** 2) / (2 * norm * bi)))  # eq (1b)
    # |p_i| > 1: leg i cannot reach; rho_i = 0 then, and the roots found do not close
    auxiliary += [(rho1, sp.sqrt(sp.Max(0, 1 - p1**2))), (rho2, sp.sqrt(sp.Max(0, 1 - p2**2)))]
    # E1, E2 biquadratic in the tangent half angles x = tan(phi / 2), y = tan(psi / 2);
    # the resultant in y is the degree-8 forward polynomial in x = t
    first, second = cone_grids()
    elimination = biquadratic_resultant(T_HALF)
    for symbols, grid in zip((elimination.first, elimination.second), (first, second), strict=True):
        full = half_angle_grid(grid)  # [p, q]: coefficient of x^p y^q
        auxiliary += [(symbols[k][j], sp.expand(full[j, k])) for k in range(3) for j in range(3)]
    # the grids themselves, for the back substitution on the unit circle
    grid_symbols = [sp.Matrix(3, 3, sp.symbols(f"E{n}_0:3(0:3)", real=True)) for n in (1, 2)]
    for symbols, grid in zip(grid_symbols, (first, second), strict=True):
        auxiliary += [(symbols[j, k], grid[j, k]) for j in range(3) for k in range(3)]

    # back substitution: phi from t; at a root, E1 and E2 are alpha + beta cos psi + gamma sin psi
    # with a common zero psi; it is taken from E = |E1| E1 + |E2| E2 (|.| the coefficient norm:
    # E1 alone vanishes identically where b1o = +-a2o, E2 alone where a3o is normal to b3o's
    # circle), on branch tau (its other zero is not a configuration and does not close, except at
    # a double root t, where both are configurations); then b1o, b2o, R and Newton polish
    tau = sp.Symbol("tau", real=True)
    cos_phi, sin_phi = sp.symbols("cos_phi sin_phi", real=True)
    f_phi = sp.Matrix([1, cos_phi, sin_phi])
    back: list[tuple[sp.Symbol, sp.Expr]] = [
        (cos_phi, (1 - T_HALF**2) / (1 + T_HALF**2)),
        (sin_phi, 2 * T_HALF / (1 + T_HALF**2)),
    ]
    lines, weights = [], []
    for n, symbols in enumerate(grid_symbols, start=1):
        line = sp.Matrix(sp.symbols(f"E{n}_alpha E{n}_beta E{n}_gamma", real=True))
        weight = sp.Symbol(f"E{n}_weight", real=True)
        row = f_phi.T * symbols
        back += [*((line[k], row[k]) for k in range(3)), (weight, sp.sqrt(line.dot(line)))]
        lines.append(line)
        weights.append(weight)
    lin = sp.Matrix(sp.symbols("E_alpha E_beta E_gamma", real=True))
    norm2, disc, root = sp.symbols("E_norm2 E_discriminant E_root", real=True)
    cos_psi, sin_psi = sp.symbols("cos_psi sin_psi", real=True)
    combined = weights[0] * lines[0] + weights[1] * lines[1]
    back += [
        *((lin[k], combined[k]) for k in range(3)),
        (norm2, lin[1] ** 2 + lin[2] ** 2),
        (disc, norm2 - lin[0] ** 2),
        # a slightly negative discriminant (where the two zeros meet) is clamped
        (root, tau * sp.sqrt(sp.Max(0, disc))),
        (cos_psi, (-lin[0] * lin[1] - root * lin[2]) / norm2),
        (sin_psi, (-lin[0] * lin[2] + root * lin[1]) / norm2),
    ]
    b1o = sp.Matrix(sp.symbols("b1o_x b1o_y b1o_z", real=True))
    b2o = sp.Matrix(sp.symbols("b2o_x b2o_y b2o_z", real=True))
    a2o = sp.Matrix([c12, s12, 0])
    z = sp.Matrix([0, 0, 1])
    b1_value = sp.Matrix([p1, rho1 * cos_phi, rho1 * sin_phi])
    b2_value = p2 * a2o + rho2 * (cos_psi * z.cross(a2o) + sin_psi * z)
    back += [*((b1o[k], b1_value[k]) for k in range(3)), *((b2o[k], b2_value[k]) for k in range(3))]
    # R = [x y z]: x along b1o, y along the part of b2o normal to it, z = x cross y (the platform
    # frame is canonical); normalised, so that R is a rotation for every real root, even one that
    # is not a configuration; such roots do not close
    x_axis = sp.Matrix(sp.symbols("x_axis1:4", real=True))
    y_axis = sp.Matrix(sp.symbols("y_axis1:4", real=True))
    x_norm, y_norm = sp.symbols("x_axis_norm y_axis_norm", real=True)
    back += [(x_norm, sp.sqrt(b1o.dot(b1o)))]
    back += [(x_axis[k], b1o[k] / x_norm) for k in range(3)]
    y_raw = b2o - x_axis.dot(b2o) * x_axis
    back += [(y_norm, sp.sqrt(y_raw.dot(y_raw)))]
    back += [(y_axis[k], y_raw[k] / y_norm) for k in range(3)]
    rotation = sp.Matrix.hstack(x_axis, y_axis, x_axis.cross(y_axis))
    start = sp.Matrix(3, 3, sp.symbols("R0_11 R0_12 R0_13 R0_21 R0_22 R0_23 R0_31 R0_32 R0_33", real=True))
    back += [(start[j, k], rotation[j, k]) for j in range(3) for k in range(3)]
    current = start
    for step in range(1, NEWTON_STEPS + 1):
        assignments, current = _cayley_newton(base, radii, current, step)
        back += assignments
    return ForwardElimination(
        unknown=T_HALF,
        coefficients=elimination.coefficients,
        branches=[tau],
        auxiliary=auxiliary,
        back_substitution=back,
        pose=homogeneous(current, [0, 0, 0]),
        degeneracies={},
    )
