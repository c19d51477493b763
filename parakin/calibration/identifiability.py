"""What a calibration's measurements determine: the rank of the whitened parameter Jacobian, its
null space (the parameter combinations no measurement can see) named in parameter terms, the
covariance of the estimate, and the observability indices O1..O5.

The Jacobian J (rows: whitened residuals, columns: free parameters) is analysed with its columns
scaled to unit norm (so that metres and radians weigh alike): J S^-1 = U diag(s) V^T. A singular
value below ``tolerance * s_max`` is a null direction; the null space in parameter units is
S^-1 V_null. The covariance of the estimate (noise as given by sigma) is the pseudo-inverse
S^-1 V_r diag(s_r^-2) V_r^T S^-1 over the identifiable subspace.

Observability indices (Y. Sun and J. M. Hollerbach, "Observability index selection for robot
calibration", ICRA 2008, eqs 3-7), over the r non-null singular values of the scaled Jacobian
and the number of poses m:

* O1 = (s_1 s_2 ... s_r)^(1/r) / sqrt(m)   (Borm and Menq)
* O2 = s_r / s_1                          (inverse condition number; Driels and Pathre)
* O3 = s_r                                (smallest singular value; Nahvi et al.)
* O4 = s_r^2 / s_1                        (noise amplification index; Nahvi and Hollerbach)
* O5 = 1 / (1/s_1 + ... + 1/s_r)          (Sun and Hollerbach)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from parakin.results import Array

#: a singular value below this fraction of the largest one (column-scaled Jacobian) is null
RANK_TOLERANCE = 1e-8
#: a parameter is identifiable when every null direction leaves it alone to this (scaled) size
IDENTIFIABLE_TOLERANCE = 1e-6
#: coefficients of a null combination below this are zero; within it of a simple fraction, that fraction
ROUNDING = 1e-6


@dataclass(frozen=True)
class Combination:
    """A direction in parameter space that no measurement sees: moving every named parameter by
    its coefficient times any small amount leaves every residual unchanged (to first order).

    ``coefficients`` maps names to coefficients, the pivot (first) name with coefficient 1.
    ``str`` reads it as a sum: ``R + r`` means that R and r moving by equal amounts change
    nothing (only R - r is identified).
    """

    coefficients: dict[str, float]

    def __str__(self) -> str:
        terms = []
        for name, value in self.coefficients.items():
            magnitude = abs(value)
            fraction = Fraction(magnitude).limit_denominator(12)
            if abs(float(fraction) - magnitude) <= ROUNDING * max(1.0, magnitude):
                text = "" if fraction == 1 else f"{fraction} "
            else:
                text = f"{magnitude:.4g} "
            sign = "-" if value < 0 else "+"
            terms.append(f"{sign} {text}{name}")
        joined = " ".join(terms)
        return joined[2:] if joined.startswith("+ ") else "-" + joined[2:]

    def vector(self, names: Sequence[str]) -> Array:
        """The direction as a vector over ``names`` (zeros elsewhere)."""
        return np.array([self.coefficients.get(name, 0.0) for name in names])


@dataclass(frozen=True)
class Identifiability:
    """The analysis of one whitened Jacobian (module docstring)."""

    names: tuple[str, ...]
    rank: int
    singular_values: Array
    null_space: Array
    combinations: tuple[Combination, ...]
    identifiable: tuple[str, ...]
    covariance: Array
    observability: dict[str, float]


def _snap(value: float) -> float:
    if abs(value) < ROUNDING:
        return 0.0
    fraction = Fraction(value).limit_denominator(12)
    return float(fraction) if abs(float(fraction) - value) <= ROUNDING * max(1.0, abs(value)) else value


def readable(null_space: Array, names: Sequence[str]) -> tuple[Combination, ...]:
    """A null-space basis (n, k) in parameter units turned into k readable combinations: reduced
    row echelon form of its transpose with complete pivoting (each combination has a pivot
    parameter with coefficient 1 that the others do not contain; the sparsest first, each with
    its other terms by decreasing magnitude), coefficients below
    ``ROUNDING`` set to zero and those within it of a fraction p/q (q <= 12) snapped to it."""
    rows = null_space.T.copy()
    k, n = rows.shape
    pivots: list[int] = []
    for row in range(k):
        free = [c for c in range(n) if c not in pivots]
        sub = np.abs(rows[row:, free])
        # the largest entry; among equal ones (to rounding) the first parameter, then the first row
        ties = np.argwhere(sub >= sub.max() * (1.0 - 1e-9))
        at_row, at_col = min(ties, key=lambda rc: (rc[1], rc[0]))
        pivot_row, pivot = row + int(at_row), free[int(at_col)]
        rows[[row, pivot_row]] = rows[[pivot_row, row]]
        rows[row] /= rows[row, pivot]
        for other in range(k):
            if other != row:
                rows[other] -= rows[other, pivot] * rows[row]
        pivots.append(pivot)
    combinations = []
    for row, pivot in enumerate(pivots):
        # the pivot first, then the others by decreasing magnitude (ties in parameter order)
        others = sorted((c for c in range(n) if c != pivot), key=lambda c: (-round(abs(rows[row, c]), 9), c))
        coefficients = {names[c]: _snap(float(rows[row, c])) for c in [pivot, *others]}
        combinations.append(Combination({key: value for key, value in coefficients.items() if value != 0.0}))
    # the sparsest (most readable) first
    return tuple(sorted(combinations, key=lambda c: len(c.coefficients)))


def observability(singular: Array, poses: int) -> dict[str, float]:
    """O1..O5 (module docstring) of the non-null singular values ``singular`` (descending)."""
    if singular.size == 0:
        return {f"O{i}": 0.0 for i in range(1, 6)}
    first, last = float(singular[0]), float(singular[-1])
    return {
        "O1": float(np.exp(np.mean(np.log(singular))) / np.sqrt(poses)),
        "O2": last / first,
        "O3": last,
        "O4": last**2 / first,
        "O5": float(1.0 / np.sum(1.0 / singular)),
    }


def thin_svd(matrix: Array) -> tuple[Array, Array, Array]:
    """U (rows, k), s (k,), V^T (k, n) of a tall matrix through its QR factors (the SVD of the
    small triangular factor): the same decomposition as ``np.linalg.svd(full_matrices=False)``,
    without LAPACK's blocked bidiagonalisation of the tall matrix, which multithreaded BLAS
    slows by two orders of magnitude on a loaded machine. A wide matrix (rows < n) gets the full
    SVD (V square, for the whole null space)."""
    rows, columns = matrix.shape
    if rows < columns:
        u, singular, vt = np.linalg.svd(matrix, full_matrices=True)
        return np.asarray(u), np.asarray(singular), np.asarray(vt)
    q, r = np.linalg.qr(matrix)
    u, singular, vt = np.linalg.svd(r)
    return np.asarray(q @ u), np.asarray(singular), np.asarray(vt)


def analyse(jacobian: Array, names: Sequence[str], poses: int, tolerance: float = RANK_TOLERANCE) -> Identifiability:
    """Rank, null space, readable combinations, identifiable parameters, covariance and O1..O5
    of a whitened Jacobian (rows, n) over the parameters ``names`` measured at ``poses`` poses.

    Parameters
    ----------
    jacobian : (rows, n)
        d(residual / sigma) / d(parameter), parameters in their units (m, rad, 1).
    names : sequence of n str
    poses : int
        The number of poses (O1 divides by its square root).
    tolerance : float
        Relative singular-value threshold of a null direction.

    Returns
    -------
    Identifiability
    """
    norms = np.linalg.norm(jacobian, axis=0)
    scale = np.where(norms > 0.0, norms, 1.0)
    _, singular, vt = thin_svd(jacobian / scale)
    singular = np.concatenate([singular, np.zeros(max(0, len(names) - singular.size))])
    largest = float(singular[0]) if singular.size else 0.0
    rank = int(np.sum(singular > tolerance * largest)) if largest > 0 else 0
    v = vt.T
    kept, null = v[:, :rank], v[:, rank:]
    covariance = (kept / singular[:rank]) @ (kept / singular[:rank]).T / np.outer(scale, scale)
    identifiable = tuple(
        name for i, name in enumerate(names) if null.shape[1] == 0 or np.abs(null[i]).max() < IDENTIFIABLE_TOLERANCE
    )
    null_units = null / scale[:, None]
    null_units = null_units / np.linalg.norm(null_units, axis=0) if null.shape[1] else null_units
    return Identifiability(
        tuple(names),
        rank,
        singular,
        null_units,
        readable(null_units, names) if null.shape[1] else (),
        identifiable,
        covariance,
        observability(singular[:rank], poses),
    )
