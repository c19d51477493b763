"""Batched real roots of univariate polynomials (the FKU polynomials of the generator)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

Array = NDArray[np.float64]


def real_roots(coefficients: Array, imaginary_tolerance: float = 1e-7) -> tuple[Array, NDArray[np.bool_]]:
    """Roots of sum_k c[..., k] x^k, as (roots (..., d), real mask (..., d)).

    A root counts as real when its imaginary part is below ``imaginary_tolerance`` times
    (1 + |root|): a near-double root, split into a complex pair by rounding, is kept (twice)
    rather than dropped; Newton polishing downstream decides. Leading coefficients that vanish
    (relative 1e-14) lower the degree; the missing roots are reported as not real.
    """
    c = np.asarray(coefficients, dtype=float)
    degree = c.shape[-1] - 1
    if degree == 2:
        return quadratic_real_roots(c)
    flat = c.reshape(-1, degree + 1)
    scale = np.abs(flat).max(axis=-1, keepdims=True)
    scale[scale == 0] = 1.0
    normalised = flat / scale
    roots = np.zeros((flat.shape[0], degree), dtype=complex)
    found = np.zeros((flat.shape[0], degree), dtype=bool)
    full = np.abs(normalised[:, -1]) > 1e-14
    if full.any():
        # batched companion matrices: one LAPACK call for the whole batch
        monic = normalised[full, :-1] / normalised[full, -1:]
        companion = np.zeros((monic.shape[0], degree, degree))
        companion[:, np.arange(1, degree), np.arange(degree - 1)] = 1.0
        companion[:, :, -1] = -monic
        roots[full] = np.linalg.eigvals(companion)
        found[full] = True
    for i in np.nonzero(~full)[0]:
        nonzero = np.nonzero(np.abs(normalised[i]) > 1e-14)[0]
        if nonzero.size and nonzero[-1] > 0:
            lower = np.roots(normalised[i, : nonzero[-1] + 1][::-1])
            roots[i, : lower.size] = lower
            found[i, : lower.size] = True
    real = found & (np.abs(roots.imag) <= imaginary_tolerance * (1 + np.abs(roots)))
    shape = c.shape[:-1] + (degree,)
    return np.where(real, roots.real, 0.0).reshape(shape), real.reshape(shape)


def quadratic_real_roots(coefficients: Array, tolerance: float = 1e-10) -> tuple[Array, NDArray[np.bool_]]:
    """Vectorised roots of c0 + c1 x + c2 x^2 (..., 3) with the cancellation-free formula.
    A discriminant within ``tolerance`` (relative) below zero is a double root, not a miss."""
    c0, c1, c2 = (np.asarray(coefficients, dtype=float)[..., k] for k in range(3))
    scale = np.maximum(c1 * c1, np.abs(4 * c0 * c2))
    discriminant = c1 * c1 - 4 * c0 * c2
    real = discriminant >= -tolerance * scale
    root = np.sqrt(np.maximum(discriminant, 0.0))
    q = -0.5 * (c1 + np.where(c1 >= 0, root, -root))
    with np.errstate(divide="ignore", invalid="ignore"):
        first = np.where(c2 != 0, q / c2, -c0 / c1)
        second = np.where(q != 0, c0 / q, first)
    linear = np.abs(c2) <= 1e-14 * np.maximum(np.abs(c1), np.abs(c0))
    roots = np.stack([first, np.where(linear, 0.0, second)], -1)
    mask = np.stack([real, real & ~linear], -1)
    return np.where(mask, roots, 0.0), mask
