"""Closed configurations sampled around a mechanism's home configuration, from its manifest alone.

Used by ``make bench``, the contract tests and design studies: the actuated inputs are perturbed
(revolute by ``spread`` rad, prismatic by ``spread`` times their home value) and each
configuration is closed by Newton from the home configuration; the ones that converge are kept.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from parakin.results import Array, Configuration

if TYPE_CHECKING:
    from parakin.mechanism import Mechanism


def sample_configurations(m: Mechanism, count: int, spread: float = 0.05, seed: int = 0) -> Configuration:
    """Up to ``count`` closed configurations near home (a batch; fewer where Newton failed or
    an actuated value fell outside its declared range)."""
    rng = np.random.default_rng(seed)
    revolute = np.array([v.revolute for v in m.manifest.actuated])
    scale = np.where(revolute, 1.0, np.maximum(np.abs(m.home_actuated), 1e-3))
    actuated = m.home_actuated + spread * scale * rng.standard_normal((count, m.home_actuated.size))
    low, high = m.actuated_bounds
    actuated = actuated[((actuated >= low) & (actuated <= high)).all(-1)]
    guess = np.broadcast_to(m.home_passive, (actuated.shape[0], m.home_passive.size))
    solved = m.forward_pose(actuated, guess, strict=False)
    keep = np.asarray(solved.converged)
    return Configuration(actuated[keep], solved.passive[keep], solved.pose[keep])


def closure_singularity(m: Mechanism, state: Configuration) -> Array:
    """Signed, scale-free distance to a type II singularity: det of the closure Jacobian (in the
    passive variables) divided by the product of its row norms; 0 at the singularity, |.| <= 1."""
    # the raw kernel: invalid inverse branches (NaN, negative lengths) are masked by the caller
    jacobian = m.backend.call("loop_closure", state.actuated, state.passive, m.params)["jacobian"]
    rows = np.linalg.norm(jacobian, axis=-1).prod(-1)
    return np.linalg.det(jacobian) / np.where(rows > 0, rows, 1.0)


def near_singular_configurations(
    m: Mechanism, levels: tuple[float, ...], count: int, seed: int = 0, spread: float = 0.4
) -> tuple[Configuration, Array]:
    """Configurations at given distances to a type II singularity, from the manifest alone.

    Along straight lines in (x, y, z, Z-Y-X Euler) between sampled poses, an inverse branch is
    followed; where ``closure_singularity`` changes sign it is bisected to the singular pose,
    then the line is walked back to each level in ``levels`` (|measure| = level, within 2x).
    Returns the configurations (k, ...) made by the inverse pose, and each one's measure.
    Needs a closed-form inverse."""
    from parakin.pose import pose_from_xyz_euler, xyz_euler_from_pose

    rng = np.random.default_rng(seed)
    sample = sample_configurations(m, 4 * count, spread=spread, seed=seed)
    coordinates = xyz_euler_from_pose(sample.pose)
    grid = np.linspace(0.0, 1.0, 33)
    found: list[Configuration] = []
    measures: list[float] = []

    def along(start: Array, end: Array, branch: int, s: Array) -> tuple[Configuration, Array, np.ndarray]:
        poses = pose_from_xyz_euler(start + s[:, None] * (end - start))
        inverse = m.inverse_pose(poses, strict=False)
        state = inverse.branch(branch)
        with np.errstate(all="ignore"):
            # the configuration's own pose: an inverse that reads only what the actuators control
            # (a lower-mobility platform) returns the reachable pose nearest the line's
            reached = m.backend.call("platform_pose", state.actuated, state.passive, m.params)["pose"]
            state = Configuration(state.actuated, state.passive, reached)
            return state, closure_singularity(m, state), inverse.valid[:, branch]

    pairs = rng.permutation(len(coordinates))
    for first, second in zip(pairs[0::2], pairs[1::2], strict=False):
        if len(found) >= count * len(levels):
            break
        branches = m.inverse_pose(sample.pose[first], strict=False)
        matching = np.abs(branches.passive - sample.passive[first]).max(-1)
        branch = int(np.argmin(np.where(branches.valid, matching, np.inf)))
        _, measure, valid = along(coordinates[first], coordinates[second], branch, grid)
        change = np.nonzero(valid[:-1] & valid[1:] & (np.sign(measure[:-1]) * np.sign(measure[1:]) < 0))[0]
        if change.size == 0:
            continue
        low, high = grid[change[0]], grid[change[0] + 1]
        sign_low = np.sign(measure[change[0]])
        for _ in range(60):
            middle = 0.5 * (low + high)
            _, value, _ = along(coordinates[first], coordinates[second], branch, np.array([middle]))
            low, high = (middle, high) if np.sign(value[0]) == sign_low else (low, middle)
        singular = 0.5 * (low + high)
        outside = grid[change[0]]  # the valid side of the crossing walked back to each level
        for level in levels:
            near, far = singular, outside
            for _ in range(80):  # bisection on log |measure| between the singular and outer points
                middle = 0.5 * (near + far)
                _, value, _ = along(coordinates[first], coordinates[second], branch, np.array([middle]))
                near, far = (middle, far) if abs(value[0]) < level else (near, middle)
            state, value, valid = along(coordinates[first], coordinates[second], branch, np.array([near]))
            if valid[0] and level / 2 <= abs(value[0]) <= 2 * level:
                found.append(state)
                measures.append(float(value[0]))
    if not found:
        empty = np.zeros((0,))
        return Configuration(
            empty.reshape(0, len(m.actuated_names)), empty.reshape(0, len(m.passive_names)), empty.reshape(0, 4, 4)
        ), empty
    return (
        Configuration(
            np.concatenate([c.actuated for c in found]),
            np.concatenate([c.passive for c in found]),
            np.concatenate([c.pose for c in found]),
        ),
        np.array(measures),
    )


__all__ = ["closure_singularity", "near_singular_configurations", "sample_configurations"]
