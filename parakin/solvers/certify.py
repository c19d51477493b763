"""Certified roots of square polynomial systems: Krawczyk's test in norm form, NumPy only.

A system of n equations in n complex unknowns z is sparse: term t is ``coefficients[..., t] *
prod_i z_i ** exponents[t, i]`` in equation ``equation[t]``; leading axes of ``coefficients`` are a
batch of systems. :func:`certify_roots` proves per candidate that a box (max-norm ball, a polydisk)
around it holds exactly one root, decides whether that root is real, and whether the boxes of an
input are disjoint: certified, distinct real endpoints of a homotopy are then provably distinct roots.

The test (Krawczyk 1969; Rump, Acta Numerica 2010; Breiding, Rose, Timme, ACM TOMS 2023): for a
centre x, any matrix Y and B = B(x, r), if
    ||Y F(x)|| + (||I - Y J(x)|| + ||Y|| L(r)) r < r,   L(r) >= max_{z in B} ||J(z) - J(x)||
(max-norm, operator infinity norm), then z -> z - Y F(z) maps B into itself with Lipschitz constant
< 1 and Y is invertible, so B holds exactly one root. We take L(r) = r max_k H_k(rho), rho = |x| + r,
    H_k(rho) = sum_{t in equation k} |c_t| sum_{i,j} a_ti (a_tj - [i = j]) rho^(a_t - e_i - e_j):
for |h_j| <= r, |(x + h)^b - x^b| <= rho^b - |x|^b (expand the product, triangle inequality)
<= r sum_j b_j rho^(b - e_j) (mean value theorem on s -> (|x| + s)^b, whose derivative grows with s);
with b = a_t - e_i for entry (k, i) of J, summed over the row.

Rounding model: the standard model without underflow (Higham, Accuracy and Stability, 2.2):
fl(a op b) = (a op b)(1 + d), |d| <= u = 2^-53; a complex product counts as 3 roundings (its error is
below sqrt(5) u), |z| as 2; matrix products use a conventional algorithm (any summation order).
K = 4 (d + n) + 2 T + U + V + 32 (degree d, T terms, U distinct monomials of F and J, V of the second
derivatives; ``_System.count``) bounds the roundings on any evaluation path and g = 4 K u >= 2 gamma_K,
gamma_K = K u / (1 - K u). Then |F(x) - F~| <= g S~ and |J(x) - J~| <= g SJ~ (S~, SJ~: the computed
absolute-value polynomials sum |c_t| |x^a_t| and their Jacobian analogue) and |Y J~ - fl(Y J~)| <=
g |Y| SJ~, so ||Y F(x)|| <= || |Y| (|F~| + g S~) || and ||I - Y J(x)|| <= || |fl(I - Y J~)| + 2 g |Y| SJ~ ||.
The rest are sums of products of non-negative numbers (at most K roundings), so the computed left
side times (1 + g) bounds the exact one: no box passes that the exact test with these bounds
rejects. Overflow gives inf or NaN, which fails the test.

Realness is decided by the one test's own bounds where it can be (krawczyk.h's argument, stated in
its opening comment; here in this rounding model). For a system whose coefficients are real (the
patch's excepted), the conjugate of a root is a root, and a passing box holds exactly one root: where
it also holds that root's conjugate, the root is real. So: (1) an affine candidate within NEAR of the
real space is projected onto it, sharpened by Newton steps kept real and tested there (a box about a
real point is its own conjugate); (2) at a complex centre x, the bounds at x are tried once more on
the radius (r + 2 max |Im x_i|) (1 + 4 u), which holds the root and its conjugate; (3) homogeneous
unknowns: on a radius that holds B(x, r) and its image under the patched system's mirror
(``_mirror_radius``: the conjugate moved back into the patch, whose fixed points are the real
projective points). Where these fail, a second test at Re x (affine) or in the real chart z_j = 1
(homogeneous) on a conjugation-symmetric box holding B(x, r); a box missing the real space (or the
real projective points) holds a non-real root.
"""

from __future__ import annotations

import ctypes
import functools
import threading
import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from parakin.errors import BadInputError, StaleLibraryError

if TYPE_CHECKING:
    from parakin.packages.compiled import CompiledBackend

UNIT = 2.0**-53
#: Newton may move a candidate at most this times its max-norm, and a box is at most that wide: a
#: candidate far from a root is not certified even where Newton would find one
NEAR = 1e-6
#: radii tried, times the bound on the Newton step (the smallest passing one is kept)
MULTIPLIERS = np.array([2.0, 8.0, 64.0, 1024.0, 65536.0])
#: Newton steps that sharpen each candidate before the test
NEWTON_STEPS = 2
#: the steps stop after one of at most this times the centre's max-norm: Newton converges
#: quadratically, so the centre is then at rounding unless J is ill conditioned (the tracker's
#: endpoints take one such step); any value is sound: Newton only sharpens the centre, the test decides
SETTLED = 1e-10
#: absolute radius floor (an exact root has a zero Newton step)
FLOOR = 2.0**-600
#: a coordinate of a candidate at most this times the candidate's largest is a zero to rounding
#: (a coordinate that is 0 at the root, left at 1e-30..1e-15 by the tracker): it has no size to
#: measure its coordinate by (``_typical_size``). Were it counted, a coordinate that is 0 at half
#: of the roots or more (a symmetric input: a 3-RRS at its home, x = y = 0 at 18 of 32 endpoints
#: after one path ended on another's root) would get a typical size of 2e-15, and no box about
#: such a root could be that narrow in it: 4 real roots of undecided realness, the home pose lost
ZERO_SIZE = 2.0**-40


@dataclass(frozen=True)
class Certificate:
    """Per root p of each input: ``unique`` (..., P) the box of centre ``center[..., p, :]`` (the
    candidate after Newton sharpening) and half-widths ``radii[..., p, :]`` per coordinate (NaN
    if not certified) holds exactly one root of F; ``radius`` the max-norm radius of the ball
    about the centre inside that box; ``real`` +1 that root is certified real (in the real chart
    for homogeneous unknowns), -1 certified non-real, 0 undecided; per input, ``distinct`` no two
    certified boxes overlap, ``certified_distinct`` the number of clusters of overlapping certified
    boxes (a lower bound on the number of distinct roots), and ``labels`` (..., P) per root its
    cluster's first member (-1 where not ``unique``: ``cluster_labels``)."""

    unique: NDArray[np.bool_]
    radius: NDArray[np.float64]
    real: NDArray[np.int8]
    distinct: NDArray[np.bool_]
    certified_distinct: NDArray[np.int64]
    center: NDArray[np.complex128]
    radii: NDArray[np.float64]
    labels: NDArray[np.intp] | None = None


#: a polynomial map is evaluated through a dense per-input table of monomial by output (a matrix
#: product) when at least this share of the table's entries are terms, else term by term
DENSE = 0.08


class _Layout:
    """Where the terms of a polynomial map go, fixed by the family: term q adds to output
    ``target[q]`` its coefficient times monomial ``monomial[q]`` (of ``monomials``); the terms
    sorted by destination once, so that each evaluation sums contiguous runs."""

    def __init__(self, monomial: np.ndarray, target: np.ndarray, monomials: int, size: int, dense: float) -> None:
        self.size, self.monomial, self.monomials = size, monomial, monomials
        self.dense = monomial.size >= dense * monomials * size
        index = monomial * size + target if self.dense else target
        self.order = np.argsort(index, kind="stable")
        ordered = index[self.order]
        self.starts = np.r_[0, np.nonzero(np.diff(ordered))[0] + 1] if index.size else np.zeros(0, np.int64)
        self.present = ordered[self.starts]


class _Polynomials:
    """Outputs out_k = sum over terms q with target[q] = k of coefficients[..., q] * m[monomial[q]],
    for monomial values m (..., P, U): either a matrix product with the per-input table of
    coefficient sums (dense maps, a fast BLAS product) or a sum per output of the terms' products
    (sparse maps, where most of a table would be zeros). Each output is one sum (counted in K)."""

    def __init__(self, coefficients: np.ndarray, layout: _Layout):
        self.layout, self.coefficients = layout, coefficients
        if layout.dense:
            self.table = self._sum(coefficients, layout.monomials * layout.size).reshape(
                coefficients.shape[:-1] + (layout.monomials, layout.size)
            )

    @property
    def dense(self) -> bool:
        return self.layout.dense

    def _sum(self, values: np.ndarray, size: int) -> np.ndarray:
        layout = self.layout
        out = np.zeros(values.shape[:-1] + (size,), values.dtype)
        if layout.starts.size:
            out[..., layout.present] = np.add.reduceat(values[..., layout.order], layout.starts, axis=-1)
        return out

    def __call__(self, m: np.ndarray) -> np.ndarray:
        if self.layout.dense:
            return m @ self.table
        return self._sum(self.coefficients[..., None, :] * m[..., self.layout.monomial], self.layout.size)


def _monomials(x: np.ndarray, table_rows: np.ndarray) -> np.ndarray:
    """x (..., m, n) -> x^e (..., m, U) for the rows e of table_rows, by repeated products."""
    powers = np.empty(x.shape + (int(table_rows.max(initial=0)) + 1,), x.dtype)
    powers[..., 0] = 1
    for k in range(1, powers.shape[-1]):
        powers[..., k] = powers[..., k - 1] * x
    out = powers[..., 0, table_rows[:, 0]]
    for i in range(1, x.shape[-1]):
        out = out * powers[..., i, table_rows[:, i]]
    return out


class _Structure:
    """What the certificate needs of a family that its coefficients do not change, computed once
    per family (``_structure``): the distinct monomials of F and J (``rows``) and of the second
    derivatives (``second``), where each term of F, J and H goes, and the rounding count K."""

    def __init__(self, exponents: np.ndarray, equation: np.ndarray, dense: float) -> None:
        terms, n = exponents.shape
        self.n, eye = n, np.eye(n, dtype=np.int64)
        self.tj, ij = np.nonzero(exponents > 0)  # Jacobian terms: d/dz_i of term t
        rows = np.concatenate([exponents, exponents[self.tj] - eye[ij]])
        self.rows, where = np.unique(rows, axis=0, return_inverse=True)
        where = where.reshape(-1)
        self.weight = exponents[self.tj, ij].astype(float)
        u = self.rows.shape[0]
        self.f = _Layout(where[:terms], equation, u, n, dense)
        self.j = _Layout(where[terms:], equation[self.tj] * n + ij, u, n * n, dense)
        pair = exponents[:, :, None] * (exponents[:, None, :] - eye)  # a_ti (a_tj - [i = j])
        self.th, ih, jh = np.nonzero(pair > 0)
        self.second, at = np.unique(exponents[self.th] - eye[ih] - eye[jh], axis=0, return_inverse=True)
        self.pair = pair[self.th, ih, jh]
        self.h = _Layout(at.reshape(-1), equation[self.th], self.second.shape[0], n, dense)
        degree = int(exponents.sum(1).max(initial=0))
        # roundings on any path (module docstring): F~, J~: 3 (degree + n + 1) + terms + monomials;
        # L: 4 degree + n (rho's error raised to the degree) + 2 terms (2 pairs (i, j) per term) + the
        # second-derivative monomials; the Y products 2 n; the assembly of the test a constant
        self.count = 4 * (degree + n) + 2 * terms + self.rows.shape[0] + self.second.shape[0] + 32


@functools.lru_cache(maxsize=64)
def _cached_structure(exponents: bytes, shape: tuple[int, int], equation: bytes, dense: float) -> _Structure:
    return _Structure(
        np.frombuffer(exponents, np.int64).reshape(shape).copy(), np.frombuffer(equation, np.int64).copy(), dense
    )


def _structure(exponents: np.ndarray, equation: np.ndarray) -> _Structure:
    """The family's ``_Structure``, computed on its first certificate and kept (a single input's
    certificate would otherwise spend most of its time here)."""
    e = np.ascontiguousarray(exponents, dtype=np.int64)
    return _cached_structure(e.tobytes(), e.shape, np.ascontiguousarray(equation, dtype=np.int64).tobytes(), DENSE)


class _System:
    """F, J, the absolute-value polynomials S, SJ and the sums H_k (module docstring) as
    polynomial maps over the distinct monomials of F and J (``rows``) and of the second
    derivatives (``second``), for the coefficients c (..., T)."""

    def __init__(self, c: np.ndarray, exponents: np.ndarray, equation: np.ndarray) -> None:
        structure = _structure(exponents, equation)
        self.n, self.rows, self.second = structure.n, structure.rows, structure.second
        cj = c[..., structure.tj] * structure.weight
        self.F, self.S = (_Polynomials(v, structure.f) for v in (c, abs(c)))
        self.J, self.SJ = (_Polynomials(v, structure.j) for v in (cj, abs(cj)))
        self.H = _Polynomials(abs(c[..., structure.th]) * structure.pair, structure.h)
        self.count = structure.count
        self.gain = 4.0 * self.count * UNIT

    def evaluate(self, x: np.ndarray) -> tuple[np.ndarray, ...]:
        """F~, J~ (k, i), S~, SJ~ at x (..., m, n)."""
        m = _monomials(x, self.rows)
        size = abs(m)
        shape = x.shape[:-1] + (self.n, self.n)
        return self.F(m), self.J(m).reshape(shape), self.S(size), self.SJ(size).reshape(shape)

    def bounds(self, x: np.ndarray) -> tuple[np.ndarray, ...]:
        """Bounds on ||Y F(x)||, ||I - Y J(x)||, ||Y|| and the Newton step Y F~ at x."""
        f, jac, s, sj = self.evaluate(x)
        finite = np.isfinite(jac).all((-2, -1))
        y = _inverse(np.where(finite[..., None, None], jac, np.eye(self.n)))
        absolute = abs(y)
        step = (absolute @ (abs(f) + self.gain * s)[..., None])[..., 0].max(-1)
        residual = np.eye(self.n) - y @ jac
        contraction = (abs(residual) + absolute @ (2 * self.gain * sj)).sum(-1).max(-1)
        return np.where(finite, step, np.nan), contraction, absolute.sum(-1).max(-1), (y @ f[..., None])[..., 0]

    def passes(self, x: np.ndarray, r: np.ndarray, bounds: tuple[np.ndarray, ...]) -> np.ndarray:
        """The test on B(x, r) for radii r (..., m, R)."""
        a, b, c = (v[..., None] for v in bounds[:3])
        rho = abs(x)[..., None, :] + r[..., None]
        flat = rho.reshape(rho.shape[:-3] + (-1, self.n))
        hessian = self.H(_monomials(flat, self.second)).max(-1).reshape(r.shape)
        return np.asarray((a + (b + c * r * hessian) * r) * (1 + self.gain) < r)

    def contains(self, x: np.ndarray, need: np.ndarray, floor: np.ndarray) -> np.ndarray:
        """A box of radius >= need around x passes the test (Newton-free: x is kept as given)."""
        bounds = self.bounds(x)
        r = MULTIPLIERS * np.fmax(need, bounds[0])[..., None] + floor[..., None]
        return np.asarray(self.passes(x, r, bounds).any(-1))


def _inverse(jac: np.ndarray) -> np.ndarray:
    """Approximate inverses; any matrix keeps the test sound, so singular ones get a pseudo-inverse."""
    try:
        return np.linalg.inv(jac)
    except np.linalg.LinAlgError:
        pass
    # only the singular ones (an exactly zero pivot) get the costly SVD-based pseudo-inverse
    singular = ~(np.linalg.det(jac) != 0)
    out = np.empty_like(jac)
    out[~singular] = np.linalg.inv(jac[~singular])
    try:
        out[singular] = np.linalg.pinv(jac[singular])
    except np.linalg.LinAlgError:
        out[singular] = np.nan
    return out


def homogeneous_group(exponents: ArrayLike, equation: ArrayLike, patch_equation: int, declared: list[int]) -> list[int]:
    """The unknowns in which every equation but the patch is homogeneous: ``declared`` where they
    suffice, else every unknown (Study coordinates: the quadrics are homogeneous in (e, g) jointly
    while the patch normalises e alone). Raises BadInputError when neither is. Decided once per
    family (every certificate of a homotopy asks)."""
    e = np.ascontiguousarray(exponents, dtype=np.int64)
    k = np.ascontiguousarray(equation, dtype=np.int64)
    shown = f"{declared}"  # the message names them as the caller wrote them
    return list(_cached_group(e.tobytes(), e.shape, k.tobytes(), k.shape, patch_equation, tuple(declared), shown))


@functools.lru_cache(maxsize=64)
def _cached_group(
    exponents: bytes,
    shape: tuple[int, ...],
    equation: bytes,
    length: tuple[int, ...],
    patch: int,
    declared: tuple,
    shown: str,
) -> tuple[int, ...]:
    e = np.frombuffer(exponents, np.int64).reshape(shape)
    k = np.frombuffer(equation, np.int64).reshape(length)
    others = k != patch
    for group in (sorted(int(i) for i in declared), list(range(e.shape[1]))):
        degree = e[:, group].sum(1)
        if all(np.ptp(degree[others & (k == j)]) == 0 for j in set(k[others].tolist())):
            return tuple(group)
    raise BadInputError(f"the equations but the patch {patch} are homogeneous neither in {shown} nor in all unknowns")


def _typical_size(z: np.ndarray) -> np.ndarray:
    """Per system and coordinate (..., 1, n): a power of two near the median size of that
    coordinate over the system's finite candidates z (..., P, n) where it is not zero to rounding
    (``ZERO_SIZE`` times the candidate's largest coordinate, or less); 1 where there is none."""
    size = np.where(np.isfinite(z).all(-1)[..., None], abs(z), np.nan)
    largest = np.where(np.isnan(size), -np.inf, size).max(-1, keepdims=True)
    # a root at 0 has no size to measure by, nor one whose coordinate is 0 to rounding
    size = np.where((size > 0) & (size > ZERO_SIZE * largest), size, np.nan)
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an all-NaN slice: no candidate
        median = np.nanmedian(size, axis=-2, keepdims=True)
    usable = np.isfinite(median) & (median > 0)
    return np.where(usable, np.exp2(np.round(np.log2(np.where(usable, median, 1.0)))), 1.0)


@np.errstate(all="ignore")  # NaN rows and overflow are handled: never a warning
def _checked_system(
    coefficients: ArrayLike, exponents: ArrayLike, equation: ArrayLike, roots: ArrayLike
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, tuple[int, ...]]:
    """The systems and candidates of a certificate checked (BadInputError naming what is wrong)
    and broadcast to one batch: coefficients (..., T), exponents (T, n), equation (T,), roots
    (..., P, n) and the batch shape."""
    exponents = np.asarray(exponents, dtype=np.int64)
    equation = np.asarray(equation, dtype=np.int64)
    c = np.asarray(coefficients, dtype=np.complex128)
    z = np.asarray(roots, dtype=np.complex128)
    _check_structure(exponents.tobytes(), exponents.shape, equation.tobytes(), equation.shape)
    terms, n = exponents.shape
    if c.ndim < 1 or c.shape[-1] != terms or z.ndim < 2 or z.shape[-1] != n:
        raise BadInputError(f"coefficients (..., {terms}) and roots (..., P, {n}) expected: {c.shape}, {z.shape}")
    try:
        batch = np.broadcast_shapes(c.shape[:-1], z.shape[:-2])
    except ValueError as error:
        raise BadInputError(f"batch shapes {c.shape[:-1]} and {z.shape[:-2]} do not broadcast") from error
    return np.broadcast_to(c, batch + (terms,)), exponents, equation, np.broadcast_to(z, batch + z.shape[-2:]), batch


@functools.lru_cache(maxsize=64)
def _check_structure(exponents: bytes, shape: tuple[int, ...], equation: bytes, length: tuple[int, ...]) -> None:
    """BadInputError unless the exponents (T, n) are non-negative and the equation (T,) indices in
    [0, n) (``_checked_system``); checked once per family (every certificate of a homotopy asks)."""
    a = np.frombuffer(exponents, np.int64).reshape(shape)
    k = np.frombuffer(equation, np.int64).reshape(length)
    if a.ndim != 2 or a.shape[1] < 1 or (a < 0).any():
        raise BadInputError(f"exponents must be (terms, unknowns) non-negative integers, got shape {a.shape}")
    terms, n = a.shape
    if k.shape != (terms,) or ((k < 0) | (k >= n)).any():
        raise BadInputError(f"equation must be ({terms},) indices in [0, {n}), got {k}")


def certify_roots(
    coefficients: ArrayLike,
    exponents: ArrayLike,
    equation: ArrayLike,
    roots: ArrayLike,
    real_coefficients: bool = True,
    homogeneous: list[int] | None = None,
    patch_equation: int | None = None,
) -> Certificate:
    """Certificate of each candidate ``roots`` (..., P, n) (NaN rows: no candidate) of the systems
    ``coefficients`` (..., T), ``exponents`` (T, n), ``equation`` (T,) (module docstring).

    Realness (+1) needs ``real_coefficients`` and, per input, coefficients whose imaginary parts are
    exactly 0 (the patch's excepted); it is decided from the one test's bounds first (module
    docstring), as ``certify_roots_compiled`` does: a root certified at a real centre has that real
    centre (imaginary parts 0). With ``homogeneous`` unknowns and the complex linear
    ``patch_equation`` sum a_i z_i - 1 over them (every other equation homogeneous in them),
    realness is decided in the real chart z_j = 1, j the homogeneous unknown of largest |z_j|."""
    c, exponents, equation, z, batch = _checked_system(coefficients, exponents, equation, roots)
    terms, n = exponents.shape
    if homogeneous is None:
        # each candidate in its own coordinates w = z / D, D = diag of powers of two >= |z_i|:
        # the test's max-norm box becomes a box of radius r D_i per coordinate, fitting roots of
        # very different sizes (a root near infinity); the scaling is exact in floating point.
        # A coordinate near 0 is measured in its typical size over the candidates of its system
        # (the median: a few roots near infinity do not move it), not in absolute units, so a
        # geometry in millimetres is certified as the same geometry in metres
        k = np.where(np.isfinite(z), np.ceil(np.log2(np.fmax(abs(z), _typical_size(z)))), 0.0).astype(np.int64)
        shift = k @ exponents.T  # (..., P, T): c_t prod_i D_i^a_ti
        scaled = np.ldexp(c.real[..., None, :], shift) + 1j * np.ldexp(c.imag[..., None, :], shift)
        w = (z / np.ldexp(1.0, k))[..., None, :]
        unique, radius, code, x = _certify(scaled, exponents, equation, w, real_coefficients, None, None, unit=0.5)
        scale = np.ldexp(1.0, k)
        centre, radii = x[..., 0, :] * scale, radius[..., 0, None] * scale
        labels, distinct = cluster_labels(centre, np.where(unique[..., 0, None], radii, 0.0), unique[..., 0])
        inner = radius[..., 0] * scale.min(-1)
        count = _cluster_count(labels)
        return Certificate(unique[..., 0], inner, code[..., 0], distinct, count, centre, radii, labels)
    unique, radius, code, x = _certify(c, exponents, equation, z, real_coefficients, homogeneous, patch_equation)
    radii = radius[..., None] * np.ones(n)
    labels, distinct = cluster_labels(x, np.where(unique[..., None], radii, 0.0), unique)
    return Certificate(unique, radius, code, distinct, _cluster_count(labels), x, radii, labels)


def _certify(
    c: np.ndarray,
    exponents: np.ndarray,
    equation: np.ndarray,
    z: np.ndarray,
    real_coefficients: bool,
    homogeneous: list[int] | None,
    patch_equation: int | None,
    unit: float = 1e-150,
) -> tuple[np.ndarray, ...]:
    """The test on each candidate (``certify_roots``, validated and broadcast): unique, radius,
    realness code and the sharpened centres (NaN where no candidate was given)."""
    terms, n = exponents.shape
    group, patch = np.zeros(n, bool), np.zeros(terms, bool)
    if homogeneous is not None:
        if not all(0 <= int(i) < n for i in homogeneous) or patch_equation not in range(n):
            raise BadInputError(f"homogeneous {homogeneous} and patch_equation {patch_equation}: indices in [0, {n})")
        group[list(homogeneous)] = True
        patch = equation == patch_equation
        linear = (exponents[patch] * ~group).sum(1) + np.maximum(exponents[patch].sum(1) - 1, 0)
        degree = (exponents * group).sum(1)
        if not group.any() or linear.any() or not patch.any():
            raise BadInputError(
                f"homogeneous {homogeneous} needs a linear patch_equation in them, got {patch_equation}"
            )
        if any(np.ptp(degree[equation == k]) for k in set(equation[~patch].tolist())):
            raise BadInputError(f"every equation but the patch must be homogeneous in the unknowns {homogeneous}")
    given = np.asarray(np.isfinite(z).all(-1))
    # the realness arguments need F (but the patch) to have exactly real coefficients
    real_system = np.broadcast_to(
        ((c.imag[..., ~patch] == 0).all(-1) & bool(real_coefficients))[..., None], given.shape
    )
    # ``unit``: the least size a candidate is measured against (scaled coordinates: their
    # typical size, 1/2 after rounding; a root at the origin moves relative to that)
    scale = NEAR * np.fmax(abs(z).max(-1), unit)
    unique, radius = np.zeros(given.shape, bool), np.full(given.shape, np.nan)
    x, floor = np.where(given[..., None], z, 1.0 + 0j), np.zeros(given.shape)
    wide, real = np.zeros(given.shape, bool), np.zeros(given.shape, bool)
    todo = given
    if homogeneous is None:  # within the test's reach of the real space: one test at a real centre
        near = given & real_system & (abs(z.imag).max(-1) <= scale)
        if near.any():
            found = _attempt(c, exponents, equation, z, scale, near, True, None)
            real = found[0].copy()  # B(x, r) about a real x is its own conjugate: its one root is real
            for out, value in zip((unique, radius, x, floor), found[:4], strict=True):
                np.copyto(out, value, where=near[(...,) + (None,) * (out.ndim - near.ndim)])
            todo = given & ~real
    if todo.any():
        mirror = (patch_equation, group, patch) if homogeneous is not None else None
        found = _attempt(c, exponents, equation, z, scale, todo, False, mirror)
        for out, value in zip((unique, radius, x, floor, wide), found, strict=True):
            np.copyto(out, value, where=todo[(...,) + (None,) * (out.ndim - todo.ndim)])
    r = np.where(unique, radius, 0.0)[..., None]
    candidates = unique & real_system & ~real
    # a root whose box misses the real space is non-real
    nonreal = (abs(x.imag) > r)[..., ~group].any(-1) & ~real
    if homogeneous is None:
        # the one test's bounds at x passed on B(x, r + 2 max |Im x|) (wide): real; else a second
        # test: B(x, r) lies in the conjugation-symmetric B(Re x, need)
        real |= wide & candidates & ~nonreal
        need = (abs(x.imag).max(-1) + r[..., 0]) * (1 + 4 * UNIT)
        real |= _contains_where(c, exponents, equation, x.real + 0j, need, floor, candidates & ~nonreal & ~real)
    else:
        jmax = np.asarray(homogeneous)[abs(x[..., homogeneous]).argmax(-1)]
        xj = np.take_along_axis(x, jmax[..., None], -1)
        mi, mj = abs(x), abs(xj)
        # a real projective point has Im(z_i conj z_j) = 0; over B(x, r) it moves <= r (|x_i| + |x_j| + r)
        cross = abs(x.imag * xj.real - x.real * xj.imag)
        slack = (r * (mi + mj + r) + 8 * UNIT * mi * mj) * (1 + 16 * UNIT)
        nonreal |= (cross > slack)[..., group].any(-1)
        # the mirror's box (wide) passed: the root is its own mirror image, a real projective point
        real = wide & candidates & ~nonreal
        keep = ~patch
        chart_exponents = np.concatenate([exponents[keep], np.zeros((2, n), np.int64)])
        chart_equation = np.r_[equation[keep], [patch_equation, patch_equation]]
        ones = np.broadcast_to(np.array([1.0, -1.0]), c.shape[:-1] + (2,))
        chart_c = np.concatenate([c[..., keep], ones], -1)
        for j in homogeneous:  # the real chart: z_j - 1 = 0 replaces the patch
            chart_exponents[-2] = np.eye(n, dtype=np.int64)[j]
            w = x.real.copy()
            w[..., group] = (x / x[..., j : j + 1]).real[..., group]
            w[..., j] = 1.0
            # the chart image of B(x, r) (4 r <= |x_j|) lies in B(w, need): for i homogeneous,
            # |z_i/z_j - x_i/x_j| <= 2 r (|x_i| + |x_j|) / |x_j|^2 and |x_i/x_j - w_i| = |x_i - w_i x_j| / |x_j|
            gap = (abs(x - w * xj) + 2 * UNIT * abs(w) * mj + 2 * r * (mi + mj) / mj) / mj
            need = np.where(group, gap, abs(x.imag) + r).max(-1) * (1 + 16 * UNIT)
            pick = candidates & ~nonreal & ~real & (jmax == j) & (4 * r[..., 0] <= mj[..., 0])
            real |= _contains_where(chart_c, chart_exponents, chart_equation, w + 0j, need, floor, pick)
    code = np.where(real, 1, np.where(unique & nonreal, -1, 0)).astype(np.int8)
    return unique, radius, code, np.where(given[..., None], x, np.nan)


def _attempt(
    c: np.ndarray,
    exponents: np.ndarray,
    equation: np.ndarray,
    z: np.ndarray,
    scale: np.ndarray,
    mask: np.ndarray,
    real_centre: bool,
    mirror: tuple | None,
) -> tuple[np.ndarray, ...]:
    """One test per candidate z (..., m, n) where ``mask`` (..., m), on systems built for those
    only: Newton steps (kept real from Re z where ``real_centre``), then the smallest passing radius
    (at most ``scale``, the centre within ``scale`` of z). Returns, shaped as ``mask`` (and x as z),
    unique, radius, the centre x, the radius floor and (a complex centre) whether the same bounds
    at x pass on the box that holds the root's conjugate too (affine: r + 2 max |Im x|; homogeneous,
    ``mirror`` = (patch equation, group, patch terms): ``_mirror_radius``)."""
    index = np.nonzero(mask)
    cs = np.broadcast_to(c[..., None, :], mask.shape + c.shape[-1:])[index]
    given = z[index][:, None, :]
    near = scale[index][:, None]
    system = _System(cs, exponents, equation)
    x = given.real + 0j if real_centre else given
    settled = np.zeros(near.shape, bool)
    for _ in range(NEWTON_STEPS):  # sharpen; a step that leaves the finite numbers is dropped
        step = system.bounds(x)[3]
        step = step.real + 0j if real_centre else step
        new = x - step
        take = np.isfinite(new).all(-1) & ~settled
        x = np.where(take[..., None], new, x)
        settled |= take & (abs(step).max(-1) <= SETTLED * abs(x).max(-1))
    bounds = system.bounds(x)
    valid = abs(x - given).max(-1) <= near
    floor = 4 * UNIT * abs(x).max(-1) + FLOOR
    radii = MULTIPLIERS * bounds[0][..., None] + floor[..., None]
    ok = system.passes(x, radii, bounds) & (radii <= near[..., None]) & valid[..., None]
    unique = ok.any(-1)
    radius = np.where(unique, np.take_along_axis(radii, ok.argmax(-1)[..., None], -1)[..., 0], np.nan)
    wide = np.zeros(unique.shape, bool)
    if not real_centre and unique.any():
        r = np.where(unique, radius, 0.0)
        if mirror is None:  # B(x, R) holds the root and its conjugate (rounded up: one sum)
            outer = (r + 2 * abs(x.imag).max(-1)) * (1 + 4 * UNIT)
        else:
            outer = _mirror_radius(cs, exponents, x, r, mirror, system.gain)
        usable = unique & (outer > 0) & np.isfinite(outer)
        wide = system.passes(x, np.where(usable, outer, 1.0)[..., None], bounds)[..., 0] & usable
    out = [np.zeros(mask.shape, bool), np.full(mask.shape, np.nan), np.full(z.shape, np.nan + 0j), np.zeros(mask.shape)]
    out.append(np.zeros(mask.shape, bool))
    for target, value in zip(out, (unique, radius, x, floor, wide), strict=True):
        target[index] = value[:, 0]
    return tuple(out)


def _mirror_radius(
    c: np.ndarray, exponents: np.ndarray, x: np.ndarray, r: np.ndarray, mirror: tuple, gain: float
) -> np.ndarray:
    """A radius about homogeneous centres x (K, 1, n) that holds B(x, r) (r (K, 1)) and its image
    under the patched system's mirror s(z) = (m conj z_G, conj z_rest), m = -c0 / M(z), M(z) =
    sum_t c_t conj z_(k_t) over the patch's linear terms (krawczyk.h's kw_mirror_radius), 0 where
    |M| has no positive lower bound over B(x, r). Over B(x, r): |M(v) - M~| <= g A + C r (A = sum
    |c_t| |x_(k_t)|, C = sum |c_t|, g the system's ``gain`` >= 2 gamma of these few operations), so
    |M| >= low; |s(v)_i - x_i| = |-c0 conj v_i - x_i M(v)| / |M(v)| on G, each term bounded as
    in the module docstring's model (every computed non-negative bound times 1 + g)."""
    _, group, patch = mirror
    terms = np.nonzero(patch)[0]
    linear = exponents[terms].sum(1) > 0
    k = exponents[terms[linear]].argmax(1)
    cl, constant = c[:, None, terms[linear]], c[:, None, terms[~linear]]
    c0, c0_size = constant.sum(-1), abs(constant).sum(-1)
    xk = x[..., k]
    total = (cl * xk.conj()).sum(-1)
    size, spread = (abs(cl) * abs(xk)).sum(-1), abs(cl).sum(-1)
    g = gain
    low = (abs(total) * (1 - g) - (g * size + spread * r) * (1 + g)) * (1 - g)
    ax, rr = abs(x), r[..., None]
    # a bound that overflowed to inf - inf is NaN: it proves nothing, so it must not be dropped
    # (np.maximum keeps it, and the radius is then 0)
    with np.errstate(all="ignore"):
        top = -c0[..., None] * x.conj() - x * total[..., None]
        error = g * c0_size[..., None] * (ax + rr) + abs(c0)[..., None] * rr + ax * (g * size + spread * r)[..., None]
        top_up = (abs(top) + error + g * ax * (abs(c0) + abs(total))[..., None]) * (1 + g)
        gap = np.where(group, top_up / low[..., None] * (1 + g), (rr + 2 * abs(x.imag)) * (1 + 4 * UNIT))
    wide = np.maximum(gap.max(-1), r)
    return np.where((low > 0) & np.isfinite(wide), wide, 0.0)


def _contains_where(
    c: np.ndarray,
    exponents: np.ndarray,
    equation: np.ndarray,
    x: np.ndarray,
    need: np.ndarray,
    floor: np.ndarray,
    mask: np.ndarray,
) -> np.ndarray:
    """``_System.contains`` for the candidates x (..., P, n) where ``mask`` (..., P), False
    elsewhere: the systems (..., T) are built for the inputs of those candidates only, so the test
    costs what is asked (the realness test of the few candidates that may be real)."""
    out = np.zeros(mask.shape, bool)
    if not mask.any():
        return out
    index = np.nonzero(mask)
    coefficients = np.broadcast_to(c, mask.shape[:-1] + c.shape[-1:])[index[:-1]]
    system = _System(coefficients, exponents, equation)
    out[index] = system.contains(x[index][:, None, :], need[index][:, None], floor[index][:, None])[:, 0]
    return out


def cluster_labels(
    x: np.ndarray, r: np.ndarray, unique: np.ndarray, library: Any = None
) -> tuple[np.ndarray, np.ndarray]:
    """Clusters of overlapping certified boxes (centres x (..., P, n), radii r (..., P, n) per
    coordinate): per root its cluster's first member (-1 where not ``unique``), and per input
    whether no two boxes overlap. Two boxes are apart where in some coordinate the distance of
    their centres (``np.hypot`` of its parts: the C library's ``hypot``, bit for bit) times
    1 - 8 UNIT exceeds the sum of their radii times 1 + 8 UNIT.

    Where ``library`` (a compiled backend) has ``certify_clusters`` (every homotopy package's
    ``NAME_certify_clusters``, krawczyk.h's ``kw_clusters``), the same labels and flags are
    computed there, bit for bit (``tests/test_clusters_in_c.py``)."""
    clusters = getattr(library, "certify_clusters", None)
    if clusters is not None and x.ndim >= 2 and r.shape == x.shape and unique.shape == x.shape[:-1]:
        return _clusters_in_c(clusters, x, r, unique)
    count = unique.shape[-1]
    both = unique[..., :, None] & unique[..., None, :]
    pending = both & _off_diagonal(count)  # pairs of distinct certified boxes
    # two boxes are apart where they are apart in some coordinate: the first coordinate over
    # whole planes (..., P, P) (distinct roots mostly are apart there), the others only for the
    # pairs still touching (a sign symmetry's images share coordinates: prs3's 16 pairs are
    # apart only in the fifth)
    apart = _apart(x[..., 0], r[..., 0]) if x.shape[-1] else np.zeros(both.shape, dtype=bool)
    touching = pending & ~apart
    if x.shape[-1] > 1 and touching.any():
        index = np.nonzero(touching)
        first, second = index[:-1], index[:-2] + index[-1:]
        d = x[first][:, 1:] - x[second][:, 1:]
        gap = np.hypot(d.real, d.imag) * (1 - 8 * UNIT)
        separated = (gap > (r[first][:, 1:] + r[second][:, 1:]) * (1 + 8 * UNIT)).any(-1)
        apart[index] = separated
        touching[index] = ~separated
    distinct = ~touching.any((-2, -1))
    # a box that touches no other is its own cluster; the closure is needed only where boxes touch
    labels = np.where(unique, np.arange(count), -1)
    if not distinct.all():
        some = ~distinct
        reach = (both & ~apart)[some].astype(float)
        for _ in range(int(np.ceil(np.log2(max(count, 2))))):  # transitive closure by squaring
            reach = np.minimum(reach + reach @ reach, 1.0)
        labels[some] = np.where(unique[some], (reach > 0).argmax(-1), -1)
    return labels, distinct


def _apart(xk: np.ndarray, rk: np.ndarray) -> np.ndarray:
    """Per pair of boxes (..., P, P): apart in the coordinate of centres xk (..., P) and radii rk
    (..., P), with rounding margins."""
    d = xk[..., :, None] - xk[..., None, :]
    gap = np.hypot(d.real, d.imag) * (1 - 8 * UNIT)
    return np.asarray(gap > (rk[..., :, None] + rk[..., None, :]) * (1 + 8 * UNIT))


#: ``_clusters_in_c`` keeps per thread the buffers of a job of at most this many coordinates in all
#: (a control loop's one input: copies into them cost less than fresh arrays' pointers)
REUSED_CLUSTER_SIZE = 4096
_CLUSTER_BUFFERS = threading.local()


class _ClusterBuffers:
    """Inputs and outputs of one shape (..., P, n) of ``NAME_certify_clusters``, with their pointers."""

    def __init__(self, shape: tuple[int, ...]) -> None:
        self.x, self.r = np.empty(shape, np.complex128), np.empty(shape)
        self.unique, self.labels = np.empty(shape[:-1], np.bool_), np.empty(shape[:-1], np.int64)
        self.distinct = np.empty(shape[:-2], np.bool_)
        self.pointers = tuple(a.ctypes.data for a in (self.x, self.r, self.unique, self.labels, self.distinct))


def _clusters_in_c(clusters: Any, x: np.ndarray, r: np.ndarray, unique: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``cluster_labels`` by a library's ``certify_clusters`` (shapes checked by the caller)."""
    shape = x.shape
    systems, count, n = int(np.prod(shape[:-2], dtype=np.int64)), shape[-2], shape[-1]
    if x.size > REUSED_CLUSTER_SIZE:
        buffers = _ClusterBuffers(shape)
    else:
        cache = getattr(_CLUSTER_BUFFERS, "cache", None)
        if cache is None:
            cache = _CLUSTER_BUFFERS.cache = {}
        kept = cache.get(shape)
        if kept is None:
            if len(cache) >= 16:
                cache.clear()
            kept = cache[shape] = _ClusterBuffers(shape)
        buffers = kept
    np.copyto(buffers.x, x)
    np.copyto(buffers.r, r)
    np.copyto(buffers.unique, unique, casting="unsafe")
    clusters(systems, count, n, *buffers.pointers)
    return buffers.labels.copy(), buffers.distinct.copy()[()]


@functools.cache
def _off_diagonal(count: int) -> np.ndarray:
    """(count, count): every pair of distinct indices (read only)."""
    others = ~np.eye(count, dtype=bool)
    others.flags.writeable = False
    return others


def distinct_clusters(x: np.ndarray, r: np.ndarray, unique: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Disjointness of the certified boxes (centres x (..., P, n), radii r (..., P, n) per
    coordinate) and the number of connected clusters of overlapping ones."""
    labels, distinct = cluster_labels(x, r, unique)
    return distinct, _cluster_count(labels)


def _cluster_count(labels: np.ndarray) -> np.ndarray:
    """The clusters of ``cluster_labels``' labels (..., P): the roots that are their cluster's first."""
    return (labels == np.arange(labels.shape[-1])).sum(-1)


def _certify_arguments(
    coefficients: Any, exponents: Any, equation: Any, roots: Any, homogeneous: list[int] | None, patch: int | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, tuple[int, ...]]:
    """``certify_roots``' inputs checked (``_checked_system``) with the homogeneous group, and
    flattened for C: coefficients (N, T), exponents, equation, roots (N, P, n), the batch shape."""
    plain = _plain_arguments(coefficients, exponents, equation, roots, homogeneous, patch)
    if plain is not None:
        return plain
    c, exponents, equation, z, batch = _checked_system(coefficients, exponents, equation, roots)
    exponents, equation = np.ascontiguousarray(exponents), np.ascontiguousarray(equation)
    terms, n = exponents.shape
    if homogeneous is not None:
        _check_group(
            exponents.tobytes(), exponents.shape, equation.tobytes(), tuple(homogeneous), patch, f"{homogeneous}"
        )
    c = np.ascontiguousarray(np.broadcast_to(c, batch + (terms,)).reshape(-1, terms))
    z = np.ascontiguousarray(np.broadcast_to(z, batch + z.shape[-2:]).reshape(-1, *z.shape[-2:]))
    return c, exponents, equation, z, batch


#: the families ``_plain_arguments`` has checked, by the identity of their arrays (which it
#: keeps, so an identity is never reused): (exponents, equation, group, patch) -> the arrays
_CHECKED: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}


def _plain_arguments(
    coefficients: Any, exponents: Any, equation: Any, roots: Any, homogeneous: list[int] | None, patch: int | None
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, tuple[int, ...]] | None:
    """``_certify_arguments`` for the solvers' usual call, without its conversions: C-contiguous
    complex coefficients (N, T) and roots (N, P, n), int64 exponents (T, n) and equation (T,) of
    a family already checked (by the identity of its arrays: a homotopy's, every call). The
    family's checks run once, as in ``_certify_arguments``; None for anything else."""
    arrays = (coefficients, roots, exponents, equation)
    if any(type(x) is not np.ndarray or not x.flags.c_contiguous for x in arrays):
        return None
    if coefficients.dtype != np.complex128 or roots.dtype != np.complex128:
        return None
    if exponents.dtype != np.int64 or equation.dtype != np.int64 or exponents.ndim != 2 or equation.ndim != 1:
        return None
    terms, n = exponents.shape
    if coefficients.ndim != 2 or roots.ndim != 3 or coefficients.shape != (roots.shape[0], terms):
        return None
    if roots.shape[2] != n or equation.shape != (terms,):
        return None
    key = (id(exponents), id(equation), None if homogeneous is None else tuple(homogeneous), patch)
    known = _CHECKED.get(key)
    if known is None or known[0] is not exponents or known[1] is not equation:
        _check_structure(exponents.tobytes(), exponents.shape, equation.tobytes(), equation.shape)
        if homogeneous is not None:
            _check_group(
                exponents.tobytes(), exponents.shape, equation.tobytes(), tuple(homogeneous), patch, f"{homogeneous}"
            )
        if len(_CHECKED) >= 64:
            _CHECKED.clear()
        _CHECKED[key] = (exponents, equation)
    return coefficients, exponents, equation, roots, (roots.shape[0],)


@functools.lru_cache(maxsize=64)
def _check_group(
    exponents: bytes, shape: tuple[int, int], equation: bytes, homogeneous: tuple, patch: Any, shown: str
) -> None:
    """BadInputError unless ``homogeneous`` (indices; ``shown`` as the caller wrote them) and the
    equation ``patch`` are a projective group of the family (``_certify_arguments``); checked once
    per family."""
    a = np.frombuffer(exponents, np.int64).reshape(shape)
    k = np.frombuffer(equation, np.int64)
    n = shape[1]
    group = np.zeros(n, bool)
    if not all(0 <= int(i) < n for i in homogeneous) or patch not in range(n):
        raise BadInputError(f"homogeneous {shown} and patch_equation {patch}: indices in [0, {n})")
    group[list(homogeneous)] = True
    in_patch = k == patch
    degree = (a * group).sum(1)
    linear = ((a * ~group).sum(1) > 0) | (degree > 1)
    if not group.any() or linear[in_patch].any() or not in_patch.any():
        raise BadInputError(f"homogeneous {shown} needs a linear patch_equation in them, got {patch}")
    if any(np.ptp(degree[k == j]) for j in set(k[~in_patch].tolist())):
        raise BadInputError(f"every equation but the patch must be homogeneous in the unknowns {shown}")


def certify_roots_compiled(
    library: CompiledBackend,
    coefficients: Any,
    exponents: Any,
    equation: Any,
    roots: Any,
    real_coefficients: bool = True,
    homogeneous: list[int] | None = None,
    patch_equation: int | None = None,
    clusters: bool = True,
) -> Certificate:
    """``parakin.solvers.certify.certify_roots`` in the package's C (``NAME_certify_roots``):
    Krawczyk's test in complex interval arithmetic with outward rounding, the same scaling, radii
    and realness arguments; the clusters of overlapping boxes are counted in the library's C too
    (``cluster_labels`` with the library), where it has them.

    Every box the reference certifies is certified here too, and more: ||Y F(x)|| is bounded by
    the computed Y F~ (not |Y| |F~|), and a candidate double precision leaves undecided is tried
    again with F in double-word arithmetic, Newton steps that may move it a quarter of its size,
    and where J is conditioned beyond double Rump's preconditioner Y = Y2 Y1 (J and Y1 J in
    double-word). Roots near infinity (rus6's, size 1e4..1e8) that need the exact-arithmetic
    certificate (``parakin.solvers.exact_certify``) in NumPy are decided here in ~0.3 ms each.

    Realness of a real system's root is decided by its one test where it can be, as in
    ``certify_roots`` (the module docstring's argument), before a second test: a box that passes
    holds exactly one root, so where it also holds that root's conjugate (a root too) the root is
    real. A candidate within the test's reach of the real space is tested at its projection (a
    box about a real point is its own conjugate); otherwise the test's bounds at the complex
    centre x are tried on B(x, r + 2 max |Im x_i|); a homogeneous system's on a box that holds
    the conjugate moved back into the patch; where these fail, the second test (at Re x, or in
    the real chart). A root certified at a real centre has that real centre (its imaginary parts
    0). Dietmaier's 40 real modes: 0.65 -> 0.36 ms, no second test.

    Parameters
    ----------
    library : CompiledBackend
        A homotopy package's compiled backend (``m.backend`` of ``parakin.load(name,
        backend="compiled")``); any package's serves any system.
    coefficients : array_like, complex, shape (..., T)
        Term coefficients of each system (leading axes: a batch).
    exponents : array_like, int, shape (T, n)
        Term t is ``coefficients[..., t] * prod_i z_i ** exponents[t, i]``.
    equation : array_like, int, shape (T,)
        The equation each term adds to.
    roots : array_like, complex, shape (..., P, n)
        Candidates per system (a non-finite row: no candidate).
    real_coefficients : bool
        Whether realness may be certified (the coefficients' imaginary parts must also be 0).
    homogeneous : list of int, optional
        Unknowns of one projective group (with ``patch_equation``, the linear patch in them).
    patch_equation : int, optional
        The patch's equation.
    clusters : bool, optional
        False: the boxes only, for a caller that clusters them itself with others (a flat batch
        only: ``distinct``, ``certified_distinct`` and ``labels`` are then None).

    Returns
    -------
    Certificate
        As ``certify_roots``: unique, radius, real, distinct, certified_distinct, center, radii, labels.

    Raises
    ------
    BadInputError
        Shapes, indices or a homogeneous group as ``certify_roots`` refuses them.
    StaleLibraryError
        The library has no C certificate (a closed-form package, or an older generator).

    Example
    -------
    >>> m = parakin.load("rus6", backend="compiled")  # doctest: +SKIP
    >>> certify_roots_compiled(m.backend, [1, -4], [[2], [0]], [0], [[2.0], [-2.0 + 1e-9j]]).real  # doctest: +SKIP
    array([1, 1], dtype=int8)
    """
    if getattr(library, "certify", None) is None or getattr(library, "certify_workspace", None) is None:
        raise StaleLibraryError(f"{getattr(library, 'path', library)} has no C certificate (NAME_certify_roots)")
    c, a, e, z, batch = _certify_arguments(coefficients, exponents, equation, roots, homogeneous, patch_equation)
    known, radius, real, centre, radii = _compiled_boxes(
        library, c, a, e, z, real_coefficients, homogeneous, patch_equation
    )
    systems, paths, n = z.shape
    if not clusters and batch == (systems,):  # the caller counts the clusters itself
        return Certificate(known, radius, real, None, None, centre, radii, None)  # type: ignore[arg-type]
    labels, distinct = cluster_labels(centre, np.where(known[..., None], radii, 0.0), known, library)
    if batch == (systems,):  # the solvers' flat batch: every array has its shape already
        count = _cluster_count(labels)
        return Certificate(known, radius, real, distinct, count, centre, radii, labels)
    shape = batch + (paths,)
    return Certificate(
        known.reshape(shape),
        radius.reshape(shape),
        real.reshape(shape),
        distinct.reshape(batch)[()],  # a scalar for one system, as certify_roots
        _cluster_count(labels).reshape(batch)[()],
        centre.reshape(shape + (n,)),
        radii.reshape(shape + (n,)),
        labels.reshape(shape),
    )


#: jobs of at most this many systems keep their buffers per thread (``_ReusedJob``): a control
#: loop's one input; larger batches allocate theirs per call
REUSED_SYSTEMS = 4
#: per thread: (library id, sizes, family arrays' ids) -> its ``_ReusedJob``
_REUSED = threading.local()


class _ReusedJob:
    """A certificate job and its buffers (outputs, workspace) for one library, job size and family
    (its exponents, equation and homogeneous group, kept alive here so that their identities are
    not reused). Kept per thread for small jobs (``_compiled_boxes``): a call copies the inputs in
    and the outputs out. Built for one call over the caller's own inputs ``c`` and ``z``: it reads
    them in place and hands its outputs over."""

    def __init__(
        self,
        library: CompiledBackend,
        shape: tuple[int, int, int, int],
        family: tuple,
        c: np.ndarray | None = None,
        z: np.ndarray | None = None,
    ) -> None:
        systems, paths, terms, n = shape
        a, e, group, real_coefficients, patch = family
        self.library, self.family, self.reused = library, family, c is None
        degree = int(a.max(initial=0))
        self.workspace = np.empty(int(library.certify_workspace(paths, terms, n, degree)) // 8 + 2)
        self.c = np.empty((systems, terms), np.complex128) if c is None else c
        self.z = np.empty((systems, paths, n), np.complex128) if z is None else z
        self.unique, self.real = np.zeros((systems, paths), np.int32), np.zeros((systems, paths), np.int32)
        self.radius, self.radii = np.empty((systems, paths)), np.empty((systems, paths, n))
        self.centre = np.empty((systems, paths, n), np.complex128)
        self.job = library.CertifyJob(
            systems, paths, terms, n, self.c.ctypes.data, a.ctypes.data, e.ctypes.data, self.z.ctypes.data,
            int(bool(real_coefficients)), group.ctypes.data, group.size, -1 if patch is None else int(patch),
            self.unique.ctypes.data, self.real.ctypes.data, self.radius.ctypes.data, self.centre.ctypes.data,
            self.radii.ctypes.data, self.workspace.ctypes.data, self.workspace.nbytes,
        )  # fmt: skip
        self.pointer = ctypes.byref(self.job)

    def run(
        self, c: np.ndarray | None = None, z: np.ndarray | None = None
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        if self.reused:
            self.c[...] = c
            self.z[...] = z
        if self.library.certify(self.pointer) != 0:
            raise BadInputError("the C certificate refused its job (sizes or indices out of range)")
        keep = np.copy if self.reused else np.asarray  # a reused job's buffers are overwritten next call
        return (
            self.unique.astype(bool), keep(self.radius), self.real.astype(np.int8), keep(self.centre),
            keep(self.radii),
        )  # fmt: skip


def _compiled_boxes(
    library: CompiledBackend,
    c: np.ndarray,
    a: np.ndarray,
    e: np.ndarray,
    z: np.ndarray,
    real_coefficients: bool = True,
    homogeneous: list[int] | None = None,
    patch_equation: int | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The C certificate's boxes of checked, flat arguments (``_certify_arguments``: coefficients
    c (N, T), exponents a (T, n), equation e (T,), roots z (N, P, n)), without their clusters:
    unique (N, P) bool, radius (N, P), real (N, P) int8, centre (N, P, n) complex and radii
    (N, P, n), each array the caller's own. A job of at most ``REUSED_SYSTEMS`` systems reuses
    this thread's buffers for its sizes and family (``_ReusedJob``)."""
    systems, paths, n = z.shape
    shape = (systems, paths, a.shape[0], n)

    def family() -> tuple:
        group = np.ascontiguousarray(homogeneous if homogeneous is not None else [], dtype=np.int64)
        return (a, e, group, real_coefficients, patch_equation)

    if systems > REUSED_SYSTEMS:
        return _ReusedJob(library, shape, family(), c, z).run()
    group_key = None if homogeneous is None else tuple(homogeneous)
    key = (id(library), systems, paths, a.shape[0], n, id(a), id(e), group_key, real_coefficients, patch_equation)
    jobs = getattr(_REUSED, "jobs", None)
    if jobs is None:
        jobs = _REUSED.jobs = {}
    reused = jobs.get(key)
    if reused is None or reused.library is not library or reused.family[0] is not a or reused.family[1] is not e:
        if len(jobs) >= 32:
            jobs.clear()
        reused = jobs[key] = _ReusedJob(library, shape, family())
    return reused.run(c, z)
