"""Root counts proven where the mechanism's own relations hold (generator/subfamily.py): parameters
sharing a value, constant angles. The count of the generic member of a polynomial family is not
the mechanism's when its parameters coincide (a user's Hexaglide with two sliders on each of three
shared rails: 8 of the family's 80 roots at infinity for every input, so no input could be
certified complete); the start instances are then drawn in the subfamily and its count proven.

Independent sources: closed-form solutions of small systems; for the Hexaglide, the family's 80
generic solutions (two total-degree runs of 8192 paths) followed to a random member of the shared-rail
subfamily, where exactly 72 stay finite (slow)."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("sympy")

import sympy as sp  # noqa: E402
from parakin.generator import start_systems  # noqa: E402
from parakin.generator.polynomial_form import PolynomialForm, circle_parameter  # noqa: E402
from parakin.generator.subfamily import family_relations  # noqa: E402

z1, z2, b1, b2, c1, c2 = sp.symbols("z1 z2 b1 b2 c1 c2")
#: (b1 - b2) z1^2 + z1 - c1 = 0, z2^2 - c2 = 0: 4 solutions for generic values, 2 where b1 = b2
#: (the other z1 at infinity): z1 = c1, z2 = +-sqrt(c2)
EQUATIONS = [(b1 - b2) * z1**2 + z1 - c1, z2**2 - c2]


def _form() -> PolynomialForm:
    return PolynomialForm([z1, z2], EQUATIONS, [(s, s) for s in (b1, b2, c1, c2)], [z1, z2])


@pytest.fixture()
def private_cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    cache = tmp_path / "cache"
    cache.mkdir(mode=0o700)
    monkeypatch.setenv("PARAKIN_CACHE", str(cache))
    return cache


def _solutions(record: dict, which: str = "solutions") -> np.ndarray:
    return np.array([[complex(*c) for c in row] for row in record[which]])


def _instance(record: dict, which: str = "instance") -> np.ndarray:
    return np.array([complex(*v) for v in record[which]])


def _closed_form(q: np.ndarray) -> np.ndarray:
    """Every solution of EQUATIONS at q = (b1, b2, c1, c2), from the quadratic formula."""
    a = q[0] - q[1]
    if a == 0:
        first = np.array([q[2]])
    else:
        root = np.sqrt(1 + 4 * a * q[2])
        first = np.array([(-1 + root) / (2 * a), (-1 - root) / (2 * a)])
    second = np.sqrt(q[3]) * np.array([1, -1])
    return np.array([[x, y] for x in first for y in second])


def _same_set(found: np.ndarray, expected: np.ndarray) -> bool:
    return len(found) == len(expected) and all(np.abs(found - e).max(-1).min() < 1e-9 for e in expected)


def test_parameters_sharing_a_value_prove_the_count_of_their_subfamily(private_cache: Path) -> None:
    form = _form()
    began = time.process_time()
    _, generic = start_systems.start_systems("coincidence_test", form, EQUATIONS, 7, "automatic")
    values = {b1: 0.3, b2: 0.3, c1: 0.5, c2: 0.7}
    _, shared = start_systems.start_systems("coincidence_test", form, EQUATIONS, 7, "automatic", values)
    # the generic count (4) and the subfamily's (2), each against the closed form at its instance
    assert _same_set(_solutions(generic), _closed_form(_instance(generic)))
    assert len(_solutions(generic)) == 4 and "relations" not in generic and generic["proof"]["proven"]
    q = _instance(shared)
    assert q[0] == q[1], "the start instance is drawn where b1 = b2"
    assert _same_set(_solutions(shared), _closed_form(q)) and len(_solutions(shared)) == 2
    second = _instance(shared, "second_instance")
    assert second[0] == second[1] and _same_set(_solutions(shared, "second_solutions"), _closed_form(second))
    assert shared["proof"]["proven"] and shared["relations"].describe() == "b1 = b2"
    assert shared["key"] != generic["key"]
    # read back from the cache, as it was
    _, again = start_systems.start_systems("coincidence_test", form, EQUATIONS, 7, "automatic", values)
    assert again["solutions"] == shared["solutions"] and again["key"] == shared["key"]
    assert time.process_time() - began < 10


def test_a_relation_that_keeps_the_count_keeps_the_generic_start_system(private_cache: Path) -> None:
    """c1 = c2 loses no solution: the family's record (cached) stays, with no subfamily."""
    form = _form()
    _, generic = start_systems.start_systems("coincidence_test", form, EQUATIONS, 7, "automatic")
    values = {b1: 0.3, b2: 0.4, c1: 0.5, c2: 0.5}
    _, kept = start_systems.start_systems("coincidence_test", form, EQUATIONS, 7, "automatic", values)
    assert "relations" not in kept and kept["key"] == generic["key"]
    assert kept["solutions"] == generic["solutions"] and len(kept["solutions"]) == 4


def test_relations_found_from_the_values() -> None:
    """Equal parameters group, a constant angle is constant, different values and inputs stay free."""
    s, y1, y2, y3, alpha = sp.symbols("s y1 y2 y3 alpha")
    u, v = sp.symbols("u v")
    p = sp.Symbol("p_0")
    expressions = {s: s, y1: y1, y2: y2, y3: y3, p: sp.sqrt(y1 + 1)}
    circles = {u: 7 * sp.pi / 18, v: alpha}
    values = {y1: -0.28, y2: -0.28, y3: 0.05, alpha: 0.2}
    relations = family_relations([s, y1, y2, y3, p, u, v], expressions, circles, values)
    assert relations is not None
    assert relations.groups == [[1, 2]] and relations.constants == [5]
    assert relations.describe() == "y1 = y2; u fixed by the design"
    assert relations.constant[5] == complex(sp.N(circle_parameter(7 * sp.pi / 18), 30))
    t = np.array([1.0 + 2j, 3.0, 4.0, 5.0, 6.0])
    q = relations.full(t)
    assert q[1] == q[2] == 3.0 and relations.holds(q) and not relations.holds(q + np.eye(7)[2] * 1e-6)
    assert family_relations([s, y1, y3], expressions, {}, values) is None
    assert family_relations([s, y1, y2], expressions, {}, None) is None, "no values: no coincidence"


def _hexaglide_form(source: Path) -> tuple[dict, PolynomialForm]:
    """The fixture's parameter values and the polynomial form of its closure."""
    from parakin.generator import derive
    from parakin.generator.build import load_definition
    from parakin.generator.polynomial_form import derive as polynomial_form

    mechanism, _ = load_definition(source)
    state = [("actuated", mechanism.actuated), ("passive", mechanism.passive), ("params", list(mechanism.parameters))]
    build = derive._from_closure if mechanism.closure is not None else derive._from_legs
    closed = build(mechanism, state)
    form = polynomial_form(
        list(closed.residual), mechanism.passive, mechanism.actuated, list(mechanism.parameters), mechanism.angular
    )
    return dict(mechanism.parameters), form


@pytest.mark.slow
def test_the_shared_rail_hexaglide_proves_72_and_certifies_its_inputs(tmp_path: Path, private_cache: Path) -> None:
    """The user's Hexaglide (six rail parameters, pairwise equal: three shared rails) generates with
    its count proven on the subfamily of its coincidences, 72, in under a minute of CPU, and inputs
    near home are certified complete (at 80 none was). Independent check of 72: the family's 80
    generic solutions (proven without the relations) followed to a random member of the subfamily:
    72 end at distinct regular solutions, 8 leave every bound."""
    import parakin
    from parakin.interfaces.cli import main

    source = Path(__file__).parent / "fixtures" / "hexaglide.py"
    values, form = _hexaglide_form(source)
    began = time.process_time()
    assert main(["generate", str(source), "--out", str(tmp_path / "pkg")]) == 0
    seconds = time.process_time() - began
    m = parakin.load(tmp_path / "pkg", backend="compiled")
    forward = m.capabilities.forward_methods["automatic"]
    assert forward.homotopy is not None and forward.homotopy.root_count is not None
    count = forward.homotopy.root_count
    assert count.count == 72 and count.proven, count
    assert seconds < 60, f"{seconds:.0f} s of CPU"
    rng = np.random.default_rng(4)
    checked, complete = 0, 0
    for _ in range(40):
        near = [*(np.array([0, 0, -0.45]) + rng.uniform(-0.03, 0.03, 3)), *rng.uniform(-0.1, 0.1, 3)]
        ik = m.inverse_pose(parakin.pose_from_xyz_euler(near), strict=False)
        acts = ik.actuated[ik.valid]
        theta = acts[np.argmin(np.abs(acts - m.home_actuated).max(-1))]
        checked += 1
        complete += bool(m.forward_pose_all(theta).certificate()["complete"])
    assert checked == 40 and complete >= 0.95 * checked, f"{complete} of {checked} complete"
    # loaded with the rails apart the relations break, the 8 roots are back (80 at such inputs)
    # and the 72 no longer bound them: never "complete"
    apart = parakin.load(tmp_path / "pkg", backend="compiled", y2=-0.25, y5=0.2, y6=0.08)
    modes = apart.forward_pose_all(apart.home_actuated)
    assert int(modes.certificate()["certified_roots"]) == 72 and not modes.complete()
    assert "the root count is not proven" in str(modes)

    # independent: the generic family's count, proven without the relations, followed into them
    family, generic = start_systems.start_systems("hexaglide", form, list(form.equations), 2026, "automatic")
    assert len(generic["solutions"]) == 80 and generic["proof"]["proven"]
    # without the parameter values only the constant angles are relations (structural: the
    # platform joints' directions), and they keep the 80
    assert "relations" not in generic or not generic["relations"].groups
    relations = family_relations(family.parameters, dict(form.family), {u: a for u, a, _ in form.circles}, values)
    assert relations is not None and relations.describe().startswith("y1 = y2; y3 = y6; y4 = y5")
    target = relations.full(start_systems._random_complex(np.random.default_rng(11), relations.size))
    moved, reached = start_systems._track(
        start_systems._segment(family, _instance(generic), target), _solutions(generic)
    )
    ends = moved[reached][start_systems._regular(family, target, moved[reached])]
    distinct = start_systems._add_new(np.zeros((0, family.n), complex), ends)[0]
    assert len(distinct) == 72 and len(ends) == 72
    finite = reached & start_systems._regular(family, target, moved)
    assert finite.sum() == 72 and np.all(np.abs(moved[~finite]).max(-1) > 1e5), "8 paths leave every bound"


def test_the_runtime_check_flags_inputs_whose_parameters_break_a_relation() -> None:
    """parakin.solvers.subfamily_membership: parameters loaded with the generation's coincidences are inside
    (equal to rounding), a rail moved by 1 mm or a NaN is outside; angles (radians) compare too."""
    from parakin.solvers.subfamily_membership import outside_subfamily

    free = np.array([[0.1, -0.28, -0.28, 0.23], [0.1, -0.28, -0.28 * (1 + 1e-15), 0.23], [0.2, -0.28, -0.279, 0.23]])
    angles = np.array([[0.5, 0.5], [0.5, 0.5], [0.5, 0.5]])
    outside = outside_subfamily([[1, 2], [4, 5]], free, angles, 1e-12)
    assert outside.tolist() == [False, False, True]
    angles[0, 1] = 0.5001
    free[1, 0] = np.nan
    assert outside_subfamily([[1, 2], [4, 5]], free, angles, 1e-12).tolist() == [True, True, True]
    assert outside_subfamily([], free[:1], angles[:1], 1e-12).tolist() == [False]


def _with_subfamily(tmp_path: Path, subfamily: object) -> Path:
    """A copy of planar_3rrr whose automatic method says its count was proven where a1 = a2 (the
    family's values 12 and 13: the crank lengths, equal at its defaults)."""
    import json
    import shutil

    folder = tmp_path / "planar_3rrr"
    shutil.copytree(Path(__file__).parents[1] / "generated" / "planar_3rrr", folder)
    manifest = json.loads((folder / "manifest.json").read_text())
    manifest["capabilities"]["forward"]["methods"]["automatic"]["subfamily"] = subfamily
    (folder / "manifest.json").write_text(json.dumps(manifest))
    return folder


def test_a_count_proven_on_a_subfamily_bounds_only_parameters_inside_it(tmp_path: Path, caplog) -> None:
    """Loaded with the generation's coincidence (a1 = a2 = 0.3 m) the certificate is complete as
    before; loaded with a2 = 0.31 m the relation breaks, the count no longer bounds the roots, and
    no certificate says complete (one warning names the relation). The modes themselves are the
    same solver's: the pose the inverse gives at a2 = 0.31 is among them."""
    import parakin

    folder = _with_subfamily(tmp_path, {"identical": [[12, 13]], "tolerance": 1e-12, "relations": "a1 = a2"})
    inside = parakin.load(folder, backend="numpy")
    theta = np.deg2rad([-54.0, 174.0, -105.0])
    assert inside.forward_pose_all(theta).complete()
    outside = parakin.load(folder, backend="numpy", a2=0.31)
    with caplog.at_level("WARNING", logger="parakin"):
        modes = outside.forward_pose_all(theta)
    assert not modes.complete() and int(modes.certificate()["certified_roots"]) == 6
    assert "proven where a1 = a2" in caplog.text
    pose = modes.poses[modes.valid][0]
    ik = outside.inverse_pose(pose)
    assert np.abs(ik.actuated[ik.valid] - theta).max(-1).min() < 1e-9


@pytest.mark.parametrize(
    ("subfamily", "words"),
    [
        ({"identical": [[12]], "tolerance": 1e-12}, "fewer than two values"),
        ({"identical": [[12, 99]], "tolerance": 1e-12}, "identical[0][1]"),
        ({"identical": [[12, 13]], "tolerance": -1.0}, "tolerance"),
        ({"identical": [[12, 13]]}, "tolerance"),
    ],
)
def test_a_broken_subfamily_in_a_manifest_is_named(tmp_path: Path, subfamily: object, words: str) -> None:
    import parakin

    with pytest.raises(parakin.BrokenPackageError, match=words.replace("[", r"\[").replace("]", r"\]")):
        parakin.load(_with_subfamily(tmp_path, subfamily), backend="numpy")
