"""Tracking in projective space: a family's paths toward roots of large size stay bounded.

A generic input of a family can have roots of size 1e4-1e7 (near infinity): in the affine
unknowns z a path toward one is long and badly scaled, and a corrector tuned to relative steps
lets two such paths meet on the same root, so one root is never reached. Homogenised by one more
unknown w (every term of equation k times w^(d_k - its degree), d_k the equation's degree) and
fixed by a complex linear patch a . (z, w) = 1, the same family has the same roots, now as
bounded points (z / w = the affine root); a root near infinity is a point with small w, as well
conditioned as any other (Morgan, "Solving polynomial systems using continuation", 1987, ch. 3;
HomotopyContinuation.jl tracks in projective space the same way). The patch is a fixed
pseudo-random complex vector (generic for any family), zero on the unknowns a sign symmetry
flips, so that the symmetric pairs of paths (``parakin.solvers.path_tracking.path_pairs``) stay pairs.
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from parakin.solvers.path_tracking import PATH_DIVERGED, PATH_REACHED, PathPairs, Paths, System

#: the patch's seed: fixed so that a run is reproducible
PATCH_SEED = 20261127
#: |w| below this times |(z, w)|: the end is at infinity (w is rounding; the affine root would
#: be beyond 1e12 times the patch's scale). Affine tracking's ``ESCAPE`` (1e8) is lower because
#: there the size itself spoils the steps; here a root of size 1e9 is tracked as well as any
AT_INFINITY = 1e-12


class ProjectiveFamily(NamedTuple):
    """A family homogenised: ``exponents`` (T + n + 2, n + 1) and ``equation`` (T + n + 2,) with
    the homogenising unknown w last and the patch a . (z, w) - 1 as the last equation (its n + 2
    terms after the family's T); ``patch`` a (n + 1,); ``pairs`` the affine pairs with w unflipped."""

    exponents: NDArray[np.int64]
    equation: NDArray[np.intp]
    patch: NDArray[np.complex128]
    pairs: PathPairs | None


def projective_family(exponents: np.ndarray, equation: np.ndarray, pairs: PathPairs | None) -> ProjectiveFamily:
    """The homogenisation of the family (``exponents`` (T, n), ``equation`` (T,)) and its patch."""
    exponents = np.asarray(exponents, dtype=np.int64)
    equation = np.asarray(equation, dtype=np.intp)
    terms, n = exponents.shape
    degree = exponents.sum(-1)
    top = np.zeros(n, dtype=np.int64)
    np.maximum.at(top, equation, degree)
    homogeneous = np.zeros((terms + n + 2, n + 1), dtype=np.int64)
    homogeneous[:terms, :n] = exponents
    homogeneous[:terms, n] = top[equation] - degree
    homogeneous[terms : terms + n + 1] = np.eye(n + 1, dtype=np.int64)  # the patch's linear terms; then 1
    rng = np.random.default_rng(PATCH_SEED)
    patch = (rng.normal(size=n + 1) + 1j * rng.normal(size=n + 1)) / np.sqrt(2 * (n + 1))
    flip = np.ones(n + 1)
    if pairs is not None:
        flip[:n] = pairs.flip
        patch[:n][pairs.flip < 0] = 0.0
    projective_pairs = None if pairs is None else PathPairs(flip, pairs.partner, pairs.first, pairs.second)
    return ProjectiveFamily(homogeneous, np.r_[equation, np.full(n + 2, n)], patch, projective_pairs)


def projective_table(family: ProjectiveFamily, table: np.ndarray) -> np.ndarray:
    """The coefficients in s (inputs, powers, T) of the family with the patch's (constant in s)."""
    patch = np.zeros(table.shape[:2] + (family.patch.size + 1,), dtype=complex)
    patch[:, 0, :-1], patch[:, 0, -1] = family.patch, -1.0
    return np.concatenate([table, patch], axis=-1)


def to_projective(family: ProjectiveFamily, z: np.ndarray) -> np.ndarray:
    """Affine points (..., n) as points on the patch (..., n + 1)."""
    point = np.concatenate([z, np.ones(z.shape[:-1] + (1,), dtype=complex)], axis=-1)
    return point / (point @ family.patch)[..., None]


def to_affine(paths: Paths) -> Paths:
    """Projective endpoints back to affine ones, z / w; a reached end with |w| below
    ``AT_INFINITY`` times its size (a root at infinity) is diverged, as an affine path that escapes."""
    z, w = paths.z[:, :-1], paths.z[:, -1:]
    with np.errstate(all="ignore"):
        affine = z / w
        escaped = (paths.status == PATH_REACHED) & ~(np.abs(w[:, 0]) > AT_INFINITY * np.abs(paths.z).max(-1))
    status = np.where(escaped, PATH_DIVERGED, paths.status).astype(np.int32)
    return Paths(affine, status, paths.steps, paths.update)


#: inputs up to which ``family_system`` forms the coefficients input by input
GROUPED_INPUTS = 8


class _Terms:
    """Where each term of H, H_s and H_z goes, fixed by the family (``exponents`` (T, n),
    ``equation`` (T,)): the distinct monomials ``rows`` of H and H_z (term t's own, and its
    derivative's d/dz_i, a_ti z^(a_t - e_i)), and per entry of the sum: the coefficient (of
    [c(s), c'(s)], 2 T), the monomial, the weight a_ti (1 for H and H_s) and the output
    (H: 0..n-1, H_s: n..2n-1, H_z: 2n + k n + i), sorted by output so that one ``reduceat``
    sums them all."""

    def __init__(self, exponents: np.ndarray, equation: np.ndarray) -> None:
        terms, n = exponents.shape
        self.n = n
        tj, ij = np.nonzero(exponents > 0)
        rows = np.concatenate([exponents, exponents[tj] - np.eye(n, dtype=np.int64)[ij]])
        self.rows, where = np.unique(rows, axis=0, return_inverse=True)
        where = where.reshape(-1)
        coefficient = np.concatenate([np.arange(terms), terms + np.arange(terms), tj])
        monomial = np.concatenate([where[:terms], where[:terms], where[terms:]])
        weight = np.concatenate([np.ones(2 * terms), exponents[tj, ij]]).astype(float)
        output = np.concatenate([equation, n + equation, 2 * n + equation[tj] * n + ij])
        order = np.argsort(output, kind="stable")
        self.coefficient, self.monomial, self.weight = coefficient[order], monomial[order], weight[order]
        ordered = output[order]
        self.starts = np.r_[0, np.nonzero(np.diff(ordered))[0] + 1]
        self.present = ordered[self.starts]
        self.outputs = 2 * n + n * n
        self.top = int(self.rows.max(initial=0))


@functools.lru_cache(maxsize=16)
def _cached_terms(exponents: bytes, shape: tuple[int, int], equation: bytes) -> _Terms:
    return _Terms(np.frombuffer(exponents, np.int64).reshape(shape), np.frombuffer(equation, np.int64))


def family_system(table: np.ndarray, exponents: np.ndarray, equation: np.ndarray, paths: int) -> System:
    """The system of a family from its coefficients in s (inputs, powers, terms), as
    ``parakin.solvers.path_tracking.sparse_system`` (path p belongs to input p // ``paths``; the same
    values up to the order of the sums), evaluated over the family's distinct monomials and one
    sum per output (``_Terms``, computed once per family): a few times cheaper for the re-tracks
    of a family of hundreds of terms.

    Parameters
    ----------
    table : ndarray, shape (inputs, powers, T), complex
        Term t's coefficient in equation ``equation[t]`` is sum_d table[., d, t] s^d.
    exponents : ndarray, shape (T, n), int
        Term t is that coefficient times prod_i z_i^exponents[t, i].
    equation : ndarray, shape (T,), int
        The equation of each term.
    paths : int
        Paths per input.

    Returns
    -------
    System
        ``system(index, z, s)`` -> H (k, n), H_z (k, n, n), H_s (k, n) of the paths ``index``.

    Example
    -------
    >>> import numpy as np
    >>> table = np.zeros((1, 2, 2), complex)
    >>> table[0, 0], table[0, 1] = [1.0, -4.0], [0.0, 3.0]  # z^2 - (4 - 3 s): H_s = 3
    >>> system = family_system(table, np.array([[2], [0]]), np.array([0, 0]), 1)
    >>> value, jacobian, rate = system(np.array([0]), np.array([[1.0 + 0j]]), np.array([1.0]))
    >>> complex(value[0, 0]), complex(jacobian[0, 0, 0]), complex(rate[0, 0])
    (0j, (2+0j), (3+0j))
    """
    e = np.ascontiguousarray(exponents, dtype=np.int64)
    structure = _cached_terms(e.tobytes(), e.shape, np.ascontiguousarray(equation, dtype=np.int64).tobytes())
    n, distinct = structure.n, structure.rows
    degrees = np.arange(table.shape[1])

    def system(index: np.ndarray, z: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        inputs = index // paths
        count = index.size
        weights = (s[:, None] ** degrees).astype(complex)
        rates = (degrees * s[:, None] ** np.maximum(degrees - 1, 0)).astype(complex)
        terms = table.shape[2]
        coefficients = np.empty((count, 2 * terms), dtype=complex)  # c(s) and c'(s) per path
        which, inverse = np.unique(inputs, return_inverse=True)
        if which.size <= GROUPED_INPUTS:  # one product per input (a gathered table costs more)
            for j, own in enumerate(which):
                mine = np.nonzero(inverse.reshape(-1) == j)[0]
                stacked = np.concatenate([weights[mine], rates[mine]])
                # a sum over the few powers, not a matrix product: a threaded BLAS spends far
                # more on these small products than they cost (rus6 at home: 35 s against 2.8 s)
                both = stacked[:, :1] * table[own, 0]
                for d in range(1, degrees.size):
                    both = both + stacked[:, d : d + 1] * table[own, d]
                coefficients[mine, :terms], coefficients[mine, terms:] = both[: mine.size], both[mine.size :]
        else:
            gathered = table[inputs]
            coefficients[:, :terms] = np.einsum("kd,kdt->kt", weights, gathered)
            coefficients[:, terms:] = np.einsum("kd,kdt->kt", rates, gathered)
        power = np.empty((count, n, structure.top + 1), dtype=complex)
        power[..., 0] = 1.0
        for k in range(1, structure.top + 1):
            power[..., k] = power[..., k - 1] * z
        monomials = power[:, 0, distinct[:, 0]]
        for i in range(1, n):
            monomials = monomials * power[:, i, distinct[:, i]]
        entries = coefficients[:, structure.coefficient] * monomials[:, structure.monomial] * structure.weight
        out = np.zeros((count, structure.outputs), dtype=complex)
        if count:
            out[:, structure.present] = np.add.reduceat(entries, structure.starts, axis=1)
        return out[:, :n], out[:, 2 * n :].reshape(count, n, n), out[:, n : 2 * n]

    return system
