"""Batched Gaussian elimination with partial pivoting, the same arithmetic as the generated C
driver's ``solve_in_place``: one solve and one singularity criterion on every backend.

The pivot ratio min |u_kk| / max |u_kk| of the elimination is a scale-free reciprocal-condition
estimate; a Jacobian whose ratio is not above ``singular_ratio`` (manifest tolerances) is
singular everywhere in parakin.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from parakin.errors import BadInputError
from parakin.results import Array


def pivoted_solve(matrix: Array, rhs: Array) -> tuple[Array, Array, Array]:
    """Solve ``matrix @ x = rhs`` for (..., n, n) and (..., n); returns (x, pivot ratio (...),
    sign of det matrix (...), int32, 0 where singular).

    Entries whose ratio is 0 (a zero or non-finite pivot) get x = NaN."""
    a = np.array(matrix, dtype=float)
    b = np.array(rhs, dtype=float)
    n = a.shape[-1]
    batch = a.shape[:-2]
    if n == 0:
        return b, np.ones(batch), np.ones(batch, dtype=np.int32)
    sign = np.ones(batch, dtype=np.int32)
    smallest = np.full(batch, np.inf)
    largest = np.zeros(batch)
    index = np.indices(batch) if batch else ()
    with np.errstate(all="ignore"):
        for k in range(n):
            best = k + np.argmax(np.abs(a[..., k:, k]), axis=-1)
            sign = np.where(best != k, -sign, sign)
            # swap rows k and best (a no-op where best == k)
            row_k, row_best = a[..., k, :].copy(), a[(*index, best)].copy()
            a[..., k, :], a[(*index, best)] = row_best, row_k
            b_k, b_best = b[..., k].copy(), b[(*index, best)].copy()
            b[..., k], b[(*index, best)] = b_best, b_k
            pivot = np.abs(a[..., k, k])
            sign = np.where(a[..., k, k] < 0, -sign, sign)
            smallest = np.where(np.isfinite(pivot), np.fmin(smallest, pivot), 0.0)
            largest = np.fmax(largest, np.where(np.isfinite(pivot), pivot, 0.0))
            factor = a[..., k + 1 :, k] / a[..., k, k, None]
            a[..., k + 1 :, :] -= factor[..., None] * a[..., k, None, :]
            b[..., k + 1 :] -= factor * b[..., k, None]
        x = np.empty_like(b)
        for k in range(n - 1, -1, -1):
            x[..., k] = (b[..., k] - (a[..., k, k + 1 :] * x[..., k + 1 :]).sum(-1)) / a[..., k, k]
        ratio = np.where(largest > 0, smallest / largest, 0.0)
    ratio = np.where(np.isfinite(ratio), ratio, 0.0)
    x = np.where((ratio > 0)[..., None], x, np.nan)
    return x, ratio, np.where(ratio > 0, sign, 0).astype(np.int32)


def inverse_condition(matrix: ArrayLike) -> Array:
    """sigma_min / sigma_max of each matrix of a batch: 1/cond in the 2-norm, 0 for a singular
    (or zero) matrix.

    Parameters
    ----------
    matrix : array_like, shape (..., r, c)
        Real matrices (any units: the ratio is scale-free).

    Returns
    -------
    numpy.ndarray, shape (...)
        The ratio in [0, 1] per matrix; NaN where a matrix has an entry that is not finite.

    Raises
    ------
    BadInputError
        ``matrix`` has fewer than two axes.

    Examples
    --------
    >>> from parakin.singularity import inverse_condition
    >>> inverse_condition([[[2.0, 0.0], [0.0, 0.5]], [[1.0, 1.0], [1.0, 1.0]]]).tolist()
    [0.25, 0.0]
    """
    values = np.asarray(matrix, dtype=float)
    if values.ndim < 2:
        raise BadInputError(f"inverse_condition takes matrices (..., r, c), got shape {values.shape}")
    finite = np.isfinite(values).all(axis=(-2, -1))
    every = bool(finite.all())  # the usual case (every mode of a solver): nothing to mask
    sigma = np.linalg.svd(values if every else np.where(finite[..., None, None], values, 0.0), compute_uv=False)
    ratio = sigma[..., -1] / np.where(sigma[..., 0] > 0, sigma[..., 0], 1.0)
    return np.asarray(ratio) if every else np.where(finite, ratio, np.nan)
