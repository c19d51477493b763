"""The joint graph (``generator/graph.py``): bodies and joints, and the platform's mobility and
motion by screw analysis.

Checked against what the literature and hand derivations say, not against the code's output:

* the constraint wrench of an R-P-S leg is the force along the revolute axis through the
  spherical joint; a passive U-P leg fixed to the platform transmits the two forces through its
  universal joint normal to the leg and the couple normal to both universal axes; a delta leg
  (R, parallelogram) transmits the two couples normal to its crank axis (screw theory: a wrench
  is reciprocal to every joint twist, worked out by hand in each test);
* the 3-RPS moves in three degrees of freedom, the height and two tilts, with parasitic motion
  (Lee and Shah 1988); the delta and the linear delta translate (Clavel 1988); the planar
  3-RPR moves in the plane; the five-bar's point in the plane; the 3-SPS-1S turns about its
  spherical joint;
* a delta whose forearms are written as single bars (R-S-S) leaves the platform six degrees of
  freedom, and the generator says so instead of generating it.
"""

from __future__ import annotations

import importlib.util
from dataclasses import replace
from pathlib import Path
from types import ModuleType

import numpy as np
import pytest
import sympy as sp
from parakin.generator import graph, joints
from parakin.generator.errors import GenerationError
from parakin.generator.model import Mechanism

FIXTURES = Path(__file__).parent / "fixtures"


def fixture(name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(f"graph_fixture_{name}", FIXTURES / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def analyse(m: Mechanism) -> graph.Motion:
    assert m.joint_graph is not None and m.closure is not None
    return graph.analyse(m.joint_graph, m.closure.residual, m.actuated, m.passive, m.parameters, m.home, m.angular)


def same_span(found: np.ndarray, expected: np.ndarray) -> bool:
    """Whether two sets of rows span the same space."""
    r = graph.rank
    return r(found) == r(expected) == r(np.vstack([found, expected]))


def wrenches(leg: graph.Chain, rotation: np.ndarray, origin: np.ndarray, state: dict) -> np.ndarray:
    def values(expression: sp.Expr) -> np.ndarray:
        return np.array(sp.sympify(expression).xreplace(state).evalf(), dtype=float)

    placed = graph.place(leg, rotation, origin, values)
    twists = np.array([t for _, t in graph.joint_twists(leg, placed, values)]).T
    return graph.reciprocal(twists)


def test_rps_leg_transmits_the_force_along_its_revolute_axis_through_the_spherical_joint():
    # R about n = y at A = (0.2, 0, 0), P along A -> C, S at C = (0.15, 0, 0.3) (in the plane
    # y = 0), platform origin p = (0, 0, 0.3): a force along n through C has zero moment about
    # the revolute axis (parallel to it), is normal to the leg (n . (C - A) = 0) and passes
    # through C: reciprocal to all five joint twists; (n, (C - p) x n) = (0, 1, 0, 0, 0, 0.15)
    length = sp.Symbol("l")
    leg = joints.prismatic_leg([0.2, 0, 0], [0.15, 0, 0], length, revolute_axis=[0, 1, 0]).chain
    assert leg is not None
    found = wrenches(leg, np.eye(3), np.array([0, 0, 0.3]), {length: sp.Float(0.3041)})
    assert found.shape == (1, 6)
    assert same_span(found, np.array([[0, 1, 0, 0, 0, 0.15]]))


def test_passive_up_leg_transmits_two_forces_and_a_couple():
    # U at the origin, first axis x, the leg along R z_P fixed to the platform at its origin; at
    # R = Rot_x(0.3), p = 0.5 R z: the second U axis a2 = x cross (R z) / |.|, and the leg line
    # R z. Wrenches reciprocal to rotations about x and a2 through the origin and to the
    # translation along R z: forces through the origin normal to R z (moment about p:
    # (0 - p) x f), and the couple x cross a2 (normal to both axes)
    leg = joints.passive_leg([0, 0, 0], [1, 0, 0], [0, 0, 0], [0, 0, 1])
    turn = np.array([[1, 0, 0], [0, np.cos(0.3), -np.sin(0.3)], [0, np.sin(0.3), np.cos(0.3)]])
    line = turn @ np.array([0, 0, 1.0])
    p = 0.5 * line
    a2 = np.cross([1.0, 0, 0], line)
    forces = [np.array([1.0, 0, 0]), np.cross(line, [1.0, 0, 0])]
    expected = [np.concatenate([f, np.cross(-p, f)]) for f in forces]
    expected.append(np.concatenate([np.zeros(3), np.cross([1.0, 0, 0], a2)]))
    found = wrenches(leg, turn, p, {})
    assert found.shape == (3, 6)
    assert same_span(found, np.array(expected))


def test_delta_leg_transmits_two_couples_normal_to_its_crank_axis():
    # crank about u = y at A = (0.2, 0, 0), a parallelogram forearm hinged about u: the platform
    # keeps its orientation but may turn about u with the crank; the wrenches reciprocal to
    # rotations about three parallel axes u and a translation are the couples normal to u
    theta = sp.Symbol("theta")
    leg = joints.crank_leg([0.2, 0, 0], [0, 1, 0], [1, 0, 0], 0.3, 1.0, [0.05, 0, 0], theta, parallelogram=[0, 1, 0])
    assert leg.chain is not None
    found = wrenches(leg.chain, np.eye(3), np.array([0.2, 0.1, -0.9]), {theta: sp.Float(0.4)})
    assert found.shape == (2, 6)
    assert same_span(found, np.array([[0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 0, 1]]))


@pytest.mark.parametrize(
    ("name", "mobility", "kind", "text"),
    [
        ("delta", 3, "translation", "3 degrees of freedom, translational (3 translations)"),
        ("fixtures/linear_delta", 3, "translation", "3 degrees of freedom, translational (3 translations)"),
        ("planar_3rpr", 3, "planar", "3 degrees of freedom, planar"),
        ("five_bar", 2, "planar_translation", "2 degrees of freedom, planar translational"),
    ],
)
def test_mobility_and_motion_of_shipped_mechanisms(name: str, mobility: int, kind: str, text: str):
    if name.startswith("fixtures/"):
        m = fixture(name.split("/")[1]).build()
    else:
        m = __import__(f"parakin.mechanisms.{name}", fromlist=["build"]).build()
    found = analyse(m)
    assert found.samples >= 4  # the home and generic configurations near it
    assert (found.mobility, found.kind) == (mobility, kind)
    assert found.text().startswith(text)
    assert found.locked == [0] * found.samples  # actuators locked: the platform is held
    graph.check_motion(m.name, m.joint_graph, found, len(m.actuated))  # agrees with the declaration


@pytest.mark.slow
@pytest.mark.parametrize(
    ("name", "kind"), [("sps", "rotation"), ("spm", "rotation"), ("prs3", "transform"), ("rps3", "transform")]
)
def test_mobility_of_the_lower_mobility_and_spherical_mechanisms(name: str, kind: str):
    # the 3-PRS and the 3-RPS (Lee and Shah 1988): the height and two tilts (1T2R at the level
    # home), with parasitic motion; the SPM and the 3-SPS-1S turn about their centre
    m = __import__(f"parakin.mechanisms.{name}", fromlist=["build"]).build()
    found = analyse(m)
    assert (found.mobility, found.kind, found.samples) == (3, kind, 6)
    assert found.parasitic == (kind == "transform")
    if kind == "transform":
        assert found.text() == "3 degrees of freedom, 1T2R with parasitic motion"


def test_a_delta_with_single_bar_forearms_is_refused_saying_what_differs():
    delta = __import__("parakin.mechanisms.delta", fromlist=["build"])
    legs = [leg.chain for leg in delta.MODEL.legs]
    # the same legs with a spherical joint at each end of the forearm (R-S-S): the distance is the same
    bars = [
        replace(
            chain, joints=(chain.joints[0], graph.Joint("S", "elbow"), replace(chain.joints[-1], kind="S", axis=None))
        )
        for chain in legs
    ]
    model = joints.DistanceMechanism(joints.platform("translation"), bars)
    m = replace(delta.build(), joint_graph=model.graph)
    found = analyse(m)
    assert found.mobility == 6
    with pytest.raises(GenerationError, match=r"leave the platform 6 degrees of freedom.*3 actuated joints"):
        graph.check_motion(m.name, model.graph, found, 3)
    # and the real delta declared as turning about the origin: the declared kind and the motion named
    real = delta.build()
    assert real.joint_graph is not None
    with pytest.raises(GenerationError, match=r"declared pose kind 'rotation'.*translational"):
        graph.check_motion("delta", replace(real.joint_graph, pose_kind="rotation"), analyse(real), 3)


def test_joints_and_legs_refuse_what_they_cannot_be():
    with pytest.raises(ValueError, match="kind is one of"):
        graph.Joint("Q", "base", sp.Matrix([0, 0, 0]))
    with pytest.raises(ValueError, match="needs its point"):
        graph.Joint("S", "base")
    with pytest.raises(ValueError, match="actuated joint has one degree of freedom"):
        graph.Joint("S", "base", sp.Matrix([0, 0, 0]), actuated=True)
    s_p_f = graph.Chain(
        "leg",
        (
            graph.Joint("S", "base", sp.zeros(3, 1)),
            graph.Joint("P", "base", sp.zeros(3, 1)),
            graph.Joint("F", "platform", sp.zeros(3, 1), sp.Matrix([0, 0, 1])),
        ),
    )
    with pytest.raises(ValueError, match=r"S-P-F\) has no actuated joint.*U-P fixed"):
        joints.passive_form(s_p_f)
    lengths = sp.symbols("l1:4")
    legs = [joints.prismatic_leg([np.cos(k), np.sin(k), 0], [0.2, 0, 0], lengths[k]) for k in range(3)]
    with pytest.raises(ValueError, match="central spherical joint.*pose kind 'rotation'"):
        joints.DistanceMechanism(joints.platform("translation"), [*legs, joints.central_joint()])


def test_a_leg_written_joint_by_joint_is_the_shorthands():
    # the 3-RPS fixture's first leg as joints: R about the tangent at A, P actuated along the leg,
    # S at c: the same closure as prismatic_leg(..., revolute_axis=u)
    rps3 = fixture("rps3")
    chains = []
    for e, u, length in zip(rps3.RADIAL, rps3.TANGENT, rps3.lengths, strict=True):
        a = rps3.r_b * e
        written = (
            graph.Joint("R", "base", a, u),
            graph.Joint("P", "base", a, None, length, actuated=True),
            graph.Joint("S", "platform", rps3.r_p * e),
        )
        chains.append(graph.Chain("leg", written))
    model = joints.DistanceMechanism(joints.platform("transform"), chains)
    assert model.closure().residual == rps3.MODEL.closure().residual
    assert model.graph.describe() == "3 x R-P_-S (actuated)"


def test_inertial_symbols_are_a_mass_a_centre_and_a_symmetric_inertia():
    inertial = graph.Inertial.symbols("link1")
    assert inertial.mass.is_positive
    assert inertial.centre.shape == (3, 1)
    assert inertial.inertia == inertial.inertia.T
    assert len(inertial.inertia.free_symbols) == 6


def test_a_dh_tables_joints_in_the_graph_move_as_its_jacobian_says():
    # the SAM's S-P-U leg (Williams and Poling's Table I) as the graph's serial chain: at random
    # joint values, each joint's twist by the product of exponentials (axes at zero, carried by
    # the joints before) is the column of the table's geometric Jacobian (eq 9: frames multiplied
    # out, v of the origin of {P}, in {B})
    from parakin.generator import chains
    from parakin.mechanisms import sam

    thetas, length, phis = sp.symbols("t1:4", real=True), sp.Symbol("L", real=True), sp.symbols("p2 p3", real=True)
    offsets = sp.symbols("L1 L4", positive=True)
    serial = sam.spu_leg("left", thetas, length, phis, *offsets)
    chain = chains.graph_leg(chains.chain_leg(serial, thetas))
    assert chain.kinds == "R_-R_-R_-P-R-R"
    rng = np.random.default_rng(5)
    checked = 0
    for _ in range(5):
        state = {s: sp.Float(v) for s, v in zip([*serial.joints, *offsets], rng.uniform(0.2, 1.0, 8), strict=True)}
        end = np.array(serial.end_transform().xreplace(state).evalf(), dtype=float)
        expected = np.array(serial.geometric_jacobian().xreplace(state).evalf(), dtype=float)

        def values(expression: sp.Expr, state: dict = state) -> np.ndarray:
            return np.array(sp.sympify(expression).xreplace(state).evalf(), dtype=float)

        twists = dict((j.variable, t) for j, t in graph.serial_twists(chain, end[:3, 3], values))
        found = np.array([twists[joint] for joint in serial.joints]).T
        assert np.abs(found - expected).max() < 1e-12
        checked += 1
    assert checked == 5


def test_the_graph_as_plain_data_names_every_body_and_joint():
    import json

    delta = __import__("parakin.mechanisms.delta", fromlist=["build"]).build()
    assert delta.joint_graph is not None
    data = json.loads(json.dumps(graph.to_json(delta.joint_graph, analyse(delta))))
    assert [j["kind"] for j in data["legs"][0]["joints"]] == ["R", "R", "Pa", "R"]
    assert [leg["joints"][0]["variable"] for leg in data["legs"]] == ["theta1", "theta2", "theta3"]
    assert [j["actuated"] for j in data["legs"][0]["joints"]] == [True, False, False, False]
    assert len(data["bodies"]) == 2 + 3 * 3  # base, platform, three links per leg
    assert data["loops"] == [{"leg": f"leg{k}", "joint": 3} for k in (1, 2, 3)]
    assert data["motion"]["mobility"] == 3 and data["motion"]["kind"] == "translation"


def upu(outer: str) -> tuple[joints.DistanceMechanism, dict]:
    """A 3-UPU on a translating platform: base universal joints A_i = 0.3 e_i, platform joints
    c_i = 0.1 e_i, outer axes the tangent t_i at the base and ``outer`` ('tangent' or 'radial')
    at the platform; home p = (0, 0, 0.4)."""
    lengths = sp.symbols("l1:4", positive=True)
    legs = []
    for k in range(3):
        angle = 2 * sp.pi * k / 3
        e, t = sp.Matrix([sp.cos(angle), sp.sin(angle), 0]), sp.Matrix([-sp.sin(angle), sp.cos(angle), 0])
        axis = t if outer == "tangent" else e
        legs.append(joints.prismatic_leg(0.3 * e, 0.1 * e, lengths[k], universal_axis=t, platform_universal_axis=axis))
    model = joints.DistanceMechanism(joints.platform("translation"), legs)
    return model, model.home_at(sp.eye(3), sp.Matrix([0, 0, 0.4]), 0, {})


def test_a_3upu_translates_only_with_its_outer_axes_parallel():
    # Tsai (1996): a U-P-U leg whose outer axes are parallel (and so its inner ones) transmits
    # one couple, normal to both universal joints' planes; three such legs keep the platform
    # from turning. With the platform's outer axes radial instead, each leg transmits a wrench
    # with a force, and the platform turns as it moves: the declared translation is refused.
    for outer, translates in (("tangent", True), ("radial", False)):
        model, home = upu(outer)
        closure = model.closure().residual
        found = graph.analyse(model.graph, closure, model.actuated, list(model.motion.coordinates), {}, home)
        assert found.mobility == 3 and found.samples == 6
        if translates:
            assert found.kind == "translation"
            graph.check_motion("upu", model.graph, found, 3)
        else:
            assert found.kind == "transform" and found.rotations > 0
            with pytest.raises(GenerationError, match="declared pose kind 'translation'"):
                graph.check_motion("upu", model.graph, found, 3)
