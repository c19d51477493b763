"""Krawczyk certificates in exact dyadic arithmetic, for roots that double precision cannot
certify (ill-conditioned ones, e.g. near a singular set at infinity, where the rounding of F
alone exceeds the width of any box the double-precision test could pass).

Same test and notation as ``parakin.solvers.certify`` (module docstring there): for a centre x, any matrix
Y and B = B(x, r) (max-norm polydisc), if ||Y F(x)|| + (||I - Y J(x)|| + ||Y|| L(r)) r < r then B
holds exactly one root. Here every number is a dyadic rational m 2^e (every double is one) held as
Python integers: x, the coefficients and Y are dyadic, and F(x), J(x), Y F(x), I - Y J(x) and the
Hessian bound H_k(rho) are computed exactly (sums and products of dyadics are dyadic); each
modulus |a + bi| is bounded above by |a| + |b|. The inequality is decided exactly on upper bounds
of its terms, so no rounding model is needed. Y is J(x)^-1 by Gauss-Jordan elimination in
``FIXED``-bit fixed point (``_inverse``): a root whose Jacobian is conditioned far beyond 1e16 (rus6
roots of size 4e7, next to a singular root at infinity: ~1e19) gets a Y for which ||I - Y J|| is
small, where a double-precision inverse leaves it above 1. The centre is first refined by Newton
steps x <- x - Y F(x) with F exact and the same Y, rounded to ``BITS`` fractional bits between steps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: fractional bits of the refined centre
BITS = 160
#: Newton refinements at most (each gains about -log10(||I - Y J||) digits)
REFINEMENTS = 12
#: the unit roundoff of double precision (a quotient's relative error is below it)
UNIT_ROUNDING = 2.0**-53
#: radii tried, as powers of two times the exact bound on the Newton step (2, 8, 64, 1024)
MULTIPLIER_SHIFTS = (1, 3, 6, 10)

#: a real dyadic (m, e) = m 2^e and a complex one (re, im, e)
Real = tuple[int, int]
Complex = tuple[int, int, int]
ZERO: Complex = (0, 0, 0)
ONE: Complex = (1, 0, 0)


@dataclass(frozen=True)
class ExactCertificate:
    """``unique``: the polydisc of max-norm ``radius`` about ``center`` (doubles: the radius is
    rounded up and covers the rounding of the exact centre) holds exactly one root; ``real`` +1
    that root is real (real coefficients only), -1 it is not, 0 undecided."""

    unique: bool
    center: np.ndarray
    radius: float
    real: int


def _real(value: float) -> Real:
    mantissa, exponent = math.frexp(value)
    return int(mantissa * (1 << 53)), exponent - 53


def _complex(value: complex) -> Complex:
    (a, ea), (b, eb) = _real(value.real), _real(value.imag)
    e = min(ea, eb)
    return a << (ea - e), b << (eb - e), e


def _mul(a: Complex, b: Complex) -> Complex:
    return a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0], a[2] + b[2]


def _add(a: Complex, b: Complex) -> Complex:
    if a[2] >= b[2]:
        shift = a[2] - b[2]
        return (a[0] << shift) + b[0], (a[1] << shift) + b[1], b[2]
    shift = b[2] - a[2]
    return a[0] + (b[0] << shift), a[1] + (b[1] << shift), a[2]


def _scale(a: Complex, k: int) -> Complex:
    return a[0] * k, a[1] * k, a[2]


def _rmul(a: Real, b: Real) -> Real:
    return a[0] * b[0], a[1] + b[1]


def _radd(a: Real, b: Real) -> Real:
    if a[1] >= b[1]:
        return (a[0] << (a[1] - b[1])) + b[0], b[1]
    return a[0] + (b[0] << (b[1] - a[1])), a[1]


def _less(a: Real, b: Real) -> bool:
    e = min(a[1], b[1])
    return a[0] << (a[1] - e) < b[0] << (b[1] - e)


def _rmax(a: Real, b: Real) -> Real:
    return b if _less(a, b) else a


def _modulus_bound(a: Complex) -> Real:
    return abs(a[0]) + abs(a[1]), a[2]


def _float_of(a: Complex) -> complex:
    """The double nearest each part (ints of any size, exponents far below the double range)."""

    def part(m: int) -> float:
        if m == 0:
            return 0.0
        shift = max(m.bit_length() - 60, 0)
        return math.ldexp(m >> shift if m > 0 else -((-m) >> shift), a[2] + shift)

    return complex(part(a[0]), part(a[1]))


def _round(a: Complex, bits: int) -> Complex:
    """a rounded to ``bits`` fractional bits (a Newton iterate: no exactness needed)."""
    if a[2] >= -bits:
        return a
    shift = -bits - a[2]
    half = 1 << (shift - 1)
    return (a[0] + half) >> shift, (a[1] + half) >> shift, -bits


class _ExactSystem:
    """F and J of a sparse system (``parakin.solvers.certify`` layout) with exact dyadic coefficients."""

    def __init__(self, coefficients: np.ndarray, exponents: np.ndarray, equation: np.ndarray) -> None:
        self.exponents = [tuple(int(e) for e in row) for row in exponents]
        self.equation = [int(k) for k in equation]
        self.c = [_complex(complex(v)) for v in np.asarray(coefficients, dtype=complex)]
        self.real_coefficients = all(c[1] == 0 for c in self.c)
        self.n = len(self.exponents[0])
        self.top = max(max(row) for row in self.exponents)
        # H_k's terms: (equation, |c_t|, weight a_ti (a_tj - [i = j]), exponents a_t - e_i - e_j)
        self.second: list[tuple[int, Real, int, tuple[int, ...]]] = []
        for c, a, k in zip(self.c, self.exponents, self.equation, strict=True):
            for i in range(self.n):
                for j in range(self.n):
                    weight = a[i] * (a[j] - (i == j))
                    if weight > 0:
                        b = list(a)
                        b[i] -= 1
                        b[j] -= 1
                        self.second.append((k, _modulus_bound(c), weight, tuple(b)))

    def evaluate(self, x: list[Complex]) -> tuple[list[Complex], list[list[Complex]]]:
        n = self.n
        powers = []
        for xi in x:
            row = [ONE]
            for _ in range(self.top):
                row.append(_mul(row[-1], xi))
            powers.append(row)
        f = [ZERO] * n
        jac = [[ZERO] * n for _ in range(n)]
        for c, a, k in zip(self.c, self.exponents, self.equation, strict=True):
            factors = [powers[i][a[i]] for i in range(n)]
            # products of the factors before and after each i: 2 n products per term, not n^2
            before = [ONE]
            for factor in factors[:-1]:
                before.append(_mul(before[-1], factor))
            after = [ONE]
            for factor in factors[:0:-1]:
                after.append(_mul(after[-1], factor))
            after.reverse()
            f[k] = _add(f[k], _mul(c, _mul(before[-1], factors[-1])))
            for i in range(n):
                if a[i]:
                    term = _mul(_mul(_scale(c, a[i]), powers[i][a[i] - 1]), _mul(before[i], after[i]))
                    jac[k][i] = _add(jac[k][i], term)
        return f, jac

    def hessian_bound(self, rho: list[Real]) -> Real:
        """max_k H_k(rho) (``parakin.solvers.certify``), with |c_t| bounded by |Re| + |Im|."""
        powers = []
        for value in rho:
            row = [(1, 0)]
            for _ in range(self.top):
                row.append(_rmul(row[-1], value))
            powers.append(row)
        totals: list[Real] = [(0, 0)] * self.n
        for k, size, weight, b in self.second:
            value = (size[0] * weight, size[1])
            for m, e in enumerate(b):
                if e:
                    value = _rmul(value, powers[m][e])
            totals[k] = _radd(totals[k], value)
        largest = totals[0]
        for total in totals[1:]:
            largest = _rmax(largest, total)
        return largest


#: fractional bits of the fixed-point Gauss-Jordan elimination that inverts J (relative to its
#: largest entry): pivots down to 2^-(FIXED - BITS) of it keep BITS bits, far beyond double's 53
FIXED = 384


def _inverse(jac: list[list[Complex]]) -> list[list[Complex]] | None:
    """An approximate inverse Y of J (exact dyadic entries), by Gauss-Jordan elimination with
    partial pivoting in ``FIXED``-bit complex fixed point: accurate where J's condition number
    is far beyond 1 / double's unit roundoff (a root close to a singular one at infinity). Any Y
    keeps the test sound; an accurate one makes ||I - Y J|| small enough to pass. None where a
    pivot vanishes."""
    n = len(jac)
    top = max((max(abs(e[0]), abs(e[1])).bit_length() + e[2] for row in jac for e in row if e[0] or e[1]), default=None)
    if top is None:
        return None

    def fixed(m: int, e: int) -> int:  # m 2^e in units of 2^(top - FIXED)
        shift = e - top + FIXED
        return m << shift if shift >= 0 else m >> -shift

    a = [[(fixed(e[0], e[2]), fixed(e[1], e[2])) for e in row] + [(1 << FIXED if i == j else 0, 0) for j in range(n)]
         for i, row in enumerate(jac)]  # fmt: skip
    for k in range(n):
        pivot = max(range(k, n), key=lambda r: abs(a[r][k][0]) + abs(a[r][k][1]))
        a[k], a[pivot] = a[pivot], a[k]
        c, d = a[k][k]
        norm = c * c + d * d
        if norm == 0:
            return None
        # the pivot row divided by the pivot: (x + i y) (c - i d) / (c^2 + d^2)
        a[k] = [(((x * c + y * d) << FIXED) // norm, ((y * c - x * d) << FIXED) // norm) for x, y in a[k]]
        for r in range(n):
            if r == k:
                continue
            f, g = a[r][k]
            if not (f or g):
                continue
            a[r] = [
                (x - ((f * p - g * q) >> FIXED), y - ((f * q + g * p) >> FIXED))
                for (x, y), (p, q) in zip(a[r], a[k], strict=True)
            ]
    # a is now [I | (J 2^-top)^-1] in units of 2^-FIXED, and J^-1 = (J 2^-top)^-1 2^-top
    return [[(x, y, -FIXED - top) for x, y in row[n:]] for row in a]


def _solve(jac: list[list[Complex]], f: list[Complex]) -> list[Complex] | None:
    """Y f with Y = ``_inverse(jac)`` (exact products of the dyadic entries), or None."""
    y = _inverse(jac)
    if y is None:
        return None
    out = []
    for row in y:
        total = ZERO
        for yij, fj in zip(row, f, strict=True):
            total = _add(total, _mul(yij, fj))
        out.append(total)
    return out


def _test(system: _ExactSystem, x: list[Complex], least: Real) -> Real | None:
    """The smallest radius tried (at least ``least``, else 2^k times the exact bound on the
    Newton step) whose polydisc about x passes the test, or None."""
    n = system.n
    f, jac = system.evaluate(x)
    y = _inverse(jac)
    if y is None:
        return None
    step: Real = (0, 0)
    contraction: Real = (0, 0)
    norm_y: Real = (0, 0)
    for i in range(n):
        yf = ZERO
        row: Real = (0, 0)
        size: Real = (0, 0)
        for j in range(n):
            yf = _add(yf, _mul(y[i][j], f[j]))
            entry = ZERO
            for m in range(n):
                entry = _add(entry, _mul(y[i][m], jac[m][j]))
            if i == j:
                entry = _add(entry, (-1, 0, 0))
            row = _radd(row, _modulus_bound(entry))
            size = _radd(size, _modulus_bound(y[i][j]))
        step = _rmax(step, _modulus_bound(yf))
        contraction = _rmax(contraction, row)
        norm_y = _rmax(norm_y, size)
    magnitude = [_modulus_bound(v) for v in x]
    for shift in MULTIPLIER_SHIFTS:
        r = _rmax(least, (step[0], step[1] + shift))
        hessian = system.hessian_bound([_radd(s, r) for s in magnitude])
        inner = _radd(contraction, _rmul(_rmul(norm_y, hessian), r))
        if _less(_radd(step, _rmul(inner, r)), r):
            return r
    return None


def _newton(system: _ExactSystem, x: list[Complex], scale: float) -> list[Complex]:
    for _ in range(REFINEMENTS):
        f, jac = system.evaluate(x)
        step = _solve(jac, f)
        if step is None:
            return x
        x = [_round(_add(xi, _scale(d, -1)), BITS) for xi, d in zip(x, step, strict=True)]
        size = max(abs(_float_of(d)) for d in step)
        if not np.isfinite(size) or size <= scale * 2.0 ** (16 - BITS):
            break
    return x


def _upper_float(value: Real) -> float:
    """A double >= the non-negative dyadic ``value`` (mantissa of any size: a 384-bit mantissa does
    not convert to a float; inf where the value is beyond the double range)."""
    mantissa, exponent = value
    shift = max(0, mantissa.bit_length() - 60)
    upper = -((-mantissa) >> shift)  # rounded up to 60 bits
    try:
        return math.nextafter(math.ldexp(float(upper), exponent + shift), math.inf)
    except OverflowError:
        return math.inf


def certify_root_exactly(
    coefficients: np.ndarray, exponents: np.ndarray, equation: np.ndarray, root: np.ndarray, real_coefficients: bool
) -> ExactCertificate:
    """Certify one candidate ``root`` (n,) of the system ``coefficients`` (T,) (module docstring)."""
    system = _ExactSystem(coefficients, exponents, equation)
    start = np.asarray(root, dtype=complex)
    scale = max(1.0, float(np.abs(start).max()))
    x = _newton(system, [_complex(complex(v)) for v in start], scale)
    least = _real(scale)
    least = (least[0], least[1] - (BITS - 8))
    radius = _test(system, x, least)
    center = np.array([_float_of(v) for v in x])
    if radius is None:
        return ExactCertificate(False, center, math.nan, 0)
    # the reported double centre is within its rounding of the exact one: the radius covers it.
    # The reported box holds the root; that it holds only one is proven for B(x, r) inside it.
    # Nothing downstream needs more: disjoint boxes are distinct roots, overlapping ones one
    # cluster, realness is decided about x here (a test about the rounded centre itself fails for
    # rus6's roots of size 1e4 and beyond)
    rounding: Real = (0, 0)
    for v, c in zip(x, center, strict=True):
        rounding = _rmax(rounding, _modulus_bound(_add(v, _complex(-c))))
    total = _radd(radius, rounding)
    reported = _upper_float(total)
    real = 0
    if real_coefficients and system.real_coefficients:
        if any(_less(radius, (abs(v[1]), v[2])) for v in x):
            real = -1  # the polydisc misses the real space
        else:
            # a unique root in a conjugation-symmetric polydisc about Re x holding B(x, r) is real
            need: Real = (0, 0)
            for v in x:
                need = _rmax(need, (abs(v[1]), v[2]))
            if _test(system, [(v[0], 0, v[2]) for v in x], _radd(need, radius)) is not None:
                real = 1
    return ExactCertificate(True, center, reported, real)


def realness_in_chart(
    coefficients: np.ndarray,
    exponents: np.ndarray,
    equation: np.ndarray,
    patch_equation: int,
    homogeneous: list[int],
    root: np.ndarray,
) -> int:
    """Whether the root near ``root`` (n,) of a system whose equations but the complex linear
    ``patch_equation`` are homogeneous in the unknowns ``homogeneous``, with real coefficients,
    is a real projective point: +1 real, -1 not, 0 undecided (the root not certified, or the
    coefficients not real).

    The root is certified exactly (``certify_root_exactly``) in a box B(x, r); its image in the
    real chart z_j = 1 (j: the largest homogeneous entry, 4 r <= |x_j|) lies within ``need`` of
    the real point Re(x / x_j) (group entries: |z_i / z_j - x_i / x_j| <= 2 r (|x_i| + |x_j|) /
    |x_j|^2; the others move by r). If a polydisc of radius >= need about that real point holds
    exactly one root of the chart system (real coefficients), that root is its own conjugate: the
    image, so the root, is real. If the image's box misses the real space, it is not."""
    patch = np.asarray(equation) == patch_equation
    if not np.all(np.asarray(coefficients)[~patch].imag == 0):
        return 0
    box = certify_root_exactly(coefficients, exponents, equation, root, False)
    if not box.unique:
        return 0
    x, r = box.center, box.radius
    group = np.zeros(x.size, dtype=bool)
    group[list(homogeneous)] = True
    j = int(np.asarray(homogeneous)[np.abs(x[homogeneous]).argmax()])
    size_j = abs(x[j])
    if not 4 * r <= size_j:
        return 0
    w = np.where(group, x / x[j], x)
    # the image's distance from w, and w's own rounding (a quotient: a few units in the last place)
    moved = np.where(group, 2 * r * (np.abs(x) + size_j) / size_j**2, r) + 8 * UNIT_ROUNDING * np.abs(w)
    if (np.abs(w.imag) > moved * (1 + 1e-12)).any():
        return -1  # the image's box misses the real space
    need = float(((np.abs(w.imag) + moved) * (1 + 1e-12)).max())
    keep = ~patch
    n = x.size
    chart_exponents = np.concatenate([np.asarray(exponents)[keep], np.zeros((2, n), np.int64)])
    chart_exponents[-2, j] = 1
    chart_equation = np.r_[np.asarray(equation)[keep], [patch_equation, patch_equation]]
    chart_coefficients = np.r_[np.asarray(coefficients)[keep].real, [1.0, -1.0]]
    system = _ExactSystem(chart_coefficients, chart_exponents, chart_equation)
    centre: list[Complex] = [(mantissa, 0, exponent) for mantissa, exponent in (_real(float(v)) for v in w.real)]
    return 1 if _test(system, centre, _real(math.nextafter(need, math.inf))) is not None else 0
