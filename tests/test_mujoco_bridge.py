"""parakin's inverse dynamics against two engines, and the MuJoCo bridge.

The references are hand-written models (tests/fixtures/mjcf: a five-bar and a 6-UPS Stewart
platform, loops cut by connect site1/site2, massless legs of 1e-9 kg) and a Pinocchio tree built
here. MuJoCo's side never uses parakin's kinematics: the bridge closes the loops with MuJoCo's own
site Jacobians, sets qvel = Gamma q_dot and qacc from J qacc = -J_dot qvel (``mj_jacDot``), and
projects ``mj_inverse`` onto the actuated joints (Gamma^T qfrc_inverse). Pinocchio's side builds
its own loop Jacobian and J_dot v (``getFrameClassicalAcceleration``) and projects ``rnea`` the
same way. Claims:
* projected mj_inverse = parakin's inverse_dynamics to 1e-6 relative at 8 samples of a trajectory
  (five-bar, Stewart, and the lower-mobility 3-PRS); the massless legs' 1e-9 kg bound the
  agreement near 1e-9; MuJoCo's mobility nv - rank J is the mechanism's (2, 6, 3);
* Pinocchio's projected RNEA = parakin's on the five-bar to 1e-6 at 8 samples;
* a simulation under the platform's weight settles within 0.3 mm / 0.01 deg of ``forward_pose`` at
  the settled actuated values, and ``nearest_mode`` names the mode the start was assembled in.
"""

from pathlib import Path

import numpy as np
import pytest

import parakin
from parakin.dynamics import inverse_dynamics, rigid_inertia
from parakin.errors import BadInputError, ConvergenceError, UnsupportedOperationError

mujoco = pytest.importorskip("mujoco")
from parakin import mujoco_bridge as bridge  # noqa: E402

FIXTURES = Path(__file__).parent / "fixtures" / "mjcf"
SAMPLES = 8


# ------------------------------------------------------------------------------------ five-bar
def five_bar():
    model = mujoco.MjModel.from_xml_path(str(FIXTURES / "five_bar.xml"))
    chain = bridge.closed_chain(model, ["theta1", "theta2"], "platform")
    m = parakin.load("five_bar", backend="numpy")  # d = 0.15, a = 0.2, b = 0.25: the fixture's numbers
    return model, chain, m


def five_bar_guess(data, state, flip=(1, 1)):
    """Elbow angles from the parakin pose (the guess only: MuJoCo's Newton closes the loop)."""
    x, y = state.passive
    for leg, (base, theta) in enumerate(((-0.15, state.actuated[0]), (0.15, state.actuated[1]))):
        elbow = np.array([base + 0.2 * np.cos(theta), 0.2 * np.sin(theta)])
        data.qpos[2 * leg] = theta
        data.qpos[2 * leg + 1] = np.arctan2(y - elbow[1], x - elbow[0]) - theta


def trajectory(home, scale, t):
    """q(t) around ``home``: smooth, every derivative non-zero."""
    n = home.size
    phase = np.arange(n)
    q = home + scale * np.sin(2.0 * t + phase)
    qd = 2.0 * scale * np.cos(2.0 * t + phase)
    qdd = -4.0 * scale * np.sin(2.0 * t + phase)
    return q, qd, qdd


def test_five_bar_projected_mj_inverse_equals_inverse_dynamics():
    model, chain, m = five_bar()
    data = mujoco.MjData(model)
    state = m.forward_pose(m.home_actuated, guess=m.home_passive)
    five_bar_guess(data, state)
    errors = []
    for t in np.linspace(0.0, 1.4, SAMPLES):
        q, qd, qdd = trajectory(m.home_actuated, 0.15, t)
        residual = bridge.assemble(chain, data, q, qd, qdd)
        assert residual < 1e-12
        assert model.nv - np.linalg.matrix_rank(bridge.loop_jacobian(chain, data), tol=1e-9) == 2
        state = m.forward_pose(q, guess=state)
        engine = bridge.projected_inverse(chain, data)
        ours = inverse_dynamics(m, state, qd, qdd, platform_inertia=rigid_inertia(1.0), gravity=(0, -9.81, 0))
        assert np.abs(bridge.platform_pose(chain, data)[:2, 3] - state.pose[:2, 3]).max() < 1e-10
        errors.append(np.abs(engine - ours.efforts).max() / np.abs(ours.efforts).max())
    assert len(errors) == SAMPLES
    assert max(errors) < 1e-6, f"five-bar: projected mj_inverse vs inverse_dynamics {max(errors):.3g} relative"


def pinocchio_five_bar(pin):
    """The fixture's five-bar as a Pinocchio tree (q: theta1, elbow1, theta2, elbow2)."""
    model = pin.Model()
    tiny = pin.Inertia(1e-9, np.zeros(3), 1e-12 * np.eye(3))
    frames = []
    for base, name in ((-0.15, "1"), (0.15, "2")):
        proximal = model.addJoint(0, pin.JointModelRZ(), pin.SE3(np.eye(3), np.array([base, 0, 0])), "theta" + name)
        model.appendBodyToJoint(proximal, tiny, pin.SE3.Identity())
        distal = model.addJoint(proximal, pin.JointModelRZ(), pin.SE3(np.eye(3), np.array([0.2, 0, 0])), "elbow" + name)
        model.appendBodyToJoint(distal, tiny, pin.SE3.Identity())
        if name == "1":  # the 1 kg point mass at P
            model.appendBodyToJoint(
                distal, pin.Inertia(1.0, np.array([0.25, 0, 0]), 1e-12 * np.eye(3)), pin.SE3.Identity()
            )
        end = pin.Frame("end" + name, distal, pin.SE3(np.eye(3), np.array([0.25, 0, 0])), pin.FrameType.OP_FRAME)
        frames.append(model.addFrame(end))
    model.gravity.linear = np.array([0.0, -9.81, 0.0])
    return model, frames


def test_five_bar_pinocchio_rnea_projected_equals_inverse_dynamics():
    pin = pytest.importorskip("pinocchio")
    model, chain, m = five_bar()
    data = mujoco.MjData(model)
    pmodel, (end1, end2) = pinocchio_five_bar(pin)
    pdata = pmodel.createData()
    world = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    state = m.forward_pose(m.home_actuated, guess=m.home_passive)
    five_bar_guess(data, state)
    errors = []
    for t in np.linspace(0.0, 1.4, SAMPLES):
        q, qd, qdd = trajectory(m.home_actuated, 0.15, t)
        bridge.assemble(chain, data, q)  # positions only: Pinocchio does the rates itself
        position = np.array(data.qpos)
        pin.computeJointJacobians(pmodel, pdata, position)
        pin.updateFramePlacements(pmodel, pdata)
        gap = pdata.oMf[end1].translation - pdata.oMf[end2].translation
        assert np.abs(gap).max() < 1e-12
        jacobian = (
            pin.getFrameJacobian(pmodel, pdata, end1, world)[:3] - pin.getFrameJacobian(pmodel, pdata, end2, world)[:3]
        )
        actuated, passive = [0, 2], [1, 3]
        gamma = np.zeros((4, 2))
        gamma[actuated] = np.eye(2)
        gamma[passive] = np.linalg.lstsq(jacobian[:, passive], -jacobian[:, actuated], rcond=None)[0]
        velocity = gamma @ qd
        pin.forwardKinematics(pmodel, pdata, position, velocity, np.zeros(4))
        bias = (
            pin.getFrameClassicalAcceleration(pmodel, pdata, end1, world).linear
            - pin.getFrameClassicalAcceleration(pmodel, pdata, end2, world).linear
        )
        acceleration = np.zeros(4)
        acceleration[actuated] = qdd
        right = -jacobian[:, actuated] @ qdd - bias
        acceleration[passive] = np.linalg.lstsq(jacobian[:, passive], right, rcond=None)[0]
        engine = gamma.T @ pin.rnea(pmodel, pdata, position, velocity, acceleration)
        state = m.forward_pose(q, guess=state)
        ours = inverse_dynamics(m, state, qd, qdd, platform_inertia=rigid_inertia(1.0), gravity=(0, -9.81, 0))
        errors.append(np.abs(engine - ours.efforts).max() / np.abs(ours.efforts).max())
    assert len(errors) == SAMPLES
    assert max(errors) < 1e-6, f"five-bar: Pinocchio projected RNEA vs inverse_dynamics {max(errors):.3g} relative"


# ------------------------------------------------------------------------------------- Stewart
STEWART_INERTIA = rigid_inertia(
    10.0, (0.01, -0.005, 0.02), [[0.3, 0.01, -0.02], [0.01, 0.25, 0.015], [-0.02, 0.015, 0.4]]
)  # the fixture's <inertial>: fullinertia = (Ixx Iyy Izz Ixy Ixz Iyz) about the centre


def stewart():
    model = mujoco.MjModel.from_xml_path(str(FIXTURES / "stewart.xml"))
    chain = bridge.closed_chain(model, [f"l{i}" for i in range(1, 7)], "platform")
    base = [model.body(f"leg{i}").pos.tolist() for i in range(1, 7)]
    platform = [model.site(f"p{i}").pos.tolist() for i in range(1, 7)]
    m = parakin.load("stewart", backend="numpy", base=base, platform=platform)
    return model, chain, m


def stewart_guess(model, data, m, state):
    """Universal-joint angles pointing each leg at its platform joint, the free joint at the pose."""
    base = np.array([model.body(f"leg{i}").pos for i in range(1, 7)])
    platform = np.array([model.site(f"p{i}").pos for i in range(1, 7)])
    ends = platform @ state.rotation.T + state.pose[:3, 3]
    for i in range(6):
        u = (ends[i] - base[i]) / np.linalg.norm(ends[i] - base[i])
        address = model.joint(f"u{i + 1}x").qposadr[0]
        data.qpos[address : address + 2] = np.arctan2(-u[1], u[2]), np.arcsin(u[0])
        data.qpos[model.joint(f"l{i + 1}").qposadr[0]] = state.actuated[i]
    free = model.joint("platform").qposadr[0]
    quaternion = np.zeros(4)
    mujoco.mju_mat2Quat(quaternion, state.rotation.reshape(9))
    data.qpos[free : free + 7] = np.concatenate([state.pose[:3, 3], quaternion])


def stewart_home(m):
    pose = np.eye(4)
    pose[:3, 3] = (0.0, 0.0, 0.6)
    return m.inverse_pose(pose).branch(0)


def test_stewart_projected_mj_inverse_equals_inverse_dynamics():
    model, chain, m = stewart()
    data = mujoco.MjData(model)
    state = stewart_home(m)
    home = state.actuated
    stewart_guess(model, data, m, state)
    errors = []
    for t in np.linspace(0.0, 1.4, SAMPLES):
        q, qd, qdd = trajectory(home, 0.03, t)
        assert bridge.assemble(chain, data, q, qd, qdd) < 1e-12
        assert model.nv - np.linalg.matrix_rank(bridge.loop_jacobian(chain, data), tol=1e-9) == 6
        state = m.forward_pose(q, guess=state)
        engine = bridge.projected_inverse(chain, data)
        ours = inverse_dynamics(m, state, qd, qdd, platform_inertia=STEWART_INERTIA, gravity=model.opt.gravity)
        assert np.abs(bridge.platform_pose(chain, data) - state.pose).max() < 1e-10
        errors.append(np.abs(engine - ours.efforts).max() / np.abs(ours.efforts).max())
    assert len(errors) == SAMPLES
    assert max(errors) < 1e-6, f"Stewart: projected mj_inverse vs inverse_dynamics {max(errors):.3g} relative"


# --------------------------------------------------------------------- prs3 (lower mobility)
PRS3_INERTIA = rigid_inertia(
    5.0, (0.005, 0.01, -0.01), [[0.05, 0.002, -0.003], [0.002, 0.06, 0.001], [-0.003, 0.001, 0.09]]
)  # the fixture's <inertial>


def test_prs3_projected_mj_inverse_equals_inverse_dynamics():
    """A lower-mobility platform (3 dof, its parasitic motion from the legs' constraints):
    mobility nv - rank J = 3 in MuJoCo, and the actuator forces agree at 8 samples."""
    model = mujoco.MjModel.from_xml_path(str(FIXTURES / "prs3.xml"))
    chain = bridge.closed_chain(model, ["d1", "d2", "d3"], "platform")
    m = parakin.load("prs3", backend="numpy")  # r_b = 0.2, r_p = 0.1, L = 0.35: the fixture's numbers
    data = mujoco.MjData(model)
    state = m.forward_pose(m.home_actuated, guess=m.home_passive)
    for i in range(3):  # the guess: each link pointing from its slider at its platform joint
        e = np.array([np.cos(2 * np.pi * i / 3), np.sin(2 * np.pi * i / 3), 0.0])
        link = state.rotation @ (0.1 * e) + state.pose[:3, 3] - (0.2 * e + state.actuated[i] * np.array([0, 0, 1]))
        data.qpos[model.joint(f"d{i + 1}").qposadr[0]] = state.actuated[i]
        data.qpos[model.joint(f"r{i + 1}").qposadr[0]] = np.arctan2(link @ e, link[2])
    free = model.joint("platform").qposadr[0]
    data.qpos[free : free + 3] = state.pose[:3, 3]
    data.qpos[free + 3 : free + 7] = (1, 0, 0, 0)
    errors = []
    for t in np.linspace(0.0, 1.4, SAMPLES):
        q, qd, qdd = trajectory(m.home_actuated, 0.03, t)
        assert bridge.assemble(chain, data, q, qd, qdd) < 1e-12
        jacobian = bridge.loop_jacobian(chain, data)
        assert model.nv - np.linalg.matrix_rank(jacobian, tol=1e-9) == 3
        state = m.forward_pose(q, guess=state)
        assert np.abs(bridge.platform_pose(chain, data) - state.pose).max() < 1e-8  # the fixture's 9 decimals
        engine = bridge.projected_inverse(chain, data)
        ours = inverse_dynamics(m, state, qd, qdd, platform_inertia=PRS3_INERTIA, gravity=model.opt.gravity)
        assert ours.constraint_forces is not None and ours.constraint_forces.shape == (3,)
        errors.append(np.abs(engine - ours.efforts).max() / np.abs(ours.efforts).max())
    assert len(errors) == SAMPLES
    assert max(errors) < 1e-6, f"prs3: projected mj_inverse vs inverse_dynamics {max(errors):.3g} relative"


# ------------------------------------------------------------------------- settling and modes
def with_leg_masses(model, legs, mass):
    """The fixture with real leg masses for simulation (bodies of 1e-9 kg make a stiff, unstable
    system): every body named in ``legs`` gets ``mass`` kg and a rod-like inertia, and every joint
    a little damping so the loop's own vibration dies out."""
    for name in legs:
        body = model.body(name)
        body.mass[0] = mass
        body.inertia[:] = mass * 0.01
    model.dof_damping[:] = 0.05
    mujoco.mj_setConst(model, mujoco.MjData(model))  # the derived quantities of the new masses
    return model


def test_five_bar_settles_on_forward_pose_in_its_mode():
    """1 kg at P under in-plane gravity, servos holding the home command: settled within 0.3 mm of
    forward_pose at the settled angles; both assembly modes (elbows flipped) are kept and named."""
    model, chain, m = five_bar()
    with_leg_masses(model, ["proximal1", "distal1", "proximal2", "distal2"], 0.05)
    modes = m.forward_pose_all(m.home_actuated)
    assert modes.count == 2
    named = []
    for k in range(2):
        data = mujoco.MjData(model)
        five_bar_guess(data, modes.mode(k))
        bridge.assemble(chain, data, m.home_actuated)
        data.ctrl[:] = m.home_actuated
        settled = bridge.settle(chain, data, duration=3.0, speed=1e-7)
        assert settled.settled, f"mode {k}: joint speed {settled.speed:.3g} after {settled.time} s"
        reference = m.forward_pose(settled.actuated, guess=modes.mode(k))
        gap = np.abs(settled.pose[:2, 3] - reference.pose[:2, 3]).max()
        assert gap < 3e-4, f"mode {k}: settled {gap * 1e3:.4f} mm from forward_pose"
        nearest = bridge.nearest_mode(m, chain, data)
        assert nearest.position_error < 3e-4
        named.append(nearest.mode)
    assert named == [0, 1]


def settled_stewart():
    """The Stewart fixture with 0.2 kg legs, assembled at the home and settled under its 10 kg
    platform on the leg servos (2e4 N/m) commanded to the home lengths."""
    model, chain, m = stewart()
    with_leg_masses(model, [f"{part}{i}" for i in range(1, 7) for part in ("leg", "rod")], 0.2)
    data = mujoco.MjData(model)
    state = stewart_home(m)
    stewart_guess(model, data, m, state)
    bridge.assemble(chain, data, state.actuated)
    data.ctrl[:] = state.actuated
    settled = bridge.settle(chain, data, duration=3.0, speed=1e-6)
    assert settled.settled, f"joint speed {settled.speed:.3g} after {settled.time} s"
    return model, chain, m, data, state, settled


def test_stewart_settles_on_forward_pose():
    """The settled pose is within 0.3 mm / 0.01 deg of forward_pose at the settled leg lengths."""
    _, _, m, _, state, settled = settled_stewart()
    reference = m.forward_pose(settled.actuated, guess=state)
    gap = np.linalg.norm(settled.pose[:3, 3] - reference.pose[:3, 3])
    relative = reference.rotation.T @ settled.pose[:3, :3]
    angle = np.degrees(np.arccos(np.clip((np.trace(relative) - 1) / 2, -1, 1)))
    assert gap < 3e-4 and angle < 1e-2, f"settled {gap * 1e3:.4f} mm / {angle:.2e} deg from forward_pose"


@pytest.mark.slow
def test_stewart_nearest_mode_is_the_assembled_one():
    """Of the settled leg lengths' real assembly modes (the all-modes solver, compiled: ~3 s), the
    nearest to MuJoCo's platform is the one tracked from the home the model was assembled in."""
    model, chain, m, data, state, settled = settled_stewart()
    base = [model.body(f"leg{i}").pos.tolist() for i in range(1, 7)]
    platform = [model.site(f"p{i}").pos.tolist() for i in range(1, 7)]
    fast = parakin.load("stewart", base=base, platform=platform)
    nearest = bridge.nearest_mode(fast, chain, data)
    reference = m.forward_pose(settled.actuated, guess=state)
    assert nearest.count >= 2
    assert np.abs(nearest.configuration.pose - reference.pose).max() < 1e-9
    assert nearest.position_error < 3e-4


@pytest.mark.slow
def test_stewart_every_real_mode_kept():
    """Each real assembly mode at the home leg lengths (8 for this geometry; the all-modes solver,
    compiled: ~4 s), assembled in MuJoCo from its own pose, is the nearest mode, and stays: after
    1 s on the leg servos under the 10 kg platform it is within 0.3 mm / 0.01 deg of forward_pose
    tracked from that mode, and nearer that mode's home pose than any other's."""
    model, chain, m = stewart()
    with_leg_masses(model, [f"{part}{i}" for i in range(1, 7) for part in ("leg", "rod")], 0.2)
    base = [model.body(f"leg{i}").pos.tolist() for i in range(1, 7)]
    platform = [model.site(f"p{i}").pos.tolist() for i in range(1, 7)]
    fast = parakin.load("stewart", base=base, platform=platform)
    modes = fast.forward_pose_all(stewart_home(m).actuated)
    assert modes.count == 8
    positions = np.array([modes.mode(k).pose[:3, 3] for k in range(modes.count)])
    for k in range(modes.count):
        data = mujoco.MjData(model)
        stewart_guess(model, data, m, modes.mode(k))
        assert bridge.assemble(chain, data, modes.mode(k).actuated) < 1e-12
        if k == 0:
            assert bridge.nearest_mode(fast, chain, data).mode == 0
        data.ctrl[:] = modes.mode(k).actuated
        settled = bridge.settle(chain, data, duration=1.0, speed=1e-6)
        reference = m.forward_pose(settled.actuated, guess=modes.mode(k))
        gap = np.linalg.norm(settled.pose[:3, 3] - reference.pose[:3, 3])
        relative = reference.rotation.T @ settled.pose[:3, :3]
        angle = np.degrees(np.arccos(np.clip((np.trace(relative) - 1) / 2, -1, 1)))
        assert gap < 3e-4 and angle < 1e-2, f"mode {k}: {gap * 1e3:.4f} mm / {angle:.2e} deg"
        assert np.argmin(np.linalg.norm(positions - settled.pose[:3, 3], axis=1)) == k


def test_bridge_refuses_what_it_cannot_read():
    model, _, _ = five_bar()
    with pytest.raises(BadInputError, match="not in the model"):
        bridge.closed_chain(model, ["theta1", "theta9"], "platform")
    with pytest.raises(BadInputError, match="site"):
        bridge.closed_chain(model, ["theta1", "theta2"], "nowhere")
    anchored = mujoco.MjModel.from_xml_string(
        "<mujoco><worldbody><body name='a'><joint name='j'/><geom size='.1'/><site name='s'/></body></worldbody>"
        "<equality><connect body1='a' anchor='0 0 0'/></equality></mujoco>"
    )
    with pytest.raises(UnsupportedOperationError, match="site1/site2"):
        bridge.closed_chain(anchored, ["j"], "s")


def test_settle_refuses_a_simulation_that_diverges(tmp_path, monkeypatch):
    """A step far too long for the model (1e-9 kg legs, 0.5 s steps): MuJoCo's accelerations go
    non-finite and it resets the state and its clock; ``settle`` says so by name, after a bounded
    number of steps, instead of stepping for ever (its bound was on the clock, which the reset
    moved back)."""
    monkeypatch.chdir(tmp_path)  # MuJoCo writes MUJOCO_LOG.TXT where it runs
    model, chain, m = five_bar()
    model.opt.timestep = 0.5
    data = mujoco.MjData(model)
    data.qvel[:] = 50.0
    with pytest.raises(ConvergenceError, match="diverged"):
        bridge.settle(chain, data, duration=1e4)


def test_the_reference_examples_run():
    """Every Example of parakin.mujoco_bridge runs and prints what it shows: the module's (the
    five-bar exported by to_mjcf, assembled moving) first, then each function's from a fresh
    copy of what it defines (the API page shows them; the docs build leaves them to this test)."""
    import copy
    import doctest

    finder = doctest.DocTestFinder()
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS)
    tests = [t for t in finder.find(bridge) if t.examples]
    module = next(t for t in tests if t.name == bridge.__name__)
    start = dict(module.globs)
    for test in tests:
        if test is not module:
            setup = copy.copy(module)
            setup.globs = dict(start)
            runner.run(setup, clear_globs=False)
            test.globs.update(setup.globs)
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert len(tests) >= 10 and result.failed == 0, result
