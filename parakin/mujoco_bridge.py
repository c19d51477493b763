"""A bridge between parakin and MuJoCo for closed-chain models: the actuator forces of
``mj_inverse`` projected onto the actuated joints, the pose a simulation settles in, and the
parakin assembly mode nearest a MuJoCo state. Generic over MJCF models; needs the ``mujoco``
module (extra ``[sim]``).

Conventions:

* A closed chain in MJCF is a tree of bodies whose loops are cut by ``<connect site1=... site2=...>``
  equality constraints (the site form: the two sites coincide when the loop is closed). Every
  active equality constraint of the model must be such a connect (``closed_chain`` refuses others).
* ``actuated``: the names of the hinge or slide joints that carry parakin's actuated variables, in
  parakin's order, their positions equal to parakin's actuated values (same origin, sign and unit:
  radians, metres). ``platform_site``: a site on the platform whose frame is parakin's {P}.
* The loop Jacobian J (3 k, nv) stacks J_site1 - J_site2 of the k connects (translational,
  in the world frame). Closed-chain velocities are qvel = Gamma q_dot_a with J Gamma = 0 and
  Gamma's actuated rows the identity: the actuated joints parametrise the chain
  (``actuated_basis``). Consistent accelerations satisfy J qacc + J_dot qvel = 0, J_dot qvel from
  ``mj_jacDot`` (exact, no finite differences).
* Projected inverse: ``mj_inverse`` gives the generalised forces qfrc_inverse (nv) that produce
  qacc with the constraint forces J^T lambda it computes removed; the efforts at the actuated
  joints that produce the same motion of the closed chain are tau = Gamma^T qfrc_inverse (the
  principle of virtual power: the loops' forces J^T lambda do no work on closed-chain motions,
  Gamma^T J^T = 0).

Example
-------
The five-bar as ``parakin.mjcf.to_mjcf`` writes it (1 kg links and platform; the function
Examples below continue from here):

>>> import mujoco
>>> import numpy as np
>>> import parakin
>>> from parakin import mujoco_bridge as bridge
>>> m = parakin.load("five_bar", backend="numpy")
>>> model = mujoco.MjModel.from_xml_string(m.to_mjcf())
>>> chain = bridge.closed_chain(model, ["theta1", "theta2"], "platform")
>>> data = mujoco.MjData(model)
>>> q, rates, accelerations = m.home_actuated + 0.1, np.array([0.3, -0.2]), np.array([0.0, 1.0])
>>> bridge.assemble(chain, data, q, rates, accelerations) < 1e-12
True
>>> bridge.projected_inverse(chain, data).round(4)  # actuator torques, N m
array([-4.2653,  3.6973])
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from parakin.errors import (
    BadInputError,
    ConvergenceError,
    NoSuchModeError,
    SingularConfigurationError,
    UnsupportedOperationError,
)
from parakin.pose import LEG_TWIST
from parakin.results import Array, Configuration

if TYPE_CHECKING:
    from parakin.solvers.loaded import LoadedMechanism as Mechanism

#: a loop Jacobian's singular values below this ratio of the largest are rank-deficient
RANK_RATIO = 1e-10


def _mujoco() -> Any:
    try:
        import mujoco
    except ImportError as error:
        raise UnsupportedOperationError(
            f"the MuJoCo bridge needs the mujoco module (pip install 'parakin[sim]'): {error}"
        ) from error
    return mujoco


@dataclass(frozen=True)
class ClosedChain:
    """A MuJoCo model read as a closed chain (``closed_chain``): ``actuated`` joint names,
    ``actuated_dofs`` / ``actuated_qpos`` their dof and qpos addresses, ``passive_dofs`` every
    other dof, ``connects`` (site1, site2) ids of the loop cuts, ``platform_site`` its id."""

    model: Any
    actuated: tuple[str, ...]
    actuated_dofs: NDArray[np.intp]
    actuated_qpos: NDArray[np.intp]
    passive_dofs: NDArray[np.intp]
    connects: tuple[tuple[int, int], ...]
    platform_site: int


def closed_chain(model: Any, actuated: Sequence[str], platform_site: str) -> ClosedChain:
    """Read ``model`` as a closed chain.

    Parameters
    ----------
    model : mujoco.MjModel
        A model whose loops are cut by site-form connect constraints.
    actuated : sequence of str
        The hinge or slide joints of parakin's actuated variables, in parakin's order.
    platform_site : str
        A site whose frame is the platform frame {P}.

    Returns
    -------
    ClosedChain

    Raises
    ------
    BadInputError
        An unknown joint or site name, a repeated joint, a joint that is not a hinge or a slide.
    UnsupportedOperationError
        An active equality constraint that is not a site-form connect (body/anchor connects, welds,
        joint or tendon equalities), or a model without any.

    Examples
    --------
    >>> chain = bridge.closed_chain(model, ["theta1", "theta2"], "platform")
    >>> chain.actuated_dofs, chain.passive_dofs
    (array([0, 2]), array([1, 3]))
    """
    mujoco = _mujoco()
    names = tuple(str(name) for name in actuated)
    if len(set(names)) != len(names):
        raise BadInputError(f"actuated joints repeat a name: {list(names)}")
    dofs, qpos = [], []
    for name in names:
        joint = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, name)
        if joint < 0:
            known = [model.joint(j).name for j in range(model.njnt)]
            raise BadInputError(f"actuated joint {name!r} is not in the model (joints: {known})")
        if int(model.jnt_type[joint]) not in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)):
            raise BadInputError(f"actuated joint {name!r} must be a hinge or a slide (one dof)")
        dofs.append(int(model.jnt_dofadr[joint]))
        qpos.append(int(model.jnt_qposadr[joint]))
    site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, platform_site)
    if site < 0:
        known = [model.site(s).name for s in range(model.nsite)]
        raise BadInputError(f"platform site {platform_site!r} is not in the model (sites: {known})")
    connects = []
    for index in range(model.neq):
        if not model.eq_active0[index]:
            continue
        connect = int(model.eq_type[index]) == int(mujoco.mjtEq.mjEQ_CONNECT)
        if not connect or int(model.eq_objtype[index]) != int(mujoco.mjtObj.mjOBJ_SITE):
            raise UnsupportedOperationError(
                f"equality constraint {index} ({model.eq(index).name or 'unnamed'}) is not a connect in its "
                "site1/site2 form: only those cut the loops here (an anchor connect closes off its reference pose)"
            )
        connects.append((int(model.eq_obj1id[index]), int(model.eq_obj2id[index])))
    if not connects:
        raise UnsupportedOperationError("the model has no active connect constraint: it is not a closed chain")
    passive = np.setdiff1d(np.arange(model.nv), dofs)
    return ClosedChain(
        model, names, np.array(dofs, dtype=np.intp), np.array(qpos, dtype=np.intp), passive, tuple(connects), site
    )


def _positions(chain: ClosedChain, data: Any) -> None:
    mujoco = _mujoco()
    mujoco.mj_kinematics(chain.model, data)
    mujoco.mj_comPos(chain.model, data)


def loop_residual(chain: ClosedChain, data: Any) -> Array:
    """site1 - site2 positions (3 k,) of the k connects at ``data.qpos`` (m, world frame).

    Parameters
    ----------
    chain : ClosedChain
    data : mujoco.MjData
        Its qpos is read (positions recomputed: ``mj_kinematics``).

    Returns
    -------
    ndarray (3 k,)
        m, in the world frame {B}.

    Raises
    ------
    UnsupportedOperationError
        Without the mujoco module.

    Examples
    --------
    >>> float(np.abs(bridge.loop_residual(chain, data)).max()) < 1e-12  # closed once assembled
    True
    """
    _positions(chain, data)
    return np.concatenate([data.site_xpos[a] - data.site_xpos[b] for a, b in chain.connects])


def loop_jacobian(chain: ClosedChain, data: Any) -> Array:
    """J (3 k, nv): d(site1 - site2)/dqvel of the connects at ``data.qpos`` (world frame).

    Parameters
    ----------
    chain : ClosedChain
    data : mujoco.MjData
        Its qpos is read.

    Returns
    -------
    ndarray (3 k, nv)
        m per unit of each dof's velocity (rad/s, m/s), world frame.

    Raises
    ------
    UnsupportedOperationError
        Without the mujoco module.

    Examples
    --------
    >>> int(model.nv - np.linalg.matrix_rank(bridge.loop_jacobian(chain, data), tol=1e-9))  # the mobility
    2
    """
    mujoco = _mujoco()
    _positions(chain, data)
    rows = []
    for a, b in chain.connects:
        ja, jb = np.zeros((3, chain.model.nv)), np.zeros((3, chain.model.nv))
        mujoco.mj_jacSite(chain.model, data, ja, None, a)
        mujoco.mj_jacSite(chain.model, data, jb, None, b)
        rows.append(ja - jb)
    return np.concatenate(rows)


def loop_bias(chain: ClosedChain, data: Any) -> Array:
    """J_dot qvel (3 k,) at ``data.qpos``, ``data.qvel`` (``mj_jacDot``; m/s^2).

    Parameters
    ----------
    chain : ClosedChain
    data : mujoco.MjData
        Its qpos and qvel are read.

    Returns
    -------
    ndarray (3 k,)
        m/s^2, world frame: the connects' relative acceleration at qacc = 0.

    Raises
    ------
    UnsupportedOperationError
        Without the mujoco module.

    Examples
    --------
    >>> bridge.loop_bias(chain, data).shape  # two connects (the revolute cut)
    (6,)
    """
    mujoco = _mujoco()
    _positions(chain, data)
    mujoco.mj_comVel(chain.model, data)
    rows = []
    for a, b in chain.connects:
        out = []
        for site in (a, b):
            jdot = np.zeros((3, chain.model.nv))
            body = int(chain.model.site_bodyid[site])
            mujoco.mj_jacDot(chain.model, data, jdot, None, data.site_xpos[site].reshape(3, 1), body)
            out.append(jdot @ data.qvel)
        rows.append(out[0] - out[1])
    return np.concatenate(rows)


def _passive_solve(chain: ClosedChain, jacobian: Array, right: Array, what: str) -> Array:
    """x with J[:, passive] x = right, least squares over the loop rows (some are dependent:
    a planar loop's out-of-plane rows vanish); SingularConfigurationError when the passive
    columns do not have full rank (the actuated joints do not fix the chain)."""
    passive = jacobian[:, chain.passive_dofs]
    sigma = np.linalg.svd(passive, compute_uv=False)
    if sigma.size and not sigma[-1] > RANK_RATIO * max(sigma[0], 1e-300):
        raise SingularConfigurationError(
            f"{what}: the loop Jacobian's passive columns have rank < {passive.shape[1]} (smallest singular value "
            f"{sigma[-1]:.3g} of {sigma[0]:.3g}): the actuated joints do not determine the chain here (a "
            "type II singularity, or a model whose passive joints move without them)"
        )
    solution, *_ = np.linalg.lstsq(passive, right, rcond=None)
    return np.asarray(solution, dtype=np.float64)


def actuated_basis(chain: ClosedChain, data: Any) -> Array:
    """Gamma (nv, n_a): closed-chain velocities qvel = Gamma q_dot_a at ``data.qpos``.

    Parameters
    ----------
    chain : ClosedChain
    data : mujoco.MjData
        Its qpos is read (a closed configuration).

    Returns
    -------
    ndarray (nv, n_a)
        Its actuated rows the identity, J Gamma = 0.

    Raises
    ------
    SingularConfigurationError
        Where the actuated joints do not determine the chain, and also where they cannot move
        independently (J Gamma != 0: fewer degrees of freedom than actuated joints).

    Examples
    --------
    >>> gamma = bridge.actuated_basis(chain, data)
    >>> np.abs(gamma @ rates - data.qvel).max() < 1e-12  # what assemble set
    np.True_
    """
    jacobian = loop_jacobian(chain, data)
    actuated = jacobian[:, chain.actuated_dofs]
    gamma = np.zeros((chain.model.nv, len(chain.actuated)))
    gamma[chain.actuated_dofs] = np.eye(len(chain.actuated))
    gamma[chain.passive_dofs] = _passive_solve(chain, jacobian, -actuated, "actuated_basis")
    left = np.abs(jacobian @ gamma).max(initial=0.0)
    if left > 1e-9 * max(np.abs(jacobian).max(initial=0.0), 1e-300):
        raise SingularConfigurationError(
            f"the actuated joints {list(chain.actuated)} cannot move independently here (|J Gamma| = {left:.3g}): "
            "the chain has fewer degrees of freedom than actuated joints"
        )
    return gamma


def assemble(
    chain: ClosedChain,
    data: Any,
    actuated: ArrayLike,
    rates: ArrayLike | None = None,
    accelerations: ArrayLike | None = None,
    tolerance: float = 1e-12,
    max_iterations: int = 50,
) -> float:
    """Close the loops at the actuated positions given and set consistent velocities and
    accelerations: Newton on the passive joints from ``data.qpos`` (which selects the assembly
    mode), then qvel = Gamma q_dot_a and qacc with J qacc = -J_dot qvel.

    Parameters
    ----------
    chain : ClosedChain
    data : mujoco.MjData
        Its qpos is the starting guess; qpos, qvel and qacc are written.
    actuated, rates, accelerations : array_like (n_a,)
        Actuated positions (rad, m), rates and accelerations (default zero).
    tolerance : float
        On the loop residual's max-norm (m).
    max_iterations : int

    Returns
    -------
    float
        The loop residual reached (m).

    Raises
    ------
    BadInputError
        Wrong shapes or non-finite values.
    ConvergenceError
        Newton did not close the loops (residual in the message).
    SingularConfigurationError
        The passive joints are not determined by the actuated ones.

    Examples
    --------
    >>> data = mujoco.MjData(model)  # qpos0 (the home) near the mode wanted
    >>> bridge.assemble(chain, data, m.home_actuated + 0.1, rates=[0.3, -0.2], accelerations=[0.0, 1.0]) < 1e-12
    True
    """
    mujoco = _mujoco()
    count = len(chain.actuated)
    values = [_vector(x, name, count) for x, name in ((actuated, "actuated"), (rates, "rates"))]
    values.append(_vector(accelerations, "accelerations", count))
    position, rate, acceleration = values
    model = chain.model
    data.qpos[chain.actuated_qpos] = position
    residual = np.inf
    for _ in range(max_iterations):
        gap = loop_residual(chain, data)
        residual = float(np.abs(gap).max())
        if residual <= tolerance:
            break
        jacobian = loop_jacobian(chain, data)
        step = np.zeros(model.nv)
        step[chain.passive_dofs] = -_passive_solve(chain, jacobian, gap, "assemble")
        mujoco.mj_integratePos(model, data.qpos, step, 1.0)
    else:
        raise ConvergenceError(
            f"assemble: the loops did not close in {max_iterations} Newton steps (residual {residual:.3g} m > "
            f"{tolerance:g} m); start data.qpos nearer an assembly",
            residual=residual,
        )
    gamma = actuated_basis(chain, data)
    data.qvel[:] = gamma @ rate
    jacobian = loop_jacobian(chain, data)
    bias = loop_bias(chain, data)
    qacc = np.zeros(model.nv)
    qacc[chain.actuated_dofs] = acceleration
    right = -(jacobian[:, chain.actuated_dofs] @ acceleration) - bias
    qacc[chain.passive_dofs] = _passive_solve(chain, jacobian, right, "assemble")
    data.qacc[:] = qacc
    return residual


def _vector(value: ArrayLike | None, name: str, count: int) -> Array:
    if value is None:
        return np.zeros(count)
    array = np.asarray(value, dtype=float)
    if array.shape != (count,) or not np.isfinite(array).all():
        raise BadInputError(f"{name} must be {count} finite numbers (one per actuated joint), got {value!r}")
    return array


def projected_inverse(chain: ClosedChain, data: Any) -> Array:
    """Actuator efforts tau (n_a,) (N m for a hinge, N for a slide) that move the closed chain
    with ``data.qpos``, ``qvel``, ``qacc`` (consistent: ``assemble``): Gamma^T qfrc_inverse of
    ``mj_inverse``.

    Parameters
    ----------
    chain : ClosedChain
    data : mujoco.MjData
        A closed state with consistent qvel and qacc (``assemble``).

    Returns
    -------
    ndarray (n_a,)
        Positive along increasing actuated values.

    Raises
    ------
    SingularConfigurationError
        As ``actuated_basis``.

    Examples
    --------
    >>> bridge.assemble(chain, data, q, rates, accelerations) < 1e-12
    True
    >>> bridge.projected_inverse(chain, data).round(4)
    array([-4.2653,  3.6973])
    """
    mujoco = _mujoco()
    mujoco.mj_inverse(chain.model, data)
    force = np.array(data.qfrc_inverse)
    gamma = actuated_basis(chain, data)
    return np.asarray(gamma.T @ force, dtype=np.float64)


def platform_pose(chain: ClosedChain, data: Any) -> Array:
    """^B_P T (4, 4) of the platform site at ``data.qpos`` (the world frame is {B}).

    Parameters
    ----------
    chain : ClosedChain
    data : mujoco.MjData
        Its qpos is read.

    Returns
    -------
    ndarray (4, 4)
        Rotation and position (m) of the platform site.

    Raises
    ------
    UnsupportedOperationError
        Without the mujoco module.

    Examples
    --------
    >>> bridge.platform_pose(chain, data)[:3, 3].round(4)  # the platform's origin, m
    array([-0.023 ,  0.3293,  0.    ])
    """
    _positions(chain, data)
    pose = np.eye(4)
    pose[:3, :3] = np.asarray(data.site_xmat[chain.platform_site]).reshape(3, 3)
    pose[:3, 3] = data.site_xpos[chain.platform_site]
    return pose


@dataclass(frozen=True)
class Settled:
    """Where a simulation came to rest: the platform ``pose`` (4, 4), the ``actuated`` joint
    positions (n_a,), the simulated ``time`` (s), the largest joint speed at the end
    (``speed``, rad/s or m/s) and whether it fell below the tolerance (``settled``)."""

    pose: Array
    actuated: Array
    time: float
    speed: float
    settled: bool


def settle(chain: ClosedChain, data: Any, duration: float = 5.0, speed: float = 1e-6) -> Settled:
    """Step the simulation (``mj_step``, the model's own integrator, timestep and controls)
    until every joint speed stays below ``speed`` for 0.1 s of simulated time, or ``duration``
    seconds pass.

    Parameters
    ----------
    chain : ClosedChain
    data : mujoco.MjData
        The state to start from (e.g. ``assemble`` d or a keyframe); advanced in place.
    duration : float
        The most simulated time (s).
    speed : float
        Joint-speed tolerance (rad/s, m/s).

    Returns
    -------
    Settled
        ``settled`` False when ``duration`` ran out (the pose is then where it stopped).

    Raises
    ------
    BadInputError
        A non-positive duration or speed.

    Examples
    --------
    >>> mujoco.mj_resetDataKeyframe(model, data, 1)  # assembly mode 1, servos holding the home
    >>> settled = bridge.settle(chain, data, duration=2.0)
    >>> settled.settled, settled.time < 2.0
    (True, True)
    """
    mujoco = _mujoco()
    if not (np.isfinite(duration) and duration > 0 and np.isfinite(speed) and speed > 0):
        raise BadInputError(f"duration ({duration!r} s) and speed ({speed!r}) must be finite and > 0")
    model = chain.model
    start, still_since = data.time, None
    fastest = np.inf
    # a step count, not the clock: MuJoCo resets a diverged simulation (time back to 0), so a
    # bound on data.time alone can loop for ever
    steps = int(np.ceil(duration / model.opt.timestep))
    diverged = int(data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number)
    for _ in range(steps):
        before = data.time
        mujoco.mj_step(model, data)
        fastest = float(np.abs(data.qvel).max(initial=0.0))
        reset = data.time < before or int(data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number) > diverged
        if not np.isfinite(fastest) or reset:
            raise ConvergenceError(
                f"settle: the simulation diverged at t = {before:.4g} s (MuJoCo reset it: non-finite accelerations); "
                "a smaller timestep or stiffer/softer constraints (accuracy preset) may help"
            )
        if fastest < speed:
            still_since = data.time if still_since is None else still_since
            if data.time - still_since >= 0.1:
                break
        else:
            still_since = None
    return Settled(
        platform_pose(chain, data),
        np.array(data.qpos[chain.actuated_qpos], dtype=float),
        float(data.time - start),
        fastest,
        fastest < speed,
    )


@dataclass(frozen=True)
class NearestMode:
    """The parakin assembly mode nearest a MuJoCo state: ``mode`` its number k
    (``m.forward_pose_all(actuated).mode(k)``), ``configuration`` that mode, ``position_error``
    (m) and ``angle_error`` (rad) between its pose and the platform site's; ``count`` the modes."""

    mode: int
    configuration: Configuration
    position_error: float
    angle_error: float
    count: int


def nearest_mode(m: Mechanism, chain: ClosedChain, data: Any, length: float = 1.0) -> NearestMode:
    """The assembly mode of ``m`` at the state's actuated values whose pose is nearest the
    platform site's: distance |dp| + ``length`` x angle (rotation compared only when the
    mechanism's platform rotates: its twist has angular components).

    Parameters
    ----------
    m : Mechanism
        The parakin model of the same mechanism (same actuated values, {B} the world frame).
    chain : ClosedChain
    data : mujoco.MjData
    length : float
        Metres per radian in the distance (m).

    Returns
    -------
    NearestMode

    Raises
    ------
    BadInputError
        ``m``'s actuated variables differ in number from the chain's.
    UnsupportedOperationError
        ``m`` has no all-modes solver; NoSuchModeError (a BadInputError) when it finds no mode.

    Examples
    --------
    >>> mujoco.mj_resetDataKeyframe(model, data, 1)
    >>> bridge.nearest_mode(m, chain, data).mode
    1
    """
    if len(m.actuated_names) != len(chain.actuated):
        raise BadInputError(
            f"{m.name} has {len(m.actuated_names)} actuated variables {m.actuated_names}, the chain "
            f"{len(chain.actuated)} joints {list(chain.actuated)}"
        )
    actuated = np.array(data.qpos[chain.actuated_qpos], dtype=float)
    pose = platform_pose(chain, data)
    modes = m.forward_pose_all(actuated)
    twist = m.manifest.capabilities.rates.twist if m.manifest.capabilities.rates is not None else LEG_TWIST
    rotates = any(name.startswith("w") for name in twist)
    best: tuple[float, int, float, float] | None = None
    for k in range(int(modes.count)):
        candidate = modes.mode(k).pose
        position = float(np.linalg.norm(candidate[:3, 3] - pose[:3, 3]))
        relative = candidate[:3, :3].T @ pose[:3, :3]
        angle = float(np.arccos(np.clip((np.trace(relative) - 1) / 2, -1.0, 1.0))) if rotates else 0.0
        distance = position + length * angle
        if best is None or distance < best[0]:
            best = (distance, k, position, angle)
    if best is None:
        raise NoSuchModeError(f"{m.name} has no assembly mode at the actuated values {actuated.tolist()}")
    _, k, position, angle = best
    return NearestMode(k, modes.mode(k), position, angle, int(modes.count))


__all__ = [
    "ClosedChain",
    "NearestMode",
    "Settled",
    "actuated_basis",
    "assemble",
    "closed_chain",
    "loop_bias",
    "loop_jacobian",
    "loop_residual",
    "nearest_mode",
    "platform_pose",
    "projected_inverse",
    "settle",
]
