"""Whether an input lies where a homotopy's root count was proven.

A root count is proven for the generic member of the family, or, where the mechanism's own values
satisfy relations that lower it (parameters sharing a value: a Hexaglide's sliders on shared
rails), for the generic member of the subfamily those relations cut out; the manifest's homotopy
then names them (``subfamily``: groups of identical values, indices into the family's values, the
free values then the angles, and the relative tolerance). Parameters loaded with other values
break a relation, and the count proven under it no longer bounds the roots (the family's generic
roots that the relation sent to infinity come back, large): such inputs are never certified
complete. The relations are linear, so the homotopy's straight segment from a start instance in
the subfamily to an input there stays in it.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np


def outside_subfamily(
    identical: Sequence[Sequence[int]], free: np.ndarray, angles: np.ndarray, tolerance: float
) -> np.ndarray:
    """Per input, whether the family's values break one of the relations of its root count.

    Parameters
    ----------
    identical : sequence of sequences of int
        The manifest's ``subfamily.identical``: groups of indices into the family's values (the
        free values, then the angles) that are equal where the count was proven.
    free : ndarray, shape (n, F)
        The free values at each input (the generated ``*_family`` kernel's ``free``; metres,
        radians or whatever unit each parameter has).
    angles : ndarray, shape (n, A)
        The angles at each input (the kernel's ``angles``, radians).
    tolerance : float
        Relative agreement that counts as equal (the manifest's ``subfamily.tolerance``).

    Returns
    -------
    ndarray of bool, shape (n,)
        True where some group's values differ by more than ``tolerance`` relative (or are not
        finite): the count is not proven there and no certificate may call the input complete.

    Example
    -------
    >>> import numpy as np
    >>> outside_subfamily([[0, 1]], np.array([[0.3, 0.3], [0.3, 0.31]]), np.zeros((2, 0)), 1e-12).tolist()
    [False, True]
    """
    values = np.concatenate([np.asarray(free, dtype=float), np.asarray(angles, dtype=float)], axis=-1)
    outside = ~np.isfinite(values).all(-1)
    for group in identical:
        members = values[:, list(group)]
        first = members[:, :1]
        scale = np.maximum(np.abs(members), np.abs(first))
        with np.errstate(invalid="ignore"):
            outside |= (np.abs(members - first) > tolerance * scale).any(-1)
    return outside
