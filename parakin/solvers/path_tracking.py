"""Path tracking for parameter homotopies, vectorised over paths (NumPy, complex).

A path is a solution z(s) of H(z, s) = 0 followed from s = 1 (a start solution) to s = 0 (the
target). Each step predicts with the classical Runge-Kutta rule on dz/ds = -H_z^-1 H_s and
corrects with at most ``CORRECTIONS`` Newton iterations at the new s; a step is accepted when the
corrections contract and the last one is below ``tolerance`` (relative to |z|), otherwise it is
halved (doubled again after ``GROW_AFTER`` accepted steps in a row). Contraction keeps a path on
its own branch: a corrector that converges slowly is the sign of a step large enough to jump to
another path. At s = 0 the endpoint is refined by Newton to rounding. The generated C driver
(``generator/templates/c_driver.c.j2``) runs the same algorithm with the same constants; the
generator uses this module to find the start solutions (monodromy). A family whose equations are
each even or odd under a sign change z -> S z (a quaternion's q -> -q) has its paths in pairs
(z(s), S z(s)): one of each pair is tracked (``path_pairs``, ``track_symmetric``), in NumPy and in
C alike.
"""

from __future__ import annotations

import functools
import warnings
from collections.abc import Callable
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

#: what a path ends as
PATH_REACHED, PATH_FAILED, PATH_DIVERGED = 0, 1, 2
CORRECTIONS = 3
GROW_AFTER = 2
INITIAL_STEP = 0.05
MIN_STEP = 1e-12
#: |z| beyond this: the path goes to infinity (a solution at infinity of the target)
ESCAPE = 1e8
MAX_STEPS = 2000
REFINE = 8
END_GAP = 1e-13
#: track_hermite's (and the C driver's) step control: the first Newton correction of a step (the
#: predictor's error, relative to |z|) that the next step is sized to reach; the step's safety
#: factor, and the most it grows after an accepted step and shrinks after a rejected one
PREDICTOR_TARGET = 5e-3
STEP_SAFETY = 0.8
STEP_GROW = 2.0
STEP_SHRINK = 0.25
#: rational_predict takes the cubic Hermite value for an unknown whose rational interpolant's
#: denominator comes this close to 0 along the step (a pole in or next to the step)
RATIONAL_GUARD = 0.3
#: track_hermite's (and the C driver's) corrector stops after one Newton correction of size d
#: where the path's Newton constant omega (the last measured size / update^2 of a step's first two
#: corrections, at least OMEGA_DECAY times the one before; unknown after a rejection) gives
#: omega d <= ONE_STEP_BASIN (well inside the basin, Kantorovich's condition) and an error left
#: omega d^2 below ONE_STEP_ERROR (relative to |z|: the iterate only has to stay in its own path's
#: basin during the path; the endpoint is refined at s = 0)
ONE_STEP_BASIN = 0.25
ONE_STEP_ERROR = 1e-5
OMEGA_DECAY = 0.5
#: track_hermite's (and the C driver's) step control aims the predictor's error of the final
#: steps (END_REACH) at the smaller of PREDICTOR_TARGET and sqrt(ONE_STEP_GOAL ONE_STEP_ERROR /
#: omega), the first correction that the one-correction rule accepts (omega d^2 <
#: ONE_STEP_ERROR with a margin): where the path's Newton
#: constant is large (the target system of Dietmaier's 40 modes near s = 0) a step one correction
#: finishes costs one LU where a longer one costs two or three and is often rejected. The omega the
#: goal uses fades by OMEGA_FADE per accepted step that measured none (one-correction steps measure
#: nothing: without the fade a large omega would keep the steps short for the rest of the path);
#: the one-correction rule itself uses the omega last measured, unfaded
ONE_STEP_GOAL = 0.7
OMEGA_FADE = 0.7
#: the goal applies only where the next step, sized for PREDICTOR_TARGET, would cover at least
#: END_REACH of the rest of the path (its final steps, where Dietmaier's paths were rejected):
#: along the whole path it made rus6's paths to far and singular endpoints (omega growing
#: without bound) take hundreds of short steps (the first correction there stops shrinking with
#: the step)
END_REACH = 0.5
#: the refinement at s = 0 stops once the error its last update of size d leaves, estimated from
#: quadratic convergence as d (d / previous)^2 (previous: the update before, the final step's last
#: correction for the first), is below REFINE_ERROR (relative to |z|): four orders below what the
#: mode assembly separates (real_endpoint 1e-8, duplicate 1e-7), and the certificate begins with
#: Newton steps of its own (krawczyk.h's KW_NEWTON_STEPS); most paths stop after one update
REFINE_ERROR = 1e-12
#: A step's corrections that stop contracting can be rounding noise along the path: where H_z is
#: ill-conditioned its near-null direction is the slope's (a path to a large endpoint, z ~ c / s:
#: H_z z ~ s H_s), and Newton's updates there wander along the path by ~cond(H_z) eps (rps3, issue
#: 33: 1e-5 of |z| at s = 7e-5 with cond 1e11, across the slope 1e-13; no step size helps, and
#: a rejection, which forgets omega, stalls the path). A step short of s = 0 whose updates stop
#: contracting is accepted where its updates across the path (``_across``) converged (contracting
#: to the tolerance, or two below it) and its last update is below ACROSS_NOISE: a point of its
#: own path, shifted along it. Not a step whose updates contract but too slowly (Stewart: such
#: steps so accepted jumped paths), nor at s = 0, where a shift along the path is an error of the
#: endpoint (Stewart: a path into a near-singular endpoint converges linearly along its slope)
ACROSS_NOISE = 1e-3

#: system(index, z, s) -> (H (k, n), H_z (k, n, n), H_s (k, n)) for the paths ``index``
System = Callable[
    [NDArray[np.intp], NDArray[np.complex128], NDArray[np.float64]], tuple[np.ndarray, np.ndarray, np.ndarray]
]


class Paths(NamedTuple):
    """Endpoints (P, n), how each path ended (PATH_*), accepted + rejected steps, and the size
    of the last Newton update at s = 0 relative to |z| (how well the endpoint is determined)."""

    z: NDArray[np.complex128]
    status: NDArray[np.int32]
    steps: NDArray[np.int32]
    update: NDArray[np.float64]


class TrackedPaths(NamedTuple):
    """``Paths`` with what tracking cost per path: ``rejected`` steps (of ``steps``) and Newton
    ``evaluations`` (each with one LU; the refinement at s = 0 included), as the C driver counts."""

    z: NDArray[np.complex128]
    status: NDArray[np.int32]
    steps: NDArray[np.int32]
    update: NDArray[np.float64]
    rejected: NDArray[np.int32]
    evaluations: NDArray[np.int32]


def _solve(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Batched complex solve; a singular matrix gives inf (the step is then rejected)."""
    try:
        return np.linalg.solve(matrix, rhs[..., None])[..., 0]
    except np.linalg.LinAlgError:
        out = np.full(rhs.shape, np.inf + 0j)
        for k in range(matrix.shape[0]):
            try:
                out[k] = np.linalg.solve(matrix[k], rhs[k])
            except np.linalg.LinAlgError:
                pass
        return out


def _size(z: np.ndarray) -> np.ndarray:
    return 1.0 + np.abs(z).max(-1)


def track(system: System, start: np.ndarray, tolerance: float = 1e-7) -> Paths:
    """Follow every start solution (P, n) from s = 1 to s = 0 (module docstring)."""
    z = np.array(start, dtype=complex)
    count = z.shape[0]
    s = np.ones(count)
    h = np.full(count, INITIAL_STEP)
    streak = np.zeros(count, dtype=np.int32)
    steps = np.zeros(count, dtype=np.int32)
    status = np.full(count, -1, dtype=np.int32)
    with np.errstate(all="ignore"):
        while (status < 0).any():
            active = np.nonzero(status < 0)[0]
            za, sa = z[active], s[active]
            ha = np.minimum(h[active], sa)

            def velocity(point: np.ndarray, at: np.ndarray, active: np.ndarray = active) -> np.ndarray:
                _, jacobian, derivative = system(active, point, at)
                return -_solve(jacobian, derivative)

            # s decreases: z(s - h) = z - h dz/ds
            k1 = velocity(za, sa)
            k2 = velocity(za - 0.5 * ha[:, None] * k1, sa - 0.5 * ha)
            k3 = velocity(za - 0.5 * ha[:, None] * k2, sa - 0.5 * ha)
            k4 = velocity(za - ha[:, None] * k3, sa - ha)
            predicted = za - ha[:, None] / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
            # a remainder below END_GAP is rounding: finish at s = 0 exactly
            target = np.where(sa - ha < END_GAP, 0.0, sa - ha)
            corrected, update = predicted, np.full(active.size, np.inf)
            contracting, live = np.ones(active.size, bool), np.ones(active.size, bool)
            for iteration in range(CORRECTIONS):
                rows = np.nonzero(live)[0]
                residual, jacobian, _ = system(active[rows], corrected[rows], target[rows])
                correction = _solve(jacobian, residual)
                corrected[rows] = corrected[rows] - correction
                size = np.abs(correction).max(-1) / _size(corrected[rows])
                # converged iterates stop: at an ill-conditioned solution further updates are
                # rounding noise, which need not contract
                if iteration:
                    contracting[rows] &= size <= 0.5 * update[rows]
                update[rows] = size
                live[rows] = ~(size < tolerance) & contracting[rows]
                if not live.any():
                    break
            accepted = contracting & (update < tolerance) & np.isfinite(update)
            steps[active] += 1
            good, bad = active[accepted], active[~accepted]
            z[good], s[good] = corrected[accepted], target[accepted]
            streak[good] += 1
            grow = streak[good] >= GROW_AFTER
            h[good] = np.where(grow, 2.0 * h[good], h[good])
            streak[good] = np.where(grow, 0, streak[good])
            h[bad] *= 0.5
            streak[bad] = 0
            status[good[s[good] <= 0.0]] = PATH_REACHED
            status[bad[h[bad] < MIN_STEP]] = PATH_FAILED
            status[active[~(np.abs(z[active]).max(-1) < ESCAPE)]] = PATH_DIVERGED
            status[active[(steps[active] >= MAX_STEPS) & (status[active] < 0)]] = PATH_FAILED
        update = np.full(count, np.nan)
        reached = np.nonzero(status == PATH_REACHED)[0]
        if reached.size:
            z[reached], update[reached] = refine(system, reached, z[reached])
    return Paths(z, status, steps, update)


def _newton_with_slope(
    system: System, index: np.ndarray, z: np.ndarray, s: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One Newton step at (z, s) with the slope dz/ds = -H_z^-1 H_s from the same LU (both
    right-hand sides in one solve): the new points, their slopes and the update relative to |z|,
    inf where the system is singular or not finite there (as the C tracker's ``newton_step``)."""
    value, jacobian, rate = system(index, z, s)
    both = _solve_two(jacobian, value, rate)
    moved = z - both[..., 0]
    size = np.abs(both[..., 0]).max(-1) / _size(moved)
    return moved, -both[..., 1], np.where(np.isfinite(both).all((-2, -1)), size, np.inf)


def _across(update: np.ndarray, slope: np.ndarray) -> np.ndarray:
    """max |update - slope (slope^H update) / (slope^H slope)| per row: the part of each update
    (k, n) across the path whose slope (k, n) it is (the C tracker's ``c_across``)."""
    along = (np.conj(slope) * update).sum(-1) / (np.conj(slope) * slope).sum(-1).real
    return np.abs(update - slope * along[:, None]).max(-1)


def _solve_two(matrix: np.ndarray, first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Batched complex solve of two right-hand sides (k, n) each, one factorisation: (k, n, 2);
    inf where singular (the step is then rejected)."""
    rhs = np.stack([first, second], axis=-1)
    try:
        return np.linalg.solve(matrix, rhs)
    except np.linalg.LinAlgError:
        out = np.full(rhs.shape, np.inf + 0j)
        for k in range(matrix.shape[0]):
            try:
                out[k] = np.linalg.solve(matrix[k], rhs[k])
            except np.linalg.LinAlgError:
                pass
        return out


def hermite_predict(
    history: np.ndarray,
    s0: np.ndarray,
    z0: np.ndarray,
    v0: np.ndarray,
    s1: np.ndarray,
    z1: np.ndarray,
    v1: np.ndarray,
    target: np.ndarray,
) -> np.ndarray:
    """z at ``target`` extrapolated from a path's last two points (s0, z0) and (s1, z1) with their
    slopes v = dz/ds: the cubic Hermite interpolant of both (third order); Euler from (s1, z1, v1)
    alone where ``history`` is False (no earlier point). Shapes: (k,) for s, history and target,
    (k, n) for z and v; returns (k, n)."""
    span = np.where(history, s1 - s0, 1.0)
    u = (target - s0) / span
    u2, u3 = u * u, u * u * u
    a0, b0 = 2 * u3 - 3 * u2 + 1, (u3 - 2 * u2 + u) * span
    a1, b1 = 3 * u2 - 2 * u3, (u3 - u2) * span
    cubic = a0[:, None] * z0 + b0[:, None] * v0 + a1[:, None] * z1 + b1[:, None] * v1
    euler = z1 + (target - s1)[:, None] * v1
    return np.where(history[:, None], cubic, euler)


def rational_predict(
    history: np.ndarray,
    s0: np.ndarray,
    z0: np.ndarray,
    v0: np.ndarray,
    s1: np.ndarray,
    z1: np.ndarray,
    v1: np.ndarray,
    target: np.ndarray,
) -> np.ndarray:
    """The tracker's predictor: each unknown at ``target`` from the rational Hermite interpolant
    of a path's last two points (s0, z0) and (s1, z1) with their slopes v = dz/ds, a quadratic
    over a linear polynomial in t = s - s1,

        r(t) = (z1 + (v1 + q z1) t + p2 t^2) / (1 + q t),

    with r = z and r' = v at t = 0 and t = a = s0 - s1: with the secant d = (z0 - z1) / a,
    q = n / m, n = v0 + v1 - 2 d, m = a (d - v0), and p2 = (d - v1) / a + q d; evaluated as
    r = (m (z1 + v1 t + (d - v1) t^2 / a) + n (z1 t + d t^2)) / (m + n t), one division. Of the
    cubic's order (error ~ step^4), and exact on a simple pole z = c / (s - s*) + b (a path
    passing near a singular point of the homotopy, or heading to infinity), where polynomials
    need tiny steps. An unknown whose interpolant is not finite, or whose denominator
    |1 + q t'| comes within ``RATIONAL_GUARD`` of 0 for t' between 0 and t, takes the cubic
    Hermite value (``hermite_predict``); Euler where ``history`` is False. The C tracker's
    ``predict`` (generator/runtime/tracker.h), operation for operation.

    Parameters
    ----------
    history : ndarray, shape (k,), bool
        Whether the path has an earlier point (s0, z0, v0).
    s0, s1 : ndarray, shape (k,)
        The homotopy parameter at the earlier and at the last point.
    z0, v0, z1, v1 : ndarray, shape (k, n), complex
        The points and their slopes dz/ds.
    target : ndarray, shape (k,)
        Where to predict.

    Returns
    -------
    ndarray, shape (k, n), complex
        The predicted points.

    Example
    -------
    >>> import numpy as np
    >>> def z(s): return 1 / (s - 0.2 - 0.01j)  # a pole just off the path
    >>> s0, s1, target = np.array([0.5]), np.array([0.45]), np.array([0.4])
    >>> v = lambda s: -z(s) ** 2
    >>> one = np.ones(1, bool)
    >>> out = rational_predict(one, s0, z(s0)[:, None], v(s0)[:, None], s1, z(s1)[:, None], v(s1)[:, None], target)
    >>> bool(np.allclose(out[:, 0], z(target), rtol=1e-12))
    True
    """
    cubic = hermite_predict(history, s0, z0, v0, s1, z1, v1, target)
    a = np.where(history, s0 - s1, 1.0)[:, None]
    t = (target - s1)[:, None]
    inverse, t2 = 1.0 / a, t * t
    guard = RATIONAL_GUARD * RATIONAL_GUARD
    # in real and imaginary parts, each operation as the C's (complex.h), so that both round alike
    # (NumPy's complex product may fuse or reorder)
    z0r, z0i, z1r, z1i = z0.real, z0.imag, z1.real, z1.imag
    v0r, v0i, v1r, v1i = v0.real, v0.imag, v1.real, v1.imag
    with np.errstate(all="ignore"):
        dr, di = inverse * (z0r - z1r), inverse * (z0i - z1i)
        nr, ni = (v0r + v1r) - 2.0 * dr, (v0i + v1i) - 2.0 * di
        mr, mi = a * (dr - v0r), a * (di - v0i)
        c = t2 * inverse
        qr = (z1r + t * v1r) + c * (dr - v1r)
        qi = (z1i + t * v1i) + c * (di - v1i)
        wr, wi = t * z1r + t2 * dr, t * z1i + t2 * di
        above_r = (mr * qr - mi * qi) + (nr * wr - ni * wi)
        above_i = (mr * qi + mi * qr) + (nr * wi + ni * wr)
        below_r, below_i = mr + t * nr, mi + t * ni
        mm, nn, mn = mr * mr + mi * mi, nr * nr + ni * ni, mr * nr + mi * ni
        positive = t2 * nn > 0.0
        along = np.where(positive, -(t * mn) / np.where(positive, t2 * nn, 1.0), 0.0)
        along = np.where(along < 0.0, 0.0, np.where(along > 1.0, 1.0, along))
        least = mm + 2.0 * along * t * mn + along * along * t2 * nn
        scale = 1.0 / (below_r * below_r + below_i * below_i)
        rational = np.empty(z1.shape, dtype=complex)
        rational.real = (above_r * below_r + above_i * below_i) * scale
        rational.imag = (above_i * below_r - above_r * below_i) * scale
        usable = (least > guard * mm) & np.isfinite(rational) & history[:, None]
    return np.where(usable, rational, cubic)


def track_hermite(system: System, start: np.ndarray, tolerance: float = 1e-7) -> TrackedPaths:
    """Follow every start solution (P, n) from s = 1 to s = 0 with the predictor of the generated
    C driver (its ``track_path``, the same algorithm and constants): each step predicts by the
    rational Hermite extrapolation of the path's last two points and slopes (``rational_predict``:
    quadratic over linear, the cubic where that has a pole near the step; Euler on the first
    step) and corrects by at most ``CORRECTIONS`` contracting Newton steps at
    the new s, accepted when the error the last one leaves is below ``tolerance`` (relative to
    |z|): the update itself after one Newton step, after more the estimate of quadratic
    convergence from the last two (size^3 / previous^2, each at most half the one before). One
    correction of size d also suffices where the path's running Newton constant omega gives
    omega d <= ``ONE_STEP_BASIN`` and omega d^2 < ``ONE_STEP_ERROR`` (module constants). The last Newton step's LU also gives the slope at the new point, so an accepted step
    costs its corrector's evaluations and LUs only. The first correction measures the predictor's
    error: the next step is sized to bring it to ``PREDICTOR_TARGET``, or on the final steps
    (``END_REACH``) where the path's omega is large to what one correction finishes,
    sqrt(``ONE_STEP_GOAL`` ``ONE_STEP_ERROR`` / omega)
    (it grows as the step^4, on the first step as the step^2), within [1/2, STEP_GROW] times the step after an accepted
    step and [STEP_SHRINK, 1/2] after a rejected one, retried from the same point. The endpoint is
    refined at s = 0 (``refine``, stopped where quadratic convergence puts the error left below
    ``REFINE_ERROR``). A step short of s = 0 whose updates stop contracting is accepted where
    those across the path (without their part along the slope) converged and the last update is
    below ``ACROSS_NOISE`` (rounding noise along an ill-conditioned path).

    Parameters
    ----------
    system : System
        ``system(index, z, s)``: H, H_z and H_s of the paths ``index`` (``sparse_system``).
    start : ndarray, shape (P, n), complex
        The start solutions at s = 1.
    tolerance : float
        The last Newton update of an accepted step, relative to 1 + max|z|.

    Returns
    -------
    TrackedPaths
        The endpoints and how each path ended (``Paths``), with each path's rejected steps and
        Newton evaluations (each one LU).

    Example
    -------
    >>> import numpy as np
    >>> table = np.zeros((1, 2, 2), complex)
    >>> table[0, 0] = [1.0, -4.0]  # z^2 - 4 at s = 0 ...
    >>> table[0, 1] = [0.0, 3.0]  # ... z^2 - (4 - 3 s): z^2 - 1 at s = 1
    >>> system = sparse_system(table, np.array([[2], [0]]), np.array([0, 0]), 2)
    >>> ends = track_hermite(system, np.array([[1.0 + 0j], [-1.0 + 0j]]))
    >>> bool(np.allclose(ends.z[:, 0], [2, -2]))
    True
    """
    z = np.array(start, dtype=complex)
    count = z.shape[0]
    every = np.arange(count)
    s, s_previous = np.ones(count), np.ones(count)
    h = np.full(count, INITIAL_STEP)
    history = np.zeros(count, bool)
    omega = np.full(count, np.inf)
    fade = np.ones(count)  # OMEGA_FADE^(accepted steps since omega was last measured)
    last = np.full(count, np.inf)  # the last correction of the last accepted step
    steps, rejected, evaluations = (np.zeros(count, dtype=np.int32) for _ in range(3))
    status = np.full(count, -1, dtype=np.int32)
    with np.errstate(all="ignore"):
        z, slope, size = _newton_with_slope(system, every, z, s)  # the start's slope
        evaluations += 1
        status[~np.isfinite(size)] = PATH_FAILED
        z_previous, slope_previous = z.copy(), slope.copy()
        while (status < 0).any():
            active = np.nonzero(status < 0)[0]
            step = np.minimum(h[active], s[active])
            target = np.where(s[active] - step < END_GAP, 0.0, s[active] - step)
            corrected = rational_predict(
                history[active],
                s_previous[active],
                z_previous[active],
                slope_previous[active],
                s[active],
                z[active],
                slope[active],
                target,
            )
            next_slope = np.zeros_like(corrected)
            first, update, error, measured = (np.full(active.size, np.inf) for _ in range(4))
            across, across_error = np.full(active.size, np.inf), np.full(active.size, np.inf)
            contracting, live = np.ones(active.size, bool), np.ones(active.size, bool)
            across_contracting, across_done = np.ones(active.size, bool), np.zeros(active.size, bool)
            for iteration in range(CORRECTIONS):
                rows = np.nonzero(live)[0]
                before = corrected[rows]
                corrected[rows], next_slope[rows], size = _newton_with_slope(
                    system, active[rows], corrected[rows], target[rows]
                )
                evaluations[active[rows]] += 1
                # the update across the path: without its part along the slope (ACROSS_NOISE)
                cross = np.where(
                    np.isfinite(size),
                    _across(before - corrected[rows], next_slope[rows]) / _size(corrected[rows]),
                    np.inf,
                )
                if iteration:
                    contracting[rows] &= size <= 0.5 * update[rows]
                    across_contracting[rows] &= cross <= 0.5 * across[rows]
                    # quadratic convergence: the error left after this update is about
                    # omega size^2 with omega = size / previous^2
                    error[rows] = size * (size / update[rows]) ** 2
                    across_error[rows] = cross * (cross / across[rows]) ** 2
                    # across the path converged: as the tolerance asks, or two updates below it
                    across_done[rows] = (across_contracting[rows] & (across_error[rows] < tolerance)) | (
                        (cross < tolerance) & (across[rows] < tolerance)
                    )
                    if iteration == 1:
                        measured[rows] = size / update[rows] ** 2
                else:
                    first[rows] = size
                    # one correction suffices where the running Newton constant omega says it
                    # started well inside the basin and left an error below ONE_STEP_ERROR
                    known = omega[active[rows]]
                    enough = (known * size <= ONE_STEP_BASIN) & (known * size * size < ONE_STEP_ERROR)
                    error[rows] = np.where(enough, 0.0, size)
                update[rows], across[rows] = size, cross
                # a step whose updates stop contracting goes on while those across the path may
                # still converge (rounding noise along the path: ACROSS_NOISE)
                hope = (
                    ~across_done[rows]
                    & (size < ACROSS_NOISE)
                    & (target[rows] > 0.0)
                    & (across_contracting[rows] | (cross < tolerance))
                )
                live[rows] = ~(error[rows] < tolerance) & (contracting[rows] | hope)
                if not live.any():
                    break
            accepted = contracting & (error < tolerance) & np.isfinite(update)
            # else, updates that stopped contracting short of s = 0, where those across the path
            # converged and the last is below ACROSS_NOISE: a point of its own path, shifted
            # along it by rounding (no omega measured)
            noisy = ~contracting & across_done & (update < ACROSS_NOISE) & (target > 0.0)
            accepted |= noisy
            measured[noisy] = np.inf
            power = np.where(history[active], 0.25, 0.5)
            # the omega of the next step: this step's measurement (at least OMEGA_DECAY times the
            # one before), else the one before faded once more
            known = omega[active]
            fresh = np.isfinite(measured) & (measured > 0.0)
            ahead = np.where(
                fresh,
                np.where(np.isfinite(known), np.maximum(measured, OMEGA_DECAY * known), measured),
                known * (fade[active] * OMEGA_FADE),
            )
            goal = np.where(
                np.isfinite(ahead),
                np.minimum(PREDICTOR_TARGET, np.sqrt(ONE_STEP_GOAL * ONE_STEP_ERROR / ahead)),
                PREDICTOR_TARGET,
            )
            factor, plain = (
                np.where(
                    ~np.isfinite(first),
                    0.0,
                    np.where(first > 0, STEP_SAFETY * (aim / np.where(first > 0, first, 1.0)) ** power, STEP_GROW),
                )
                for aim in (goal, PREDICTOR_TARGET)
            )
            # the goal only where the next step (by PREDICTOR_TARGET) would cover END_REACH of what
            # is left of the path: the final steps
            reach = np.where(
                accepted,
                step * np.minimum(STEP_GROW, np.maximum(0.5, plain)),
                step * np.minimum(0.5, np.maximum(STEP_SHRINK, plain)),
            )
            factor = np.where(reach >= END_REACH * np.where(accepted, target, s[active]), factor, plain)
            steps[active] += 1
            good, bad = active[accepted], active[~accepted]
            rejected[bad] += 1
            z_previous[good], slope_previous[good], s_previous[good] = z[good], slope[good], s[good]
            z[good], slope[good], s[good] = corrected[accepted], next_slope[accepted], target[accepted]
            last[good] = update[accepted]
            history[good] = True
            omega[good] = np.where(fresh[accepted], ahead[accepted], omega[good])
            fade[good] = np.where(fresh[accepted], 1.0, fade[good] * OMEGA_FADE)
            omega[bad], fade[bad] = np.inf, 1.0
            h[good] = step[accepted] * np.minimum(STEP_GROW, np.maximum(0.5, factor[accepted]))
            h[bad] = step[~accepted] * np.minimum(0.5, np.maximum(STEP_SHRINK, factor[~accepted]))
            status[good[s[good] <= 0.0]] = PATH_REACHED
            status[bad[h[bad] < MIN_STEP]] = PATH_FAILED
            status[active[~(np.abs(z[active]).max(-1) < ESCAPE)]] = PATH_DIVERGED
            status[active[(steps[active] >= MAX_STEPS) & (status[active] < 0)]] = PATH_FAILED
        update = np.full(count, np.nan)
        reached = np.nonzero(status == PATH_REACHED)[0]
        if reached.size:
            refined = np.zeros(reached.size, dtype=np.int32)
            z[reached], update[reached] = refine(
                system, reached, z[reached], evaluations=refined, previous=last[reached]
            )
            evaluations[reached] += refined
    return TrackedPaths(z, status, steps, update, rejected, evaluations)


def refine(
    system: System,
    index: np.ndarray,
    z: np.ndarray,
    iterations: int = REFINE,
    evaluations: np.ndarray | None = None,
    previous: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Newton on H(z, 0) until the update stops shrinking or reaches rounding; returns the
    points and the last update relative to |z|. ``evaluations`` (per row of z), where given,
    counts each row's Newton evaluations. ``previous`` (per row), where given, is the update
    before the first (the tracker's last correction): a row also stops once the error its last
    update d leaves, d (d / previous)^2 from quadratic convergence, is below ``REFINE_ERROR``."""
    before = None if previous is None else np.array(previous, dtype=float)
    zero = np.zeros(index.size)
    update = np.full(index.size, np.inf)
    live = np.ones(index.size, bool)
    with np.errstate(all="ignore"):
        for _ in range(iterations):
            if not live.any():
                break
            rows = np.nonzero(live)[0]
            residual, jacobian, _ = system(index[rows], z[rows], zero[rows])
            if evaluations is not None:
                evaluations[rows] += 1
            correction = _solve(jacobian, residual)
            size = np.abs(correction).max(-1) / _size(z[rows])
            improving = np.isfinite(size) & (size < update[rows])
            z[rows[improving]] -= correction[improving]
            update[rows] = np.where(improving, size, update[rows])
            live[rows] = improving & (size > 1e-15)
            if before is not None:
                live[rows] &= ~(size * (size / before[rows]) ** 2 < REFINE_ERROR)
                before[rows] = np.where(improving, size, before[rows])
    return z, update


def circle_point(u: np.ndarray, a: complex, b: complex) -> np.ndarray:
    """(C, S, D) of the circle parametrisation (``generator/polynomial_form.py``) at u, last axis."""
    one_minus, a_minus = 1 - u, a - b * u
    return np.stack([one_minus**2 - a_minus**2, 2 * a_minus * one_minus, one_minus**2 + a_minus**2], axis=-1)


def circle_parameter(angle: np.ndarray, a: complex, b: complex) -> np.ndarray:
    """u of real angles: (sin(x/2) - a cos(x/2)) / (sin(x/2) - b cos(x/2)), finite for real x."""
    half_sin, half_cos = np.sin(angle / 2), np.cos(angle / 2)
    return (half_sin - a * half_cos) / (half_sin - b * half_cos)


def path_coefficients(
    monomials: Callable[[np.ndarray], np.ndarray],
    free: np.ndarray,
    angles: np.ndarray,
    start: np.ndarray,
    powers: int,
    constants: tuple[complex, complex],
) -> np.ndarray:
    """The coefficients (inputs, powers, terms) in s of every monomial along the segment from the
    start instance (s = 1) to the inputs (s = 0): the family moves linearly in its free values and
    in the circle parameters u; ``monomials`` (complex family values (..., F + 3 A) -> (..., T))
    is evaluated at the ``powers``-th roots of unity and one DFT gives the coefficients (exact for
    polynomials of degree < powers, and unitary)."""
    a, b = constants
    nodes = np.exp(2j * np.pi * np.arange(powers) / powers)[None, :, None]
    f = free.shape[-1]
    target_u = circle_parameter(angles, a, b)
    free_at = (1 - nodes) * free[:, None, :] + nodes * start[None, None, :f]
    u_at = (1 - nodes) * target_u[:, None, :] + nodes * start[None, None, f:]
    circle = circle_point(u_at, a, b).reshape(u_at.shape[:-1] + (-1,))
    values = monomials(np.concatenate([free_at, circle], axis=-1))  # (inputs, nodes, terms)
    return np.fft.fft(values, axis=1) / powers


def near_home(
    center: np.ndarray,
    scale: np.ndarray,
    radius: float,
    free: np.ndarray,
    angles: np.ndarray,
    constants: tuple[complex, complex],
) -> np.ndarray:
    """(inputs,) bool: the inputs whose family values (free values (inputs, F), angles (inputs,
    A) as circle parameters u) all lie within ``radius`` of ``center`` (F + A, complex), each
    relative to its ``scale``: those start at the instance near home (the manifest's ``near``;
    the generated C driver's ``near_home``). NaN values are not near."""
    point = np.concatenate([free + 0j, circle_parameter(angles, *constants)], axis=-1)
    with np.errstate(invalid="ignore"):
        return (np.abs(point - center) / scale <= radius).all(-1)


def sparse_system(table: np.ndarray, exponents: np.ndarray, equation: np.ndarray, paths: int) -> System:
    """The system of a generated homotopy from its coefficients in s (inputs, powers, terms):
    equation k is the sum over the monomials t with ``equation[t] == k`` of
    c_t(s) prod_i z_i^exponents[t, i]. Path p belongs to input p // ``paths``."""
    terms, size = exponents.shape
    powers = table.shape[1]
    degrees = np.arange(powers)
    top = int(exponents.max(initial=0))
    scatter = np.zeros((terms, size), dtype=complex)
    scatter[np.arange(terms), equation] = 1.0  # term -> equation, summed by a product (BLAS)

    def system(index: np.ndarray, z: np.ndarray, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        inputs = index // paths
        weights = s[:, None] ** degrees
        rates = degrees * s[:, None] ** np.maximum(degrees - 1, 0)
        coefficients = table[inputs]
        at = np.matmul(weights[:, None, :].astype(complex), coefficients)[:, 0]
        moving = np.matmul(rates[:, None, :].astype(complex), coefficients)[:, 0]
        # powers[p, i, e] = z_i^e; factor[p, t, i] = z_i^a_ti
        power = np.ones((z.shape[0], size, top + 1), dtype=complex)
        for e in range(1, top + 1):
            power[..., e] = power[..., e - 1] * z
        rows = np.arange(size)[None, :]
        factor = power[:, rows, exponents]  # (p, t, i)
        monomial = factor.prod(-1)
        derivative = exponents * power[:, rows, np.maximum(exponents - 1, 0)]
        # product over j != i: the monomial over z_i^a_ti, or where that is 0 (z_i = 0, rare)
        # the product of the others
        with np.errstate(all="ignore"):
            others = monomial[..., None] / factor
        zero = factor == 0
        if zero.any():
            rows_zero = np.nonzero(zero.any((-2, -1)))[0]
            f = factor[rows_zero]
            before = np.cumprod(np.concatenate([np.ones_like(f[..., :1]), f[..., :-1]], -1), -1)
            after = np.cumprod(np.concatenate([np.ones_like(f[..., :1]), f[..., :0:-1]], -1), -1)[..., ::-1]
            others[rows_zero] = before * after
        partial = derivative * others  # (p, t, i)
        value = (at * monomial) @ scatter
        rate = (moving * monomial) @ scatter
        jacobian = np.swapaxes(np.swapaxes(at[:, :, None] * partial, 1, 2) @ scatter, 1, 2)
        return value, jacobian, rate

    return system


def is_known(known: np.ndarray, candidate: np.ndarray) -> bool:
    """Whether ``candidate`` is one of the ``known`` endpoints (max-norm distance at most 1e-6
    relative to 1 + |candidate|): the one test of 'the same solution' for endpoints."""
    return bool(known.size) and bool(np.abs(known - candidate).max(-1).min() <= 1e-6 * (1 + np.abs(candidate).max()))


def real_phase(z: np.ndarray, homogeneous: list[int] | tuple[int, ...]) -> np.ndarray:
    """z (..., n) scaled, where there is a homogeneous group, so that its largest homogeneous
    entry is real and positive (a complex multiple of a real solution becomes that solution)."""
    if not homogeneous:
        return z
    block = z[..., list(homogeneous)]
    largest = np.take_along_axis(block, np.abs(block).argmax(-1)[..., None], axis=-1)
    with np.errstate(all="ignore"):
        return z * (np.abs(largest) / largest)


def phase_normalised(
    z: np.ndarray, homogeneous: list[int], typical: np.ndarray | float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """An endpoint of a homogeneous system is a complex multiple of a real solution when one
    exists: scale it so that its largest homogeneous entry is real and positive, and return it
    with the size of its imaginary part relative to |z|, or to ``typical`` (the input's typical
    root size, ``typical_root_size``; broadcast against z[..., 0]) where that is larger (0 for a
    real solution). A root at the origin (a translating platform at home) has coordinates of
    rounding size whose imaginary parts are as large: measured against themselves, 0/0."""
    z = real_phase(z, homogeneous)
    with np.errstate(all="ignore"):
        largest_imaginary = np.abs(z.imag).max(-1)
        imaginary = np.where(largest_imaginary == 0, 0.0, largest_imaginary / np.fmax(np.abs(z).max(-1), typical))
    return z, imaginary


def typical_root_size(size: np.ndarray, reached: np.ndarray) -> np.ndarray:
    """Per input, the median over its reached endpoints of their sizes max_k |z_k| (NaN where none
    is reached, which ``phase_normalised``'s fmax ignores), as the C driver (krawczyk.h's ``kw_median``).

    Parameters
    ----------
    size : ndarray, shape (n, P)
        max_k |z_k| of each input's P path ends (in the units of z).
    reached : ndarray of bool, shape (n, P)
        Which paths reached s = 0.

    Returns
    -------
    ndarray, shape (n,)
        The typical size of each input's roots.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an input with no reached path
        return np.nanmedian(np.where(reached, size, np.nan), axis=-1)


# ---------------------------------------------------------------------------------- symmetry
def sign_symmetry(exponents: np.ndarray, equation: np.ndarray) -> np.ndarray | None:
    """A sign change z -> S z (S = diag(flip), flip in {1, -1}^n, not all 1) under which every
    equation is even or odd, H_k(S z) = +-H_k(z), whatever its coefficients: the parity of
    a_t . v (v the flipped unknowns) is the same for every term t of an equation. The first
    such v of a basis of the solutions over GF(2) (e.g. q -> -q of a quaternion, which gives the
    same rotation), or None. Then the solutions of the system, and the paths of a homotopy of
    the family, come in pairs (z, S z)."""
    parity = np.asarray(exponents, dtype=np.int64) % 2
    rows = [
        (parity[members[1:]] + parity[members[0]]) % 2
        for members in (np.nonzero(np.asarray(equation) == k)[0] for k in np.unique(equation))
        if members.size > 1
    ]
    a = np.concatenate(rows).astype(np.uint8) if rows else np.zeros((0, parity.shape[1]), np.uint8)
    pivots: list[int] = []
    for column in range(a.shape[1]):  # row reduction over GF(2)
        row = next((r for r in range(len(pivots), a.shape[0]) if a[r, column]), None)
        if row is None:
            continue
        a[[len(pivots), row]] = a[[row, len(pivots)]]
        for r in range(a.shape[0]):
            if r != len(pivots) and a[r, column]:
                a[r] ^= a[len(pivots)]
        pivots.append(column)
    free = [c for c in range(a.shape[1]) if c not in pivots]
    if not free:
        return None
    v = np.zeros(a.shape[1], dtype=bool)
    v[free[0]] = True
    for r, column in enumerate(pivots):
        v[column] = bool(a[r, free[0]])
    return np.where(v, -1.0, 1.0)


def symmetric_partners(start: np.ndarray, flip: np.ndarray | None) -> np.ndarray | None:
    """For start solutions (P, n) closed under z -> flip z: partner[p] = the path whose start is
    flip * start[p] (never p itself); None when there is no symmetry or the starts do not pair
    up exactly (to 1e-8 relative): then every path is tracked."""
    if flip is None or start.shape[0] % 2:
        return None
    images = start * flip
    scale = 1.0 + np.abs(start).max(-1)
    distance = np.abs(images[:, None, :] - start[None, :, :]).max(-1) / scale[:, None]
    partner = distance.argmin(-1)
    if not (distance[np.arange(start.shape[0]), partner] <= 1e-8).all():
        return None
    if (partner == np.arange(start.shape[0])).any() or (partner[partner] != np.arange(start.shape[0])).any():
        return None
    return partner


class PathPairs(NamedTuple):
    """The start paths of a family with a sign symmetry, in pairs: ``flip`` S's signs (n,),
    ``partner`` (P,) each path's partner, ``first`` the path of each pair that is tracked (the
    lower index) and ``second`` its partner, the image (``first[k]`` pairs with ``second[k]``)."""

    flip: NDArray[np.float64]
    partner: NDArray[np.intp]
    first: NDArray[np.intp]
    second: NDArray[np.intp]


def path_pairs(exponents: np.ndarray, equation: np.ndarray, start: np.ndarray) -> PathPairs | None:
    """The pairs of the start paths ``start`` (P, n) under the family's sign symmetry
    (``sign_symmetry``, ``symmetric_partners``), or None: then every path is tracked. The one
    place the generator (the C driver's table), the NumPy pipeline and the certificates pair paths.
    Computed once per family and start system (each certificate asks)."""
    e = np.ascontiguousarray(exponents, dtype=np.int64)
    z = np.ascontiguousarray(start, dtype=complex)
    k = np.ascontiguousarray(equation, dtype=np.int64)
    return _cached_pairs(e.tobytes(), e.shape, k.tobytes(), z.tobytes(), z.shape)


@functools.lru_cache(maxsize=64)
def _cached_pairs(
    exponents: bytes, shape: tuple[int, ...], equation: bytes, start: bytes, start_shape: tuple[int, ...]
) -> PathPairs | None:
    flip = sign_symmetry(np.frombuffer(exponents, np.int64).reshape(shape), np.frombuffer(equation, np.int64))
    partner = symmetric_partners(np.frombuffer(start, complex).reshape(start_shape), flip)
    if partner is None or flip is None:
        return None
    first = np.nonzero(partner > np.arange(partner.size))[0]
    pairs = PathPairs(flip, partner, first, partner[first])
    for array in pairs:  # shared by every caller: read-only
        array.flags.writeable = False
    return pairs


def track_symmetric(
    system_for: Callable[[int], System], start: np.ndarray, count: int, tolerance: float, pairs: PathPairs | None
) -> Paths:
    """``track`` of ``count`` inputs' paths from ``start`` (P, n), or each input's own (count, P,
    n); with ``pairs`` (``path_pairs`` of ``start``), one path of each pair (z, S z) is tracked and its partner's path is its image:
    H(S z, s) = D H(z, s) along the whole homotopy, so the partner ends at S times its end, the
    same way (reached, failed or diverged). ``system_for(paths per input)`` builds the system;
    results are (count * P, ...) in path order either way."""
    start = np.broadcast_to(start, (count,) + start.shape[-2:])
    paths, size = start.shape[1:]
    if pairs is None:
        return track(system_for(paths), start.reshape(-1, size), tolerance)
    tracked = pairs.first
    half = track(system_for(tracked.size), start[:, tracked].reshape(-1, size), tolerance)
    source = np.empty(paths, dtype=np.intp)
    source[tracked], source[pairs.second] = np.arange(tracked.size), np.arange(tracked.size)
    signs = np.ones((paths, size))
    signs[pairs.second] = pairs.flip
    rows = (np.arange(count)[:, None] * tracked.size + source[None, :]).ravel()
    return Paths(half.z[rows] * np.tile(signs, (count, 1)), half.status[rows], half.steps[rows], half.update[rows])
