"""An independent oracle of the real assembly modes, and the hostile inputs that test the solvers'
certificates against it (issue 31).

Nothing here calls parakin's solvers: no ``forward_pose_all``, no homotopy, no certification.
The closure equations are written again from the geometry (the conventions of the mechanisms'
docstrings), every float is converted exactly to a rational (a float is a dyadic rational), the
system is eliminated to one univariate polynomial in exact rational arithmetic and its real roots
are counted and isolated exactly (SymPy's real root isolation over QQ: Sturm/Descartes, exact),
then back-substituted to poses in mpmath at ``DIGITS`` digits and checked by their closure
residual in the same arithmetic.

* planar 3-RPR (base A_i, platform b_i in {P}, leg lengths rho_i; pose (x, y, phi), B_i = p +
  R(phi) b_i): with q = B_1 - A_1, m_i = R (b_i - b_1) - (A_i - A_1), legs 2 and 3 minus leg 1 are
  m_i . q = (rho_i^2 - rho_1^2 - |m_i|^2) / 2, linear in q; Cramer's rule and leg 1, |q| = rho_1,
  give |adj(M) h|^2 - rho_1^2 det(M)^2 = 0, of degree 4 in (cos phi, sin phi). With phi = phi0 +
  2 atan(t) (cos phi0, sin phi0 a rational point of the circle, Pythagorean), times (1 + t^2)^4: a
  polynomial P(t) of degree 8. A real root is exactly one mode where det M != 0 there; t = infinity
  (phi = phi0 + pi) is avoided by taking the next offset phi0 when the leading coefficient
  vanishes; an input where Cramer's rule fails at a real root (gcd(P, det M) has a real root) or
  where P vanishes identically (a self-motion) is declared unusable (``Modes.count`` None), not
  guessed.
* planar 3-RRR: with the cranks given, the elbows E_i = A_i + a_i (cos theta_i, sin theta_i) are
  fixed and the links rigid: a 3-RPR on the elbows with the link lengths b_i as legs.
* five-bar: two circles about the elbows C_i (radii b_i): a quadratic whose discriminant's sign is
  decided exactly.
* three spheres (the rotary delta, a linear delta): p at distance l_i from three centres; the
  radical line of the spheres and one quadratic along it, decided exactly.

Angles of actuated revolute joints enter through cos and sin, which are not rational: they are
taken to ``TRIG_BITS`` bits (about 96 digits), so the polynomial is that of the exact input up to
1e-96 relative. The solvers evaluate them in double precision, so an input within rounding of a
fold (a step of 0 from it) may have one count for the exact input and another for the rounded
one: ``Modes.robust`` says whether the count with cos and sin rounded to double (``math``) is the
same; a test should decide only robust inputs.

Input generators (``FAMILIES``): random geometries perturbed from the defaults (seeded), scaled by
any factor (every length parameter and every prismatic input; angles unchanged), random inputs
from this module's own inverse of random poses, and near-fold inputs: one actuated value bisected
(by the oracle's exact count) to adjacent floats between an input with k and one with k + 2 real
modes, then stepped off by 0 (the two bracketing floats), 1e-9 and 1e-6 (relative to the value for
a length, in radians for an angle) to both sides.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from functools import cache, lru_cache

import mpmath
import numpy as np
import sympy as sp

#: digits of the back-substituted poses
DIGITS = 60
#: bits of cos and sin of an actuated angle taken as a rational
TRIG_BITS = 320
#: the relative move of an input within which a count must not change for a double-precision
#: certificate to be held to it (``Family.stable``): 1000 times the rounding of coefficients
STABLE = 1e-12
#: rational points (cos phi0, sin phi0) of the circle for the half-angle substitution: the next
#: one is taken when phi0 + pi is a root (the polynomial's leading coefficient vanishes)
OFFSETS = [(Fraction(1), Fraction(0)), (Fraction(3, 5), Fraction(4, 5)), (Fraction(-5, 13), Fraction(12, 13)),
           (Fraction(8, 17), Fraction(-15, 17)), (Fraction(-24, 25), Fraction(-7, 25))]  # fmt: skip
T = sp.Symbol("t")

Poly = list[Fraction]  # coefficients, constant first


@dataclass(frozen=True)
class Modes:
    """The oracle's answer for one input. ``count``: distinct real assembly modes (None: the
    oracle cannot decide, ``reason`` says why); ``poses``: the modes' passive coordinates (as
    the mechanism orders them, angles wrapped to (-pi, pi]) to ``DIGITS`` digits; ``on_fold``:
    a multiple real root (the input is exactly on a fold: no mode there is regular); ``robust``:
    the count does not change when the actuated angles' cos and sin are rounded to double;
    ``closest``: the smallest distance between two roots of the eliminant in the complex plane
    (in its own variable; how near the input is to a fold), NaN where not computed."""

    count: int | None
    poses: tuple[tuple[mpmath.mpf, ...], ...] = ()
    reason: str = ""
    on_fold: bool = False
    robust: bool = True
    closest: float = math.nan

    @property
    def usable(self) -> bool:
        """The count is decided, not on a fold and robust to the rounding of the inputs."""
        return self.count is not None and not self.on_fold and self.robust

    def array(self) -> np.ndarray:
        """The poses as floats, (count, n_passive)."""
        width = len(self.poses[0]) if self.poses else 0
        return np.array([[float(v) for v in pose] for pose in self.poses], dtype=float).reshape(len(self.poses), width)


def exact(value: float | Fraction | mpmath.mpf) -> Fraction:
    """A float (or an mpmath number, binary too) as the rational it is, exactly."""
    if isinstance(value, Fraction):
        return value
    if isinstance(value, mpmath.mpf):
        return Fraction(*mpmath.libmp.to_rational(value._mpf_))
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"not a finite number: {value!r}")
    return Fraction(value)


def trig(angle: float, rounded: bool = False) -> tuple[Fraction, Fraction]:
    """(cos, sin) of a float angle as rationals: to TRIG_BITS bits, or the double-precision
    values of ``math`` (``rounded``)."""
    if rounded:
        return Fraction(math.cos(angle)), Fraction(math.sin(angle))
    with mpmath.workprec(TRIG_BITS + 20):
        theta = mpmath.mpf(float(angle))
        c, s = mpmath.cos(theta), mpmath.sin(theta)
    return _round(c), _round(s)


def _round(value: mpmath.mpf) -> Fraction:
    return Fraction(round(exact(value) * 2**TRIG_BITS), 2**TRIG_BITS)


# ------------------------------------------------------------------ polynomials over Fractions
def _add(*polys: Poly) -> Poly:
    out = [Fraction(0)] * max(len(p) for p in polys)
    for p in polys:
        for k, v in enumerate(p):
            out[k] += v
    return out


def _mul(p: Poly, q: Poly) -> Poly:
    out = [Fraction(0)] * (len(p) + len(q) - 1)
    for i, u in enumerate(p):
        if u:
            for j, v in enumerate(q):
                out[i + j] += u * v
    return out


def _scale(p: Poly, k: Fraction) -> Poly:
    return [k * v for v in p]


def _sub(p: Poly, q: Poly) -> Poly:
    return _add(p, _scale(q, Fraction(-1)))


def _sympy(p: Poly) -> sp.Poly:
    return sp.Poly([sp.Rational(v.numerator, v.denominator) for v in reversed(p)], T, domain=sp.QQ)


def _mp(value: Fraction) -> mpmath.mpf:
    return mpmath.mpf(value.numerator) / value.denominator


def _horner(p: Poly, t: mpmath.mpf) -> mpmath.mpf:
    """p(t) in mpmath, the rational coefficients taken exactly to the working precision."""
    out = mpmath.mpf(0)
    for v in reversed(p):
        out = out * t + _mp(v)
    return out


def _wrap(angle: mpmath.mpf) -> mpmath.mpf:
    wrapped = angle - 2 * mpmath.pi * mpmath.floor((angle + mpmath.pi) / (2 * mpmath.pi))
    return mpmath.pi if wrapped == -mpmath.pi else wrapped


# ------------------------------------------------------------------ real roots, exactly
@dataclass(frozen=True)
class _Roots:
    intervals: list[tuple[Fraction, Fraction]]  # isolating intervals of the distinct real roots
    squarefree: sp.Poly
    on_fold: bool


def _real_roots(p: sp.Poly) -> _Roots:
    g = p.gcd(p.diff(T))
    on_fold = g.degree() > 0 and g.count_roots() > 0
    squarefree = p.quo(g) if g.degree() > 0 else p
    found = squarefree.intervals()
    intervals = [(Fraction(int(a.p), int(a.q)), Fraction(int(b.p), int(b.q))) for (a, b), _ in found]
    return _Roots(intervals, squarefree, on_fold)


def _refine(squarefree: sp.Poly, interval: tuple[Fraction, Fraction]) -> mpmath.mpf:
    """The root in an isolating interval of ``squarefree`` to DIGITS digits: Newton in mpmath,
    bisection where a step would leave the bracket (the sign change is kept at every step)."""
    a, b = interval
    if a == b:
        return _mp(a)
    coefficients = [_mp(Fraction(int(v.p), int(v.q))) for v in reversed(squarefree.all_coeffs())]
    derivative = [k * v for k, v in enumerate(coefficients)][1:]

    def value(poly: list[mpmath.mpf], x: mpmath.mpf) -> mpmath.mpf:
        out = mpmath.mpf(0)
        for v in reversed(poly):
            out = out * x + v
        return out

    lo, hi = _mp(a), _mp(b)
    f_lo, f_hi = value(coefficients, lo), value(coefficients, hi)
    if f_lo == 0:
        return lo
    if f_hi == 0:
        return hi
    x = (lo + hi) / 2
    tolerance = mpmath.mpf(10) ** (-DIGITS - 10)
    for _ in range(2000):
        fx = value(coefficients, x)
        if fx == 0:
            return x
        if (fx > 0) == (f_lo > 0):
            lo, f_lo = x, fx
        else:
            hi = x
        slope = value(derivative, x)
        candidate = x - fx / slope if slope != 0 else (lo + hi) / 2
        if not lo < candidate < hi:
            candidate = (lo + hi) / 2
        if abs(candidate - x) <= tolerance * max(1, abs(x)) or hi - lo <= tolerance * max(1, abs(x)):
            return candidate
        x = candidate
    raise AssertionError("oracle: a root did not converge in its isolating interval")


def _closest(p: sp.Poly) -> float:
    """The smallest distance between two roots of p (its squarefree part) in C: how near a
    fold; NaN where mpmath does not converge."""
    if p.degree() < 2:
        return math.inf
    coefficients = [_mp(Fraction(int(v.p), int(v.q))) for v in p.all_coeffs()]
    try:
        roots = mpmath.polyroots(coefficients, maxsteps=400, extraprec=400)
    except mpmath.libmp.libhyper.NoConvergence:
        return math.nan
    return float(min(abs(u - v) for i, u in enumerate(roots) for v in roots[i + 1 :]))


# ------------------------------------------------------------------ the planar 3-RPR core
def _linear(k0: Fraction, kc: Fraction, ks: Fraction, c0: Fraction, s0: Fraction) -> Poly:
    """(1 + t^2) (k0 + kc cos phi + ks sin phi) with phi = phi0 + 2 atan t."""
    w = [Fraction(1), Fraction(0), Fraction(1)]
    nc = [c0, -2 * s0, -c0]
    ns = [s0, 2 * c0, -s0]
    return _add(_scale(w, k0), _scale(nc, kc), _scale(ns, ks))


def planar_rpr(
    base: Sequence[Sequence[Fraction]],
    platform: Sequence[Sequence[Fraction]],
    lengths: Sequence[Fraction],
    count_only: bool = False,
    closest: bool = False,
) -> Modes:
    """Every real mode of a planar 3-RPR with exact rational data (module docstring): base A_i,
    platform b_i (in {P}), leg lengths rho_i. Poses (x, y, phi)."""
    for c0, s0 in OFFSETS:
        result = _planar_rpr_offset(base, platform, lengths, c0, s0, count_only, closest)
        if result is not None:
            return result
    return Modes(None, reason="the eliminant vanishes at phi0 + pi for every offset (identically zero: a self-motion)")


def _planar_rpr_offset(base, platform, lengths, c0, s0, count_only, closest) -> Modes | None:  # noqa: ANN001
    a = [(Fraction(p[0]), Fraction(p[1])) for p in base]
    b = [(Fraction(p[0]), Fraction(p[1])) for p in platform]
    rho = [Fraction(v) for v in lengths]
    mx, my, h = {}, {}, {}
    for i in (1, 2):
        ux, uy = b[i][0] - b[0][0], b[i][1] - b[0][1]
        wx, wy = a[i][0] - a[0][0], a[i][1] - a[0][1]
        # m_i = R u_i - w_i; |m_i|^2 = |u|^2 + |w|^2 - 2 cos (w . u) - 2 sin (w_y u_x - w_x u_y)
        mx[i] = _linear(-wx, ux, -uy, c0, s0)
        my[i] = _linear(-wy, uy, ux, c0, s0)
        constant = (rho[i] ** 2 - rho[0] ** 2 - ux * ux - uy * uy - wx * wx - wy * wy) / 2
        h[i] = _linear(constant, wx * ux + wy * uy, wy * ux - wx * uy, c0, s0)
    det = _sub(_mul(mx[1], my[2]), _mul(my[1], mx[2]))
    qx = _sub(_mul(h[1], my[2]), _mul(h[2], my[1]))
    qy = _sub(_mul(mx[1], h[2]), _mul(mx[2], h[1]))
    octic = _sub(_add(_mul(qx, qx), _mul(qy, qy)), _scale(_mul(det, det), rho[0] ** 2))
    if not any(octic):
        return Modes(None, reason="the eliminant vanishes identically (a self-motion, or det M = 0 for every phi)")
    if octic[-1] == 0:
        return None  # phi0 + pi is a root, or the degree drops there: the next offset
    poly = _sympy(octic)
    roots = _real_roots(poly)
    if count_only:
        return Modes(len(roots.intervals), on_fold=roots.on_fold)
    det_poly = _sympy(det) if any(det) else None
    if det_poly is None:
        return Modes(None, reason="det M vanishes for every phi (Cramer's rule fails)")
    common = poly.gcd(det_poly)
    if common.degree() > 0 and common.count_roots() > 0:
        return Modes(None, reason="Cramer's rule fails at a real root (det M = 0 there)")
    with mpmath.workdps(DIGITS + 20):
        phi0 = mpmath.atan2(_mp(s0), _mp(c0))
        poses = []
        scale2 = max(rho) ** 2
        for interval in roots.intervals:
            t = _refine(roots.squarefree, interval)
            q = (_horner(qx, t) / _horner(det, t), _horner(qy, t) / _horner(det, t))
            phi = phi0 + 2 * mpmath.atan(t)
            c, s = mpmath.cos(phi), mpmath.sin(phi)
            px = _mp(a[0][0]) + q[0] - (c * _mp(b[0][0]) - s * _mp(b[0][1]))
            py = _mp(a[0][1]) + q[1] - (s * _mp(b[0][0]) + c * _mp(b[0][1]))
            for i in range(3):  # the closure of every leg, in the same arithmetic
                dx = px + c * _mp(b[i][0]) - s * _mp(b[i][1]) - _mp(a[i][0])
                dy = py + s * _mp(b[i][0]) + c * _mp(b[i][1]) - _mp(a[i][1])
                residual = abs(dx * dx + dy * dy - _mp(rho[i]) ** 2) / _mp(scale2)
                if residual > mpmath.mpf(10) ** (-DIGITS + 15):
                    raise AssertionError(f"oracle: a root does not close leg {i + 1} ({mpmath.nstr(residual, 5)})")
            poses.append((px, py, _wrap(phi)))
    poses.sort(key=lambda pose: float(pose[2]))
    gap = _closest(roots.squarefree) if closest else math.nan
    return Modes(len(poses), tuple(poses), on_fold=roots.on_fold, closest=gap)


# ------------------------------------------------------------------ the mechanisms
def _points(parameters: dict[str, float], group: str, count: int) -> list[tuple[Fraction, Fraction]]:
    return [(exact(parameters[f"{group}_x{i}"]), exact(parameters[f"{group}_y{i}"])) for i in range(1, count + 1)]


def planar_3rpr(parameters: dict[str, float], actuated: Sequence[float], closest: bool = False) -> Modes:
    """planar_3rpr: base_x<i>/base_y<i>, platform_x<i>/platform_y<i>; actuated rho1..rho3."""
    lengths = [exact(v) for v in actuated]
    return planar_rpr(_points(parameters, "base", 3), _points(parameters, "platform", 3), lengths, closest=closest)


def planar_3rrr(parameters: dict[str, float], actuated: Sequence[float], closest: bool = False) -> Modes:
    """planar_3rrr: a 3-RPR on the elbows E_i = A_i + a_i (cos theta_i, sin theta_i), legs b_i.
    ``robust`` compares the count with cos and sin rounded to double."""
    base = _points(parameters, "base", 3)
    cranks = [exact(parameters[f"a{i}"]) for i in (1, 2, 3)]
    links = [exact(parameters[f"b{i}"]) for i in (1, 2, 3)]
    platform = _points(parameters, "platform", 3)

    def elbows(rounded: bool) -> list[tuple[Fraction, Fraction]]:
        out = []
        for (ax, ay), crank, angle in zip(base, cranks, actuated, strict=True):
            c, s = trig(angle, rounded)
            out.append((ax + crank * c, ay + crank * s))
        return out

    modes = planar_rpr(elbows(False), platform, links, closest=closest)
    if modes.count is None:
        return modes
    rounded = planar_rpr(elbows(True), platform, links, count_only=True)
    return Modes(modes.count, modes.poses, modes.reason, modes.on_fold, rounded.count == modes.count, modes.closest)


def _two_circles(c1, c2, r1, r2) -> tuple[int | None, list[tuple[mpmath.mpf, mpmath.mpf]], str, bool]:  # noqa: ANN001
    """The points at distance r1 from c1 and r2 from c2 (exact decision, mpmath points)."""
    ex, ey = c2[0] - c1[0], c2[1] - c1[1]
    w = ex * ex + ey * ey
    if w == 0:
        return None, [], "the circles are concentric", False
    alpha = (w + r1 * r1 - r2 * r2) / (2 * w)
    discriminant = r1 * r1 - alpha * alpha * w  # mu^2, mu the distance off the line of centres
    if discriminant < 0:
        return 0, [], "", False
    with mpmath.workdps(DIGITS + 20):
        norm = mpmath.sqrt(_mp(w))
        mu = mpmath.sqrt(_mp(discriminant))
        points = []
        for sign in (1,) if discriminant == 0 else (1, -1):
            x = _mp(c1[0] + alpha * ex) - sign * mu * _mp(ey) / norm
            y = _mp(c1[1] + alpha * ey) + sign * mu * _mp(ex) / norm
            points.append((x, y))
    return len(points), points, "", discriminant == 0


def five_bar(parameters: dict[str, float], actuated: Sequence[float]) -> Modes:
    """five_bar: A1 = (-d, 0), A2 = (d, 0), elbows C_i = A_i + a_i (cos, sin theta_i), distal b_i;
    poses (x, y)."""
    d = exact(parameters["d"])
    a = [exact(parameters["a1"]), exact(parameters["a2"])]
    b = [exact(parameters["b1"]), exact(parameters["b2"])]

    def elbows(rounded: bool) -> list[tuple[Fraction, Fraction]]:
        out = []
        for base_x, crank, angle in zip((-d, d), a, actuated, strict=True):
            c, s = trig(angle, rounded)
            out.append((base_x + crank * c, crank * s))
        return out

    count, points, reason, on_fold = _two_circles(*elbows(False), *b)
    if count is None:
        return Modes(None, reason=reason)
    rounded, _, _, _ = _two_circles(*elbows(True), *b)
    poses = tuple(sorted(points, key=lambda p: float(p[0])))
    return Modes(count, poses, on_fold=on_fold, robust=rounded == count)


def _cross(u, v):  # noqa: ANN001, ANN202
    return (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])


def _dot(u, v):  # noqa: ANN001, ANN202
    return sum(p * q for p, q in zip(u, v, strict=True))


def three_spheres(
    centres: Sequence[Sequence[Fraction]], radii: Sequence[Fraction]
) -> tuple[int | None, list[tuple[mpmath.mpf, ...]], str, bool]:
    """The points at distance radii[i] from centres[i] (exact decision, mpmath points)."""
    c = [tuple(Fraction(v) for v in centre) for centre in centres]
    na = tuple(p - q for p, q in zip(c[1], c[0], strict=True))
    nb = tuple(p - q for p, q in zip(c[2], c[0], strict=True))
    n = _cross(na, nb)
    n2 = _dot(n, n)
    if n2 == 0:
        return None, [], "the centres are collinear", False
    # p0 on the radical line and in the plane of the centres: v = p0 - c1 solves
    # 2 v . na = |na|^2 + r1^2 - r2^2, 2 v . nb = |nb|^2 + r1^2 - r3^2, v . n = 0
    r1, r2, r3 = (Fraction(r) ** 2 for r in radii)
    ka = (_dot(na, na) + r1 - r2) / 2
    kb = (_dot(nb, nb) + r1 - r3) / 2
    # v = (ka (nb x n) + kb (n x na)) / |n|^2
    u1, u2 = _cross(nb, n), _cross(n, na)
    v = tuple((ka * p + kb * q) / n2 for p, q in zip(u1, u2, strict=True))
    discriminant = r1 - _dot(v, v)  # lambda^2 |n|^2, p = c1 + v + lambda n
    if discriminant < 0:
        return 0, [], "", False
    points = []
    with mpmath.workdps(DIGITS + 20):
        lam = mpmath.sqrt(_mp(discriminant) / _mp(n2))
        for sign in (1,) if discriminant == 0 else (1, -1):
            points.append(tuple(_mp(c[0][k] + v[k]) + sign * lam * _mp(n[k]) for k in range(3)))
    return len(points), points, "", discriminant == 0


def delta(parameters: dict[str, float], actuated: Sequence[float]) -> Modes:
    """delta (3-RUU): p at distance l from c'_i = (R - r) e_i + L (cos theta_i e_i - sin theta_i z),
    e_i at 2 pi (i - 1) / 3 (irrational: taken to TRIG_BITS bits too); poses (x, y, z)."""
    big_r, r, arm, forearm = (exact(parameters[k]) for k in ("R", "r", "L", "l"))

    def centres(rounded: bool) -> list[tuple[Fraction, ...]]:
        out = []
        for i, angle in enumerate(actuated):
            ce, se = trig(2 * math.pi * i / 3, rounded) if rounded else _eta(i)
            c, s = trig(angle, rounded)
            radial = (big_r - r) + arm * c
            out.append((radial * ce, radial * se, -arm * s))
        return out

    count, points, reason, on_fold = three_spheres(centres(False), [forearm] * 3)
    if count is None:
        return Modes(None, reason=reason)
    rounded, _, _, _ = three_spheres(centres(True), [forearm] * 3)
    poses = tuple(sorted(points, key=lambda p: float(p[2])))
    return Modes(count, poses, on_fold=on_fold, robust=rounded == count)


def _eta(i: int) -> tuple[Fraction, Fraction]:
    with mpmath.workprec(TRIG_BITS + 20):
        angle = 2 * mpmath.pi * i / 3
        return _round(mpmath.cos(angle)), _round(mpmath.sin(angle))


def linear_delta(parameters: dict[str, float], actuated: Sequence[float]) -> Modes:
    """The linear delta of tests/fixtures/linear_delta.py (3-PUU): vertical rails through
    A_i = R e_i (e_i at 2 pi (i - 1) / 3), sliders at A_i + s_i z, platform joints p + r e_i, links
    l: p at distance l from A_i + s_i z - r e_i; poses (x, y, z)."""
    big_r, r, link = (exact(parameters[k]) for k in ("R", "r", "l"))

    def centres(rounded: bool) -> list[tuple[Fraction, ...]]:
        out = []
        for i, stroke in enumerate(actuated):
            ce, se = trig(2 * math.pi * i / 3, True) if rounded else _eta(i)
            out.append(((big_r - r) * ce, (big_r - r) * se, exact(stroke)))
        return out

    count, points, reason, on_fold = three_spheres(centres(False), [link] * 3)
    if count is None:
        return Modes(None, reason=reason)
    rounded, _, _, _ = three_spheres(centres(True), [link] * 3)
    poses = tuple(sorted(points, key=lambda p: float(p[2])))
    return Modes(count, poses, on_fold=on_fold, robust=rounded == count)


# ------------------------------------------------------------------ the families of inputs
@dataclass(frozen=True)
class Family:
    """A mechanism the oracle knows, with its input generators. ``lengths``: the length
    parameters (all of them scale); ``prismatic``: which actuated inputs are lengths; ``angular``:
    which passive coordinates are angles; ``oracle`` the exact modes; ``inverse`` this module's
    own inverse (pose, branch signs) -> actuated or None; ``pose`` a random pose near home."""

    name: str
    oracle: Callable[[dict[str, float], Sequence[float]], Modes]
    defaults: dict[str, float]
    prismatic: tuple[bool, ...]
    angular: tuple[bool, ...]
    inverse: Callable[[dict[str, float], np.ndarray, tuple[int, ...]], np.ndarray | None]
    pose: Callable[[np.random.Generator, dict[str, float]], np.ndarray]
    perturb: float = 0.12
    fold_span: float = 0.6
    method: str = "automatic"
    groups: dict[str, int] = field(default_factory=dict)

    def size(self, parameters: dict[str, float]) -> float:
        """The characteristic length: the largest length parameter."""
        return max(abs(v) for v in parameters.values())

    def geometry(self, seed: int) -> dict[str, float]:
        """A random geometry: every parameter moved by up to ``perturb`` times the size (seed 0:
        the defaults)."""
        if seed == 0:
            return dict(self.defaults)
        rng = np.random.default_rng([31, seed])
        size = self.size(self.defaults)
        out = {}
        for name, value in self.defaults.items():
            moved = value + self.perturb * size * rng.uniform(-1, 1)
            out[name] = abs(moved) if name in POSITIVE else moved
        return out

    def scaled(self, parameters: dict[str, float], factor: float) -> dict[str, float]:
        return {name: value * factor for name, value in parameters.items()}

    def scale_input(self, actuated: Sequence[float], factor: float) -> np.ndarray:
        return np.array([v * factor if p else v for v, p in zip(actuated, self.prismatic, strict=True)])

    def load_arguments(self, parameters: dict[str, float]) -> dict[str, object]:
        """``parakin.load`` keyword arguments: point groups by group name, scalars by name."""
        out: dict[str, object] = {}
        for group, count in self.groups.items():
            out[group] = [[parameters[f"{group}_x{i}"], parameters[f"{group}_y{i}"]] for i in range(1, count + 1)]
        grouped = {f"{g}_{c}{i}" for g, n in self.groups.items() for c in "xy" for i in range(1, n + 1)}
        out |= {name: value for name, value in parameters.items() if name not in grouped}
        return out

    def random_inputs(self, seed: int, parameters: dict[str, float], count: int) -> list[np.ndarray]:
        """``count`` inputs: this module's inverse of random poses near home on random branches
        (tries until each leg reaches)."""
        rng = np.random.default_rng([32, seed])
        signs = [s for s in _branch_signs(len(self.prismatic))]
        out: list[np.ndarray] = []
        for _ in range(200 * count):
            if len(out) == count:
                break
            pose = self.pose(rng, parameters)
            branch = signs[rng.integers(len(signs))]
            actuated = self.inverse(parameters, pose, branch)
            if actuated is not None and np.all(np.isfinite(actuated)):
                out.append(actuated)
        return out

    def count(self, parameters: dict[str, float], actuated: Sequence[float]) -> int | None:
        """The oracle's count alone (no poses; exact trigonometry): what bisection needs."""
        return cached_count(self.name, parameters, actuated)

    def stable(self, parameters: dict[str, float], actuated: Sequence[float], radius: float = STABLE) -> bool:
        """The oracle's count is the same with each actuated value moved by +-``radius`` (times
        the value for a length, in radians for an angle): the input is not within rounding of a
        fold. A solver evaluates its system's coefficients in double precision (relative error
        ~1e-15) and can only certify the roots of that rounded system, so an input closer to a
        fold than that has no count a double-precision certificate can be held to."""
        base = self.count(parameters, actuated)
        for joint, value in enumerate(actuated):
            unit = abs(value) if self.prismatic[joint] else 1.0
            for sign in (-1.0, 1.0):
                trial = [float(v) for v in actuated]
                trial[joint] = float(value) + sign * radius * unit
                if self.count(parameters, trial) != base:
                    return False
        return True

    def folds(self, seed: int, parameters: dict[str, float], wanted: int) -> list[Fold]:
        """Up to ``wanted`` folds of the forward map near random inputs: along one actuated value,
        a grid finds a change of the oracle's count by 2, bisection (on the exact count) narrows it
        to adjacent floats."""
        rng = np.random.default_rng([33, seed])
        out: list[Fold] = []
        for start in self.random_inputs(seed + 1000, parameters, 4 * wanted):
            if len(out) == wanted:
                break
            for joint in rng.permutation(len(start)):
                fold = self._fold_along(parameters, start, int(joint))
                if fold is not None:
                    out.append(fold)
                    break
        return out

    def _fold_along(self, parameters: dict[str, float], start: np.ndarray, joint: int) -> Fold | None:
        unit = abs(start[joint]) if self.prismatic[joint] else 1.0
        grid = start[joint] + unit * self.fold_span * np.linspace(-1, 1, 25)
        counts = []
        for value in grid:
            trial = start.copy()
            trial[joint] = value
            counts.append(self.count(parameters, trial))
        for k in range(len(grid) - 1):
            c0, c1 = counts[k], counts[k + 1]
            if c0 is not None and c1 is not None and abs(c1 - c0) == 2:
                return self._bisect(parameters, start, joint, grid[k], grid[k + 1], c0, c1)
        return None

    def _bisect(self, parameters, start, joint, lo, hi, count_lo, count_hi) -> Fold | None:  # noqa: ANN001
        def at(value: float) -> np.ndarray:
            trial = start.copy()
            trial[joint] = value
            return trial

        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if mid in (lo, hi):
                break
            count = self.count(parameters, at(mid))
            if count == count_lo:
                lo = mid
            elif count == count_hi:
                hi = mid
            else:
                return None  # a third count in between: two folds close together, not this one
        few, many = (lo, hi) if count_lo < count_hi else (hi, lo)
        return Fold(at(few), at(many), joint, self.prismatic[joint], min(count_lo, count_hi))


@dataclass(frozen=True)
class Fold:
    """Two inputs one float apart along ``joint``: ``few`` with ``count`` real modes, ``many``
    with count + 2."""

    few: np.ndarray
    many: np.ndarray
    joint: int
    prismatic: bool
    count: int

    def steps(self, steps: Sequence[float] = (0.0, 1e-9, 1e-6)) -> list[tuple[str, np.ndarray]]:
        """The inputs off the fold: step 0 is the two bracketing floats; a step h moves the value
        by h (times the value for a length) towards either side."""
        out: list[tuple[str, np.ndarray]] = []
        sign = 1.0 if self.many[self.joint] > self.few[self.joint] else -1.0
        for step in steps:
            if step == 0:
                out += [("0 (k)", self.few.copy()), ("0 (k+2)", self.many.copy())]
                continue
            unit = abs(self.few[self.joint]) if self.prismatic else 1.0
            for side, label in ((-sign, "k"), (sign, "k+2")):
                value = self.few.copy()
                value[self.joint] = self.few[self.joint] + side * step * unit
                out.append((f"{step:g} ({label})", value))
        return out


POSITIVE = {"a1", "a2", "a3", "b1", "b2", "b3", "d", "R", "r", "L", "l"}


def _branch_signs(count: int) -> list[tuple[int, ...]]:
    return [tuple(1 - 2 * ((k >> j) & 1) for j in range(count)) for k in range(2**count)]


def _rotation(phi: float) -> np.ndarray:
    return np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])


def _crank_angle(v: np.ndarray, crank: float, link: float, sign: int) -> float | None:
    """theta with |v - crank (cos, sin theta)| = link: angle(v) + sign acos(...)."""
    distance = float(np.hypot(*v))
    if distance == 0:
        return None
    cosine = (distance**2 + crank**2 - link**2) / (2 * crank * distance)
    if not -1 < cosine < 1:
        return None
    return math.atan2(v[1], v[0]) + sign * math.acos(cosine)


def _inverse_3rrr(parameters: dict[str, float], pose: np.ndarray, signs: tuple[int, ...]) -> np.ndarray | None:
    out = []
    for i in range(1, 4):
        base = np.array([parameters[f"base_x{i}"], parameters[f"base_y{i}"]])
        joint = pose[:2] + _rotation(pose[2]) @ np.array([parameters[f"platform_x{i}"], parameters[f"platform_y{i}"]])
        angle = _crank_angle(joint - base, parameters[f"a{i}"], parameters[f"b{i}"], signs[i - 1])
        if angle is None:
            return None
        out.append(angle)
    return np.array(out)


def _inverse_3rpr(parameters: dict[str, float], pose: np.ndarray, signs: tuple[int, ...]) -> np.ndarray | None:
    out = []
    for i in range(1, 4):
        base = np.array([parameters[f"base_x{i}"], parameters[f"base_y{i}"]])
        joint = pose[:2] + _rotation(pose[2]) @ np.array([parameters[f"platform_x{i}"], parameters[f"platform_y{i}"]])
        out.append(float(np.hypot(*(joint - base))))
    return np.array(out) if min(out) > 0 else None


def _inverse_five_bar(parameters: dict[str, float], pose: np.ndarray, signs: tuple[int, ...]) -> np.ndarray | None:
    out = []
    for i, base_x in enumerate((-parameters["d"], parameters["d"])):
        angle = _crank_angle(
            pose[:2] - np.array([base_x, 0.0]), parameters[f"a{i + 1}"], parameters[f"b{i + 1}"], signs[i]
        )
        if angle is None:
            return None
        out.append(angle)
    return np.array(out)


def _inverse_linear_delta(parameters: dict[str, float], pose: np.ndarray, signs: tuple[int, ...]) -> np.ndarray | None:
    out = []
    for i in range(3):
        e = np.array([math.cos(2 * math.pi * i / 3), math.sin(2 * math.pi * i / 3), 0.0])
        h = pose + (parameters["r"] - parameters["R"]) * e  # platform joint seen from the rail's foot
        square = parameters["l"] ** 2 - h[0] ** 2 - h[1] ** 2
        if square <= 0:
            return None
        out.append(h[2] + signs[i] * math.sqrt(square))
    return np.array(out)


def _pose_3rrr(rng: np.random.Generator, parameters: dict[str, float]) -> np.ndarray:
    size = max(abs(v) for v in parameters.values())
    return np.array([*(0.25 * size * rng.uniform(-1, 1, 2)), rng.uniform(-0.8, 0.8)])


def _pose_3rpr(rng: np.random.Generator, parameters: dict[str, float]) -> np.ndarray:
    size = max(abs(v) for v in parameters.values())
    home = np.array([-14.9 / 20.84 * size, 1.6 / 20.84 * size, 0.245])
    return home + np.array([*(0.3 * size * rng.uniform(-1, 1, 2)), rng.uniform(-1.0, 1.0)])


def _pose_five_bar(rng: np.random.Generator, parameters: dict[str, float]) -> np.ndarray:
    return np.array([rng.uniform(-0.25, 0.25), rng.uniform(0.05, 0.45)]) * parameters["b1"] / 0.25


def _pose_linear_delta(rng: np.random.Generator, parameters: dict[str, float]) -> np.ndarray:
    size = parameters["R"]
    return np.array([*(0.4 * size * rng.uniform(-1, 1, 2)), 0.5 * size * rng.uniform(-1, 1)])


def _defaults(name: str) -> dict[str, float]:
    import parakin

    return dict(parakin.load(name, backend="numpy").parameters)


#: the linear delta of tests/fixtures/linear_delta.py: its defaults (kept equal to the file's)
LINEAR_DELTA_DEFAULTS = {"R": 0.25, "r": 0.05, "l": 0.5}


@cache
def family(name: str) -> Family:
    """The family of a mechanism name (planar_3rrr, planar_3rpr, five_bar, linear_delta)."""
    if name == "planar_3rrr":
        return Family(name, planar_3rrr, _defaults(name), (False,) * 3, (False, False, True), _inverse_3rrr,
                      _pose_3rrr, groups={"base": 3, "platform": 3})  # fmt: skip
    if name == "planar_3rpr":
        return Family(name, planar_3rpr, _defaults(name), (True,) * 3, (False, False, True), _inverse_3rpr,
                      _pose_3rpr, perturb=0.08, fold_span=0.3, groups={"base": 3, "platform": 3})  # fmt: skip
    if name == "five_bar":
        return Family(name, five_bar, _defaults(name), (False,) * 2, (False, False), _inverse_five_bar,
                      _pose_five_bar, perturb=0.1, fold_span=math.pi)  # fmt: skip
    if name == "linear_delta":
        return Family(name, linear_delta, dict(LINEAR_DELTA_DEFAULTS), (True,) * 3, (False,) * 3,
                      _inverse_linear_delta, _pose_linear_delta, perturb=0.05, fold_span=0.3)  # fmt: skip
    raise KeyError(name)


ORACLES: dict[str, Callable[[dict[str, float], Sequence[float]], Modes]] = {
    "planar_3rpr": planar_3rpr,
    "planar_3rrr": planar_3rrr,
    "five_bar": five_bar,
    "delta": delta,
    "linear_delta": linear_delta,
}


@lru_cache(maxsize=100_000)
def _cached(name: str, parameters: tuple[tuple[str, float], ...], actuated: tuple[float, ...]) -> Modes:
    return ORACLES[name](dict(parameters), actuated)


@lru_cache(maxsize=100_000)
def _cached_count(name: str, parameters: tuple[tuple[str, float], ...], actuated: tuple[float, ...]) -> int | None:
    values = dict(parameters)
    if name == "planar_3rpr":
        base, platform = _points(values, "base", 3), _points(values, "platform", 3)
        return planar_rpr(base, platform, [exact(v) for v in actuated], count_only=True).count
    if name == "planar_3rrr":
        elbows = []
        for i, angle in enumerate(actuated, start=1):
            c, s = trig(angle)
            crank = exact(values[f"a{i}"])
            elbows.append((exact(values[f"base_x{i}"]) + crank * c, exact(values[f"base_y{i}"]) + crank * s))
        links = [exact(values[f"b{i}"]) for i in (1, 2, 3)]
        return planar_rpr(elbows, _points(values, "platform", 3), links, count_only=True).count
    return ORACLES[name](values, actuated).count


def cached_count(name: str, parameters: dict[str, float], actuated: Sequence[float]) -> int | None:
    """The oracle's count alone, kept in memory."""
    return _cached_count(name, _key(parameters), tuple(float(v) for v in actuated))


def _key(parameters: dict[str, float]) -> tuple[tuple[str, float], ...]:
    return tuple(sorted((k, float(v)) for k, v in parameters.items()))


def cached(name: str, parameters: dict[str, float], actuated: Sequence[float]) -> Modes:
    """The oracle's modes, kept in memory by (name, parameters, input)."""
    return _cached(name, _key(parameters), tuple(float(v) for v in actuated))


# ------------------------------------------------------------------ comparing with a solver
def pose_distance(a: np.ndarray, b: np.ndarray, angular: Sequence[bool], size: float) -> float:
    """Distance of two passive vectors: positions over ``size``, angles wrapped (radians)."""
    out = 0.0
    for u, v, is_angle in zip(a, b, angular, strict=True):
        if is_angle:
            out = max(out, abs(math.remainder(float(u) - float(v), 2 * math.pi)))
        else:
            out = max(out, abs(float(u) - float(v)) / size)
    return out


def match(found: np.ndarray, expected: np.ndarray, angular: Sequence[bool], size: float) -> float:
    """The largest distance of the best one-to-one pairing of two equal-sized sets of poses (inf
    where the counts differ); the pairing minimises the largest distance (sets of <= 8 poses)."""
    if len(found) != len(expected):
        return math.inf
    if len(found) == 0:
        return 0.0
    from scipy.optimize import linear_sum_assignment

    cost = np.array([[pose_distance(f, e, angular, size) for e in expected] for f in found])
    rows, cols = linear_sum_assignment(cost)
    return float(cost[rows, cols].max())


def unmatched(
    found: np.ndarray, expected: np.ndarray, angular: Sequence[bool], size: float, tol: float
) -> tuple[int, int]:
    """(oracle modes with no listed mode within ``tol``, listed modes with no oracle mode)."""
    missing = sum(1 for e in expected if not any(pose_distance(f, e, angular, size) <= tol for f in found))
    extra = sum(1 for f in found if not any(pose_distance(f, e, angular, size) <= tol for e in expected))
    return missing, extra


# ------------------------------------------------------------------ an independent Newton
def closure(name: str, parameters: dict[str, float], actuated: Sequence[float], passive: Sequence) -> list:  # noqa: ANN001
    """The closure residuals |leg|^2 - length^2 of ``passive`` in mpmath (the current precision),
    written from the geometry again (not from parakin's loop closure)."""
    v = {k: mpmath.mpf(float(x)) for k, x in parameters.items()}
    q = [mpmath.mpf(x) if not isinstance(x, mpmath.mpf) else x for x in passive]
    out = []
    if name in ("planar_3rpr", "planar_3rrr"):
        c, s = mpmath.cos(q[2]), mpmath.sin(q[2])
        for i in range(1, 4):
            px, py = v[f"platform_x{i}"], v[f"platform_y{i}"]
            bx, by = q[0] + c * px - s * py, q[1] + s * px + c * py
            if name == "planar_3rpr":
                ex, ey, length = v[f"base_x{i}"], v[f"base_y{i}"], mpmath.mpf(float(actuated[i - 1]))
            else:
                angle = mpmath.mpf(float(actuated[i - 1]))
                ex = v[f"base_x{i}"] + v[f"a{i}"] * mpmath.cos(angle)
                ey = v[f"base_y{i}"] + v[f"a{i}"] * mpmath.sin(angle)
                length = v[f"b{i}"]
            out.append((bx - ex) ** 2 + (by - ey) ** 2 - length**2)
    elif name == "five_bar":
        for i, base_x in enumerate((-v["d"], v["d"])):
            angle = mpmath.mpf(float(actuated[i]))
            ex, ey = base_x + v[f"a{i + 1}"] * mpmath.cos(angle), v[f"a{i + 1}"] * mpmath.sin(angle)
            out.append((q[0] - ex) ** 2 + (q[1] - ey) ** 2 - v[f"b{i + 1}"] ** 2)
    elif name == "linear_delta":
        for i in range(3):
            eta = 2 * mpmath.pi * i / 3
            e = (mpmath.cos(eta), mpmath.sin(eta))
            d = (q[0] + (v["r"] - v["R"]) * e[0], q[1] + (v["r"] - v["R"]) * e[1], q[2] - float(actuated[i]))
            out.append(d[0] ** 2 + d[1] ** 2 + d[2] ** 2 - v["l"] ** 2)
    else:
        raise KeyError(name)
    return out


def polish(name: str, parameters: dict[str, float], actuated: Sequence[float], guess: Sequence[float]) -> tuple | None:
    """Newton on the real closure equations from ``guess`` in DIGITS-digit arithmetic: the real
    root it converges to (a tuple of mpf), or None (no convergence: no real root near the guess,
    e.g. the real part of a near-real complex pair). Independent evidence for a disputed mode."""
    with mpmath.workdps(DIGITS):
        size = max(abs(v) for v in parameters.values()) or 1.0
        tolerance = mpmath.mpf(10) ** (-DIGITS + 10) * size**2

        def residual(*x):  # noqa: ANN002, ANN202
            return closure(name, parameters, actuated, x)

        try:
            root = mpmath.findroot(residual, [mpmath.mpf(float(g)) for g in guess], tol=tolerance, maxsteps=60)
        except (ValueError, ZeroDivisionError):
            return None
        values = tuple(root[k] for k in range(len(guess)))
        if max(abs(r) for r in residual(*values)) > tolerance * 1e6:
            return None
        return values
