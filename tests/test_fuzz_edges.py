"""Property-based edges of the contract: what the suite of ``test_fuzz.py`` did not ask (issue 18,
items 4-13), stated as properties over every mechanism x backend x public method.

* modes are indexed as modes (``mode(k)`` the k-th valid slot, ``slot(s)`` the raw slot, ``len``,
  iteration), and ``real`` means real;
* ``forward_pose`` without a guess converges wherever ``forward_pose_all`` finds modes;
* ``platform_pose`` answers a rigid transform or InconsistentInputError;
* ``stiffness`` validates its actuator stiffnesses;
* a pose the platform cannot take (an offset or a rotation along a direction the mechanism never
  moves, found from its forward poses, not from its pose kind) is refused;
* the forward solvers refuse what the inverse refuses (actuator strokes);
* sweeps: no sentinel values, every unswept variable can be fixed, bad fixed values refused;
* ``parakin.load`` and the CLI answer named errors and documented exit codes;
* manifest names and file lists cannot point outside the package folder.

Inputs come from the manifests (variables, kinds, capabilities) and from each mechanism's own
forward and inverse solutions; mechanisms are never named. The default run is small (well under a
minute); the tests marked slow check ten times as many inputs (``--run-slow``).
"""

from __future__ import annotations

import contextlib
import functools
import io
import json
import shutil
import warnings
from pathlib import Path

import contract_helpers as h
import numpy as np
import pytest
import test_fuzz as fz
from conftest import _heavy_families
from hypothesis import example, given
from hypothesis import strategies as st

import parakin
from parakin.errors import BadInputError, InconsistentInputError, ParakinError, UnknownMechanismError

NAMES, BACKENDS, CASES = fz.NAMES, fz.BACKENDS, fz.CASES
#: a reproduced pose / a closed loop, relative to the input sizes (looser than the contract's 1e-9:
#: the inputs here are solutions of other solves)
MATCH = 1e-6


@pytest.fixture(scope="module", autouse=True)
def _quiet():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        yield


def closure(m, actuated, passive) -> np.ndarray:
    """Max-norm loop residual per configuration (0 for a serial chain), in length scales."""
    if not m.passive_names:
        return np.zeros(np.shape(actuated)[:-1])
    residual = m.loop_closure(actuated, passive)["residual"]
    return np.abs(residual).max(-1) / h.length_scale(m)


def rigid(pose: np.ndarray, tolerance: float = 1e-9) -> np.ndarray:
    """Per pose (..., 4, 4): R^T R = I, det R = +1, last row (0, 0, 0, 1)."""
    rotation = pose[..., :3, :3]
    gram = np.einsum("...ji,...jk->...ik", rotation, rotation)
    with np.errstate(all="ignore"):
        return (
            (np.abs(gram - np.eye(3)).max(axis=(-2, -1)) < tolerance)
            & (np.abs(np.linalg.det(rotation) - 1.0) < tolerance)
            & (np.abs(pose[..., 3, :] - [0.0, 0.0, 0.0, 1.0]).max(-1) < tolerance)
        )


def first(mask: np.ndarray) -> tuple[int, ...]:
    """The first index where ``mask`` holds."""
    return tuple(int(i[0]) for i in np.nonzero(mask))


# ---------------------------------------------------------------------------- inputs from the solutions
@functools.cache
def motion(name: str) -> tuple[np.ndarray, np.ndarray, bool, bool]:
    """Where the platform goes, read from forward poses of actuated values near home (never from
    the pose kind): (reachable poses (k, 4, 4), translation axes of {B} it moves along (3,),
    whether it rotates, whether its rotations leave the z axis of {B} (out of the plane))."""
    m = h.load(name, "numpy")
    fx = fz.fixture(name)  # closed, well-conditioned configurations near home
    closed = (
        np.concatenate([fx.state.actuated[None], fx.states.actuated]),
        np.concatenate([fx.state.passive[None], fx.states.passive]),
    )
    rng = np.random.default_rng(h.seed(name, "motion"))
    actuated = np.stack([h.perturb_actuated(m, fx.state.actuated, rng, 0.3) for _ in range(40)])
    fk = m.forward_pose(actuated, guess=fx.state.passive if m.passive_names else None, strict=False)
    converged = np.asarray(fk.converged) & np.isfinite(fk.pose).all(axis=(-2, -1))
    # the poses of the configurations themselves (platform_pose), not the poses they were asked for
    poses = np.concatenate([m.platform_pose(*closed), fk.pose[converged]])
    assert poses.shape[0] >= 6, f"{name}: fewer than 6 poses near home"
    scale = h.length_scale(m)
    moves = np.ptp(poses[:, :3, 3], axis=0) > 1e-6 * scale
    rotates = bool(np.abs(poses[:, :3, :3] - poses[:1, :3, :3]).max() > 1e-6)
    out_of_plane = bool(np.abs(poses[:, 2, :3] - [0.0, 0.0, 1.0]).max() > 1e-6)
    return poses, moves, rotates, out_of_plane


def move_within(name: str, pose: np.ndarray, rng: np.random.Generator, size: float) -> np.ndarray:
    """``pose`` moved only along the directions the mechanism moves in (``motion``): about
    ``0.1 size`` rad and ``0.03 size`` length scales."""
    m = h.load(name, "numpy")
    _, moves, rotates, out_of_plane = motion(name)
    out = pose.copy()
    out[:3, 3] += np.where(moves, rng.normal(size=3) * 0.03 * size * h.length_scale(m), 0.0)
    if rotates:
        axis = rng.normal(size=3) if out_of_plane else np.array([0.0, 0.0, rng.normal()])
        out[:3, :3] = h.exp_so3(0.1 * size * axis / np.sqrt(3)) @ pose[:3, :3]
    return out


@functools.cache
def reachable_actuated(name: str, count: int) -> np.ndarray:
    """(<= count, n_a) actuated values of valid inverse branches at reachable poses near home
    (forward poses moved along the mechanism's own directions): inputs with at least one mode."""
    m = h.load(name, "numpy")
    poses, _, _, _ = motion(name)
    rng = np.random.default_rng(h.seed(name, "reachable actuated", count))
    if m.capabilities.inverse is None:
        return np.stack([h.perturb_actuated(m, m.home_actuated, rng) for _ in range(count)])
    graph = m.manifest.joints
    if graph is not None and graph.motion is not None and graph.motion.parasitic:
        # lower mobility with parasitic motion: a pose moved along x, y, z or a turn is off the
        # reachable set (its inverse is rightly invalid), so the targets are the forward poses of
        # actuated values near home: reachable by construction
        theta = np.stack([h.perturb_actuated(m, m.home_actuated, rng) for _ in range(count)])
        solved = m.forward_pose(theta, np.broadcast_to(m.home_passive, (count, m.home_passive.size)), strict=False)
        targets = solved.pose[np.asarray(solved.converged)]
    else:
        targets = np.stack([move_within(name, poses[i % len(poses)], rng, 1.0) for i in range(count)])
    ik = m.inverse_pose(targets, strict=False)
    rows = []
    for i in np.flatnonzero(ik.valid.any(-1)):
        branches = np.flatnonzero(ik.valid[i])
        rows.append(ik.actuated[i, branches[len(rows) % branches.size]])
    assert len(rows) >= count // 2, f"{name}: fewer than half of {count} poses near home are reachable"
    return np.array(rows)


def same_actuated(m, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Whether actuated values agree (angles modulo 2 pi), relative to their scales."""
    difference = h.wrapped(a - b, h.revolute_actuated(m)) / h.variable_scale(m, m.manifest.actuated)
    return np.abs(difference).max(-1) < MATCH * (1.0 + np.abs(b).max(-1))


# ---------------------------------------------------------------------------- item 4: modes as modes
def check_modes_indexing(m, actuated: np.ndarray) -> None:
    """mode(k) is the k-th valid slot, closed and reproducing the inputs through inverse_pose;
    len, iteration and slot(s) as documented; indices outside [0, count) are ParakinErrors."""
    modes = m.forward_pose_all(actuated, strict=False)
    valid_slots = np.flatnonzero(modes.valid)
    count = int(modes.count)
    assert count == valid_slots.size >= 1, f"count {count}, valid slots {valid_slots.tolist()} (an input with a mode)"
    assert len(modes) == count, f"len(modes) = {len(modes)}, count {count}"
    listed = list(modes)
    assert len(listed) == count, f"iteration gave {len(listed)} modes, count {count}"
    for k, slot in enumerate(valid_slots):
        mode = modes.mode(k)
        assert isinstance(mode, parakin.Configuration)
        np.testing.assert_array_equal(mode.passive, modes.passive[slot], err_msg=f"mode({k}) is not valid slot {slot}")
        np.testing.assert_array_equal(mode.pose, modes.poses[slot], err_msg=f"mode({k}) pose")
        np.testing.assert_array_equal(listed[k].passive, mode.passive, err_msg=f"iteration item {k} != mode({k})")
        residual = float(closure(m, actuated, mode.passive))
        assert residual < MATCH, f"mode({k}) does not close the loop: residual {residual:.3g} length scales"
        if m.capabilities.inverse is not None:
            inverse = m.inverse_pose(mode.pose, strict=False)
            back = inverse.valid & same_actuated(m, inverse.actuated, actuated)
            assert back.any(), f"mode({k})'s pose has no valid inverse branch with the actuated inputs {actuated}"
    for index in (count, count + 3, -1):
        with pytest.raises(ParakinError):
            modes.mode(index)
    for slot in range(modes.valid.shape[-1]):
        raw = modes.slot(slot)
        np.testing.assert_array_equal(raw.passive, modes.passive[slot], err_msg=f"slot({slot})")


def _modes_indexed(name: str, backend: str, inputs: int, examples: int) -> None:
    m = fz.mechanism(name, backend)
    if not fz.has_modes(m):
        pytest.skip(f"{name} has no forward_pose_all")
    actuated = reachable_actuated(name, inputs)
    checked = []

    @fz.fuzz_settings(examples)
    @given(row=st.integers(0, len(actuated) - 1))
    def property_holds(row):
        check_modes_indexing(m, actuated[row])
        checked.append(row)

    property_holds = example(row=0)(property_holds)
    property_holds()
    assert len(checked) >= min(examples, len(actuated)) // 2, f"only {len(checked)} inputs checked"


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_modes_are_indexed_as_modes(name, backend):
    """Issue 18 item 4: ``mode(k)`` for 0 <= k < count is the k-th valid mode (closed, and its
    pose gives back the inputs through inverse_pose); k outside is a ParakinError; ``slot(s)`` is
    raw slot s; ``len(modes) == count``; iteration yields the modes."""
    _modes_indexed(name, backend, 6, 3)


@pytest.mark.slow
@pytest.mark.parametrize(("name", "backend"), CASES)
def test_modes_are_indexed_as_modes_many_inputs(name, backend):
    _modes_indexed(name, backend, 60, 30)


# ---------------------------------------------------------------------------- item 5: real means real
REAL_ROOT_KINDS = ("simple", "cluster")


def check_real_slots(m, actuated: np.ndarray) -> str | None:
    """A slot flagged ``real`` has a real root (root kind simple or cluster) or is a mode; every
    mode is real; where the forward solve returns whole solutions (homotopy endpoints: no back
    substitution) a real slot is a real configuration: finite, closed, with a rigid pose."""
    modes = m.forward_pose_all(actuated, strict=False)
    kinds = m.manifest.abi.root_kinds
    real, valid = np.asarray(modes.real), np.asarray(modes.valid)
    kind = np.asarray(modes.root_kind)
    real_kind = np.isin(kind, [kinds.index(k) for k in REAL_ROOT_KINDS if k in kinds]) & (kind >= 0)
    if (valid & ~real).any():
        return f"a valid mode is not flagged real (input {first(valid & ~real)})"
    wrong = real & ~real_kind & ~valid
    if wrong.any():
        index = first(wrong)
        return (
            f"slot {index} is flagged real but its root kind is {kinds[kind[index]] if kind[index] >= 0 else 'none'}"
            f" (outcome {modes.outcomes[modes.outcome[index]]})"
        )
    if m.capabilities.forward is not None and m.capabilities.forward.method == "homotopy" and real.any():
        grid = np.broadcast_to(modes.actuated[..., None, :], modes.passive.shape[:-1] + modes.actuated.shape[-1:])
        finite = np.isfinite(modes.passive).all(-1)
        if (real & ~finite).any():
            return f"real endpoint {first(real & ~finite)} has non-finite passive values"
        with np.errstate(all="ignore"):
            residual = closure(m, grid[real], modes.passive[real])
        if not (residual < MATCH).all():
            return f"{int((residual >= MATCH).sum())} of {int(real.sum())} real endpoints do not close the loop"
        if not rigid(modes.poses[real], 1e-6).all():
            return "a real endpoint's pose is not a rigid transform"
    return None


def _real_means_real(name: str, backend: str, inputs: int) -> None:
    m = fz.mechanism(name, backend)
    if m.capabilities.forward is None:
        pytest.skip(f"{name} has no forward elimination (no roots)")
    rng = np.random.default_rng(h.seed(name, "real slots", inputs))
    near = reachable_actuated(name, inputs)
    far = np.stack([h.perturb_actuated(m, m.home_actuated, rng, 2.0) for _ in range(inputs // 2)])
    problems = []
    for actuated in (*near, *far):
        problem = check_real_slots(m, actuated)
        if problem:
            problems.append(f"m.forward_pose_all({fz.lit(actuated)}): {problem}")
    assert len(near) + len(far) >= inputs
    assert not problems, f"{len(problems)} inputs; first:\n" + "\n".join(problems[:3])


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_real_slots_are_real(name, backend):
    """Issue 18 item 5: ``AssemblyModes.real`` is True only for real roots / endpoints."""
    _real_means_real(name, backend, 6)


@pytest.mark.slow
@pytest.mark.parametrize(("name", "backend"), CASES)
def test_real_slots_are_real_many_inputs(name, backend):
    _real_means_real(name, backend, 60)


def _unguided_forward(name: str, backend: str, inputs: int) -> None:
    """Actuated values of reachable poses near home, and home with one input scaled by 0.8 or 1.2
    where forward_pose_all finds a mode: forward_pose without a guess converges (strict, one call
    per batch and one single call), closed."""
    m = fz.mechanism(name, backend)
    if not m.passive_names:
        pytest.skip(f"{name} is a serial chain: no Newton solve")
    scaled = []
    for i in range(len(m.actuated_names)):
        for factor in (0.8, 1.2):
            a = m.home_actuated.copy()
            a[i] = a[i] * factor if a[i] != 0 else factor - 1.0
            scaled.append(a)
    candidates = np.concatenate([reachable_actuated(name, inputs), np.array(scaled)])
    if fz.has_modes(m):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                counts = m.count_modes(candidates)["count"]
            except ParakinError:
                counts = np.array([m.count_modes(a)["count"] if _answers(m, a) else 0 for a in candidates])
        candidates = candidates[np.asarray(counts) > 0]
    assert len(candidates) >= inputs // 2, f"only {len(candidates)} inputs with modes"
    fk = m.forward_pose(candidates, strict=False)
    failed = np.flatnonzero(~np.asarray(fk.converged))
    assert failed.size == 0, (
        f"forward_pose without a guess fails on {failed.size} of {len(candidates)} inputs with modes, "
        f"e.g. m.forward_pose({fz.lit(candidates[failed[0]])})"
    )
    residual = closure(m, candidates, fk.passive)
    assert (residual < MATCH).all(), f"unguided forward_pose residual {residual.max():.3g} length scales"
    single = m.forward_pose(candidates[-1])
    assert bool(single.converged)


def _answers(m, actuated) -> bool:
    try:
        m.count_modes(actuated)
    except ParakinError:
        return False
    return True


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_forward_pose_without_guess_converges_where_modes_exist(name, backend):
    """Issue 18 item 5: forward_pose without a guess never fails where forward_pose_all finds
    modes (its seed is a real mode)."""
    _unguided_forward(name, backend, 12)


@pytest.mark.slow
@pytest.mark.parametrize(("name", "backend"), CASES)
def test_forward_pose_without_guess_converges_where_modes_exist_many_inputs(name, backend):
    _unguided_forward(name, backend, 200)


# ---------------------------------------------------------------------------- item 6: rigid platform poses
@pytest.mark.parametrize(("name", "backend"), CASES)
def test_platform_pose_is_rigid_or_inconsistent(name, backend):
    """Issue 18 item 6: platform_pose of joint values near a closed configuration (closed or not,
    one or a batch) is a rigid transform (R^T R = I, det R = 1) or raises InconsistentInputError."""
    m = fz.mechanism(name, backend)
    fx = fz.fixture(name)
    checked = []

    @fz.fuzz_settings(15)
    @given(
        size=st.sampled_from([0.0, 1e-9, 1e-6, 1e-3, 1e-2, 0.1, 0.5, 1.0]),
        batch=st.sampled_from([(), (4,)]),
        seed=st.integers(0, 2**16),
    )
    def property_holds(size, batch, seed):
        rng = np.random.default_rng(seed)
        a, p = fx.state.actuated, fx.state.passive
        if m.passive_names:
            p = p + size * h.variable_scale(m, m.manifest.passive) * rng.normal(size=batch + p.shape)
            a = np.broadcast_to(a, batch + a.shape)
        else:
            a = a + size * h.variable_scale(m, m.manifest.actuated) * rng.normal(size=batch + a.shape)
        got = fz.answer(lambda: m.platform_pose(a, p))
        code = f"m.platform_pose({fz.lit(np.asarray(a))}, {fz.lit(np.asarray(p))})"
        if got.error is not None:
            assert isinstance(got.error, InconsistentInputError), f"{code} raised {got.error!r}"
        else:
            assert rigid(np.asarray(got.result)).all(), f"{code} is not a rigid transform:\n{got.result}"
        checked.append(size)

    property_holds = example(size=0.1, batch=(), seed=0)(property_holds)
    property_holds()
    assert len(checked) >= 10


# ---------------------------------------------------------------------------- item 7: stiffness inputs
def stiffness_cases(n: int) -> dict[str, tuple[str, object]]:
    """Actuator stiffness values: (expectation, value); k is a valid diagonal."""
    k = np.linspace(1e4, 3e4, n)
    asymmetric = np.diag(k)
    asymmetric[0, -1] += 0.1 * k[0] if n > 1 else 0.0
    if n == 1:
        asymmetric = None
    return {
        "vector": ("ok", k), "list": ("ok", k.tolist()), "matrix": ("ok", np.diag(k)),
        "string": ("raise", "1e4"), "strings": ("raise", [str(v) for v in k]),
        "numeric-string-array": ("raise", k.astype(str)), "complex": ("raise", k + 1j),
        "complex-zero-imag": ("raise", k.astype(complex)), "bool": ("raise", True), "bools": ("raise", [True] * n),
        "bool-array": ("raise", np.ones(n, dtype=bool)), "negative": ("raise", -k),
        "one-negative": ("raise", np.where(np.arange(n) == n - 1, -k, k)), "nan": ("raise", np.where(np.arange(n) == 0, np.nan, k)),
        "inf": ("raise", np.where(np.arange(n) == 0, np.inf, k)), "non-symmetric": ("raise", asymmetric),
        "none-entry": ("raise", np.array([None] * n, dtype=object)), "wrong-shape": ("raise", np.append(k, 1.0)),
    }  # fmt: skip


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_stiffness_refuses_malformed_stiffnesses(name, backend):
    """Issue 18 item 7: ``stiffness(state, actuator_stiffness)`` refuses strings, complex values,
    booleans, negative, non-finite and non-symmetric stiffnesses with BadInputError; a valid one
    gives K with K t = G^T K_q G t (checked through inverse_rate and actuator_forces)."""
    m = fz.mechanism(name, backend)
    if not fz.has_rates(m):
        pytest.skip(f"{name} has no rate model")
    fx = fz.fixture(name)
    cases = {key: case for key, case in stiffness_cases(len(m.actuated_names)).items() if case[1] is not None}
    checked = []

    @fz.fuzz_settings(12)
    @given(key=st.sampled_from(sorted(cases)), through=st.sampled_from(["method", "function"]))
    def property_holds(key, through):
        expect, value = cases[key]
        from parakin.solvers.statics import stiffness

        call = (
            (lambda: m.stiffness(fx.state, value)) if through == "method" else (lambda: stiffness(m, fx.state, value))
        )
        got = fz.answer(call)
        code = f"m.stiffness({fz.lit(fx.state)}, {fz.lit(value)})"
        if expect == "raise":
            assert isinstance(got.error, BadInputError), f"{key}: {code} gave {got.error!r} / {fz.describe(got.result)}"
        else:
            assert got.error is None, f"{key}: {code} raised {got.error!r}"
            matrix = np.asarray(got.result)
            assert np.isfinite(matrix).all() and np.allclose(matrix, matrix.T, rtol=1e-9, atol=0.0)
            twist = fx.twist
            forces = m.actuator_forces(fx.state, -(matrix @ twist))
            expected = np.diag(np.linspace(1e4, 3e4, len(m.actuated_names))) @ m.inverse_rate(fx.state, twist).actuated
            assert np.allclose(forces, expected, rtol=1e-6, atol=1e-9 * np.abs(expected).max()), key
        checked.append(key)

    for i, key in enumerate(sorted(cases)):
        property_holds = example(key=key, through=("method", "function")[i % 2])(property_holds)
    property_holds()
    assert len(checked) >= len(cases)


# ---------------------------------------------------------------------------- item 8: pose kinds
def off_motion_poses(name: str, pose: np.ndarray, size: float, rng: np.random.Generator) -> dict[str, np.ndarray]:
    """``pose`` moved along each direction the mechanism never moves in (``motion``), by ``size``
    length scales or ``size`` rad: {what: pose}."""
    m = h.load(name, "numpy")
    _, moves, rotates, out_of_plane = motion(name)
    out = {}
    for axis in np.flatnonzero(~moves):
        moved = pose.copy()
        moved[axis, 3] += size * h.length_scale(m)
        out[f"translation along {'xyz'[axis]}"] = moved
    if not rotates:
        moved = pose.copy()
        moved[:3, :3] = h.exp_so3(size * rng.normal(size=3) / np.sqrt(3)) @ pose[:3, :3]
        out["a rotation"] = moved
    elif not out_of_plane:
        moved = pose.copy()
        moved[:3, :3] = h.exp_so3(np.array([size, -size, 0.0])) @ pose[:3, :3]
        out["a rotation out of the plane"] = moved
    return out


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_poses_off_the_mechanisms_motion_are_refused(name, backend):
    """Issue 18 item 8: a pose moved along a direction the mechanism never moves in (read from
    its forward poses near home: a z offset of a planar one, a rotation of a translating one, a
    translation of an orienting one, a tilt of a planar one) is refused by inverse_pose with
    BadInputError; the reachable pose itself is accepted."""
    m = fz.mechanism(name, backend)
    if m.capabilities.inverse is None:
        pytest.skip(f"{name} has no inverse_pose")
    poses, moves, rotates, out_of_plane = motion(name)
    checked = []

    @fz.fuzz_settings(12)
    @given(index=st.integers(0, len(poses) - 1), size=st.sampled_from([1e-4, 1e-2, 0.1, 0.5]), seed=st.integers(0, 99))
    def property_holds(index, size, seed):
        pose = poses[index]
        assert fz.answer(lambda: m.inverse_pose(pose, strict=False)).error is None
        for what, moved in off_motion_poses(name, pose, size, np.random.default_rng(seed)).items():
            got = fz.answer(lambda moved=moved: m.inverse_pose(moved, strict=False))
            assert isinstance(got.error, BadInputError), (
                f"{what} of {size:g} is not refused (moves along {'xyz'} = {moves.tolist()}, rotates {rotates}, "
                f"out of the plane {out_of_plane}): m.inverse_pose({fz.lit(moved)}) gave "
                f"{repr(got.error) if got.error else fz.describe(got.result)}"
            )
            checked.append(what)

    property_holds = example(index=0, size=0.1, seed=0)(property_holds)
    property_holds()
    if moves.all() and rotates and out_of_plane:
        pytest.skip(f"{name} moves in every direction: nothing to refuse")
    assert len(checked) >= 10


# ---------------------------------------------------------------------------- item 9: actuated ranges
def _forward_agrees_with_inverse(name: str, backend: str, count: int) -> None:
    m = fz.mechanism(name, backend)
    if m.capabilities.inverse is None or not fz.has_modes(m):
        pytest.skip(f"{name} lacks inverse_pose or forward_pose_all")
    poses, _, _, _ = motion(name)
    rng = np.random.default_rng(h.seed(name, "strokes", count))
    targets = np.stack([move_within(name, poses[i % len(poses)], rng, 3.0) for i in range(count)])
    ik = m.inverse_pose(targets, strict=False)
    finite = np.isfinite(ik.actuated).all(-1) & np.isfinite(ik.passive).all(-1)
    problems, checked = [], 0
    for i, b in zip(*np.nonzero(finite), strict=True):
        a, q, pose = ik.actuated[i, b], ik.passive[i, b], targets[i]
        reasons = {name for name, mask in ik.failures.items() if mask[i, b]}
        code = f"m.forward_pose_all({fz.lit(a)})"
        if reasons and reasons <= {"actuator_range"}:
            for method in (m.forward_pose, m.forward_pose_all):
                got = fz.answer(lambda method=method, a=a: method(a))
                if not isinstance(got.error, BadInputError):
                    problems.append(f"outside the actuator ranges, {code} (or forward_pose) gave {got.error!r}")
        got = fz.answer(lambda a=a: m.forward_pose_all(a, strict=False))
        if got.error is not None:
            if not isinstance(got.error, ParakinError):
                problems.append(f"{code} raised {got.error!r}")
            elif not reasons:
                problems.append(f"{code} refused the inputs of a valid inverse branch: {got.error!r}")
            checked += 1
            continue
        modes = got.result
        found = modes.valid & (h.pose_tolerance(m, modes.poses, pose) < MATCH)
        if reasons and found.any():
            problems.append(
                f"inverse_pose marks the branch invalid ({', '.join(sorted(reasons))}) but {code} returns it as a "
                f"valid mode (pose {fz.lit(pose)})"
            )
        fk = fz.answer(lambda a=a, q=q: m.forward_pose(a, guess=q, strict=False))
        if reasons and fk.error is None:
            result = fk.result
            if bool(result.converged) and bool(result.within_limits) and h.pose_tolerance(m, result.pose, pose) < MATCH:
                problems.append(f"forward_pose({fz.lit(a)}, guess=...) accepts a branch inverse_pose marks invalid")
        checked += 1
    assert checked >= count // 2, f"only {checked} finite branches checked"
    assert not problems, f"{len(problems)} of {checked} branches; first:\n" + "\n".join(problems[:3])


@pytest.mark.parametrize(("name", "backend"), CASES)
def test_forward_refuses_what_the_inverse_refuses(name, backend):
    """Issue 18 item 9: actuated values of an inverse branch that inverse_pose marks invalid (an
    actuator stroke, a joint limit) are no valid forward mode at that pose; values outside the
    declared actuator ranges are refused by forward_pose and forward_pose_all (BadInputError)."""
    _forward_agrees_with_inverse(name, backend, 12)


@pytest.mark.slow
@pytest.mark.parametrize(("name", "backend"), CASES)
def test_forward_refuses_what_the_inverse_refuses_many_poses(name, backend):
    _forward_agrees_with_inverse(name, backend, 120)


# ---------------------------------------------------------------------------- item 10: sweeps
def sweep_of(m, quantities, axes, fixed=None):
    from parakin.studies.sweep import sweep

    return sweep(m, quantities, axes, fixed=fixed, scheduler="synchronous")


def pose_coordinates(m) -> tuple[str, ...]:
    from parakin.studies.sweep import POSE_COORDINATES

    return POSE_COORDINATES[m.manifest.pose_kind]


def coordinate_values(m) -> dict[str, float]:
    """The sweep coordinates of the fixture's pose (Z-Y-X Euler angles as parakin.pose; phi the
    angle about z)."""
    fx = fz.fixture(m.name)
    pose = m.platform_pose(fx.state.actuated, fx.state.passive)
    six = parakin.xyz_euler_from_pose(pose)
    values = dict(zip(("x", "y", "z", "alpha", "beta", "gamma"), map(float, six), strict=True))
    values["phi"] = values["alpha"]
    return values


def sweep_parameter_names(m) -> dict[str, str]:
    """Sweep name -> parameter name (``param_`` where a parameter shadows a pose coordinate or an
    actuated variable)."""
    taken = {*pose_coordinates(m), *m.actuated_names}
    return {(f"param_{p.name}" if p.name in taken else p.name): p.name for p in m.manifest.parameters}


def sweep_mechanism(name: str):
    """The compiled backend where a compiler works (sweeps of every mode are many solves)."""
    return fz.mechanism(name, "compiled")


@pytest.mark.parametrize("name", NAMES)
def test_sweep_modes_are_counts_or_missing(name):
    """Issue 18 item 10: a 'modes' sweep holds the count of forward_pose_all's modes where the
    elimination is defined and NaN where it is not (never a sentinel such as -1), with another
    variable flagging those points; checked against count_modes on the same inputs. A point of
    the axis outside its actuator's range (the manifest's limits: count_modes refuses it) is
    missing too, flagged by a code of its own, and the rest of the sweep is computed."""
    m = sweep_mechanism(name)
    if m.capabilities.forward is None:
        pytest.skip(f"{name} has no forward elimination: no 'modes' sweep")
    fx = fz.fixture(name)
    first = m.actuated_names[0]
    scale = h.variable_scale(m, m.manifest.actuated)[0]
    values = fx.state.actuated[0] + scale * np.array([-0.5, -0.1, 0.0, 0.1, 0.5])
    values = np.unique(np.append(values, m.home_actuated[0]))
    others = dict(zip(m.actuated_names[1:], map(float, fx.state.actuated[1:]), strict=True))
    result = sweep_of(m, ["modes"], {first: values}, fixed=others)
    theta = np.tile(fx.state.actuated, (values.size, 1))
    theta[:, 0] = values
    low, high = (np.array([v.limits[k] for v in m.manifest.actuated]) for k in (0, 1))
    inside = ((theta >= low) & (theta <= high)).all(-1)
    assert inside.sum() >= 3, f"only {inside.sum()} of the axis values {values} inside the actuated ranges"
    counts = m.count_modes(theta[inside])
    defined = np.zeros(values.size, dtype=bool)
    defined[inside] = np.asarray(counts["status"]) == 0
    got = np.asarray(result["modes"].values, dtype=float)
    assert not (got < 0).any(), f"sentinel values in 'modes': {got}"
    expected = np.full(values.size, np.nan)
    expected[inside] = np.where(defined[inside], np.asarray(counts["count"], dtype=float), np.nan)
    np.testing.assert_array_equal(got, expected, err_msg="sweep 'modes' vs count_modes on the same inputs")
    flags = [key for key in result.data_vars if key != "modes"]
    if not defined.all():
        flagged = [key for key in flags if (np.asarray(result[key].values != 0) == ~defined).all()]
        assert flagged, f"no variable flags the undefined points {np.flatnonzero(~defined)}: {flags}"
    if not inside.all():  # the outside points: a flag of their own, named, none of count_modes' codes
        codes = {}
        for key in flags:
            attributes = result[key].attrs
            named = dict(
                zip(attributes.get("flag_values", []), str(attributes.get("flag_meanings", "")).split(), strict=True)
            )
            held = {int(c) for c in np.asarray(result[key].values)[~inside]}
            if len(held) == 1 and not held & {int(c) for c in np.asarray(result[key].values)[inside]}:
                codes[key] = named.get(held.pop())
        own = {key: meaning for key, meaning in codes.items() if meaning and meaning not in m.manifest.abi.input_status}
        assert own, f"no flag of their own for the points outside the actuated ranges {values[~inside]}: {codes}"


@pytest.mark.parametrize("name", NAMES)
def test_sweep_refuses_a_fixed_actuated_value_outside_its_range(name):
    """A fixed actuated value beyond its actuator's range (every point would be missing: no solver
    takes it) is BadInputError naming it; the same value inside the range is computed."""
    m = sweep_mechanism(name)
    bounded = [k for k, v in enumerate(m.manifest.actuated) if np.isfinite(v.limits[1])]
    if m.capabilities.forward is None or len(m.actuated_names) < 2 or not bounded:
        pytest.skip(f"{name}: no 'modes' sweep with a bounded actuator to fix")
    fx = fz.fixture(name)
    k = bounded[0]
    j = 1 if k == 0 else 0
    scale = h.variable_scale(m, m.manifest.actuated)
    axes = {m.actuated_names[j]: fx.state.actuated[j] + 0.01 * scale[j] * np.arange(3)}
    beyond = m.manifest.actuated[k].limits[1] + 0.1 * scale[k]
    got = fz.answer(lambda: sweep_of(m, ["modes"], axes, fixed={m.actuated_names[k]: beyond}))
    assert isinstance(got.error, BadInputError) and m.actuated_names[k] in str(got.error), got.error
    inside = sweep_of(m, ["modes"], axes, fixed={m.actuated_names[k]: float(fx.state.actuated[k])})
    assert (np.asarray(inside["modes_status"].values) == 0).all()


@pytest.mark.parametrize("name", NAMES)
def test_sweep_refuses_bad_fixed_values(name):
    """Issue 18 item 10: a fixed value for a swept coordinate, or one that is not a finite real
    number (a list, an array, a string, None, complex, a mapping, NaN), is BadInputError."""
    m = sweep_mechanism(name)
    coordinates = pose_coordinates(m)
    swept, other = coordinates[0], coordinates[1]
    base = coordinate_values(m)
    axes = {swept: base[swept] + 0.01 * np.arange(3)}
    cases = {
        "swept": {swept: base[swept]}, "list": {other: [0.1, 0.2]}, "array": {other: np.array([0.1, 0.2])},
        "nested": {other: [[0.1]]}, "string": {other: "abc"}, "numeric-string": {other: "0.1"}, "none": {other: None},
        "complex": {other: 0.1j}, "mapping": {other: {"a": 1.0}}, "nan": {other: np.nan}, "inf": {other: np.inf},
        "unknown-name": {"no_such_name": 0.1}, "not-a-mapping": [(other, 0.1)],
    }  # fmt: skip
    checked = []

    @fz.fuzz_settings(6)
    @given(key=st.sampled_from(sorted(cases)))
    def property_holds(key):
        got = fz.answer(lambda: sweep_of(m, ["reachable"], axes, fixed=cases[key]))
        assert isinstance(got.error, BadInputError), f"sweep(fixed={fz.lit(cases[key])}) gave {got.error!r}"
        checked.append(key)

    for key in sorted(cases):
        property_holds = example(key=key)(property_holds)
    property_holds()
    assert len(checked) >= len(cases)


def fixable(m) -> list[tuple[str, str, float, str, str, np.ndarray, dict[str, float]]]:
    """Every name a sweep can fix, with a value, the quantity that reads it, a swept axis and the
    other fixed values: (kind, name, value, quantity, axis, axis values, others). A parameter's
    case fixes the other pose coordinates too (their default, the home pose, is the design's)."""
    fx = fz.fixture(m.name)
    base = coordinate_values(m)
    coordinates = pose_coordinates(m)
    cases = []
    for name in coordinates:
        axis = next(c for c in coordinates if c != name)
        cases.append(("pose", name, base[name] + 0.01, "reachable", axis, base[axis] + 0.02 * np.arange(3), {}))
    if m.capabilities.forward is not None and len(m.actuated_names) > 1:
        scale = h.variable_scale(m, m.manifest.actuated)
        for k, name in enumerate(m.actuated_names):
            j = 1 if k == 0 else 0
            axis_values = fx.state.actuated[j] + 0.01 * scale[j] * np.arange(3)
            cases.append(("actuated", name, float(fx.state.actuated[k]), "modes", m.actuated_names[j], axis_values, {}))
    domains = {p.name: p.domain for p in m.manifest.parameters}
    for sweep_name, parameter in sweep_parameter_names(m).items():
        value = m.parameters[parameter] * 1.001 if m.parameters[parameter] else 1e-3
        if domains[parameter] == "sign":  # +1 or -1: the other sign (x 1.001 is no sign)
            value = -m.parameters[parameter]
        axis = coordinates[0]
        others = {c: base[c] for c in coordinates[1:]}
        cases.append(("parameter", sweep_name, value, "reachable", axis, base[axis] + 0.02 * np.arange(3), others))
    return cases


@pytest.mark.parametrize("name", NAMES)
def test_sweep_every_unswept_variable_can_be_fixed(name):
    """Issue 18 item 10: every pose coordinate, actuated variable and parameter that is not swept
    can be fixed, and fixing it at v gives the same values as sweeping it over the one value v."""
    m = sweep_mechanism(name)
    cases = fixable(m)
    kinds = sorted({case[0] for case in cases})
    checked = []

    @fz.fuzz_settings(6)
    @given(index=st.integers(0, len(cases) - 1))
    def property_holds(index):
        kind, fixed_name, value, quantity, axis, axis_values, others = cases[index]
        given_fixed = {**others, fixed_name: value}
        fixed = fz.answer(lambda: sweep_of(m, [quantity], {axis: axis_values}, fixed=given_fixed))
        code = f"sweep(m, [{quantity!r}], {{{axis!r}: {fz.lit(axis_values)}}}, fixed={fz.lit(given_fixed)})"
        assert fixed.error is None, f"{kind} {fixed_name!r} cannot be fixed: {code} raised {fixed.error!r}"
        swept = sweep_of(m, [quantity], {axis: axis_values, fixed_name: np.array([value])}, fixed=others or None)
        for key in fixed.result.data_vars:
            np.testing.assert_array_equal(
                np.asarray(fixed.result[key].values),
                np.asarray(swept[key].values).reshape(np.shape(fixed.result[key].values)),
                err_msg=f"{code}: {key} differs from the sweep over {fixed_name} = [{value!r}]",
            )
        checked.append(kind)

    for kind in kinds:  # one of each kind at least
        property_holds = example(index=next(i for i, c in enumerate(cases) if c[0] == kind))(property_holds)
    property_holds()
    assert set(checked) == set(kinds) and len(checked) >= len(kinds) + 3


# ---------------------------------------------------------------------------- item 12: load and the CLI
NON_NAMES = st.one_of(
    st.integers(-10, 10),
    st.none(),
    st.floats(allow_nan=True),
    st.binary(max_size=8),
    st.lists(st.sampled_from(NAMES), max_size=2),
    st.builds(lambda n: "x" * n, st.integers(256, 6000)),
    st.sampled_from(
        [
            "no/such/mechanism",
            "no\\such",
            "../nowhere",
            "/nonexistent/folder",
            "",
            "\x00",
            ".",
            "..",
            "a" * 5000,
            "sps\x00",
            "~/nowhere",
        ]
    ),  # fmt: skip
    st.text(alphabet=st.sampled_from("ab/\\.~:\x00 _"), max_size=12),
)


def test_load_answers_named_errors_for_any_name():
    """Issue 18 item 12: parakin.load of something that is no mechanism name (an int, None, bytes,
    a list, a 5,000-character string, a path that does not exist, a name with separators) raises
    a ParakinError (BadInputError / UnknownMechanismError), never a raw TypeError or OSError."""
    checked = []

    @fz.fuzz_settings(40)
    @given(value=NON_NAMES)
    def property_holds(value):
        got = fz.answer(lambda: parakin.load(value, backend="numpy"))
        if got.error is None:  # a string that names a package after all
            assert isinstance(got.result, parakin.Mechanism)
        else:
            assert isinstance(got.error, ParakinError), f"parakin.load({value!r}) raised {got.error!r}"
        checked.append(value)

    for value in (5, None, "x" * 5000, "no/such/mechanism", b"sps", 3.5):
        property_holds = example(value=value)(property_holds)
    property_holds()
    assert len(checked) >= 30


def wrong_cases(name: str, taken: set[str]) -> list[str]:
    return sorted({v for v in (name.lower(), name.upper(), name.swapcase(), name.capitalize()) if v not in taken})


@pytest.mark.parametrize("name", NAMES)
def test_load_wrong_case_parameter_names_the_parameter(name):
    """Issue 18 item 12: a parameter (or parameter group) spelt in another case is a BadInputError
    that is not UnknownMechanismError (the mechanism exists) and names the right parameter."""
    info = parakin.metadata(name)
    names = [p.name for p in info.parameters] + [g.name for g in info.parameter_groups]
    cases = [(right, wrong) for right in names for wrong in wrong_cases(right, set(names))]
    if not cases:
        pytest.skip(f"{name}: every case variant of its parameters is another parameter")
    checked = []

    @fz.fuzz_settings(10)
    @given(pick=st.integers(0, len(cases) - 1))
    def property_holds(pick):
        right, wrong = cases[pick]
        value = np.asarray(info.parameter_defaults.get(right, 0.0))
        got = fz.answer(lambda: parakin.load(name, backend="numpy", **{wrong: value}))
        assert isinstance(got.error, BadInputError) and not isinstance(got.error, UnknownMechanismError), (
            f"parakin.load({name!r}, {wrong}=...) raised {got.error!r}"
        )
        assert right in str(got.error), f"the message does not name {right!r}: {got.error}"
        checked.append(pick)

    property_holds = example(pick=0)(property_holds)
    property_holds()
    assert len(checked) >= min(len(cases), 5)


def cli_arguments(draw_name, values, tmp: Path) -> st.SearchStrategy[list[str]]:
    """Command lines of every subcommand: mechanism names (and bad ones), pose / actuated values
    of any count (NaN, inf, huge), parameters (right, wrong-case, unknown, malformed, 'limits'),
    sweep axes and fixed values, backends and flags."""
    numbers = st.lists(values, min_size=0, max_size=8).map(lambda xs: [repr(float(x)) for x in xs])
    params = st.lists(
        st.one_of(
            st.builds(lambda n, v: f"{n}={v}", st.sampled_from(["L1", "l1", "limits", "beta", "zzz", "", "a b"]),
                      st.sampled_from(["0.5", "nan", "[1, 2]", "abc", "1e400", "-1", "{}"])),
            st.sampled_from(["noequals", "=1"]),
        ),
        max_size=2,
    ).map(lambda items: [x for item in items for x in ("--param", item)])  # fmt: skip
    common = st.lists(st.sampled_from(["--json", "--backend=numpy", "--backend=casadi", "--backend=auto"]), max_size=2)

    def line(command, name, xs, ps, flags, axis, fixed):
        out = str(tmp / "out")
        if command == "list":
            return ["list", *flags]
        if command == "inspect":
            return ["inspect", name, "--lines", "2"]
        if command == "demo":
            return ["demo", name]
        if command == "export":
            return ["export", name, "--out", out]
        if command == "generate":
            return ["generate", str(tmp / "missing.py"), "--out", out]
        head = [command, name, *ps]
        if command == "ik":
            return [*head, "--pose", *xs] if xs else [*head, "--pose-deg"]
        if command == "fk":
            return [*head, "--actuated", *xs] if xs else [*head, "--actuated"]
        if command == "plot":
            return [*head, "--output", str(tmp / "plot.png"), *(["--actuated", *xs] if xs else [])]
        return [*head, "reachable", "modes", "--axis", axis, *(["--fixed", fixed] if fixed else [])]

    return st.builds(
        line,
        st.sampled_from(["list", "inspect", "ik", "fk", "plot", "export", "sweep", "generate", "demo"]),
        draw_name,
        numbers,
        params,
        common,
        st.sampled_from(["x=0:0.1:3", "theta1=0:0.5:2", "z=1", "x=a:b:c", "nosuch=0:1:2", "x=0:1:-1"]),
        st.sampled_from(["", "y=0.1", "x=0.1", "theta2=0.1", "y=nan", "y=[1,2]", "y=abc"]),
    )


def run_cli(argv: list[str]) -> tuple[int, str, str]:
    from parakin.interfaces.cli import main

    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            code = main(argv)
        except SystemExit as exit_:  # argparse: usage errors exit 2, --help 0
            code = exit_.code if isinstance(exit_.code, int) else 2
    return code, stdout.getvalue(), stderr.getvalue()


def test_cli_exits_0_1_or_2_and_1_only_for_no_solution(tmp_path):
    """Issue 18 item 12: any command line of any subcommand exits 0 (done), 1 (no solution: the
    message says so) or 2 (a named error, usage); never an exception out of main, never 1 (or the
    'internal error' status) with a traceback."""
    # the mechanisms whose all-modes solver is slow (conftest.HEAVY_PATHS) are left to --run-slow
    light = [name for name in NAMES if name not in _heavy_families()]
    names = st.sampled_from([*light, "no_such_mechanism", "x" * 300, "../nowhere"])
    values = st.one_of(st.floats(-2, 2), st.sampled_from([np.nan, np.inf, 1e300, 0.0]))
    checked = []

    @fz.fuzz_settings(40)
    @given(argv=cli_arguments(names, values, tmp_path))
    def property_holds(argv):
        got = fz.answer(lambda: run_cli(argv))
        assert got.error is None, f"parakin {' '.join(argv)} raised {got.error!r}"
        code, _, err = got.result
        assert code in (0, 1, 2), f"parakin {' '.join(argv)} exited {code}:\n{err[-2000:]}"
        assert "Traceback" not in err, f"parakin {' '.join(argv)} printed a traceback:\n{err[-2000:]}"
        if code == 1:
            assert "no " in err.lower(), f"parakin {' '.join(argv)} exited 1 without 'no solution':\n{err[-2000:]}"
        checked.append(code)

    first = NAMES[0]
    for argv in (["ik", first, "--param", "limits=[1, 2]", "--pose", "0", "0", "0"], ["fk", first, "--actuated"],
                 ["list"], ["sweep", first, "reachable", "--axis", "x=0:0.1:3", "--fixed", "x=0.1"]):  # fmt: skip
        property_holds = example(argv=argv)(property_holds)
    property_holds()
    assert len(checked) >= 30


# ---------------------------------------------------------------------------- item 13: manifest paths
ESCAPES = ("../x.h", "../../x.h", "sub/../../x.h", "..", "a/../../../x.h", "~/x.h", "")


def smallest_package() -> Path:
    """The generated package with the fewest bytes (copied for each manifest case)."""
    from parakin.packages.package import discover

    sizes = {path: sum(f.stat().st_size for f in path.iterdir() if f.is_file()) for path in discover().values()}
    return min(sizes, key=sizes.get)


def files_under(root: Path) -> set[Path]:
    return {p for p in root.rglob("*") if p.is_file()}


def test_manifest_names_and_files_outside_the_package_are_refused(tmp_path):
    """Issue 18 item 13: a manifest whose name or C file lists (sources, headers, header) point
    outside the package folder (``..``, absolute paths, separators in the name) is refused when
    read, by a ParakinError, and nothing is written outside the folders asked for."""
    source = smallest_package()
    manifest = json.loads((source / "manifest.json").read_text())
    fields = ["name", "c.sources", "c.headers", "c.header"]
    checked = []

    @fz.fuzz_settings(20)
    @given(field=st.sampled_from(fields), value=st.sampled_from(ESCAPES + ("absolute", "a/b", "a\\b")))
    def property_holds(field, value):
        root = tmp_path / f"case{len(checked)}"
        package = root / "one" / "two" / "package"
        shutil.copytree(source, package)
        (root / "one" / "x.h").write_text("/* outside */\n")
        path = str(root / "one" / "x.h") if value == "absolute" else value
        data = json.loads(json.dumps(manifest))
        if field == "name":
            data["name"] = path
        elif field == "c.header":
            data["c"]["header"] = path
        else:
            key = field.split(".")[1]
            data["c"][key] = [*data["c"][key], path]
        (package / "manifest.json").write_text(json.dumps(data))
        before = files_under(root)
        out = root / "one" / "two" / "out"
        for label, call in (
            ("parakin.load", lambda: parakin.load(package, backend="numpy")),
            ("parakin.metadata", lambda: parakin.metadata(package)),
            (
                "export_c",
                lambda: __import__("parakin.packages.package").packages.package.GeneratedPackage(package).export_c(out),
            ),
        ):
            got = fz.answer(call)
            assert isinstance(got.error, ParakinError), f"{label} of a manifest with {field} = {path!r}: {got.error!r}"
        assert files_under(root) == before, f"files written: {sorted(files_under(root) - before)}"
        checked.append(field)

    property_holds = example(field="name", value="../../x.h")(property_holds)
    property_holds = example(field="c.headers", value="../../x.h")(property_holds)
    property_holds()
    assert len(checked) >= 15


@pytest.mark.parametrize("name", NAMES)
def test_export_c_writes_only_inside_its_folder(name, tmp_path):
    """Issue 18 item 13: export_c writes the package's C files into its folder and nowhere else."""
    from parakin.packages.package import GeneratedPackage

    out = tmp_path / "deep" / "out"
    before = files_under(tmp_path)
    written = GeneratedPackage.find(name).export_c(out)
    assert written, "nothing exported"
    for path in written:
        assert Path(path).resolve().is_relative_to(out.resolve()), f"{path} is outside {out}"
    assert files_under(tmp_path) - before == {Path(p) for p in written}
