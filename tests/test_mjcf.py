"""The MJCF export (``parakin.mjcf.to_mjcf``) checked with MuJoCo as the independent engine, and
the manifest's joint graph reader.

MuJoCo's side never uses parakin's kinematics: it compiles the exported text, evaluates its own
forward kinematics and constraint Jacobians, and simulates. Claims, for the five-bar, the delta
(parallelograms as four bars), a 6-UPS Stewart platform and the lower-mobility 3-RPS and Tricept:
* every keyframe is assembled: the equality residual after ``mj_forward`` < 1e-9 m, the actuated
  qpos equal to ``ctrl`` and to the actuated values to 1e-12, the platform site at the mode's pose
  to 1e-9; one keyframe per real assembly mode; MuJoCo's mobility nv - rank(J_c) = the DOF;
* the actuated joints' positions are parakin's actuated values (origin, sign, unit): moved away
  from the keyframe and closed by MuJoCo's own Newton (the bridge), the platform is at
  ``forward_pose`` of the moved values to 1e-9;
* under gravity (1 kg planar, 10 kg spatial) with the servos holding, the simulation settles
  within 0.3 mm / 0.01 deg (preset "fast") of ``forward_pose`` at the settled actuated values, and
  the nearest parakin mode is the keyframe's; 10 um / 2e-3 deg with "accurate".

The packages here are the shipped ones: their manifests carry the joint graph
(``generator/manifest_writer.py``); a package without one is tested on a copy given the graph
that ``generator.graph.to_json`` derives from the same mechanism file.
"""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import parakin
from parakin.errors import BadInputError, BrokenPackageError, ParakinError, UnsupportedOperationError
from parakin.packages.expression import evaluate
from parakin.packages.manifest import Manifest

mujoco = pytest.importorskip("mujoco")
from parakin import mjcf  # noqa: E402
from parakin import mujoco_bridge as bridge  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
#: a regular 6-UPS hexapod (the bridge's hand-written fixture's numbers): base joints on a 0.5 m
#: circle, platform joints on a 0.3 m circle, the home 0.6 m above the base
STEWART_BASE = [[0.5 * math.cos(a), 0.5 * math.sin(a), 0.0] for a in np.radians([-15, 15, 105, 135, 225, 255])]
STEWART_PLATFORM = [[0.3 * math.cos(a), 0.3 * math.sin(a), 0.0] for a in np.radians([-40, 40, 80, 160, 200, 280])]


def graph_of(name: str) -> dict:
    """The joint graph of mechanisms/<name>.py as the generator writes it (generator.graph.to_json)."""
    from parakin.generator import graph
    from parakin.generator.build import load_definition

    mechanism, _ = load_definition(ROOT / "mechanisms" / f"{name}.py")
    assert mechanism.joint_graph is not None, name
    return graph.to_json(mechanism.joint_graph)


@pytest.fixture(scope="module")
def packages(tmp_path_factory: pytest.TempPathFactory):
    """name -> a package folder whose manifest carries the joint graph."""
    folder = tmp_path_factory.mktemp("graphs")
    made: dict[str, Path] = {}

    def package(name: str) -> Path:
        if name not in made:
            shipped = ROOT / "generated" / name
            if "joints" in json.loads((shipped / "manifest.json").read_text()):
                made[name] = shipped
            else:
                target = folder / name
                shutil.copytree(shipped, target)
                manifest = json.loads((target / "manifest.json").read_text())
                manifest["joints"] = graph_of(name)
                (target / "manifest.json").write_text(json.dumps(manifest))
                made[name] = target
        return made[name]

    return package


def load(packages, name: str, **parameters) -> parakin.Mechanism:
    return parakin.load(packages(name), **parameters)


def stewart(packages):
    m = load(packages, "stewart", base=STEWART_BASE, platform=STEWART_PLATFORM)
    pose = np.eye(4)
    pose[2, 3] = 0.6
    return m, m.inverse_pose(pose).branch(0)


def rotates(m) -> bool:
    return m.manifest.pose_kind in ("transform", "rotation", "planar")


def angle_between(a: np.ndarray, b: np.ndarray) -> float:
    """The angle (rad) of a^T b, accurate for small angles too."""
    relative = a.T @ b
    vee = np.array([relative[2, 1] - relative[1, 2], relative[0, 2] - relative[2, 0], relative[1, 0] - relative[0, 1]])
    return math.atan2(float(np.linalg.norm(vee)) / 2, (float(np.trace(relative)) - 1) / 2)


def connect_jacobian(model, data) -> np.ndarray:
    """MuJoCo's J_c: site1 - site2 Jacobians of every connect, stacked (3 per connect, nv)."""
    rows = []
    for e in range(model.neq):
        ja, jb = np.zeros((3, model.nv)), np.zeros((3, model.nv))
        mujoco.mj_jacSite(model, data, ja, None, int(model.eq_obj1id[e]))
        mujoco.mj_jacSite(model, data, jb, None, int(model.eq_obj2id[e]))
        rows.append(ja - jb)
    return np.concatenate(rows)


def exported(packages, name: str, **options):
    """(m, reference or None, MjModel, the modes of the keyframes' actuated values)."""
    reference = None
    if name == "stewart":
        m, reference = stewart(packages)
        options.setdefault("reference", reference)
    else:
        m = load(packages, name)
    planar = m.manifest.pose_kind.startswith("planar")
    options.setdefault("payload", 1.0 if planar else 10.0)
    text = mjcf.to_mjcf(m, **options)
    model = mujoco.MjModel.from_xml_string(text)
    actuated = m.home_actuated if reference is None else reference.actuated
    return m, model, m.forward_pose_all(actuated), text


# ---------------------------------------------------------------------------- keyframes assembled
#: the Stewart platform's all-modes solver (a 40-path homotopy, ~3 s a call) runs in the slow set
STEWART = pytest.param("stewart", marks=pytest.mark.slow)


@pytest.mark.parametrize("name", ["five_bar", "delta", "rps3", "tricept", STEWART])
def test_every_keyframe_assembled_with_the_mechanisms_mobility(packages, name):
    """One keyframe per real assembly mode; each closed in MuJoCo (equality residual < 1e-9 m at
    mj_forward), its actuated qpos = ctrl = the actuated values to 1e-12, its platform site at the
    mode's pose to 1e-9; nv - rank(J_c) = the number of actuated variables at each."""
    m, model, modes, _ = exported(packages, name, modes="all" if name != "stewart" else [0, 1])
    chain = bridge.closed_chain(model, m.actuated_names, "platform")
    wanted = range(int(modes.count)) if name != "stewart" else range(2)
    assert [model.key(k).name for k in range(model.nkey)] == [f"mode{k}" for k in wanted]
    if name != "stewart":
        assert model.nkey == modes.count >= 2
    dof = len(m.actuated_names)
    for key in range(model.nkey):
        k = int(model.key(key).name.removeprefix("mode"))
        data = mujoco.MjData(model)
        mujoco.mj_resetDataKeyframe(model, data, key)
        mujoco.mj_forward(model, data)
        residual = float(np.abs(data.efc_pos[: data.ne]).max())
        assert data.ne == 3 * model.neq and residual < 1e-9, f"{name} mode {k}: loop residual {residual:.3g} m"
        actuated = data.qpos[chain.actuated_qpos]
        assert np.abs(actuated - data.ctrl).max() < 1e-12
        assert np.abs(actuated - modes.mode(k).actuated).max() < 1e-12
        pose = bridge.platform_pose(chain, data)
        expected = modes.mode(k).pose
        assert np.abs(pose[:3, 3] - expected[:3, 3]).max() < 1e-9, f"{name} mode {k}: platform off"
        if rotates(m):
            assert angle_between(pose[:3, :3], expected[:3, :3]) < 1e-9
        jacobian = connect_jacobian(model, data)
        sigma = np.linalg.svd(jacobian, compute_uv=False)
        rank = int(np.sum(sigma > 1e-9 * sigma[0]))
        assert model.nv - rank == dof, f"{name} mode {k}: mobility {model.nv - rank}, DOF {dof}"


@pytest.mark.parametrize("name", ["five_bar", "delta", "tricept", STEWART])
def test_actuated_joints_are_parakins_actuated_values(packages, name):
    """From the first keyframe, the actuated joints moved by 0.02 (rad or m) each and the loops
    closed by MuJoCo's own Newton (bridge.assemble): the platform is where forward_pose puts it
    for the moved values (1e-9): same origin, sign and unit."""
    m, model, modes, _ = exported(packages, name, modes=[0])
    chain = bridge.closed_chain(model, m.actuated_names, "platform")
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, 0)
    steps = 0.02 * np.array([1.0, -1.0, 0.5, -0.5, 0.75, -0.25])[: len(m.actuated_names)]
    moved = modes.mode(0).actuated + steps
    assert bridge.assemble(chain, data, moved) < 1e-12
    reference = m.forward_pose(moved, guess=modes.mode(0))
    pose = bridge.platform_pose(chain, data)
    assert np.abs(pose[:3, 3] - reference.pose[:3, 3]).max() < 1e-9
    if rotates(m):
        assert angle_between(pose[:3, :3], reference.pose[:3, :3]) < 1e-9


# ---------------------------------------------------------------------------- settling under load
def settle_in_mode(m, model, modes, key: int, duration: float = 1.0):
    chain = bridge.closed_chain(model, m.actuated_names, "platform")
    k = int(model.key(key).name.removeprefix("mode"))
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, key)
    settled = bridge.settle(chain, data, duration=duration, speed=1e-6)
    reference = m.forward_pose(settled.actuated, guess=modes.mode(k))
    gap = float(np.linalg.norm(settled.pose[:3, 3] - reference.pose[:3, 3]))
    angle = math.degrees(angle_between(settled.pose[:3, :3], reference.pose[:3, :3])) if rotates(m) else 0.0
    moved = float(np.linalg.norm(settled.pose[:3, 3] - modes.mode(k).pose[:3, 3]))
    return k, gap, angle, moved, bridge.nearest_mode(m, chain, data).mode


@pytest.mark.parametrize("name", ["five_bar", "delta", "rps3", "tricept", STEWART])
def test_fast_preset_settles_on_forward_pose(packages, name):
    """1 kg (planar) / 10 kg (spatial) payload, servos holding the keyframe: after 1 s the pose is
    within 0.3 mm / 0.01 deg of forward_pose at the settled actuated values (issue 34, 'fast'),
    the platform did sag (the check is not of a model that never moved), and the nearest mode is
    the keyframe's."""
    m, model, modes, text = exported(packages, name, modes=[0])
    assert 'timestep="0.001"' in text and 'solref="0.002 1"' in text
    k, gap, angle, moved, nearest = settle_in_mode(m, model, modes, 0)
    assert moved > 1e-5, f"{name}: the platform moved {moved * 1e3:.4f} mm under its load"
    assert gap < 3e-4 and angle < 1e-2, f"{name}: {gap * 1e3:.4f} mm / {angle:.2e} deg from forward_pose"
    assert nearest == k


@pytest.mark.slow
@pytest.mark.parametrize("name", ["five_bar", "delta", "rps3", "tricept", "stewart"])
def test_accurate_preset_settles_on_forward_pose_in_every_mode(packages, name):
    """'accurate' (0.2 ms, stiff solimp): every keyframe (the Stewart's 8) settles within
    10 um / 2e-3 deg of forward_pose at its settled actuated values, in the mode it settles in,
    and stays in its own mode; except, possibly, modes of the lower-mobility 3-RPS (at its former
    0.2 m / 0.1 m defaults three tilted modes snapped through to another under 10 kg on the
    servos: a loss of stability of the compliant mechanism, not of the loops, whose gap stayed
    within the bound)."""
    m, model, modes, text = exported(packages, name, accuracy="accurate")
    assert 'solimp="0.98999999999999999 0.999' in text
    chain = bridge.closed_chain(model, m.actuated_names, "platform")
    kept = 0
    for key in range(model.nkey):
        k = int(model.key(key).name.removeprefix("mode"))
        data = mujoco.MjData(model)
        mujoco.mj_resetDataKeyframe(model, data, key)
        settled = bridge.settle(chain, data, duration=0.5, speed=1e-6)
        nearest = bridge.nearest_mode(m, chain, data)
        reference = m.forward_pose(settled.actuated, guess=modes.mode(nearest.mode))
        gap = float(np.linalg.norm(settled.pose[:3, 3] - reference.pose[:3, 3]))
        angle = math.degrees(angle_between(settled.pose[:3, :3], reference.pose[:3, :3])) if rotates(m) else 0.0
        assert gap < 1e-5 and angle < 2e-3, f"{name} mode {k}: {gap * 1e6:.3f} um / {angle:.2e} deg"
        kept += nearest.mode == k
    assert model.nkey == modes.count
    if name != "rps3":  # the lower-mobility 3-RPS on compliant servos may leave a mode (docstring)
        assert kept == modes.count, f"{name}: {kept} of {modes.count} modes kept"


# ---------------------------------------------------------------------------- refusals and the CLI
def test_a_package_without_joint_graph_is_refused_by_name(packages, tmp_path):
    folder = tmp_path / "five_bar"
    shutil.copytree(ROOT / "generated" / "five_bar", folder)
    manifest = json.loads((folder / "manifest.json").read_text())
    manifest.pop("joints", None)
    (folder / "manifest.json").write_text(json.dumps(manifest))
    m = parakin.load(folder)
    assert m.manifest.joints is None
    with pytest.raises(UnsupportedOperationError, match="joint graph"):
        mjcf.to_mjcf(m)
    with_graph = load(packages, "five_bar")
    for bad in (dict(accuracy="exact"), dict(timestep=-1.0), dict(modes="some"), dict(modes=[7]), dict(payload=-1.0)):
        with pytest.raises(BadInputError):
            mjcf.to_mjcf(with_graph, **bad)


def test_a_home_that_does_not_close_asks_for_a_reference(packages):
    """The Stewart platform with the regular hexapod's joints: the manifest's home lengths (the
    default geometry's) do not close; the error says to pass reference=."""
    m = load(packages, "stewart", base=STEWART_BASE, platform=STEWART_PLATFORM)
    with pytest.raises(ParakinError, match="reference="):
        mjcf.to_mjcf(m, modes="none")


def test_serial_chain_legs_without_joint_variables_are_refused_by_name(packages, tmp_path):
    """A leg placed by products of exponentials needs every joint's value (SAM's carry them and
    export: tests/test_mjcf_cuts.py); the five-bar's legs marked so, whose passive joints carry
    no variable, are refused by name, not exported wrong."""
    folder = tmp_path / "five_bar"
    shutil.copytree(packages("five_bar"), folder)
    manifest = json.loads((folder / "manifest.json").read_text())
    for leg in manifest["joints"]["legs"]:
        for joint in leg["joints"]:
            joint["site"], joint["point"] = "chain", joint["point"] or ["0", "0", "0"]
    (folder / "manifest.json").write_text(json.dumps(manifest))
    with pytest.raises(UnsupportedOperationError, match="joint 2 \\(R\\) of a serial chain carries no variable"):
        mjcf.to_mjcf(parakin.load(folder), modes="none")


def test_parallelograms_are_four_bars(packages):
    """The delta's forearms: two bars and two short sides per leg, the second bar cut by two
    connects along the hinge axis; MuJoCo's mobility is still 3 (one bar per forearm gives 6)."""
    m, model, _, text = exported(packages, "delta", modes="none")
    bodies = {model.body(b).name for b in range(model.nbody)}
    for leg in (1, 2, 3):
        assert {f"leg{leg}_link3_bar1", f"leg{leg}_link3_bar2", f"leg{leg}_link3", f"leg{leg}_link2"} <= bodies
    assert text.count("_bar2_cut") == 6 and "anchor=" not in text


def test_command_line_writes_the_file(packages, tmp_path):
    from parakin.interfaces.cli import main

    out = tmp_path / "five_bar.xml"
    assert main(["mjcf", str(packages("five_bar")), "--out", str(out), "--accuracy", "accurate"]) == 0
    model = mujoco.MjModel.from_xml_path(str(out))
    assert model.nkey == 2 and math.isclose(model.opt.timestep, 2e-4)
    # the masses: --link-mass the links' (thin rods, as inverse_dynamics' leg_inertias=0.3)
    assert (
        main(["mjcf", str(packages("five_bar")), "--out", str(out), "--link-mass", "0.3", "--platform-mass", "2"]) == 0
    )
    model = mujoco.MjModel.from_xml_path(str(out))
    masses = {model.body(b).name: float(model.body_mass[b]) for b in range(1, model.nbody)}
    assert masses == {"leg1_link1": 0.3, "leg1_link2": 0.3, "platform": 2.0, "leg2_link1": 0.3, "leg2_link2": 0.3}


# ---------------------------------------------------------------------------- the manifest's graph
GRAPHS = ("five_bar", "delta", "stewart", "tricept", "rps3", "prs3", "sps")


@pytest.mark.parametrize("name", GRAPHS)
def test_graph_expressions_evaluate_as_sympy_does(name):
    """Every point, axis, reach and link expression of the graph, evaluated by the SymPy-free
    reader at the default parameters, equals SymPy's evaluation of the same text (1e-12)."""
    data = graph_of(name)
    m = parakin.load(name)
    values = {k: float(v) for k, v in m.parameters.items()}
    texts = [
        *(t for leg in data["legs"] for j in leg["joints"] for key in ("point", "axis") for t in (j[key] or [])),
        *(t for leg in data["legs"] if leg["reach"] for t in [leg["reach"]["length"], *leg["reach"]["direction"]]),
        *(leg["link"] for leg in data["legs"] if leg["link"]),
    ]
    assert len(texts) >= 6
    for text in texts:
        symbols = {k: sp.Symbol(k) for k in values}  # a parameter named gamma or beta is not SymPy's function
        expected = float(sp.sympify(text, locals=symbols).subs({symbols[k]: v for k, v in values.items()}).evalf(30))
        assert abs(evaluate(text, values) - expected) <= 1e-12 * max(1.0, abs(expected)), text


def test_every_allowed_function_evaluates_as_sympy_does():
    """Hand-written texts using every allowed function and operator (spm's trigonometry,
    sps's clamp) at three parameter sets: the reader's value equals SymPy's to 1e-12."""
    texts = [
        "-sin(gamma)*cos(alpha1) + sqrt(3)*sin(beta)/2",
        "2*sin(alpha2/2)**2 - tan(beta)/pi",
        "b3*sqrt(Max(0, 1 - (b2**2 - beta**2)/(4*b2**2)))",
        "Min(alpha1, -beta, gamma) + Abs(-b2) - +b3",
    ]
    checked = 0
    for values in ({"alpha1": 0.3, "alpha2": 1.1, "beta": 0.2, "gamma": 0.7, "b2": 0.5, "b3": 0.4},
                   {"alpha1": -1.0, "alpha2": 0.1, "beta": 0.45, "gamma": 2.0, "b2": 0.3, "b3": 2.0},
                   {"alpha1": 2.5, "alpha2": -3.0, "beta": -0.4, "gamma": -1.0, "b2": 1.5, "b3": 0.1}):  # fmt: skip
        symbols = {k: sp.Symbol(k) for k in values}
        for text in texts:
            expected = float(sp.sympify(text, locals=symbols).subs({symbols[k]: v for k, v in values.items()}))
            assert abs(evaluate(text, values) - expected) <= 1e-12 * max(1.0, abs(expected)), text
            checked += 1
    assert checked == 12
    for bad in ("exp(1)", "sin(1, 2)", "Max(1)", "b2.real", "[1]", "1 < 2", "lambda: 1"):
        with pytest.raises(BrokenPackageError):
            evaluate(bad, {"b2": 1.0})
    with pytest.raises(BadInputError, match="undefined"):
        evaluate("sqrt(-b2)", {"b2": 1.0})


HOSTILE_GRAPH = [
    (("legs", 0, "joints", 0, "kind"), "X", "joints.legs.joints.kind"),
    (("legs", 0, "joints", 0, "point", 0), "__import__('os').getcwd()", "joints.legs.joints.point"),
    (("legs", 0, "joints", 0, "point", 1), "q.real", "joints.legs.joints.point"),
    (("legs", 0, "joints", 0, "point", 2), "unknown_length", "joints.legs.joints.point"),
    (("legs", 0, "joints", 0, "axis"), None, "joints.legs.joints.axis"),
    (("legs", 0, "joints", 0, "variable"), "not_actuated", "joints.legs.joints.variable"),
    (("legs", 0, "bodies"), ["leg1_link1"], "joints.legs.bodies"),
    (("legs", 1, "name"), "leg1", "joints.legs.name"),
    (("loops", 0, "leg"), "leg9", "joints.loops.leg"),
    (("loops", 0, "joint"), 7, "joints.loops.joint"),
    (("pose_kind",), "translation", "joints.pose_kind"),
    (("legs",), [], "joints.legs"),
]


def test_hostile_joint_graph_fields_are_named():
    """The shipped five-bar's manifest with the graph added loads with a typed graph; each hostile
    value of a graph field is a BrokenPackageError naming that field."""
    manifest = json.loads((ROOT / "generated" / "five_bar" / "manifest.json").read_text())
    manifest["joints"] = graph_of("five_bar")
    graph = Manifest.from_dict(manifest).joints
    assert graph is not None and [leg.name for leg in graph.legs] == ["leg1", "leg2"]
    assert graph.legs[0].joints[0].point == ("-d", "0", "0") and graph.legs[0].joints[0].actuated
    checked = 0
    for path, value, field in HOSTILE_GRAPH:
        broken = json.loads(json.dumps(manifest))
        target = broken["joints"]
        for key in path[:-1]:
            target = target[key]
        target[path[-1]] = value
        with pytest.raises(BrokenPackageError, match=field.replace(".", r"\.")):
            Manifest.from_dict(broken)
        checked += 1
    assert checked == len(HOSTILE_GRAPH)


def test_command_line_keyframes_of_given_inputs_in_degrees(packages, tmp_path):
    """``parakin mjcf five_bar --actuated-deg A B``: the keyframes are the modes of those inputs,
    their ctrl the inputs in radians (as ``--actuated`` in radians gives), and a wrong count of
    values is a named error (exit 2)."""
    from parakin.interfaces.cli import main

    m = parakin.load(str(packages("five_bar")), backend="numpy")
    theta = m.home_actuated + np.array([0.05, -0.04])
    out = tmp_path / "deg.xml"
    degrees = [f"{v:.15g}" for v in np.rad2deg(theta)]
    assert main(["mjcf", str(packages("five_bar")), "--out", str(out), "--actuated-deg", *degrees]) == 0
    model = mujoco.MjModel.from_xml_path(str(out))
    modes = m.forward_pose_all(theta)
    assert model.nkey == int(modes.count) >= 1
    np.testing.assert_allclose(model.key_ctrl.reshape(model.nkey, -1), np.tile(theta, (model.nkey, 1)), atol=1e-12)
    assert main(["mjcf", str(packages("five_bar")), "--out", str(out), "--actuated-deg", "100"]) == 2


def test_inputs_without_an_assembly_mode_write_no_model(tmp_path, capsys):
    """The five-bar cannot close with its cranks at (pi, 0): no keyframe, so no file and exit 1
    (as `parakin fk` for the same inputs), not a model that looks like success."""
    from parakin.interfaces.cli import main

    out = tmp_path / "none.xml"
    assert main(["fk", "five_bar", "--actuated", "3.14159", "0"]) == 1
    capsys.readouterr()
    assert main(["mjcf", "five_bar", "--actuated", "3.14159", "0", "--out", str(out)]) == 1
    assert "no real assembly mode" in capsys.readouterr().err and not out.exists()
    assert main(["mjcf", "five_bar", "--actuated", "3.14159", "0", "--no-modes", "--out", str(out)]) == 0
    assert out.exists() and "<key " not in out.read_text()


def test_the_exported_gravity_is_the_dynamics_default():
    """One robot: MuJoCo's gravity in the exported file is parakin.dynamics' default."""
    mujoco = pytest.importorskip("mujoco")
    from parakin.dynamics import STANDARD_GRAVITY

    m = parakin.load("stewart")
    model = mujoco.MjModel.from_xml_string(m.to_mjcf(modes="none"))
    assert np.array_equal(np.asarray(model.opt.gravity), np.asarray(STANDARD_GRAVITY))
