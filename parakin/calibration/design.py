"""``design_poses``: where to measure. From candidate poses inside the reachable workspace, pick
n whose stacked calibration Jacobian is best by an observability criterion (greedy, then
exchange), keeping a margin from singular configurations.

Criteria, on the information matrix M = J^T J of the whitened Jacobian with columns scaled by
their norms over all candidates (so metres and radians weigh alike):

* ``"O1"``: (product of J's singular values)^(1/n) / sqrt(poses) (Borm and Menq);
* ``"D"``: log det M (D-optimal: the smallest volume of the parameters' confidence ellipsoid);
* ``"E"``: the smallest eigenvalue of M (E-optimal: the worst-determined direction).

Before n poses determine every parameter, M + eps I (eps = 1e-9 trace(M_all) / n_free) keeps the
criteria finite. Greedy adds the candidate that improves the criterion most; exchange then swaps
a chosen pose for an unchosen one while that improves it (Fedorov's exchange).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from parakin.calibration.data import CalibrationData
from parakin.calibration.fit import Problem
from parakin.calibration.identifiability import observability, thin_svd
from parakin.errors import CalibrationDataError
from parakin.mechanism import Mechanism
from parakin.results import Array

CRITERIA = ("O1", "D", "E")
#: the regularisation of M before it is full rank, relative to trace(M_all) / n_free
REGULARISATION = 1e-9
#: exchange passes at most
MAX_PASSES = 20


@dataclass(frozen=True)
class PoseDesign:
    """The chosen poses.

    Attributes
    ----------
    indices : (n,) int
        Indices into the candidates.
    poses : (n, 4, 4)
        ^B_P T of the chosen poses.
    actuated : (n, n_a)
        The nominal model's actuated joints there (the branch asked for).
    criterion : str
    value : float
        The criterion of the chosen set (without regularisation where it is full rank).
    greedy_value : float
        The criterion after the greedy pass, before exchange.
    observability : dict
        O1..O5 of the chosen set (``parakin.calibration.identifiability``; columns scaled by
        their norms over all eligible candidates).
    rank : int
        Rank of the chosen set's Jacobian (column-scaled, relative 1e-8).
    eligible : int
        Candidates that were reachable on the branch and outside the singularity margin.
    """

    indices: NDArray[np.intp]
    poses: Array
    actuated: Array
    criterion: str
    value: float
    greedy_value: float
    observability: dict[str, float]
    rank: int
    eligible: int


def _criterion(information: Array, name: str, count: int, eps: float) -> Array:
    """The criterion (batched over leading axes) of information matrices (..., n, n)."""
    eigen = np.linalg.eigvalsh(information + eps * np.eye(information.shape[-1]))
    eigen = np.maximum(eigen, 1e-300)
    if name == "E":
        return np.asarray(eigen[..., 0])
    if name == "D":
        return np.asarray(np.sum(np.log(eigen), axis=-1))
    return np.asarray(np.exp(0.5 * np.mean(np.log(eigen), axis=-1)) / np.sqrt(max(count, 1)))


def _scores(information: Array, rows: Array, name: str, count: int, eps: float) -> Array:
    """The criterion of information + rows_k^T rows_k for every candidate k (rows (K, s, n)):
    log det by the matrix determinant lemma, log det(M + R^T R) = log det M + log det(I + R M^-1
    R^T), for D and O1 (s x s determinants instead of n x n); eigenvalues for E."""
    if name == "E":
        return _criterion(information + np.einsum("kri,krj->kij", rows, rows), name, count, eps)
    regular = information + eps * np.eye(information.shape[-1])
    _, base = np.linalg.slogdet(regular)
    inverse = np.linalg.inv(regular)
    small = np.eye(rows.shape[1]) + rows @ inverse @ np.swapaxes(rows, 1, 2)
    logdet = base + np.linalg.slogdet(small)[1]
    if name == "D":
        return np.asarray(logdet)
    return np.asarray(np.exp(0.5 * logdet / information.shape[-1]) / np.sqrt(max(count, 1)))


def _reciprocal_condition(matrix: Array) -> Array:
    singular = np.linalg.svd(matrix, compute_uv=False)
    return np.asarray(singular[..., -1] / np.maximum(singular[..., 0], 1e-300))


def design_poses(
    m: Mechanism,
    candidates: ArrayLike,
    n: int,
    criterion: str = "O1",
    *,
    kind: str = "pose",
    sigma: float | Sequence[float] = 1.0,
    free: Sequence[str] | None = None,
    fixed: Sequence[str] = (),
    unknown: Sequence[str] = (),
    tracker: ArrayLike | None = None,
    tool: ArrayLike | None = None,
    branch: int = 0,
    margin: float = 1e-3,
    exchange: bool = True,
) -> PoseDesign:
    """Choose ``n`` of ``candidates`` to measure for calibrating ``m`` (module docstring).

    Parameters
    ----------
    m : Mechanism
        The nominal model.
    candidates : array_like (N, 4, 4) or the pose kind's short form
        Poses ^B_P T to choose from (e.g. a grid or random sample of the workspace).
    n : int
        How many to choose (at most the eligible candidates).
    criterion : str
        ``"O1"``, ``"D"`` or ``"E"``.
    kind, sigma, unknown, tracker, tool
        The measurement planned (``CalibrationData``).
    free, fixed : sequence of str
        The parameters to identify (``calibrate``'s default when None).
    branch : int
        The inverse branch the robot works in.
    margin : float
        The reciprocal condition numbers of the loop closure's passive Jacobian (type II) and
        actuated Jacobian (serial) must exceed it; closer candidates are not eligible.
    exchange : bool
        Improve the greedy choice by exchange.

    Returns
    -------
    PoseDesign
        The chosen candidates' indices, poses and actuated joints (what to command), the
        criterion's value after the greedy pass and after exchange, and the chosen set's rank and
        observability indices.

    Raises
    ------
    CalibrationDataError
        An unknown criterion, n < 1 or more than the eligible candidates, a branch the inverse
        does not have, candidates that are not a batch, or a measurement (``kind``, ``sigma``,
        frames) that ``CalibrationData`` refuses.
    BadInputError
        Candidates that are not poses of the mechanism's kind, or an unknown name in ``free`` or
        ``fixed`` (the message suggests the closest names).

    Examples
    --------
    Where to measure a delta's platform with a tracker: 8 of 200 random points within 0.1 m of
    home, D-optimal for its parameters and encoder offsets:

    >>> import numpy as np, parakin
    >>> from parakin.calibration import design_poses
    >>> m = parakin.load("delta", backend="numpy")
    >>> candidates = m.home_passive + np.random.default_rng(1).uniform(-0.1, 0.1, (200, 3))
    >>> design = design_poses(m, candidates, 8, criterion="D", kind="position", sigma=20e-6)
    >>> design.eligible, design.rank, design.actuated.shape  # rank 6 of 7: R + r is one direction
    (200, 6, (8, 3))
    >>> bool(design.value >= design.greedy_value)  # exchange never loses what greedy found
    True
    >>> design_poses(m, candidates, 8, criterion="A", kind="position")
    Traceback (most recent call last):
    ...
    parakin.errors.CalibrationDataError: criterion must be one of ('O1', 'D', 'E'), got 'A'
    """
    if criterion not in CRITERIA:
        raise CalibrationDataError(f"criterion must be one of {CRITERIA}, got {criterion!r}")
    inverse = m.inverse_pose(candidates, strict=False)
    if inverse.actuated.ndim != 3:
        raise CalibrationDataError(f"candidates must be a batch of poses (N, ...), got shape {inverse.pose.shape}")
    if not 0 <= branch < inverse.actuated.shape[1]:
        raise CalibrationDataError(f"branch must be in [0, {inverse.actuated.shape[1]}), got {branch}")
    valid = np.asarray(inverse.valid[:, branch])
    theta, passive = inverse.actuated[:, branch], inverse.passive[:, branch]
    safe = np.where(valid[:, None], theta, m.home_actuated)
    safe_q = np.where(valid[:, None], passive, m.home_passive)
    with np.errstate(all="ignore"):
        closure = m.backend.call("loop_closure", safe, safe_q, m.params)["jacobian"]
        actuated = m.backend.call("loop_closure_actuated", safe, safe_q, m.params)["jacobian_actuated"]
        conditions = np.minimum(_reciprocal_condition(closure), _reciprocal_condition(actuated))
    eligible = np.flatnonzero(valid & (conditions > margin))
    if not isinstance(n, int | np.integer) or n < 1 or n > eligible.size:
        raise CalibrationDataError(
            f"n must be an integer in [1, {eligible.size}] (the candidates reachable on branch {branch} and "
            f"outside the singularity margin {margin:g}), got {n!r}"
        )
    poses = np.asarray(inverse.pose)[eligible]
    tracker_t = np.eye(4) if tracker is None else np.asarray(tracker, dtype=float)
    tool_t = np.eye(4) if tool is None else np.asarray(tool, dtype=float)
    seen = np.linalg.inv(tracker_t) @ poses @ tool_t
    measured = {
        "pose": seen,
        "position": seen[:, :3, 3],
        "z": seen[:, 2, 3],
        "distance": np.linalg.norm(seen[:, :3, 3], axis=1),
    }.get(kind, seen)
    data = CalibrationData(theta[eligible], measured, kind, sigma, tracker_t, tool_t, unknown, passive[eligible])
    problem = Problem(m, data, free, fixed, None)
    q = problem.close(problem.nominal, passive[eligible])
    jacobian = problem.evaluate(problem.nominal, q)[1]
    jacobian = jacobian.reshape(len(eligible), data.size, -1)
    scale = np.linalg.norm(jacobian.reshape(-1, jacobian.shape[-1]), axis=0)
    jacobian = jacobian / np.where(scale > 0, scale, 1.0)
    blocks = np.einsum("kri,krj->kij", jacobian, jacobian)  # each candidate's J^T J
    eps = REGULARISATION * float(np.trace(blocks.sum(0))) / blocks.shape[-1]
    chosen: list[int] = []
    information = np.zeros(blocks.shape[1:])
    for step in range(n):
        remaining = np.setdiff1d(np.arange(len(eligible)), chosen)
        scores = _scores(information, jacobian[remaining], criterion, step + 1, eps)
        best = int(remaining[int(np.argmax(scores))])
        chosen.append(best)
        information = information + blocks[best]
    greedy_value = float(_criterion(information, criterion, n, eps))
    value = greedy_value
    for _ in range(MAX_PASSES if exchange else 0):
        improved = False
        for slot in range(n):
            without = information - blocks[chosen[slot]]
            remaining = np.setdiff1d(np.arange(len(eligible)), chosen)
            if remaining.size == 0:
                break
            scores = _scores(without, jacobian[remaining], criterion, n, eps)
            best = int(np.argmax(scores))
            if scores[best] > value + 1e-12 * abs(value):
                chosen[slot] = int(remaining[best])
                information = without + blocks[chosen[slot]]
                value = float(scores[best])
                improved = True
        if not improved:
            break
    stacked = jacobian[chosen].reshape(-1, jacobian.shape[-1])
    singular = thin_svd(stacked)[1]
    rank = int(np.sum(singular > 1e-8 * singular[0]))
    picked = eligible[chosen]
    return PoseDesign(
        indices=picked,
        poses=poses[chosen],
        actuated=theta[picked],
        criterion=criterion,
        value=float(_criterion(information, criterion, n, 0.0 if rank == len(scale) else eps)),
        greedy_value=greedy_value,
        observability=observability(singular[:rank], n),
        rank=rank,
        eligible=int(eligible.size),
    )


__all__ = ["CRITERIA", "PoseDesign", "design_poses"]
