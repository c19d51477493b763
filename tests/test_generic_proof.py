"""A user's layout with coordinates at zero does not restrict the proven root count (issue 32,
item 3; ``generator/start_systems.py``'s ``GENERIC_MAX_PATHS`` rule).

The planar 2-RPR of ``fixtures/rpr2_zeros.py`` is written like docs/tutorials/my_robot.py: base
joints at (0, 0) and (1, 0), so base_x1 = base_y1 = base_y2 = 0 are parameters sharing a value.
Its family is small (Bezout number 4), so the count is proven for any parameter values: the
manifest names no subfamily, and the package loaded with another base certifies every input
complete, its two modes the two circles' intersection computed here (independent of the
generated code). Where the count for any parameter values is not proven, the subfamily's proof
takes over (soundness: a generic count not proven is never kept). Generation: about 1 s of CPU.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from parakin.generator import start_systems
from parakin.generator.build import generate_file
from parakin.generator.polynomial_form import PolynomialForm
from parakin.generator.subfamily import Relations

import parakin

FIXTURE = Path(__file__).parent / "fixtures" / "rpr2_zeros.py"
#: another base, every coordinate apart from the others (no relation holds)
BASE = np.array([[0.1, 0.2], [1.1, -0.15]])


def _generate(folder: Path, cache: Path) -> dict:
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("PARAKIN_CACHE", str(cache))  # a new proof, not a record another build left
        generate_file(FIXTURE, folder)
    return json.loads((folder / "manifest.json").read_text())


def _subfamilies(tree: object) -> list:
    """Every ``subfamily`` entry anywhere in a manifest."""
    if isinstance(tree, dict):
        found = [tree["subfamily"]] if "subfamily" in tree else []
        return found + [entry for value in tree.values() for entry in _subfamilies(value)]
    if isinstance(tree, list):
        return [entry for value in tree for entry in _subfamilies(value)]
    return []


@pytest.fixture(scope="module")
def package(tmp_path_factory) -> tuple[Path, dict]:
    root = tmp_path_factory.mktemp("rpr2_zeros")
    return root / "package", _generate(root / "package", root / "cache")


def two_circles(a1: np.ndarray, a2: np.ndarray, l1: float, l2: float) -> np.ndarray:
    """The points at distance l1 from a1 and l2 from a2 (2, 2): along the centre line d from a1,
    a = (l1^2 - l2^2 + d^2) / (2 d), then +-h = sqrt(l1^2 - a^2) across it."""
    d = np.linalg.norm(a2 - a1)
    along = (a2 - a1) / d
    a = (l1**2 - l2**2 + d**2) / (2 * d)
    h = np.sqrt(l1**2 - a**2)
    across = np.array([-along[1], along[0]])
    return np.array([a1 + a * along + h * across, a1 + a * along - h * across])


def test_the_count_is_proven_for_any_base(package) -> None:
    _, manifest = package
    assert _subfamilies(manifest) == []
    count = manifest["capabilities"]["forward"]["methods"]["automatic"]["root_count"]
    assert count["proven"] is True and count["count"] == 2  # two circles meet in two points


def test_loaded_with_another_base_every_input_is_certified_complete(package) -> None:
    folder, _ = package
    m = parakin.load(folder, backend="numpy", base=BASE.tolist())
    rng = np.random.default_rng(5)
    points = rng.uniform([0.2, 0.3], [0.9, 0.9], size=(12, 2))  # output points off the base line
    lengths = np.linalg.norm(points[:, None, :] - BASE[None, :, :], axis=-1)
    modes = m.forward_pose_all(lengths, method="automatic")
    assert modes.root_count == 2 and modes.root_count_proven
    checked = 0
    for index, (l1, l2) in enumerate(lengths):
        assert bool(modes.complete()[index])
        expected = two_circles(BASE[0], BASE[1], l1, l2)
        found = modes.passive[index][modes.valid[index]]
        assert len(found) == 2
        for point in expected:
            assert np.min(np.linalg.norm(found - point, axis=1)) < 1e-10
        checked += 1
    assert checked == 12


def test_a_generic_count_not_proven_leaves_the_subfamily_proof(tmp_path, monkeypatch) -> None:
    made = start_systems._new_record

    def unproven_generic(name, family, *rest):
        record = made(name, family, *rest)
        if family.relations is None:  # the proof for any parameter values: said not to close
            record = {**record, "proof": {**record["proof"], "proven": False}}
        return record

    monkeypatch.setattr(start_systems, "_new_record", unproven_generic)
    manifest = _generate(tmp_path / "package", tmp_path / "cache")
    (subfamily,) = _subfamilies(manifest)
    assert subfamily["relations"] == "base_x1 = base_y1 = base_y2"
    count = manifest["capabilities"]["forward"]["methods"]["automatic"]["root_count"]
    assert count["proven"] is True and count["count"] == 2
    stored = [json.loads(path.read_text()) for path in (tmp_path / "cache" / "homotopy").glob("*.json")]
    assert stored and all(record["proof"]["proven"] for record in stored)  # the unproven one is not kept


def test_constants_only_keeps_the_constants_and_frees_the_identical_values() -> None:
    # values: a, b = a, constant 2, c = a: one coordinate and a constant
    relations = Relations((0, 0, -1, 0), (0j, 0j, 2 + 0j, 0j), ("a", "b", "k", "c"))
    free = relations.constants_only()
    assert free is not None and free.coordinate == (0, 1, -1, 2) and free.groups == []
    assert free.constants == [2] and free.full(np.array([1.0, 3.0, 5.0]))[2] == 2
    assert Relations((0, 0, 1), (0j, 0j, 0j), ("a", "b", "c")).constants_only() is None


# ------------------------------------------------- the rule on a family whose solutions are known
z1, z2, b1, b2, c1, c2 = sp.symbols("z1 z2 b1 b2 c1 c2")
#: (b1 - b2) z1^2 + z1 - c1 = 0, z2^2 - c2 = 0: 4 solutions for generic values, 2 where b1 = b2
#: (the other z1 goes to infinity), 4 where c1 = c2 (nothing degenerates)
EQUATIONS = [(b1 - b2) * z1**2 + z1 - c1, z2**2 - c2]


def _start(values: dict, cache: Path) -> dict:
    form = PolynomialForm([z1, z2], EQUATIONS, [(s, s) for s in (b1, b2, c1, c2)], [z1, z2])
    with pytest.MonkeyPatch.context() as patch:
        cache.mkdir(mode=0o700, exist_ok=True)
        patch.setenv("PARAKIN_CACHE", str(cache))
        return start_systems.start_systems("generic_rule_test", form, EQUATIONS, 7, "automatic", values)[1]


def _closed_form_count(record: dict) -> int:
    """The number of solutions at the record's instance, from the quadratic formula."""
    q = np.array([complex(*v) for v in record["instance"]])
    return (1 if q[0] == q[1] else 2) * 2


def test_with_no_record_a_relation_that_keeps_the_count_gets_the_count_for_any_values(tmp_path) -> None:
    record = _start({b1: 0.3, b2: 0.4, c1: 0.5, c2: 0.5}, tmp_path / "cache")
    q = np.array([complex(*v) for v in record["instance"]])
    assert "relations" not in record and record["proof"]["proven"]
    assert q[2] != q[3], "drawn for any values: c1 and c2 apart"
    assert len(record["solutions"]) == _closed_form_count(record) == 4


def test_with_no_record_a_relation_that_loses_roots_is_proven_on_its_subfamily(tmp_path) -> None:
    record = _start({b1: 0.3, b2: 0.3, c1: 0.5, c2: 0.7}, tmp_path / "cache")
    q = np.array([complex(*v) for v in record["instance"]])
    assert record["relations"].describe() == "b1 = b2" and record["proof"]["proven"]
    assert q[0] == q[1] and len(record["solutions"]) == _closed_form_count(record) == 2
    # the count for any values was tried first (small family), proven (4) and stored, then not kept
    stored = sorted(
        len(json.loads(p.read_text())["solutions"]) for p in (tmp_path / "cache" / "homotopy").glob("*.json")
    )
    assert stored == [2, 4]
