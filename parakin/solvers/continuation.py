"""Where Newton's square solve does not apply: self-motions and incompatible inputs.

Self-motions: the one-dimensional solution set of the loop closure with locked actuators.

Where a forward elimination degenerates (an architecturally singular design, or inputs on a
self-motion), the platform is not determined by its actuators. ``trace_self_motion`` finds
closed configurations by minimum-norm Gauss-Newton and follows each curve by pseudo-arclength
continuation (tangent = null vector of the passive Jacobian), generically for any mechanism.
Incompatible inputs (locked actuators that no configuration satisfies exactly, e.g. rounded
printed values on a self-motion): ``least_squares_configuration`` minimises the loop-closure
residual by Levenberg-Marquardt; its residual is the distance from compatible inputs.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from parakin.pose import rigid_or_nan
from parakin.results import Array

if TYPE_CHECKING:
    from parakin.solvers.loaded import LoadedMechanism


@dataclass(frozen=True)
class SelfMotion:
    """Points on the solution set for locked ``actuated`` values: ``passive`` (k, n_p), ``poses``
    (k, 4, 4), ``residual`` (k,) and ``curve`` (k,), the index of the traced curve each point is
    on; ``closed[c]`` says whether curve c returned to its start (a circuit)."""

    actuated: Array
    passive: Array
    poses: Array
    residual: Array
    curve: Array
    closed: tuple[bool, ...]

    @property
    def count(self) -> int:
        return int(self.passive.shape[0])


def _closure(m: LoadedMechanism, theta: Array, q: Array) -> tuple[Array, Array]:
    out = m.backend.call("loop_closure", theta, q, m.params)
    return out["residual"], out["jacobian"]


def _correct(m: LoadedMechanism, theta: Array, q: Array, tolerance: float, iterations: int = 12) -> tuple[Array, float]:
    """Minimum-norm Gauss-Newton onto the solution set (the Jacobian is rank deficient there);
    a false closure (an alignment measure not positive: a half-turn, a mirror) counts as none."""
    residual = np.inf
    for _ in range(iterations):
        out = m.backend.call("loop_closure", theta, q, m.params)
        r, jacobian = out["residual"], out["jacobian"]
        residual = float(np.abs(r).max())
        if not np.isfinite(residual):
            return q, np.inf
        if residual < tolerance:
            if not (out["alignment"] > 0).all():
                return q, np.inf
            break
        if not np.isfinite(jacobian).all():
            return q, np.inf
        step = np.linalg.lstsq(jacobian, -r, rcond=1e-10)[0]
        q = q + step
    return q, residual


def _tangent(m: LoadedMechanism, theta: Array, q: Array, previous: Array | None) -> Array:
    _, jacobian = _closure(m, theta, q)
    tangent = np.linalg.svd(jacobian)[2][-1]
    if previous is not None and tangent @ previous < 0:
        tangent = -tangent
    return np.asarray(tangent, dtype=float)


def trace_self_motion(
    m: LoadedMechanism,
    actuated: Array,
    starts: Array | None = None,
    step: float = 0.02,
    max_points: int = 400,
    seed: int = 0,
) -> SelfMotion:
    """Trace every curve of the solution set reached from ``starts`` (k, n_p) (default: the home
    configuration and 32 random perturbations of it), in steps of ``step`` (passive units), at
    most ``max_points`` points per curve, stopping where a curve leaves the joint limits."""
    tolerance = m.tolerances["closure"]
    theta = np.asarray(actuated, dtype=float)
    if starts is None:
        rng = np.random.default_rng(seed)
        scale = 0.3 * (1 + np.abs(m.home_passive))
        starts = m.home_passive + rng.normal(size=(32, m.home_passive.size)) * scale
        starts = np.vstack([m.home_passive, starts])
    points: list[Array] = []
    curves: list[int] = []
    closed: list[bool] = []
    for start in np.atleast_2d(starts):
        q0, residual = _correct(m, theta, np.array(start, dtype=float), tolerance, iterations=40)
        if residual >= tolerance:
            continue
        if points and np.min(np.abs(np.array(points) - q0).max(-1)) < 2 * step:
            continue  # on a curve already traced
        curve = len(closed)
        path = [q0]
        loop = False
        for direction in (1.0, -1.0):
            q, previous = q0, direction * _tangent(m, theta, q0, None)
            h = step
            while len(path) < max_points and h > step / 64:
                tangent = _tangent(m, theta, q, previous)
                candidate, residual = _correct(m, theta, q + h * tangent, tolerance)
                if residual >= tolerance or np.abs(candidate - q).max() > 4 * h:
                    h /= 2
                    continue
                if not m.within_limits(candidate):
                    break  # the curve leaves the joint ranges: the rest is not a configuration
                q, previous = candidate, tangent
                path.append(q)
                if len(path) > 8 and np.abs(q - q0).max() < h:
                    loop = True
                    break
                h = min(step, 1.5 * h)
            if loop:
                break
        points.extend(path)
        curves.extend([curve] * len(path))
        closed.append(loop)
    passive = np.array(points).reshape(-1, m.home_passive.size)
    poses = m.platform_pose(np.broadcast_to(theta, (passive.shape[0], theta.size)), passive)
    residual_values = np.abs(_closure(m, theta, passive)[0]).max(-1) if passive.shape[0] else np.zeros(0)
    return SelfMotion(theta, passive, poses, residual_values, np.array(curves, dtype=int), tuple(closed))


@dataclass(frozen=True)
class LeastSquares:
    """The passive values minimising |residual|_2 for locked actuated values, the pose (NaN
    where those values give no rigid pose: see ``Mechanism.platform_pose``), the residual vector
    at the optimum, its norm and the iterations used."""

    passive: Array
    pose: Array
    residual: Array
    norm: float
    iterations: int


def least_squares_configuration(
    m: LoadedMechanism, actuated: Array, start: Array, iterations: int = 200
) -> LeastSquares:
    """Levenberg-Marquardt on the loop closure from ``start`` (n_p,); converges to a local
    minimum (zero residual where the inputs are compatible)."""
    theta, q = np.asarray(actuated, dtype=float), np.array(start, dtype=float)
    damping = 1e-3
    r, jacobian = _closure(m, theta, q)
    cost = float(r @ r)
    used = 0
    while used < iterations:
        used += 1
        gram = jacobian.T @ jacobian
        step = np.linalg.solve(gram + damping * np.diag(np.diag(gram) + 1e-12), -jacobian.T @ r)
        r_new, jacobian_new = _closure(m, theta, q + step)
        cost_new = float(r_new @ r_new)
        if np.isfinite(cost_new) and cost_new < cost:
            q, r, jacobian, damping = q + step, r_new, jacobian_new, max(damping / 3, 1e-12)
            converged = cost - cost_new < 1e-15 * max(cost, 1e-300) or np.abs(step).max() < 1e-13
            cost = cost_new
            if converged:
                break
        else:
            damping *= 4
            if damping > 1e12:
                break
    # inputs that no configuration satisfies leave q open: its pose is NaN where the pose
    # kernel then gives no rigid transform (``Mechanism.platform_pose`` would refuse it)
    kernel = m.backend.call("platform_pose", theta, q, m.params)["pose"]
    return LeastSquares(q, rigid_or_nan(kernel)[0], r, float(np.sqrt(cost)), used)


__all__ = ["LeastSquares", "SelfMotion", "least_squares_configuration", "trace_self_motion"]
