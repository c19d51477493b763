"""The reading of a pose onto a lower-mobility platform's reachable set, derived from its legs.

The subproblem (the 3-PRS, 3-RPS and 3-RRS): three legs whose revolute joints keep each platform
joint C_i = p + R c_i in a fixed plane through A_i with unit normal n_i, the three planes
containing one common axis (direction k, n_i . k = 0, through a point o on every plane). Then:

* the constraints are (p - o) . n_i + (R c_i) . n_i = 0, and k is in none of them: the height
  h = p . k is free;
* write n = R^T k (the tilt: the axis seen from {P}) and R = Rot_k(psi) R0, R0 the tilt about an
  axis normal to k (R0 n = k, no turn about k: R0 = I + [v]x + [v]x^2 / (1 + n . k), v = n x k).
  With lambda_i = (n_j x n_l) . k (i, j, l cyclic), sum lambda_i n_i = 0, so the combination
  sum lambda_i (constraint i) is free of p and of o: a cos psi + b sin psi = 0 with
  a = sum lambda_i (R0 c_i) . n_i, b = sum lambda_i (k x R0 c_i) . n_i. Two turns keep the
  joints in their planes, psi* (cos psi* >= 0) and psi* + pi (the half-turn); psi* = 0 at every
  tilt where a vanishes identically (the symmetric designs: prs3, rps3, rrs3);
* the position across k follows from the constraints, linear in p:
  p = (M^T M)^-1 (sum_i (A_i . n_i - (R c_i) . n_i) n_i + h k), M the rows n_1, n_2, n_3, k.

So the reachable poses are a 3-D set with the controlled coordinates (h, n) and the choice of
turn; the parasitic ones (p across k, the turn psi about k) follow. The inverse reads h and n from
the given pose and the turn nearer the given pose's own (the sign of cos(psi_R - psi*),
R R0^T = Rot_k(psi_R)), and returns the reachable pose with them: the given pose itself where it
is reachable.
"""

from __future__ import annotations

import random
from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from .frames import sign_or_plus
from .model import POSE_POSITION, POSE_ROTATION


def vanishes(expr: sp.Expr) -> bool:
    """Whether an expression of the parameters (and free symbols) vanishes identically: at three
    random points of its symbols (30 digits, within 1e-12: a design given in floating-point
    numbers has rounding in it), a polynomial identity test for the rational expressions here."""
    expr = sp.sympify(expr)
    free = sorted(expr.free_symbols, key=str)
    rng = random.Random(20261128)
    for _ in range(3):
        value = expr.xreplace({v: sp.Float(rng.uniform(0.5, 1.5), 30) for v in free}).evalf(30)
        if not value.is_number or abs(complex(value)) > 1e-12:
            return False
    return True


def _skew(v: sp.Matrix) -> sp.Matrix:
    return sp.Matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def tilt(axis: sp.Matrix, n: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix]:
    """The tilt R0 with R0 n = ``axis`` k (no turn about k) and its unit quaternion (q0 > 0).

    Parameters
    ----------
    axis : Matrix
        The unit axis k, 3 x 1, in {B}.
    n : Matrix
        A unit vector, 3 x 1: R^T k of the pose, in {P}.

    Returns
    -------
    tuple of Matrix
        R0 = I + [v]x + [v]x^2 / (1 + n . k), v = n x k (3 x 3), and its quaternion
        (1 + n . k, v) / sqrt(2 (1 + n . k)) (4 x 1, scalar first). Singular where n = -k (the
        platform upside down).

    Example
    -------
    >>> rotation, q = tilt(sp.Matrix([0, 0, 1]), sp.Matrix([0, 0, 1]))
    >>> rotation == sp.eye(3), list(q)
    (True, [1, 0, 0, 0])
    """
    v = n.cross(axis)
    cosine = n.dot(axis)
    rotation = sp.eye(3) + _skew(v) + (v * v.T - v.dot(v) * sp.eye(3)) / (1 + cosine)
    root = sp.sqrt(2 * (1 + cosine))
    return rotation, sp.Matrix([(1 + cosine) / root, *(v / root)])


def _product(p: Sequence[sp.Expr], q: Sequence[sp.Expr]) -> list[sp.Expr]:
    """The quaternion product p q (scalar first)."""
    pv, qv = sp.Matrix(p[1:]), sp.Matrix(q[1:])
    vector = p[0] * qv + q[0] * pv + pv.cross(qv)
    return [p[0] * q[0] - pv.dot(qv), *vector]


@dataclass(frozen=True)
class AxisReading:
    """Three plane constraints whose planes contain one axis (module docstring): the unit axis k,
    the planes' unit normals n_i and points A_i (in {B}), the platform joints c_i (in {P}), and
    whether the turn psi* is 0 at every tilt (``symmetric``)."""

    axis: sp.Matrix
    normals: tuple[sp.Matrix, ...]
    bases: tuple[sp.Matrix, ...]
    joints: tuple[sp.Matrix, ...]
    weights: tuple[sp.Expr, ...]
    symmetric: bool

    def describe(self) -> str:
        """The controlled and parasitic coordinates, in words (for the manifest)."""
        k = [str(c) for c in self.axis]
        if self.symmetric:  # psi* = 0 at every tilt
            turn = "the turn about k, none (the platform only tilts) or a half-turn"
        else:
            turn = "the turn about k, which the tilt fixes up to a half-turn"
        return (
            f"controlled: the height p . k and the tilt n = R^T k, k = ({', '.join(k)}); parasitic: the position "
            f"across k, and {turn}: two separate sets of reachable poses, one per turn"
        )

    def steps(
        self, coordinates: Sequence[sp.Symbol]
    ) -> tuple[list[tuple[sp.Symbol, sp.Expr]], tuple[sp.Matrix, sp.Matrix]]:
        """The inverse's reading: assignments from the pose symbols to the platform's coordinates
        (x, y, z, q0..q3), and the reachable pose (rotation, position) in the steps' symbols.

        Parameters
        ----------
        coordinates : sequence of Symbol
            The transform platform's x, y, z, q0, q1, q2, q3.

        Returns
        -------
        tuple
            The steps (target, expression), and (R, p) of the reachable pose read.
        """
        k = self.axis
        x, y, z, *quaternion = coordinates
        n = sp.Matrix(sp.symbols("n_x n_y n_z", real=True))
        r0 = sp.Matrix(3, 3, sp.symbols("tilt11 tilt12 tilt13 tilt21 tilt22 tilt23 tilt31 tilt32 tilt33", real=True))
        turn = sp.Symbol("turn", real=True)  # +1: the turn psi*, -1: psi* + pi
        rotation, q_tilt = tilt(k, n)
        steps: list[tuple[sp.Symbol, sp.Expr]] = list(zip(n, POSE_ROTATION.T * k, strict=True))
        steps += list(zip(r0, rotation, strict=True))
        # the torsion reference: a unit e normal to k, its image under R R0^T = Rot_k(psi_R)
        e = _normal_to(k)
        cosine = (POSE_ROTATION.T * e).dot(r0.T * e)
        if self.symmetric:
            turn_of = cosine
            torsion = sp.eye(3)
            q_turn = [sp.Integer(1), 0, 0, 0]
        else:
            c, s = sp.symbols("torsion_cos torsion_sin", real=True)
            a, b = self._coefficients(r0)
            side = sp.Symbol("torsion_side", real=True)
            size = sp.Symbol("torsion_size", positive=True)
            steps += [
                (side, sign_or_plus(b)),
                (size, sp.sqrt(a**2 + b**2)),
                (c, side * b / size),
                (s, -side * a / size),
            ]
            sine = (POSE_ROTATION.T * k.cross(e)).dot(r0.T * e)
            turn_of = c * cosine + s * sine
            torsion = c * sp.eye(3) + s * _skew(k) + (1 - c) * k * k.T
            half = sp.sqrt(2 * (1 + c))
            q_turn = [(1 + c) / half, *(s * k / half)]
        steps.append((turn, sign_or_plus(turn_of)))
        flip = turn * sp.eye(3) + (1 - turn) * k * k.T  # Rot_k(pi) where turn = -1
        reached = flip * torsion * r0
        # the position: the plane constraints, linear in p, with the height read
        height = POSE_POSITION.dot(k)
        rows = sp.Matrix.vstack(*(normal.T for normal in self.normals), k.T)
        solve = sp.simplify((rows.T * rows).inv())
        right = sum(
            ((base.dot(normal) - (reached * joint).dot(normal)) * normal
             for base, joint, normal in zip(self.bases, self.joints, self.normals, strict=True)),
            height * k,
        )  # fmt: skip
        position = solve * right
        if self.symmetric:  # small (prs3: x = r_p turn (tilt11 - tilt22) / 2); elsewhere slow to simplify
            position = position.applyfunc(lambda entry: sp.factor_terms(sp.simplify(entry)))
        steps += list(zip((x, y, z), position, strict=True))
        # the quaternion: Rot_k(pi)^h Rot_k(psi*) R0, q0 >= 0
        q = _product(q_turn, list(q_tilt))
        half = [(1 + turn) / 2, (1 - turn) / 2]
        turned = [half[0] * a + half[1] * b for a, b in zip(q, _product([0, *k], q), strict=True)]
        if self.symmetric:  # q0 = half[0] (1 + n . k) / root >= 0
            steps += list(zip(quaternion, turned, strict=True))
        else:
            unsigned = sp.Matrix(sp.symbols("q_read0:4", real=True))
            steps += list(zip(unsigned, turned, strict=True))
            steps += [(v, sign_or_plus(unsigned[0]) * u) for v, u in zip(quaternion, unsigned, strict=True)]
        return steps, (flip * torsion * r0, sp.Matrix([x, y, z]))

    def _coefficients(self, r0: sp.Matrix) -> tuple[sp.Expr, sp.Expr]:
        """a and b of a cos psi + b sin psi = 0 at the tilt R0."""
        k = self.axis
        a = sum(w * (r0 * c).dot(n) for w, c, n in zip(self.weights, self.joints, self.normals, strict=True))
        b = sum(w * k.cross(r0 * c).dot(n) for w, c, n in zip(self.weights, self.joints, self.normals, strict=True))
        return sp.Integer(0) + a, sp.Integer(0) + b


def _normal_to(k: sp.Matrix) -> sp.Matrix:
    """A unit vector normal to k: x (or y) less its part along k."""
    for guess in (sp.Matrix([1, 0, 0]), sp.Matrix([0, 1, 0])):
        e = guess - guess.dot(k) * k
        if not vanishes(e.dot(e)):
            return sp.simplify(e / sp.sqrt(e.dot(e)))
    raise ValueError("no direction normal to the axis")  # k is a unit vector: unreachable


def common_axis(
    normals: Sequence[sp.Matrix], bases: Sequence[sp.Matrix], joints: Sequence[sp.Matrix]
) -> AxisReading | None:
    """The axis reading of three plane constraints, or None where they are not the subproblem.

    Parameters
    ----------
    normals : sequence of Matrix
        The planes' unit normals n_i (3 x 1, in {B}).
    bases : sequence of Matrix
        A point A_i of each plane (3 x 1, in {B}).
    joints : sequence of Matrix
        The platform joints c_i held in them (3 x 1, in {P}).

    Returns
    -------
    AxisReading or None
        The reading where there are three planes, pairwise not parallel, containing one common
        axis, and the turn about it is determined (a and b not both identically zero); None
        otherwise (the inverse then reads the pose as given).

    Example
    -------
    >>> import sympy as sp
    >>> s = sp.sqrt(3) / 2
    >>> radial = [sp.Matrix([1, 0, 0]), sp.Matrix([-sp.Rational(1, 2), s, 0]), sp.Matrix([-sp.Rational(1, 2), -s, 0])]
    >>> tangent = [sp.Matrix([-e[1], e[0], 0]) for e in radial]
    >>> found = common_axis(tangent, [2 * e for e in radial], radial)
    >>> list(found.axis), found.symmetric
    ([0, 0, 1], True)
    """
    if len(normals) != 3:
        return None
    cross = normals[0].cross(normals[1])
    if vanishes(cross.dot(cross)):
        return None
    k = sp.simplify(cross / sp.sqrt(cross.dot(cross)))
    if not k.free_symbols:  # the direction whose last non-zero component is positive
        last = [float(c) for c in k if abs(float(c)) > 1e-12][-1]
        k = -k if last < 0 else k
    if not vanishes(normals[2].dot(k)):
        return None
    # a point o on planes 1 and 2 (and o . k = 0) must lie on plane 3
    rows = sp.Matrix.vstack(normals[0].T, normals[1].T, k.T)
    point = rows.inv() * sp.Matrix([bases[0].dot(normals[0]), bases[1].dot(normals[1]), 0])
    if not vanishes((bases[2] - point).dot(normals[2])):
        return None
    weights = tuple(sp.simplify(normals[(i + 1) % 3].cross(normals[(i + 2) % 3]).dot(k)) for i in range(3))
    found = AxisReading(k, tuple(normals), tuple(bases), tuple(joints), weights, symmetric=False)
    n = sp.Matrix(sp.symbols("n_x n_y n_z", real=True))
    a, b = found._coefficients(tilt(k, n)[0])
    if vanishes(a):
        return AxisReading(k, tuple(normals), tuple(bases), tuple(joints), weights, symmetric=True)
    if vanishes(b):
        return None
    return found
