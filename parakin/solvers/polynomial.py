"""Batched real roots of univariate polynomials (the FKU polynomials of the generator): one
isolation algorithm, the same decisions as the generated C (``real_roots.h``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

Array = NDArray[np.float64]


MAX_DEGREE = 64
ROOT_SIMPLE, ROOT_CLUSTER, ROOT_NEAR = 0, 1, 2
_EPS = float(np.finfo(np.float64).eps)
_CLUSTER_TOLERANCE = 1.0 * _EPS  # one ulp of backward error: see PK_CLUSTER_TOLERANCE
_TINY = 1e-300
_NOISE = 64.0 * _EPS  # absolute rounding noise of computed coefficients: PK_NOISE
_MAX_ITERATIONS = 200

Signs = NDArray[np.int8]
Indices = NDArray[np.int64]


@dataclass(frozen=True)
class IsolatedRoots:
    """Real roots of a batch of polynomials (see :func:`isolate_real_roots`).

    ``roots`` (..., degree) ascending, NaN after ``count``; ``kind`` (..., degree) per root:
    ``ROOT_SIMPLE`` (0), ``ROOT_CLUSTER`` (1, a multiple root to working precision, reported once),
    ``ROOT_NEAR`` (2, a complex pair close to the real axis: a candidate, not a root), -1 padding;
    ``count`` (...) roots of all kinds; ``at_infinity`` (...) dropped leading coefficients;
    ``vanishing`` (...) polynomials with nothing to isolate (all zero or non-finite).
    """

    roots: Array
    kind: NDArray[np.int8]
    count: NDArray[np.int64]
    at_infinity: NDArray[np.int64]
    vanishing: NDArray[np.bool_]


def isolate_real_roots(
    coefficients: ArrayLike, leading_tolerance: float = 1e-13, near_tolerance: float = 1e-9
) -> IsolatedRoots:
    """Every real root of sum_k c[..., k] x^k, isolated by the recursive-derivative method.

    Coefficients (..., degree + 1) are ascending, degree <= ``MAX_DEGREE``, any batch shape.
    They are normalised by max_k |c_k|; leading ones at most ``leading_tolerance`` (relative)
    are dropped and counted in ``at_infinity``. At a critical point z (a root of p') with
    S(z) = sum_k |c_k| |z|^k, |p(z)| <= eps S(z) reports a cluster at z and |p(z)| <=
    ``near_tolerance`` S(z) at a minimum of |p| that does not cross zero a near-real candidate.
    Simple roots are refined to ~4 eps (1 + |x|). Identical to ``pk_real_roots`` in
    ``generator/templates/real_roots.h``.
    """
    c = np.asarray(coefficients, dtype=np.float64)
    if c.ndim == 0 or c.shape[-1] == 0:
        raise ValueError(f"coefficients need a last axis of length degree + 1, got shape {c.shape}")
    degree = c.shape[-1] - 1
    if degree > MAX_DEGREE:
        raise ValueError(f"degree {degree} exceeds MAX_DEGREE = {MAX_DEGREE}")
    flat = c.reshape(-1, degree + 1)
    n = flat.shape[0]
    with np.errstate(invalid="ignore"):
        scale = np.abs(flat).max(axis=1, initial=0.0)
        vanishing = ~(np.isfinite(flat).all(axis=1) & (scale >= _TINY))
        a = np.where(vanishing[:, None], 0.0, flat / np.where(vanishing, 1.0, scale)[:, None])
    threshold = leading_tolerance if leading_tolerance > _TINY else _TINY
    significant = np.abs(a) > threshold
    significant[:, 0] = True
    m = degree - np.argmax(significant[:, ::-1], axis=1).astype(np.int64)
    at_infinity = np.where(vanishing, 0, degree - m).astype(np.int64)
    a = np.where(np.arange(degree + 1) <= m[:, None], a, 0.0)

    roots = np.full((n, degree), np.nan)
    kind = np.full((n, degree), -1, dtype=np.int8)
    count = np.zeros(n, dtype=np.int64)
    critical = np.full((n, degree), np.nan)
    n_critical = np.zeros(n, dtype=np.int64)
    factorial = [1.0]
    for k in range(1, degree + 1):
        factorial.append(factorial[-1] * float(k))
    divisors = np.arange(1, degree + 1, dtype=np.float64)
    q = np.zeros((n, degree + 1))
    # step j holds p^(j) for every entry: level m - j, padded with exact zeros above it
    for j in range(degree, -1, -1):
        q = np.concatenate([a[:, j : j + 1] * factorial[j], q[:, :-1] / divisors], axis=1)
        level = m - j
        rows = np.nonzero(level >= 1)[0]
        if rows.size == 0:
            continue
        values, kinds, found = _level(
            q[rows, : degree - j + 1], level[rows], critical[rows], n_critical[rows], near_tolerance
        )
        if j == 0:
            width = min(values.shape[1], degree)
            roots[rows, :width] = values[:, :width]
            kind[rows, :width] = kinds[:, :width]
            count[rows] = found
            break
        # near-real candidates are not roots of this level: the next one is monotone across them
        separating = (kinds == ROOT_SIMPLE) | (kinds == ROOT_CLUSTER)
        values = _compact(values, separating)
        width = min(values.shape[1], degree)
        critical[rows] = np.nan
        critical[rows, :width] = values[:, :width]
        n_critical[rows] = separating.sum(axis=1)
    shape = c.shape[:-1]
    return IsolatedRoots(
        roots=roots.reshape(shape + (degree,)),
        kind=kind.reshape(shape + (degree,)),
        count=count.reshape(shape),
        at_infinity=at_infinity.reshape(shape),
        vanishing=vanishing.reshape(shape),
    )


def _sign(v: Array) -> Signs:
    """-1, 0, +1 (0 for NaN too, as pk_sign)."""
    return (v > 0).astype(np.int8) - (v < 0).astype(np.int8)


def _compact(values: Array, keep: NDArray[np.bool_]) -> Array:
    """Each row's kept values first, in order, then NaN."""
    order = np.argsort(~keep, axis=1, kind="stable")
    return np.take_along_axis(np.where(keep, values, np.nan), order, axis=1)


def _value_curvature_size(q: Array, x: Array) -> tuple[Array, Array, Array]:
    """q(x), q''(x) and S(x) = sum_k |q_k| |x|^k per row of q (P, top + 1) at x (P, R)."""
    magnitude, ax = np.abs(q), np.abs(x)
    p = np.broadcast_to(q[:, -1:], x.shape)
    s = np.broadcast_to(magnitude[:, -1:], x.shape)
    d = np.zeros_like(x)
    dd = np.zeros_like(x)
    for k in range(q.shape[1] - 2, -1, -1):
        dd = dd * x + d
        d = d * x + p
        p = p * x + q[:, k : k + 1]
        s = s * ax + magnitude[:, k : k + 1]
    return p, 2.0 * dd, s


def _value_slope_size(q: Array, x: Array) -> tuple[Array, Array, Array]:
    """q(x), q'(x) and S(x) per row of q (P, top + 1) at x (P,)."""
    magnitude, ax = np.abs(q), np.abs(x)
    p = q[:, -1].copy()
    s = magnitude[:, -1].copy()
    d = np.zeros_like(x)
    for k in range(q.shape[1] - 2, -1, -1):
        d = d * x + p
        p = p * x + q[:, k]
        s = s * ax + magnitude[:, k]
    return p, d, s


def _split(lo: Array, hi: Array) -> Array:
    """A point strictly inside (lo, hi); in the exponent far from the origin (pk_split)."""
    with np.errstate(invalid="ignore"):
        conditions = [
            (lo >= 1.0) & (hi > 4.0 * lo),
            (hi <= -1.0) & (lo < 4.0 * hi),
            (lo < -4.0) & (hi > 4.0),
            (lo < 1.0) & (hi > 4.0),
            (hi > -1.0) & (lo < -4.0),
        ]
        choices = [
            np.sqrt(lo) * np.sqrt(hi),
            -(np.sqrt(-lo) * np.sqrt(-hi)),
            np.zeros_like(lo),
            np.sqrt(hi),
            -np.sqrt(-lo),
        ]
        return np.select(conditions, choices, 0.5 * (lo + hi))


def _refine(q: Array, lo: Array, hi: Array, s_hi: Signs, x: Array) -> Array:
    """The one root of each row of q in its bracket from x (pk_refine): Newton when it stays
    inside and at least halves the previous step, else a split; stops on the predicted next
    correction or at one ulp of backward error. Rows leave the loop as they converge."""
    x, lo, hi = x.copy(), lo.copy(), hi.copy()
    last = hi - lo
    newton_before = np.zeros(x.size, dtype=np.bool_)
    live = np.arange(x.size)
    for _ in range(_MAX_ITERATIONS):
        if live.size == 0:
            break
        xl, sl = x[live], s_hi[live]
        with np.errstate(over="ignore", invalid="ignore"):
            v, slope, size = _value_slope_size(q[live], xl)
        s = np.where(np.isnan(v), np.where(xl > 0.0, sl, -sl), _sign(v))
        up = s == sl
        lo_l = np.where(up, lo[live], xl)
        hi_l = np.where(up, xl, hi[live])
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            step = v / slope
            newton = xl - step
            inside = (newton >= lo_l) & (newton <= hi_l)
            resolved = np.abs(v) <= _CLUSTER_TOLERANCE * size
            use_newton = inside & (np.abs(step) <= 0.5 * np.abs(last[live]))
            following = np.where(use_newton, newton, _split(lo_l, hi_l))
            moved = following - xl
            ratio = moved / last[live]
            predicted = np.where(use_newton & newton_before[live], np.abs(moved) * ratio * ratio, np.abs(moved))
        # an exact zero stays put; at one ulp of backward error the Newton step is the last
        stay = (v == 0.0) | (resolved & ~inside)
        following = np.where(resolved & inside, newton, following)
        done = (v == 0.0) | resolved | (predicted <= 4.0 * _EPS * (1.0 + np.abs(following)))
        moving = ~stay
        target = live[moving]
        x[target] = following[moving]
        lo[target], hi[target], last[target] = lo_l[moving], hi_l[moving], moved[moving]
        newton_before[target] = use_newton[moving]
        live = live[~done]
    return x


def _quadratic_root(q: Array, lo: Array, hi: Array, upper: NDArray[np.bool_]) -> Array:
    """The lower (upper) root of each quadratic row, clamped to its bracket (pk_quadratic_root)."""
    q0, q1, q2 = q[:, 0], q[:, 1], q[:, 2]
    disc = q1 * q1 - 4.0 * q0 * q2
    t = -0.5 * (q1 + np.copysign(np.sqrt(np.where(disc > 0.0, disc, 0.0)), q1))
    r1 = t / q2
    with np.errstate(divide="ignore", invalid="ignore"):
        r2 = np.where(t != 0.0, q0 / t, r1)
    x = np.where(upper, np.where(r1 > r2, r1, r2), np.where(r1 < r2, r1, r2))
    return np.where(x < lo, lo, np.where(x > hi, hi, x))


def _level(
    q: Array, level: Indices, z: Array, r: Indices, near_tolerance: float
) -> tuple[Array, NDArray[np.int8], Indices]:
    """One level for P rows (pk_level): roots of q (P, top + 1) of degree ``level`` given the
    distinct real roots z (P, >= max r) of q'. Returns roots, kinds (P, 2 R + 1) compacted to the
    left and the number found per row."""
    p_rows = q.shape[0]
    width = int(r.max())
    z = z[:, :width]
    every = np.arange(p_rows)
    lead = q[every, level]
    s_plus = _sign(lead)
    s_minus = np.where(level % 2 == 1, -s_plus, s_plus).astype(np.int8)
    largest = np.where(np.arange(q.shape[1]) < level[:, None], np.abs(q), 0.0).max(axis=1)
    bound = 1.0 + largest / np.abs(lead)

    valid = np.arange(width) < r[:, None]
    # far out, with a tiny leading_tolerance, Horner may overflow: handled as in C, no warning
    with np.errstate(over="ignore", invalid="ignore"):
        v, curvature, size = _value_curvature_size(q, z)
        cluster = valid & (np.abs(v) <= _CLUSTER_TOLERANCE * size)
    s = np.where(cluster | ~valid, 0, _sign(v)).astype(np.int8)
    # consecutive clusters are one multiple root, reported at its smallest |q|
    keep = cluster.copy()
    best = np.full(p_rows, -1)
    magnitude = np.abs(v)
    for i in range(width):
        here = cluster[:, i]
        running = here & (best >= 0)
        better = running & (magnitude[:, i] < magnitude[every, np.maximum(best, 0)])
        keep[every[better], best[better]] = False
        keep[running & ~better, i] = False
        best = np.where(~here, -1, np.where((here & (best < 0)) | better, i, best))

    lows, highs, signs, has_root = [], [], [], []
    for i in range(width + 1):
        at_end = r == i
        inner = i < width
        lows.append(-bound if i == 0 else z[:, i - 1])
        highs.append(np.where(at_end, bound, z[:, i] if inner else bound))
        s_lo = s_minus if i == 0 else s[:, i - 1]
        s_hi = np.where(at_end, s_plus, s[:, i] if inner else s_plus)
        signs.append(s_hi)
        # an end that is a cluster has sign 0: a root next to it is that cluster
        has_root.append((i <= r) & (s_lo * s_hi < 0))
    has = np.stack(has_root, axis=1)
    pair_row, pair_slot = np.nonzero(has)
    lo = np.stack(lows, axis=1)[pair_row, pair_slot]
    hi = np.stack(highs, axis=1)[pair_row, pair_slot]
    s_hi_pairs = np.stack(signs, axis=1)[pair_row, pair_slot].astype(np.int8)
    pair_level = level[pair_row]
    found = np.empty(pair_row.size)
    linear, quadratic, general = pair_level == 1, pair_level == 2, pair_level >= 3
    if linear.any():
        found[linear] = -q[pair_row[linear], 0] / q[pair_row[linear], 1]
    if quadratic.any():
        rows, upper = pair_row[quadratic], pair_slot[quadratic] == r[pair_row[quadratic]]
        found[quadratic] = _quadratic_root(q[rows, :3], lo[quadratic], hi[quadratic], upper)
    if general.any():
        rows, slots, low, high = pair_row[general], pair_slot[general], lo[general], hi[general]
        start = _split(low, high)
        if width:
            # start where the second-order model at the end critical point with the smaller |q|
            # crosses zero (as pk_level): ~5 Newton steps instead of ~8 from the middle
            left_smaller = magnitude[rows, np.maximum(slots - 1, 0)] <= magnitude[rows, np.minimum(slots, width - 1)]
            expand = np.where(slots == 0, 0, np.where((slots == r[rows]) | left_smaller, slots - 1, slots))
            at = np.minimum(expand, width - 1)
            with np.errstate(divide="ignore", invalid="ignore"):
                t = -2.0 * v[rows, at] / curvature[rows, at]
                guess = np.where(expand == slots, z[rows, at] - np.sqrt(t), z[rows, at] + np.sqrt(t))
                usable = (expand < r[rows]) & (t > 0.0) & (guess > low) & (guess < high)
            start = np.where(usable, guess, start)
        found[general] = _refine(q[rows], low, high, s_hi_pairs[general], start)

    near = np.zeros_like(cluster)
    for i in range(width):
        last_point = r - 1 == i
        here = magnitude[:, i]
        left = s_minus if i == 0 else s[:, i - 1]
        right = np.where(last_point, s_plus, s[:, i + 1] if i + 1 < width else s_plus)
        with np.errstate(invalid="ignore"):
            lower_left = True if i == 0 else here < magnitude[:, i - 1]
            lower_right = last_point | (here < magnitude[:, i + 1] if i + 1 < width else True)
            # within the coefficients' absolute rounding noise is near-real too, as in C
            top = np.fmax(largest, np.abs(lead))
            powers = np.zeros(p_rows)
            for k in range(q.shape[1] - 1, -1, -1):
                powers = powers * np.abs(z[:, i]) + (k <= level)
            small = here <= np.fmax(near_tolerance * size[:, i], _NOISE * top * powers)
        near[:, i] = (s[:, i] != 0) & (left == s[:, i]) & (right == s[:, i]) & lower_left & lower_right & small

    values = np.full((p_rows, 2 * width + 1), np.nan)
    kinds = np.full((p_rows, 2 * width + 1), -1, dtype=np.int8)
    values[pair_row, 2 * pair_slot] = found
    kinds[pair_row, 2 * pair_slot] = ROOT_SIMPLE
    values[:, 1::2] = z
    kinds[:, 1::2] = np.where(keep, ROOT_CLUSTER, np.where(near & valid, ROOT_NEAR, -1))
    order = np.argsort(kinds < 0, axis=1, kind="stable")
    values = np.take_along_axis(values, order, axis=1)
    kinds = np.take_along_axis(kinds, order, axis=1)
    values[kinds < 0] = np.nan
    return values, kinds, (kinds >= 0).sum(axis=1).astype(np.int64)
