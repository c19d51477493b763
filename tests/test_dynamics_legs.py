"""parakin.dynamics with legs of mass (issue 34): the tree of the legs' serial chains, its loop
closures and its recursive Newton-Euler, checked against two engines and two identities.

Claims, each against an independent source:
* projected ``mj_inverse`` of the exported MJCF (``to_mjcf`` with the same link inertias: one
  robot in both) = ``inverse_dynamics(..., leg_inertias=...)`` to 1e-6 relative at 8 samples of a
  trajectory for five_bar, delta (parallelograms as four bars), stewart and the lower-mobility
  prs3; MuJoCo closes the loops and differentiates them with its own site Jacobians and
  ``mj_jacDot`` (``parakin.mujoco_bridge``), parakin with its own tree code; slow: every
  mechanism with a joint graph (13);
* Pinocchio's RNEA on the same MJCF (``pinocchio.buildModelFromMJCF``, its own loop Jacobians
  from the cut sites' frames and J_dot v from ``getFrameClassicalAcceleration``), projected onto
  the actuated joints = parakin's to 1e-6 (five_bar, prs3; delta and stewart slow);
* tau = Y theta with the legs' columns to 1e-12 (five_bar, prs3; delta and stewart slow; a batch; Y by Jacobian transposes of each
  body's force per parameter, tau by the recursive pass);
* power balance: tau . q_dot = dK/dt + dV/dt along a trajectory to 1e-6, K summed over the
  platform (from ``forward_rate``) and every link (from the tree's body twists), dK/dt by
  fourth-order central differences (five_bar; prs3 and stewart slow);
* the tree's own kinematics carry a free platform exactly as the generated rate model does:
  the platform's inertia put on the tree's platform body gives the massless-leg efforts;
* without an A/B rate model (sam) the tree carries the platform: twist = forward_rate, twist
  rate = its differences, efforts = projected mj_inverse, Y theta = tau.
"""

from pathlib import Path

import numpy as np
import pytest

import parakin
from parakin import dynamics
from parakin.dynamics import (
    RigidInertia,
    dynamics_regressor,
    inverse_dynamics,
    leg_parameters,
    leg_tree,
    link_inertias,
    rigid_inertia,
)
from parakin.errors import BadInputError, ParakinError

SAMPLES = 8
#: the trajectory's amplitude: rad for a revolute actuator, m for a prismatic one
AMPLITUDE = {True: 0.15, False: 0.01}
#: the platform (2 kg) as to_mjcf writes it: a sphere of this radius (a point platform turns with
#: the link it ends in MuJoCo, not in parakin: its rotational inertia, 8e-9 kg m^2, is negligible)
PLATFORM_MASS, PLATFORM_RADIUS = 2.0, 1e-4
PLATFORM = rigid_inertia(PLATFORM_MASS, inertia=np.full(3, 0.4 * PLATFORM_MASS * PLATFORM_RADIUS**2))


def gravity(m: parakin.Mechanism) -> np.ndarray:
    """to_mjcf's gravity: standard gravity, 9.80665 m/s^2, along -y for a planar mechanism, -z otherwise."""
    planar = m.manifest.pose_kind in ("planar", "planar_translation")
    return np.array((0.0, -9.80665, 0.0) if planar else (0.0, 0.0, -9.80665))


def trajectory(m: parakin.Mechanism, t: float, scale: float = 1.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """q(t) = home + A sin(2 t + phase): smooth, every derivative non-zero."""
    amplitude = scale * np.array([AMPLITUDE[variable.revolute] for variable in m.manifest.actuated])
    phase = np.arange(len(m.actuated_names))
    q = m.home_actuated + amplitude * np.sin(2.0 * t + phase)
    return q, 2.0 * amplitude * np.cos(2.0 * t + phase), -4.0 * amplitude * np.sin(2.0 * t + phase)


def random_links(m: parakin.Mechanism, seed: int) -> dict[str, RigidInertia]:
    """Every link its own body: a mass of 0.2 to 1.5 kg, a centre off the rod's, a full inertia."""
    rng = np.random.default_rng(seed)
    out = {}
    for name, rod in link_inertias(m, 1.0).items():
        assert rod is not None
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        principal = rng.uniform(0.5, 1.0, 3) * 1e-3
        out[name] = rigid_inertia(
            rng.uniform(0.2, 1.5), rod.centre + rng.normal(size=3) * 0.02, q @ np.diag(principal) @ q.T
        )
    return out


def home(m: parakin.Mechanism) -> parakin.Configuration:
    return m.forward_pose(m.home_actuated, guess=m.home_passive)


# ------------------------------------------------------------------------------------ MuJoCo
def mujoco_agreement(name: str, seed: int, scale: float = 1.0) -> tuple[list[float], list[float]]:
    """At 8 samples: |projected mj_inverse - inverse_dynamics| / |tau| with the same random link
    inertias in both, and the legs' share of the efforts."""
    mujoco = pytest.importorskip("mujoco")
    from parakin import mujoco_bridge as bridge

    m = parakin.load(name, backend="numpy")
    links = random_links(m, seed)
    xml = m.to_mjcf(modes="none", link_mass=links, platform_mass=PLATFORM_MASS, platform_radius=PLATFORM_RADIUS)
    model = mujoco.MjModel.from_xml_string(xml)
    chain = bridge.closed_chain(model, list(m.actuated_names), "platform")
    data = mujoco.MjData(model)  # qpos0: the home
    g = gravity(m)
    assert np.allclose(model.opt.gravity, g, rtol=0, atol=1e-15)
    state = home(m)
    errors, legs_share = [], []
    for t in np.linspace(0.0, 1.4, SAMPLES):
        q, qd, qdd = trajectory(m, t, scale)
        assert bridge.assemble(chain, data, q, qd, qdd) < 1e-12
        state = m.forward_pose(q, guess=state)
        assert np.abs(bridge.platform_pose(chain, data)[:3, 3] - state.pose[:3, 3]).max() < 1e-9
        engine = bridge.projected_inverse(chain, data)
        ours = inverse_dynamics(m, state, qd, qdd, platform_inertia=PLATFORM, gravity=g, leg_inertias=links).efforts
        massless = inverse_dynamics(m, state, qd, qdd, platform_inertia=PLATFORM, gravity=g).efforts
        errors.append(np.abs(engine - ours).max() / np.abs(engine).max())
        legs_share.append(np.abs(ours - massless).max() / np.abs(ours).max())
    return errors, legs_share


@pytest.mark.parametrize("name", ["five_bar", "delta", "stewart", "prs3"])
def test_legs_equal_projected_mj_inverse_of_the_exported_model(name):
    errors, legs_share = mujoco_agreement(name, 1)
    assert len(errors) == SAMPLES
    assert min(legs_share) > 0.05, f"{name}: the legs change the efforts by only {min(legs_share):.3g}"
    assert max(errors) < 1e-6, f"{name}: projected mj_inverse vs inverse_dynamics with legs {max(errors):.3g} relative"


@pytest.mark.slow
def test_every_exported_mechanism_with_legs_equals_projected_mj_inverse():
    """Every mechanism with a joint graph (all but sphere2r; sam's serial chains along a fifth
    of the amplitude, where MuJoCo's Newton keeps its branch), 8 samples each, 1e-6 relative."""
    checked = {}
    for name in parakin.available():
        graph = parakin.load(name, backend="numpy").manifest.joints
        if graph is None:
            continue
        errors, legs_share = mujoco_agreement(name, 5, 0.2 if any(leg.serial for leg in graph.legs) else 1.0)
        assert max(errors) < 1e-6 and min(legs_share) > 0.01, (name, max(errors), min(legs_share))
        checked[name] = max(errors)
    assert len(checked) >= 13, checked


# --------------------------------------------------------------------------------- Pinocchio
def pinocchio_projected_rnea(pin, mujoco, model, pmodel, pdata, qpos, qd, qdd, actuated):
    """Pinocchio's RNEA of the tree at MuJoCo's closed qpos, its velocities and accelerations from
    its own loop Jacobian (the cut sites' frames) and J_dot v, projected on the actuated joints."""
    # both readers lay the joints out depth first in the file's order (a body's two hinges are
    # one composite joint in Pinocchio): the same coordinates, but for a free joint, whose
    # Pinocchio coordinates are its body's pose relative to the body's placement in the file
    assert pmodel.nq == model.nq
    q = np.array(qpos, dtype=float)
    for j in range(model.njnt):
        if int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_FREE):
            address = int(model.jnt_qposadr[j])
            rotation = np.zeros(9)
            mujoco.mju_quat2Mat(rotation, qpos[address + 3 : address + 7])
            world = pin.SE3(rotation.reshape(3, 3), qpos[address : address + 3])
            placement = pmodel.jointPlacements[pmodel.getJointId(model.joint(j).name)]
            q[address : address + 7] = pin.SE3ToXYZQUAT(placement.inverse() * world)
    world = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    pin.computeJointJacobians(pmodel, pdata, q)
    pin.updateFramePlacements(pmodel, pdata)
    pairs = [
        tuple(
            pmodel.getFrameId(model.site(int(s)).name, pin.FrameType.OP_FRAME)
            for s in (model.eq_obj1id[e], model.eq_obj2id[e])
        )
        for e in range(model.neq)
    ]
    gaps = [pdata.oMf[a].translation - pdata.oMf[b].translation for a, b in pairs]
    assert np.abs(gaps).max() < 1e-11
    jacobian = np.concatenate(
        [
            pin.getFrameJacobian(pmodel, pdata, a, world)[:3] - pin.getFrameJacobian(pmodel, pdata, b, world)[:3]
            for a, b in pairs
        ]
    )
    act = [pmodel.idx_vs[pmodel.getJointId(name)] for name in actuated]
    passive = [i for i in range(pmodel.nv) if i not in act]
    gamma = np.zeros((pmodel.nv, len(act)))
    gamma[act] = np.eye(len(act))
    gamma[passive] = np.linalg.lstsq(jacobian[:, passive], -jacobian[:, act], rcond=None)[0]
    velocity = gamma @ qd
    pin.forwardKinematics(pmodel, pdata, q, velocity, np.zeros(pmodel.nv))
    bias = np.concatenate(
        [
            pin.getFrameClassicalAcceleration(pmodel, pdata, a, world).linear
            - pin.getFrameClassicalAcceleration(pmodel, pdata, b, world).linear
            for a, b in pairs
        ]
    )
    acceleration = np.zeros(pmodel.nv)
    acceleration[act] = qdd
    acceleration[passive] = np.linalg.lstsq(jacobian[:, passive], -jacobian[:, act] @ qdd - bias, rcond=None)[0]
    return gamma.T @ pin.rnea(pmodel, pdata, q, velocity, acceleration)


@pytest.mark.parametrize(
    "name", ["five_bar", "prs3", *(pytest.param(n, marks=pytest.mark.slow) for n in ("delta", "stewart"))]
)
def test_legs_equal_pinocchio_rnea_projected(name, tmp_path):
    mujoco = pytest.importorskip("mujoco")
    pin = pytest.importorskip("pinocchio")
    from parakin import mujoco_bridge as bridge

    m = parakin.load(name, backend="numpy")
    links = random_links(m, 2)
    xml = m.to_mjcf(modes="none", link_mass=links, platform_mass=PLATFORM_MASS, platform_radius=PLATFORM_RADIUS)
    model = mujoco.MjModel.from_xml_string(xml)
    chain = bridge.closed_chain(model, list(m.actuated_names), "platform")
    data = mujoco.MjData(model)
    # Pinocchio's MJCF reader takes one tree: the legs and the platform under one fixed base body
    path = Path(tmp_path) / f"{name}.xml"
    path.write_text(
        xml.replace("<worldbody>", '<worldbody><body name="base">').replace("</worldbody>", "</body></worldbody>")
    )
    pmodel = pin.buildModelFromMJCF(str(path))
    pmodel.gravity.linear = gravity(m)
    pdata = pmodel.createData()
    assert pmodel.nv == model.nv
    state, errors = home(m), []
    for t in np.linspace(0.0, 1.4, SAMPLES):
        q, qd, qdd = trajectory(m, t)
        bridge.assemble(chain, data, q)  # positions only: Pinocchio does the rates itself
        engine = pinocchio_projected_rnea(
            pin, mujoco, model, pmodel, pdata, np.array(data.qpos), qd, qdd, m.actuated_names
        )
        state = m.forward_pose(q, guess=state)
        ours = inverse_dynamics(m, state, qd, qdd, platform_inertia=PLATFORM, gravity=gravity(m), leg_inertias=links)
        errors.append(np.abs(engine - ours.efforts).max() / np.abs(engine).max())
    assert len(errors) == SAMPLES
    assert max(errors) < 1e-6, f"{name}: Pinocchio's projected RNEA vs inverse_dynamics with legs {max(errors):.3g}"


# ------------------------------------------------------------------------- identities
@pytest.mark.parametrize(
    "name", ["five_bar", "prs3", *(pytest.param(n, marks=pytest.mark.slow) for n in ("delta", "stewart"))]
)
def test_regressor_with_legs_times_parameters_equals_efforts(name):
    """Y theta = tau to 1e-12 relative over a batch of 4 samples, theta the platform's ten and
    every link's; the batch equals each sample alone."""
    m = parakin.load(name, backend="numpy")
    links = random_links(m, 3)
    samples = [trajectory(m, t) for t in (0.1, 0.5, 0.9, 1.3)]
    states = [m.forward_pose(s[0], guess=home(m)) for s in samples]
    batch = parakin.Configuration(
        np.stack([s.actuated for s in states]),
        np.stack([s.passive for s in states]),
        np.stack([s.pose for s in states]),
    )
    qd, qdd = np.stack([s[1] for s in samples]), np.stack([s[2] for s in samples])
    platform = rigid_inertia(
        3.0, (0.01, -0.02, 0.005), [[0.02, 0.001, 0.0], [0.001, 0.03, -0.002], [0.0, -0.002, 0.04]]
    )
    y = dynamics_regressor(m, batch, qd, qdd, gravity=gravity(m), leg_inertias=links)
    assert y.shape == (4, len(m.actuated_names), 10 * (1 + len(leg_tree(m).links)))
    theta = np.concatenate([platform.parameters(), leg_parameters(m, links)])
    tau = inverse_dynamics(m, batch, qd, qdd, platform_inertia=platform, gravity=gravity(m), leg_inertias=links).efforts
    checked = 0
    for k in range(4):
        assert np.abs(y[k] @ theta - tau[k]).max() <= 1e-12 * np.abs(tau[k]).max()
        alone = inverse_dynamics(
            m, states[k], qd[k], qdd[k], platform_inertia=platform, gravity=gravity(m), leg_inertias=links
        )
        assert np.abs(alone.efforts - tau[k]).max() <= 1e-13 * np.abs(tau[k]).max()
        checked += 1
    assert checked == 4


def body_energy(body: RigidInertia, rotation, origin, twist, g) -> tuple[float, float]:
    """Kinetic energy and gravity's power on a body of spatial velocity ``twist`` (w; v at the
    origin of {B}) with its frame at (rotation, origin)."""
    w, v0 = twist[:3], twist[3:]
    centre = rotation @ body.centre + origin
    v_c = v0 + np.cross(w, centre)
    inertia = rotation @ body.inertia @ rotation.T
    return 0.5 * body.mass * v_c @ v_c + 0.5 * w @ inertia @ w, body.mass * g @ v_c


@pytest.mark.parametrize("name", ["five_bar", *(pytest.param(n, marks=pytest.mark.slow) for n in ("prs3", "stewart"))])
def test_power_balance_with_legs(name):
    """tau . q_dot = dK/dt - (power of gravity) at 8 instants to 1e-6 relative, K over the
    platform (its twist from forward_rate) and every link (its twist from the tree's joint rates),
    dK/dt by fourth-order central differences (step 1e-4) along q(t)."""
    m = parakin.load(name, backend="numpy")
    links = random_links(m, 4)
    tree = leg_tree(m)
    bodies = dynamics._tree_bodies(m, links)
    g = gravity(m)

    def energy(t, near):
        q, qd, qdd = trajectory(m, t)
        state = m.forward_pose(q, guess=near)
        twist = np.zeros(6)
        for column, component in enumerate(m.manifest.capabilities.rates.twist):
            twist[("vx", "vy", "vz", "wx", "wy", "wz").index(component)] = m.forward_rate(state, qd)[column]
        v, w = twist[:3], twist[3:]
        origin = state.pose[:3, 3]
        kinetic, power = body_energy(PLATFORM, state.rotation, origin, np.concatenate([w, v - np.cross(w, origin)]), g)
        (joints,) = dynamics._tree_states(m, tree, q[None], state.pose[None])
        motion = dynamics._tree_motion(tree, m, joints, qd, qdd, g)
        for i, body in enumerate(bodies):
            if body is not None:
                k, p = body_energy(body, *motion.frames[i], motion.velocities[i], g)
                kinetic, power = kinetic + k, power + p
        return kinetic, power

    checked, state = 0, home(m)
    for t in np.linspace(0.0, 1.4, SAMPLES):
        q, qd, qdd = trajectory(m, t)
        state = m.forward_pose(q, guess=state)
        h = 1e-4
        k = [energy(t + s * h, state)[0] for s in (-2, -1, 1, 2)]
        kinetic_rate = (8 * (k[2] - k[1]) - (k[3] - k[0])) / (12 * h)
        gravity_power = energy(t, state)[1]
        tau = inverse_dynamics(m, state, qd, qdd, platform_inertia=PLATFORM, gravity=g, leg_inertias=links).efforts
        power = tau @ qd
        scale = np.linalg.norm(tau) * np.linalg.norm(qd)
        assert abs(power - (kinetic_rate - gravity_power)) <= 1e-6 * scale, (
            f"{name} t = {t}: tau . qdot = {power:.12g} W, dK/dt - P_gravity = {kinetic_rate - gravity_power:.12g} W"
        )
        checked += 1
    assert checked == SAMPLES


@pytest.mark.parametrize("name", ["delta", "stewart", "prs3"])
def test_the_tree_moves_a_free_platform_as_the_rate_model_does(name):
    """The platform's inertia on the tree's platform body (legs massless) gives the efforts of the
    generated rate model's Newton-Euler path to 1e-10 relative: the tree's closure kinematics
    (positions by Newton, rates and accelerations from the cuts) against the generated ones."""
    m = parakin.load(name, backend="numpy")
    tree = leg_tree(m)
    platform = rigid_inertia(4.0, (0.01, 0.02, -0.03), [[0.05, 0.002, 0.0], [0.002, 0.04, 0.001], [0.0, 0.001, 0.06]])
    bodies = [platform if body.platform else None for body in tree.bodies]
    g = np.array([0.5, -0.3, -9.81])
    checked, state = 0, home(m)
    for t in (0.2, 0.7, 1.2):
        q, qd, qdd = trajectory(m, t)
        state = m.forward_pose(q, guess=state)
        (joints,) = dynamics._tree_states(m, tree, q[None], state.pose[None])
        through_tree = dynamics._tree_efforts(tree, dynamics._tree_motion(tree, m, joints, qd, qdd, g), bodies)
        expected = inverse_dynamics(m, state, qd, qdd, platform_inertia=platform, gravity=g).efforts
        assert np.abs(through_tree - expected).max() <= 1e-10 * np.abs(expected).max()
        checked += 1
    assert checked == 3


def test_leg_inertias_forms_and_errors():
    """A link mass is every link a rod (to_mjcf's link_mass: the MJCF's inertials are those
    bodies'), a mapping names bodies (others massless), bad forms are BadInputErrors."""
    m = parakin.load("five_bar", backend="numpy")
    rods = link_inertias(m, 0.5)
    assert list(rods) == ["leg1_link1", "leg1_link2", "leg2_link1", "leg2_link2"]
    first = rods["leg1_link1"]
    assert first is not None and first.mass == 0.5
    a = m.parameters["a1"]
    # a uniform rod of length a1 from the base joint: centre at a1 / 2, m a^2 / 12 + m 1e-4 across it
    assert abs(np.linalg.norm(first.centre) - a / 2) < 1e-15
    assert abs(first.inertia[2, 2] - 0.5 * (a**2 / 12 + 1e-4)) < 1e-15
    only = link_inertias(m, {"leg2_link2": 0.3})
    assert only["leg1_link1"] is None and only["leg2_link2"] is not None
    for bad, match in (
        ([1.0], "leg_inertias must be"),
        ({"leg9": 1.0}, "not link bodies"),
        ({"leg1_link1": "x"}, "inertia of leg1_link1"),
    ):
        with pytest.raises(BadInputError, match=match):
            link_inertias(m, bad)
    with pytest.raises(BadInputError, match="not link bodies"):
        m.to_mjcf(modes="none", link_mass={"leg9": 1.0})
    # a Stewart platform of other joints: the manifest's home lengths do not close, so the legs
    # cannot be laid out there (the bodies' frames are the home's)
    angles = np.radians([-15, 15, 105, 135, 225, 255]), np.radians([-40, 40, 80, 160, 200, 280])
    base, plat = (
        [[r * np.cos(a), r * np.sin(a), 0.0] for a in angle] for r, angle in zip((0.5, 0.3), angles, strict=True)
    )
    other = parakin.load("stewart", backend="numpy", base=base, platform=plat)
    pose = np.eye(4)
    pose[2, 3] = 0.6
    state = other.inverse_pose(pose).branch(0)
    with pytest.raises(ParakinError, match="laid out at the manifest's home, which does not close"):
        inverse_dynamics(other, state, np.zeros(6), np.zeros(6), platform_inertia=PLATFORM, leg_inertias=1.0)


def test_without_a_rate_model_the_tree_carries_the_platform():
    """sam (two RRRPRR chains, no A/B rate model): inverse_dynamics runs on the tree alone, the
    platform one of its bodies. Its twist = forward_rate (the leg-Jacobian model) to 1e-12, its
    twist rate = fourth-order central differences of forward_rate to 1e-7; the efforts with legs
    of mass = projected mj_inverse of the exported MJCF to 1e-6 at 8 samples; Y theta = tau."""
    m = parakin.load("sam", backend="numpy")
    errors, legs_share = mujoco_agreement("sam", 6, scale=0.2)
    assert len(errors) == SAMPLES and min(legs_share) > 0.05
    assert max(errors) < 1e-6, f"sam: projected mj_inverse vs inverse_dynamics {max(errors):.3g}"
    links = random_links(m, 7)
    platform = rigid_inertia(
        3.0, (0.01, -0.02, 0.005), [[0.02, 0.001, 0.0], [0.001, 0.03, -0.002], [0.0, -0.002, 0.04]]
    )
    state, h, checked = home(m), 1e-3, 0
    for t in (0.3, 0.9):
        q, qd, qdd = trajectory(m, t, 0.2)
        state = m.forward_pose(q, guess=state)
        out = inverse_dynamics(m, state, qd, qdd, platform_inertia=platform, gravity=(0, 0, -9.81), leg_inertias=links)
        assert np.abs(out.twist - m.forward_rate(state, qd)).max() <= 1e-12 * np.abs(out.twist).max()

        def twist(s, near=state):
            q_s, qd_s, _ = trajectory(m, s, 0.2)
            return m.forward_rate(m.forward_pose(q_s, guess=near), qd_s)

        differences = (8 * (twist(t + h) - twist(t - h)) - (twist(t + 2 * h) - twist(t - 2 * h))) / (12 * h)
        assert np.abs(out.twist_rate - differences).max() <= 1e-7 * np.abs(differences).max()
        y = dynamics_regressor(m, state, qd, qdd, gravity=(0, 0, -9.81), leg_inertias=links)
        theta = np.concatenate([platform.parameters(), leg_parameters(m, links)])
        assert np.abs(y @ theta - out.efforts).max() <= 1e-12 * np.abs(out.efforts).max()
        checked += 1
    assert checked == 2
