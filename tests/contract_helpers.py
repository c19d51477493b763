"""Helpers of the mechanism contract suite (tests/test_contract.py): everything is read from a
mechanism's typed manifest (variables, pose kind, capabilities, kernels, examples), never from
its name, so that a new generated package is tested as soon as it exists.
"""

from __future__ import annotations

import functools
import warnings
import weakref
import zlib

import numpy as np
import pytest

import parakin
from parakin.errors import CompiledUnavailableError
from parakin.mechanism import Mechanism
from parakin.pose import pose_vector

BACKENDS = ("numpy", "casadi", "compiled")

#: dimension of the platform's pose space per manifest pose kind
POSE_DIMENSIONS = {"transform": 6, "rotation": 3, "planar": 3, "translation": 3, "planar_translation": 2}

#: twist components a rate model may name (capabilities.rates.twist), in the (v, w) order
TWIST_COMPONENTS = ("vx", "vy", "vz", "wx", "wy", "wz")

#: loop-closure residual of a closed configuration (the manifest's own closure tolerance is 1e-9)
CLOSURE = 1e-9


def seed(*parts: object) -> int:
    """A reproducible seed from the test's identity (mechanism name, test name, backend)."""
    return zlib.crc32("/".join(str(p) for p in parts).encode())


# ---------------------------------------------------------------------------- loading
@functools.cache
def usable_parameters(name: str) -> tuple[tuple[str, float], ...]:
    """The default parameters, or, when the defaults are architecturally singular (singular at
    every pose: a self-motion everywhere), a deterministic small perturbation of every scalar
    parameter (5 % of its size, or of the median parameter size for zeros) that is not."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        m = parakin.load(name, backend="numpy")
        if not m.is_architecturally_singular():
            return ()
        rng = np.random.default_rng(seed(name, "architecture"))
        values = dict(m.parameters)
        sizes = [abs(v) for v in values.values() if v != 0.0]
        typical = float(np.median(sizes)) if sizes else 1.0
        for _ in range(50):
            trial = {k: v + 0.05 * max(abs(v), typical) * rng.uniform(-1, 1) for k, v in values.items()}
            if not parakin.load(name, backend="numpy", **trial).is_architecturally_singular():
                return tuple(trial.items())
    raise AssertionError(f"{name}: no non-singular geometry within 5 % of the defaults")


def load(name: str, backend: str) -> Mechanism:
    """A mechanism on ``backend`` with usable parameters; the test is skipped where the
    compiled backend has no working C compiler."""
    try:
        return _load(name, backend)
    except CompiledUnavailableError as error:
        pytest.skip(f"backend 'compiled' unavailable: {error}")


@functools.cache
def _load(name: str, backend: str) -> Mechanism:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        return parakin.load(name, backend=backend, **dict(usable_parameters(name)))


def dof(m: Mechanism) -> int:
    return len(m.manifest.actuated)


def full_dof(m: Mechanism) -> bool:
    """Whether the actuators determine every pose coordinate of the pose kind (a 2R pointing
    chain in a 'rotation' pose space does not: its inverse reads only the pointing axis)."""
    return dof(m) == POSE_DIMENSIONS[m.manifest.pose_kind]


# ---------------------------------------------------------------------------- rotations and angles
def skew(w: np.ndarray) -> np.ndarray:
    x, y, z = w
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def exp_so3(w: np.ndarray) -> np.ndarray:
    """Rodrigues: the rotation by |w| about w / |w|."""
    angle = float(np.linalg.norm(w))
    if angle == 0.0:
        return np.eye(3)
    k = skew(np.asarray(w, dtype=float) / angle)
    return np.eye(3) + np.sin(angle) * k + (1.0 - np.cos(angle)) * k @ k


def log_so3(rotation: np.ndarray) -> np.ndarray:
    """The rotation vector of R (|angle| < pi)."""
    cosine = np.clip((np.trace(rotation) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(cosine)
    axis = np.array([rotation[2, 1] - rotation[1, 2], rotation[0, 2] - rotation[2, 0], rotation[1, 0] - rotation[0, 1]])
    factor = 0.5 if angle < 1e-8 else angle / (2.0 * np.sin(angle))
    return factor * axis


def wrapped(difference: np.ndarray, revolute: np.ndarray) -> np.ndarray:
    """Differences of joint values, angles taken modulo 2 pi into (-pi, pi]."""
    return np.where(revolute, (difference + np.pi) % (2 * np.pi) - np.pi, difference)


def revolute_actuated(m: Mechanism) -> np.ndarray:
    return np.array([v.revolute for v in m.manifest.actuated], dtype=bool)


def revolute_passive(m: Mechanism) -> np.ndarray:
    return np.array([v.revolute for v in m.manifest.passive], dtype=bool)


def is_rigid(pose: np.ndarray, tolerance: float = 1e-9) -> bool:
    rotation = pose[:3, :3]
    return bool(
        np.isfinite(pose).all()
        and np.abs(rotation.T @ rotation - np.eye(3)).max() < tolerance
        and np.linalg.det(rotation) > 0
        and np.abs(pose[3] - [0, 0, 0, 1]).max() < tolerance
    )


# ---------------------------------------------------------------------------- scales
def length_scale(m: Mechanism) -> float:
    """A characteristic length: the home platform distance from {B}, else the largest home
    value of a length (a quaternion's unit components are not lengths), else 1 (metres)."""
    position = float(np.linalg.norm(home_pose(m)[:3, 3]))
    lengths = [abs(v.home or 0.0) for v in (*m.manifest.actuated, *m.manifest.passive) if v.kind == "prismatic"]
    return max(position, *lengths, 0.0) or 1.0


def variable_scale(m: Mechanism, variables) -> np.ndarray:
    """Per variable: 1 rad for revolute joints, 1 for dimensionless ones (quaternion components),
    the length scale for prismatic ones."""
    scale = length_scale(m)
    return np.array([scale if v.kind == "prismatic" else 1.0 for v in variables], dtype=float)


def pose_tolerance(m: Mechanism, pose_a: np.ndarray, pose_b: np.ndarray) -> np.ndarray:
    """Max deviation of two poses: rotation entries, and positions relative to the length scale."""
    rotation = np.abs(pose_a[..., :3, :3] - pose_b[..., :3, :3]).max(axis=(-2, -1))
    position = np.abs(pose_a[..., :3, 3] - pose_b[..., :3, 3]).max(-1) / length_scale(m)
    return np.maximum(rotation, position)


# ---------------------------------------------------------------------------- configurations
_HOME_POSES: weakref.WeakKeyDictionary[Mechanism, np.ndarray] = weakref.WeakKeyDictionary()


def home_pose(m: Mechanism) -> np.ndarray:
    """^B_P T at the manifest's home configuration: ``m.platform_pose(home)``, or, where the home
    values are only a Newton seed that does not close the loop (so the chain formula is not a
    rigid pose there), the pose Newton closes from them."""
    if m not in _HOME_POSES:
        try:
            pose = m.platform_pose(m.home_actuated, m.home_passive)
        except parakin.InconsistentInputError:  # not closed and not rigid: refused (issue 18 item 6)
            pose = None
        if pose is None or not is_rigid(pose):
            closed = m.forward_pose(m.home_actuated, guess=m.home_passive, strict=False)
            assert closed.converged, f"{m.name}: the home configuration is no rigid pose and Newton does not close it"
            pose = closed.pose
        _HOME_POSES[m] = pose
    return _HOME_POSES[m].copy()


def perturb_pose(m: Mechanism, pose: np.ndarray, rng: np.random.Generator, size: float = 1.0) -> np.ndarray:
    """A random pose near ``pose`` that respects the pose kind: a rotation of about
    ``0.1 size`` rad and a translation of about ``0.03 size`` length scales."""
    kind = m.manifest.pose_kind
    out = pose.copy()
    angle, shift = 0.1 * size, 0.03 * size * length_scale(m)
    if kind in ("transform", "rotation"):
        out[:3, :3] = exp_so3(rng.normal(scale=angle / np.sqrt(3), size=3)) @ pose[:3, :3]
    elif kind == "planar":
        out[:3, :3] = exp_so3(np.array([0.0, 0.0, rng.normal(scale=angle)])) @ pose[:3, :3]
    if kind in ("transform", "translation"):
        out[:3, 3] += rng.normal(scale=shift / np.sqrt(3), size=3)
    elif kind in ("planar", "planar_translation"):
        out[:2, 3] += rng.normal(scale=shift / np.sqrt(2), size=2)
    elif kind != "rotation":
        raise AssertionError(f"{m.name}: unknown pose kind {kind!r}")
    return out


def perturb_actuated(m: Mechanism, actuated: np.ndarray, rng: np.random.Generator, size: float = 1.0) -> np.ndarray:
    """Actuated values near ``actuated``: 0.1 size rad, 0.03 size length scales, reflected into
    each actuator's declared range (a leg length stays >= 0, a crank inside its range: outside it
    is no input at all). A range bounded on both sides folds the values back and forth into it."""
    scale = variable_scale(m, m.manifest.actuated) * np.where(revolute_actuated(m), 0.1, 0.03)
    values = actuated + size * rng.normal(size=actuated.shape) * scale
    low = np.array([v.limits[0] for v in m.manifest.actuated])
    high = np.array([v.limits[1] for v in m.manifest.actuated])
    values = np.where(values < low, 2 * low - values, values)
    bounded = np.isfinite(low) & np.isfinite(high)
    width = np.where(bounded, high - low, 1.0)
    above = np.where(bounded, values, 0.0) - np.where(bounded, low, 0.0)
    folded = np.abs((above + width) % (2 * width) - width)  # distance from low, folded
    return np.where(bounded, low + folded, values)


def sample_poses(m: Mechanism, rng: np.random.Generator, count: int) -> tuple[np.ndarray, np.ndarray | None]:
    """(count, 4, 4) poses near the home pose, and the actuated values they came from (or None).

    A mechanism whose actuators span its pose space gets perturbed poses (rotation and
    translation as the pose kind allows). One with fewer actuators (a 2R pointing chain in a
    'rotation' pose space) can reach only a submanifold: it gets the poses of perturbed
    actuated values (forward pose from home), returned with those values."""
    home = home_pose(m)
    if full_dof(m):
        return np.stack([perturb_pose(m, home, rng) for _ in range(count)]), None
    actuated = np.stack([perturb_actuated(m, m.home_actuated, rng) for _ in range(count)])
    fk = m.forward_pose(actuated, guess=m.home_passive, strict=False)
    assert fk.converged.all(), f"{m.name}: forward pose from home did not converge near home"
    return fk.pose, actuated


def twist_components(m: Mechanism) -> list[int]:
    """Indices into (vx, vy, vz, wx, wy, wz) of the mechanism's twist (rate model names, or all
    six for leg Jacobians)."""
    rates = m.capabilities.rates
    if rates is None:
        return list(range(6))
    unknown = [n for n in rates.twist if n not in TWIST_COMPONENTS]
    assert not unknown, f"{m.name}: twist components {unknown} are not among {TWIST_COMPONENTS}"
    return [TWIST_COMPONENTS.index(n) for n in rates.twist]


def finite_difference_twist(pose_minus: np.ndarray, pose_plus: np.ndarray, step: float) -> np.ndarray:
    """Central difference (v of the origin of {P}, w), both in {B}: v = dp/dt and
    [w] = dR/dt R^T, from the poses at -step and +step."""
    v = (pose_plus[:3, 3] - pose_minus[:3, 3]) / (2 * step)
    w = log_so3(pose_plus[:3, :3] @ pose_minus[:3, :3].T) / (2 * step)
    return np.concatenate([v, w])


def move_pose(pose: np.ndarray, twist6: np.ndarray, t: float) -> np.ndarray:
    """The pose after moving for time t with the constant twist (v of the origin of {P}, w in {B})."""
    out = pose.copy()
    out[:3, :3] = exp_so3(t * twist6[3:]) @ pose[:3, :3]
    out[:3, 3] = pose[:3, 3] + t * twist6[:3]
    return out


# ---------------------------------------------------------------------------- kernel inputs
def kernel_inputs(m: Mechanism, kernel: str, rng: np.random.Generator, batch: int) -> list[np.ndarray]:
    """Random inputs of a generated kernel with the manifest's input sizes: joint values near
    home, the mechanism's parameters, sampled poses, branch signs, roots; uniform otherwise."""
    inputs = []
    for io in m.manifest.kernels[kernel].inputs:
        size = io.shape[0]
        if io.name == "params":
            assert size == m.params.size, f"{m.name}.{kernel}: params size {size} != {m.params.size}"
            value = np.broadcast_to(m.params, (batch, size)).copy()
        elif io.name == "actuated" and size == len(m.manifest.actuated):
            value = np.stack([perturb_actuated(m, m.home_actuated, rng, 3.0) for _ in range(batch)])
        elif io.name == "passive" and size == len(m.manifest.passive):
            scale = variable_scale(m, m.manifest.passive) * np.where(revolute_passive(m), 0.3, 0.1)
            value = m.home_passive + rng.normal(size=(batch, size)) * scale
        elif io.name == "pose" and size == 12:
            value = pose_vector(np.stack([perturb_pose(m, home_pose(m), rng, 3.0) for _ in range(batch)]))
        elif io.name == "branch":
            value = rng.choice([-1.0, 1.0], size=(batch, size))
        elif io.name == "root":
            value = rng.uniform(-3, 3, size=(batch, size))
        else:
            value = rng.uniform(-1, 1, size=(batch, size))
        inputs.append(np.ascontiguousarray(value, dtype=float))
    return inputs


# ---------------------------------------------------------------------------- conditioning
def scaled_closure_jacobian(m: Mechanism, actuated: np.ndarray, passive: np.ndarray) -> np.ndarray:
    """The loop closure's passive Jacobian with passive columns in scaled units (rad, length scales)."""
    return m.loop_closure(actuated, passive)["jacobian"] * variable_scale(m, m.manifest.passive)


def condition(m: Mechanism, actuated: np.ndarray, passive: np.ndarray) -> np.ndarray:
    """Condition number of the scaled loop-closure Jacobian (1 with no passive variables):
    large near a type II singularity, where forward quantities lose accuracy."""
    if not m.manifest.passive:
        return np.ones(np.shape(actuated)[:-1])
    values = np.linalg.svd(scaled_closure_jacobian(m, actuated, passive), compute_uv=False)
    return values[..., 0] / values[..., -1]


def newton_tolerance(
    m: Mechanism, actuated: np.ndarray, passive: np.ndarray, residual: float, base: float = 1e-9
) -> np.ndarray:
    """How far (scaled passive units) a configuration whose loop residual is at most ``residual``
    (max-norm) may lie from the exact one: base + 10 ||J_s^-1|| sqrt(n) residual, the forward
    error bound of a backward error ``residual`` (generous near a type II singularity)."""
    if not m.manifest.passive:
        return np.full(np.shape(actuated)[:-1], base)
    values = np.linalg.svd(scaled_closure_jacobian(m, actuated, passive), compute_uv=False)
    return base + 10.0 * np.sqrt(values.shape[-1]) * residual / values[..., -1]


def feasible_twist(m: Mechanism, state, twist: np.ndarray) -> np.ndarray:
    """``twist`` itself, or for a lower-mobility platform (a rate model with constraint wrenches
    C) its projection on the motions it can make, C twist = 0 (least-squares, per batch entry)."""
    rates = m.capabilities.rates
    if rates is None or not rates.constraints:
        return twist
    c = np.asarray(m.rate_jacobians(state)["constraints"])
    gram = c @ np.swapaxes(c, -1, -2)
    along = np.linalg.solve(gram, (c @ twist[..., None]))
    return twist - (np.swapaxes(c, -1, -2) @ along)[..., 0]
