"""Legs the MJCF export writes beyond S and R cuts (issue 34). A universal joint at the platform, cut on its own: the 6-SPS ``gough`` exported with
each leg's platform joint a U (the link's idle spin locked at the platform, its base joint then a
ball) instead of the S the package has. Kinematically the same mechanism, so MuJoCo must agree
with parakin as for the export the package describes:

* every real assembly mode a keyframe, assembled (loop gap < 1e-9 m at ``mj_forward``, actuated
  qpos = parakin's to 1e-12), mobility nv - rank J = 6 at each;
* projected ``mj_inverse`` of a payload at rest (with minus without) = ``actuator_forces`` of
  its weight to 1e-7 relative at every keyframe;
* with legs of mass (the cross bodies included) projected ``mj_inverse`` = ``inverse_dynamics``
  at 8 samples of a trajectory to 1e-6 relative (parakin's tree has the same cross bodies and
  ball joints).

A cylindrical joint at the platform (the 3-RPR's first leg, about the plane's normal: the same
planar mechanism): keyframes, mobility 3, statics and legs of mass as above; a prismatic one locks the platform's turn
against that leg (mobility 2). And serial-chain legs (sam: two RRRPRR chains placed by products of exponentials): keyframes,
mobility 6 and the payload's statics as above, the actuated joints parakin's.
"""

import dataclasses

import numpy as np
import pytest

import parakin
from parakin.dynamics import inverse_dynamics, leg_tree, link_inertias, rigid_inertia
from parakin.mjcf import to_mjcf

mujoco = pytest.importorskip("mujoco")
from parakin import mujoco_bridge as bridge  # noqa: E402


class WithGraph:
    """A loaded mechanism seen through another joint graph (its kinematics unchanged)."""

    def __init__(self, m: parakin.Mechanism, graph) -> None:
        self._m, self.manifest = m, dataclasses.replace(m.manifest, joints=graph)

    def __getattr__(self, name):
        return getattr(self._m, name)


def gough_with_universal_cuts() -> WithGraph:
    return with_platform_joint("gough", "U", legs=6)


def weight_wrench(m, model, payload: float) -> np.ndarray:
    """The payload's weight at the platform's origin, (f, 0) in {B} (MuJoCo's gravity), on the
    mechanism's twist components (all six without a rate model)."""
    wrench = np.concatenate([payload * np.array(model.opt.gravity), np.zeros(3)])
    rates = m.manifest.capabilities.rates
    if rates is None:
        return wrench
    return wrench[[("vx", "vy", "vz", "wx", "wy", "wz").index(name) for name in rates.twist]]


def with_platform_joint(name: str, kind: str, legs: int = 1) -> WithGraph:
    """``name`` with the platform joint of its first ``legs`` legs of another kind (same axis)."""
    m = parakin.load(name, backend="numpy")
    graph = m.manifest.joints
    assert graph is not None
    changed = tuple(
        dataclasses.replace(leg, joints=(*leg.joints[:-1], dataclasses.replace(leg.joints[-1], kind=kind)))
        if i < legs
        else leg
        for i, leg in enumerate(graph.legs)
    )
    return WithGraph(m, dataclasses.replace(graph, legs=changed))


def keyframes_mobility_and_statics(m, payload: float = 10.0, modes=None) -> float:
    """Every keyframe assembled with the mechanism's mobility and the mode's pose; returns the
    largest relative difference between the payload's projected mj_inverse and actuator_forces."""
    found = m.forward_pose_all(m.home_actuated)
    wanted = list(range(int(found.count))) if modes is None else list(modes)
    loaded = mujoco.MjModel.from_xml_string(to_mjcf(m, payload=payload, modes=wanted))
    empty = mujoco.MjModel.from_xml_string(to_mjcf(m, payload=0.0, modes=wanted))
    assert loaded.nkey == len(wanted) >= 2
    chain = bridge.closed_chain(loaded, list(m.actuated_names), "platform")
    chain0 = bridge.closed_chain(empty, list(m.actuated_names), "platform")
    errors = []
    for key, k in enumerate(wanted):
        data, data0 = mujoco.MjData(loaded), mujoco.MjData(empty)
        mujoco.mj_resetDataKeyframe(loaded, data, key)
        mujoco.mj_resetDataKeyframe(empty, data0, key)
        mujoco.mj_forward(loaded, data)
        mujoco.mj_forward(empty, data0)
        assert np.abs(bridge.loop_residual(chain, data)).max() < 1e-9
        assert np.abs(data.qpos[chain.actuated_qpos] - m.home_actuated).max() < 1e-12
        jacobian = bridge.loop_jacobian(chain, data)
        assert loaded.nv - np.linalg.matrix_rank(jacobian, tol=1e-9) == len(m.actuated_names)
        assert np.abs(bridge.platform_pose(chain, data) - found.mode(k).pose).max() < 1e-9
        for state in (data, data0):  # at rest: mj_forward left the accelerations of a free fall there
            state.qacc[:] = 0.0
        weight = bridge.projected_inverse(chain, data) - bridge.projected_inverse(chain0, data0)
        expected = m.actuator_forces(found.mode(k), weight_wrench(m, loaded, payload))
        errors.append(np.abs(weight - expected).max() / np.abs(expected).max())
    assert len(errors) == len(wanted)
    return max(errors)


def test_universal_cut_keyframes_mobility_and_statics():
    m = gough_with_universal_cuts()
    text = to_mjcf(m, modes="none")
    assert 'type="ball"' in text and "anchor=" not in text
    model = mujoco.MjModel.from_xml_string(text)
    crosses = [model.body(f"leg{i}_cross") for i in range(1, 7)]
    assert all(int(model.body_dofnum[b.id]) == 1 for b in crosses)  # one hinge each, cut along the other axis
    error = keyframes_mobility_and_statics(m)
    assert error < 1e-7, f"payload's projected mj_inverse vs actuator_forces: {error:.3g}"


def test_serial_chain_legs_export():
    """sam's two RRRPRR chains (placed by products of exponentials): each chain's bodies at the
    home, cut from a free platform at its last revolute joint. Every mode a keyframe, mobility 6,
    the payload's statics; the actuated joints moved and MuJoCo's loops closed by its own Newton
    put the platform where forward_pose does (1e-9)."""
    m = parakin.load("sam", backend="numpy")
    error = keyframes_mobility_and_statics(m)
    assert error < 1e-7, f"sam: payload's projected mj_inverse vs actuator_forces: {error:.3g}"
    model = mujoco.MjModel.from_xml_string(to_mjcf(m, modes="none"))
    chain = bridge.closed_chain(model, list(m.actuated_names), "platform")
    data = mujoco.MjData(model)
    state, checked = m.forward_pose(m.home_actuated, guess=m.home_passive), 0
    for step in (0.01, 0.02, 0.03):
        moved = m.home_actuated + step * np.array([1.0, -1.0, 0.5, -0.5, 0.75, -0.25])
        assert bridge.assemble(chain, data, moved) < 1e-12
        state = m.forward_pose(moved, guess=state)
        assert np.abs(bridge.platform_pose(chain, data) - state.pose).max() < 1e-9
        checked += 1
    assert checked == 3


def legs_of_mass_agreement(m, amplitude: float) -> float:
    """Projected mj_inverse vs inverse_dynamics with every link its own inertia (the cut's
    cross or slider included) at 8 samples of a trajectory; the largest relative difference."""
    rods = link_inertias(m, 1.0)
    assert all(rod is not None for rod in rods.values())
    links = {
        name: rigid_inertia(0.5 + 0.1 * i, rod.centre, rod.inertia * 0.7)
        for i, (name, rod) in enumerate(rods.items())
        if rod is not None
    }
    platform = rigid_inertia(10.0, inertia=np.full(3, 0.4 * 10.0 * 0.05**2))
    model = mujoco.MjModel.from_xml_string(to_mjcf(m, modes="none", link_mass=links, platform_mass=10.0))
    chain = bridge.closed_chain(model, list(m.actuated_names), "platform")
    data = mujoco.MjData(model)
    state = m.forward_pose(m.home_actuated, guess=m.home_passive)
    n = len(m.actuated_names)
    errors = []
    for t in np.linspace(0.0, 1.4, 8):
        phase = 2.0 * t + np.arange(n)
        q, qd = m.home_actuated + amplitude * np.sin(phase), 2 * amplitude * np.cos(phase)
        qdd = -4 * amplitude * np.sin(phase)
        assert bridge.assemble(chain, data, q, qd, qdd) < 1e-12
        state = m.forward_pose(q, guess=state)
        engine = bridge.projected_inverse(chain, data)
        gravity = np.array(model.opt.gravity)
        ours = inverse_dynamics(m, state, qd, qdd, platform_inertia=platform, gravity=gravity, leg_inertias=links)
        errors.append(np.abs(engine - ours.efforts).max() / np.abs(engine).max())
    assert len(errors) == 8
    return max(errors)


def test_universal_cut_with_legs_of_mass_equals_inverse_dynamics():
    m = gough_with_universal_cuts()
    assert "leg1_cross" in leg_tree(m).links
    error = legs_of_mass_agreement(m, 0.05)
    assert error < 1e-6, f"U cuts, legs of mass: projected mj_inverse vs inverse_dynamics {error:.3g}"


def test_cylindrical_cut_keyframes_mobility_and_statics():
    """The 3-RPR with its first leg's platform joint a C about the plane's normal: in the plane the
    same mechanism (the slide along the normal is held by the other legs), so every mode a
    keyframe with mobility 3 and the payload's statics as parakin's (mode 1, whose legs the
    export assembles only from random starts, left out for time), and with legs of mass (the
    slider one of them) inverse_dynamics = projected mj_inverse."""
    m = with_platform_joint("planar_3rpr", "C")
    model = mujoco.MjModel.from_xml_string(to_mjcf(m, modes="none"))
    assert int(model.body_dofnum[model.body("leg1_slider").id]) == 1
    error = keyframes_mobility_and_statics(m, payload=1.0, modes=[0, 2, 3, 4, 5])  # mode 1: 2 s of random starts
    assert error < 1e-7, f"C cut: payload's projected mj_inverse vs actuator_forces: {error:.3g}"
    error = legs_of_mass_agreement(m, 0.01)
    assert error < 1e-6, f"C cut, legs of mass: projected mj_inverse vs inverse_dynamics {error:.3g}"


def test_prismatic_cut_locks_the_turn():
    """The 3-RPR with its first leg's platform joint a P along the plane's normal: the platform
    no longer turns relative to that leg's link, so MuJoCo's mobility drops from 3 to 2 (a
    revolute cut in its place: 3), the loops closed at qpos0 (the home)."""
    mobility = {}
    for kind in ("R", "P"):
        m = with_platform_joint("planar_3rpr", kind)
        model = mujoco.MjModel.from_xml_string(to_mjcf(m, modes="none"))
        chain = bridge.closed_chain(model, list(m.actuated_names), "platform")
        data = mujoco.MjData(model)
        assert np.abs(bridge.loop_residual(chain, data)).max() < 1e-12
        mobility[kind] = model.nv - np.linalg.matrix_rank(bridge.loop_jacobian(chain, data), tol=1e-9)
    assert mobility == {"R": 3, "P": 2}
