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
flips, so that the symmetric pairs of paths (``parakin.solvers.homotopy.path_pairs``) stay pairs.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from parakin.solvers.homotopy import PATH_DIVERGED, PATH_REACHED, PathPairs, Paths

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
