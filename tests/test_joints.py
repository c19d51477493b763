"""The joint-level modelling language (``parakin.generator.joints``): every derivation checked on
random configurations against an independent source: the hand-derived prismatic-leg block
(expressions), the loop closure itself (every valid inverse branch closes it and reproduces the
pose), the closure's time derivative (the rate model against central differences of the
inverse) and det A (the parallel factor, however it is written), for each kind of leg
(prismatic, crank, slider) and the pose kinds transform, planar and translation. The mechanisms
re-expressed in the language (stewart, rus6, delta, five_bar, planar_3rpr, planar_3rrr) were
compared with their hand-derived packages when they were (byte-identical, or on 1000 samples:
inverse branches and validity, rates, singularity factors in ratio 1, modes); their paper tests
and the contract tests keep them so."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import point_defaults, prismatic_legs
from parakin.generator.model import POSE_POSITION, POSE_ROTATION
from parakin.mechanisms import planar_3rrr, prs3, stewart

SAMPLES = 300


def test_six_prismatic_legs_reproduce_the_hand_derived_block():
    """stewart's kind of model: closure rows, rate matrices and inverse lengths equal
    ``blocks.PrismaticLegs`` (written by hand) as expressions."""
    base, platform = sp.Matrix(6, 3, sp.symbols("a0:18")), sp.Matrix(6, 3, sp.symbols("b0:18"))
    lengths = sp.symbols("l1:7", positive=True)
    legs = [joints.prismatic_leg(base.row(k).T, platform.row(k).T, lengths[k]) for k in range(6)]
    model = joints.DistanceMechanism(joints.platform("transform"), legs)
    hand = prismatic_legs(base, platform, model.motion.rotation, model.motion.position)
    assert list(model.closure().residual[:6]) == list(hand.residual(lengths, squared=True))
    rates, reference = model.rates(), hand.rate_model(lengths)
    assert rates.a == reference.a and rates.b == reference.b and rates.serial_factors == reference.serial_factors
    steps = dict(model.inverse().steps)
    by_pose = prismatic_legs(base, platform, POSE_ROTATION, POSE_POSITION).inverse_steps(lengths)
    assert all(steps[length] == value for length, value in by_pose)


def test_legs_refuse_directions_that_are_not_unit_or_not_normal():
    theta = sp.Symbol("theta")
    with pytest.raises(ValueError, match="crank's axis must be a unit vector"):
        joints.crank_leg([0, 0, 0], [0, 0, 2], [1, 0, 0], 0.1, 0.3, [0, 0, 0], theta)
    with pytest.raises(ValueError, match="must be normal to its axis"):
        joints.crank_leg([0, 0, 0], [0, 0, 1], [0, 0.6, 0.8], 0.1, 0.3, [0, 0, 0], theta)
    with pytest.raises(ValueError, match="slider's axis must be a unit vector"):
        joints.slider_leg([0, 0, 0], [1, 1, 0], 0.3, [0, 0, 0], theta)
    with pytest.raises(ValueError, match="revolute axis .* must be normal to the slider's axis"):
        joints.slider_leg([0, 0, 0], [0, 0, 1], 0.3, [0, 0, 0], theta, revolute_axis=[0, 0.6, 0.8])
    with pytest.raises(ValueError, match="1 to 3 coordinates"):
        joints.prismatic_leg([0, 0, 0, 0], [0, 0, 0], theta)
    # directions written with parameters are accepted as given (their values are not known here)
    u = sp.Matrix(sp.symbols("u_x u_y u_z"))
    assert joints.crank_leg([0, 0, 0], u, [1, 0, 0], 0.1, 0.3, [0, 0, 0], theta).axis == u
    # the same slider leg written joint by joint: refused by the distance form (it was taken for a
    # fixed plane, (C - A) . n = 0, where the plane moves with the stroke)
    rail = joints.Joint("P", "base", sp.Matrix([0, 0, 0]), sp.Matrix([0, 0, 1]), theta, actuated=True)
    tilted = joints.Joint("R", "elbow", None, sp.Matrix([0, 0.6, 0.8]))
    end = joints.Joint("S", "platform", sp.Matrix([0, 0, 0]))
    with pytest.raises(ValueError, match="not normal to the slider's axis .* no subproblem matches"):
        joints.distance_form(joints.Chain("leg", (rail, tilted, end), link=0.3))


def test_a_model_refuses_a_leg_count_that_does_not_match_its_motion():
    leg = joints.prismatic_leg([0, 0, 0], [0, 0, 0], sp.Symbol("l"))
    with pytest.raises(ValueError, match="one leg per degree of freedom"):
        joints.DistanceMechanism(joints.platform("planar"), [leg, leg])
    with pytest.raises(ValueError, match="unknown pose kind"):
        joints.platform("screw")


class _Numeric:
    """The model's inverse, closure and rate model as NumPy functions at fixed parameters."""

    def __init__(self, model: joints.DistanceMechanism, values: dict) -> None:
        self.model, inverse = model, model.inverse()
        known = [*POSE_ROTATION, *POSE_POSITION, *inverse.branches]
        self.steps = []
        for target, expression in inverse.steps:
            self.steps.append((target, sp.lambdify(known, expression.xreplace(values), "numpy")))
            known.append(target)
        self.validity = [sp.lambdify(known, v.xreplace(values), "numpy") for v in inverse.validity.values()]
        self.branches = list(itertools.product((1, -1), repeat=len(inverse.branches)))
        state = [*model.actuated, *model.motion.coordinates]
        self.residual = sp.lambdify(state, model.closure().residual.xreplace(values), "numpy")
        self.pose = sp.lambdify(model.motion.coordinates, model.closure().pose.xreplace(values), "numpy")
        rates = model.rates()
        self.a = sp.lambdify(state, rates.a.xreplace(values), "numpy")
        self.b = sp.lambdify(state, rates.b.xreplace(values), "numpy")
        self.columns = [joints.TWIST.index(name) for name in rates.twist]
        (factor,) = model.parallel_factors().values()
        self.parallel = sp.lambdify(state, factor.xreplace(values), "numpy")

    def inverse(self, pose: np.ndarray, branch: int) -> tuple[np.ndarray, np.ndarray, bool]:
        """(actuated, coordinates, valid) of one pose (4 x 4) on one branch."""
        args = [*pose[:3, :3].ravel(), *pose[:3, 3], *self.branches[branch]]
        out = {}
        for target, function in self.steps:
            out[target] = float(function(*args))
            args.append(out[target])
        valid = all(float(v(*args)) > 1e-6 for v in self.validity)
        actuated = np.array([out[v] for v in self.model.actuated])
        return actuated, np.array([out[v] for v in self.model.motion.coordinates]), valid


def _check(model: joints.DistanceMechanism, values: dict, poses: list[np.ndarray]) -> tuple[int, int]:
    """Every valid branch closes the loop at the pose's coordinates and reproduces the pose; on
    branch 0 the rate model holds against central differences of the inverse along a random
    motion. Returns (branch cases, rate cases) checked."""
    numeric = _Numeric(model, values)
    rng = np.random.default_rng(4)
    closed = rated = 0
    for pose in poses:
        for branch in range(len(numeric.branches)):
            theta, q, valid = numeric.inverse(pose, branch)
            if not valid:
                continue
            assert np.abs(numeric.residual(*theta, *q)).max() < 1e-9
            assert np.abs(numeric.pose(*q) - pose).max() < 1e-9
            closed += 1
            if branch:
                continue
            # a motion of the coordinates, the actuated rates and the twist by central differences
            direction, h = rng.standard_normal(q.size), 1e-6
            if model.motion.dimensionless:  # stay on the unit sphere of quaternions
                k = list(model.motion.coordinates).index(model.motion.dimensionless[0])
                direction[k:] -= (direction[k:] @ q[k:]) * q[k:]
            ends = [numeric.pose(*(q + s * h * direction)) for s in (1, -1)]
            turned = [numeric.inverse(e, 0) for e in ends]
            if not all(t[2] for t in turned):
                continue
            rates = (turned[0][0] - turned[1][0]) / (2 * h)
            velocity = (ends[0][:3, 3] - ends[1][:3, 3]) / (2 * h)
            spin = (ends[0][:3, :3] - ends[1][:3, :3]) / (2 * h) @ pose[:3, :3].T  # [w]x = R_dot R^T
            twist = np.concatenate([velocity, [spin[2, 1], spin[0, 2], spin[1, 0]]])[numeric.columns]
            a, b = np.asarray(numeric.a(*theta, *q), float), np.asarray(numeric.b(*theta, *q), float)
            assert np.abs(a @ twist - b @ rates).max() < 1e-6 * (1 + np.abs(a @ twist).max())
            # the parallel factor, however it is written, is det A
            assert abs(float(numeric.parallel(*theta, *q)) - np.linalg.det(a)) < 1e-9 * (1 + abs(np.linalg.det(a)))
            rated += 1
    return closed, rated


def _poses(kind: str, centre: np.ndarray, spread: float, count: int, seed: int) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    poses = []
    for _ in range(count):
        pose = np.eye(4)
        pose[:3, 3] = centre + spread * rng.standard_normal(3) * (np.array([1, 1, 0]) if kind == "planar" else 1)
        if kind == "planar":
            angle = 0.3 * rng.standard_normal()
            pose[:2, :2] = [[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]]
        elif kind == "transform":
            axis = rng.standard_normal(3)
            angle, k = 0.2 * rng.standard_normal(), axis / np.linalg.norm(axis)  # Rodrigues
            skew = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
            pose[:3, :3] = np.eye(3) + math.sin(angle) * skew + (1 - math.cos(angle)) * skew @ skew
        poses.append(pose)
    return poses


def test_stewart_six_prismatic_legs_close_and_rate():
    values = {
        **point_defaults(stewart.BASE, stewart.DIETMAIER_BASE),
        **point_defaults(stewart.PLATFORM, stewart.DIETMAIER_PLATFORM),
    }
    centre = np.array(stewart.DIETMAIER_POSITION)
    poses = [p for p in _poses("transform", centre, 0.05, SAMPLES, 1)]
    for p in poses:
        p[:3, :3] = p[:3, :3] @ np.array(stewart.DIETMAIER_ROTATION)
    closed, rated = _check(stewart.MODEL, values, poses)
    assert closed == SAMPLES and rated >= SAMPLES * 0.9


def test_planar_three_crank_legs_close_and_rate_on_every_branch():
    closed, rated = _check(
        planar_3rrr.MODEL, planar_3rrr.defaults(), _poses("planar", np.zeros(3), 0.05, SAMPLES // 3, 2)
    )
    assert closed >= 4 * (SAMPLES // 3) and rated >= 0.9 * (SAMPLES // 3)  # several of the 8 branches each


def _circle(radius: float, k: int, z: float = 0.0) -> list[float]:
    angle = 2 * math.pi * k / 3
    return [radius * math.cos(angle), radius * math.sin(angle), z]


def test_spatial_crank_legs_about_tilted_axes_close_and_rate():
    """A 3-RUS (delta-like) on a translating platform: cranks about the tangents of a circle,
    zero direction radial, links of fixed length."""
    theta = sp.symbols("t1:4", real=True)
    legs = []
    for k in range(3):
        angle = 2 * math.pi * k / 3
        axis = [-math.sin(angle), math.cos(angle), 0.0]
        legs.append(joints.crank_leg(_circle(0.2, k), axis, _circle(1.0, k), 0.15, 0.4, _circle(0.06, k), theta[k]))
    model = joints.DistanceMechanism(joints.platform("translation"), legs, parallel_name="links_coplanar")
    closed, rated = _check(model, {}, _poses("translation", np.array([0.0, 0.0, -0.35]), 0.03, SAMPLES // 3, 3))
    assert closed >= 4 * (SAMPLES // 3) and rated >= 0.9 * (SAMPLES // 3)
    assert set(model.parallel_factors()) == {"links_coplanar"}


def test_slider_legs_on_vertical_rails_close_and_rate():
    """A linear delta (3-PSS, translating platform): sliders on vertical rails, links of fixed length."""
    strokes = sp.symbols("s1:4", real=True)
    legs = [joints.slider_leg(_circle(0.3, k), [0, 0, 1], 0.35, _circle(0.1, k), strokes[k]) for k in range(3)]
    model = joints.DistanceMechanism(joints.platform("translation"), legs)
    closed, rated = _check(model, {}, _poses("translation", np.array([0.0, 0.0, 0.1]), 0.03, SAMPLES // 3, 5))
    assert closed >= 8 * (SAMPLES // 3) * 0.9 and rated >= 0.9 * (SAMPLES // 3)


def test_planar_prismatic_legs_close_and_rate():
    """A 3-RPR on a planar platform."""
    lengths = sp.symbols("l1:4", positive=True)
    legs = [joints.prismatic_leg(_circle(0.5, k), _circle(0.2, k + 0.5), lengths[k]) for k in range(3)]
    model = joints.DistanceMechanism(joints.platform("planar"), legs)
    closed, rated = _check(model, {}, _poses("planar", np.zeros(3), 0.05, SAMPLES // 3, 6))
    assert closed == SAMPLES // 3 and rated >= 0.9 * (SAMPLES // 3)


def test_prs_legs_constrain_the_platform_and_rate_with_constraint_wrenches():
    """3-PRS (``prs3.MODEL``, P-R-S legs: lower mobility): at reachable poses (Z-Y-Z Euler
    (alpha, beta, -alpha) with the parasitic centre, ``prs3.euler_pose``) every valid branch
    closes the loop (plane rows included) and reproduces the pose; along a motion of (alpha,
    beta, height) the twist by central differences satisfies the constraint wrenches (C twist = 0)
    and A twist = B rates with the rates by central differences of the inverse; the parallel
    factor is det [A; C]."""
    model, values = prs3.MODEL, prs3.DEFAULTS
    numeric = _Numeric(model, values)
    rates_model = model.rates()
    assert rates_model.constraints is not None and rates_model.constraints.shape == (3, 6)
    state = [*model.actuated, *model.motion.coordinates]
    constraints = sp.lambdify(state, rates_model.constraints.xreplace(values), "numpy")
    rng = np.random.default_rng(9)
    closed = rated = 0
    for _ in range(SAMPLES // 3):
        alpha, beta, height = rng.uniform(-np.pi, np.pi), rng.uniform(0, 0.5), rng.uniform(0.4, 0.7)
        pose = np.array(prs3.euler_pose(alpha, beta, height), dtype=float)
        for branch in range(len(numeric.branches)):
            theta, q, valid = numeric.inverse(pose, branch)
            if not valid:
                continue
            assert np.abs(numeric.residual(*theta, *q)).max() < 1e-9
            assert np.abs(numeric.pose(*q) - pose).max() < 1e-9
            closed += 1
            if branch:
                continue
            direction, h = rng.standard_normal(3) * [1.0, 0.3, 0.1], 1e-6
            ends = [
                np.array(prs3.euler_pose(*(np.array([alpha, beta, height]) + s * h * direction)), float)
                for s in (1, -1)
            ]
            turned = [numeric.inverse(e, 0) for e in ends]
            rates = (turned[0][0] - turned[1][0]) / (2 * h)
            velocity = (ends[0][:3, 3] - ends[1][:3, 3]) / (2 * h)
            spin = (ends[0][:3, :3] - ends[1][:3, :3]) / (2 * h) @ pose[:3, :3].T
            twist = np.concatenate([velocity, [spin[2, 1], spin[0, 2], spin[1, 0]]])
            a, b = np.asarray(numeric.a(*theta, *q), float), np.asarray(numeric.b(*theta, *q), float)
            c = np.asarray(constraints(*theta, *q), float)
            assert np.abs(c @ twist).max() < 1e-6 * np.abs(twist).max()
            assert np.abs(a @ twist - b @ rates).max() < 1e-6 * (1 + np.abs(a @ twist).max())
            overall = np.linalg.det(np.vstack([a, c]))
            assert abs(float(numeric.parallel(*theta, *q)) - overall) < 1e-9 * (1 + abs(overall))
            rated += 1
    assert closed >= SAMPLES // 3 and rated >= 0.9 * (SAMPLES // 3)
