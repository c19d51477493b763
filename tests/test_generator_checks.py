"""The generator's own checks, scaled to the mechanism: a five-bar of millimetres generates and
solves; a model with nothing reachable to sample around is refused with a message saying which
check, how many samples reached, and what to change; pose kinds are validated against their twist;
every banner carries pyproject.toml's version."""

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest
from parakin.generator.build import GenerationError, generate_file
from parakin.generator.emit import package_version

import parakin

ROOT = Path(__file__).resolve().parent.parent
FIVE_BAR = (ROOT / "mechanisms" / "five_bar.py").read_text()
SCALE = 0.01  # 0.15 m -> 0.15 cm: every length of the five-bar in centimetres

#: appended to a copy of mechanisms/five_bar.py: build() with every length times SCALE (the
#: parameters, the home's x, y, the examples' poses and printed passive values)
SCALED = f"""

import dataclasses as _dataclasses

_SCALE = {SCALE}
_original_build = build


def _scale_pose(pose):
    return [[v * _SCALE if j == 3 and i < 3 else v for j, v in enumerate(row)] for i, row in enumerate(pose)]


def build():
    m = _original_build()
    m.parameters = {{k: v * _SCALE for k, v in m.parameters.items()}}
    m.home = {{k: (v * _SCALE if k in m.passive else v) for k, v in m.home.items()}}
    examples = []
    for e in m.examples:
        expected = dict(e.expected)
        if "passive" in expected:
            expected["passive"] = [v * _SCALE for v in expected["passive"]]
        if "poses" in expected:
            expected["poses"] = [_scale_pose(p) for p in expected["poses"]]
        pose = _scale_pose(e.pose) if e.pose else None
        examples.append(_dataclasses.replace(e, pose=pose, expected=expected))
    m.examples = examples
    return m
"""


def _mutated(tmp_path: Path, name: str, body: str) -> Path:
    """A copy of the five-bar file whose build() applies ``body`` (lines using ``m``)."""
    source = tmp_path / f"{name}.py"
    indented = "\n".join(f"    {line}" for line in body.strip().splitlines())
    source.write_text(
        FIVE_BAR
        + f"\n\nimport math\n_original = build\n\n\ndef build():\n    m = _original()\n{indented}\n    return m\n"
    )
    return source


def test_a_five_bar_in_centimetres_generates_and_solves(tmp_path):
    """d = 0.15 cm, a = 0.2 cm, b = 0.25 cm (the checks sampled a fixed 1 m box before: 0 of 600
    samples reachable). P = (0.3, 3) mm solves in four branches, and each branch's inputs give
    back P among two assembly modes; each elbow is b from P (by hand: C_i = A_i + a (cos, sin))."""
    source = tmp_path / "five_bar_cm.py"
    source.write_text(FIVE_BAR + SCALED)
    package = tmp_path / "out" / "five_bar_cm"
    generate_file(source, package)
    m = parakin.load(str(package), backend="numpy")
    d, a, b = 0.15 * SCALE, 0.2 * SCALE, 0.25 * SCALE
    point = np.array([0.3e-3, 3e-3])
    ik = m.inverse_pose(point)
    assert int(ik.valid.sum()) == 4
    for theta in ik.actuated:
        for i, base in enumerate((-d, d)):
            elbow = np.array([base + a * np.cos(theta[i]), a * np.sin(theta[i])])
            assert abs(np.linalg.norm(point - elbow) - b) < 1e-15
        modes = m.forward_pose_all(theta)
        assert int(modes.count) == 2
        assert np.abs(modes.poses[modes.valid][:, :2, 3] - point).max(axis=-1).min() < 1e-15
    chosen = json.loads((package / "manifest.json").read_text())["c"]["example"]
    assert chosen["verified"]


def test_nothing_reachable_to_sample_around_is_explained(tmp_path):
    """A home whose elbows are 0.7 m apart (theta = (pi, 0): the distal links, 0.5 m together,
    cannot meet) and one example pose 5 m away: the message names the check, says 0 of the tried
    samples reached, that the home does not close, and what to change, in one line."""
    source = _mutated(
        tmp_path,
        "far_bar",
        """
m.home = {**m.home, m.actuated[0]: math.pi, m.actuated[1]: 0.0, m.passive[0]: 0.0, m.passive[1]: 3.0}
far = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 5.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]
m.examples = [dataclasses.replace(m.examples[0], name="far", pose=far)]
""",
    )
    source.write_text(source.read_text().replace("import math\n", "import dataclasses\nimport math\n"))
    with pytest.raises(GenerationError) as raised:
        generate_file(source, tmp_path / "out" / "far_bar")
    message = str(raised.value)
    assert "\n" not in message
    assert "cannot check det A = product of parallel_factors ['distal_links_aligned']" in message
    assert "only 0 of 600 poses sampled around example 'far'" in message
    assert "the home does not close" in message
    assert "give a home configuration that closes" in message and "named examples with poses" in message
    assert not (tmp_path / "out" / "far_bar").exists()


def test_without_any_anchor_the_home_is_named(tmp_path):
    """No example, and a home that does not close: there is nothing to sample around."""
    source = _mutated(
        tmp_path,
        "lost_bar",
        "m.home = {**m.home, m.actuated[0]: math.pi, m.actuated[1]: 0.0}\nm.examples = []",
    )
    with pytest.raises(GenerationError, match=r"no pose to sample around \(the home does not close"):
        generate_file(source, tmp_path / "out" / "lost_bar")


@pytest.mark.parametrize(
    ("kind", "message"),
    [
        ("planer", r"pose_kind 'planer' is not one of \['planar', 'planar_translation', 'rotation', 'transform', "),
        (
            "translation",
            r"twist \['vx', 'vy'\] does not match pose_kind 'translation', whose twist is \['vx', 'vy', 'vz'\]",
        ),
    ],
)
def test_pose_kinds_are_validated(tmp_path, kind, message):
    source = _mutated(tmp_path, "kind_bar", f"m.pose_kind = {kind!r}")
    with pytest.raises(GenerationError, match=message):
        generate_file(source, tmp_path / "out" / "kind_bar")


def test_every_banner_carries_the_version_of_pyproject():
    """One place for the version: pyproject.toml's [project] version, in the manifest and in the
    banner of every generated file (C, headers, Python) and the C README."""
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    assert package_version() == version
    folder = ROOT / "generated" / "five_bar"
    assert json.loads((folder / "manifest.json").read_text())["generator"]["version"] == version
    for name in ("driver.c", "kernels.c", "kernels.h", "five_bar.h", "real_roots.h", "example_main.c"):
        assert (folder / name).read_text().startswith(f"// Generated by parakin generator {version} "), name
    for name in ("numpy_kernels.py", "casadi_functions.py", "symbolic.py"):
        assert (folder / name).read_text().startswith(f"# Generated by parakin generator {version} "), name
    assert f"Generated by parakin {version} from" in (folder / "README_C.md").read_text()


def test_drawing_parts_declared_named_or_inferred_and_bad_parts_refused():
    """A polyline's part: declared, else said by its name, else base when every vertex is fixed
    (no state variable in its point set's expressions) and leg otherwise."""
    import sympy as sp
    from parakin.generator.drawing import drawing_metadata
    from parakin.generator.errors import GenerationError
    from parakin.generator.model import Drawing

    q, a = sp.symbols("q a", real=True)
    points = {"anchors": sp.Matrix([[0, a], [0, 0], [0, 0]]), "tips": sp.Matrix([[sp.cos(q)], [sp.sin(q)], [0]])}
    polylines = {
        "ground": [("anchors", 0), ("anchors", 1)],
        "x1": [("anchors", 0), ("tips", 0)],
        "x2": [("anchors", 0)],
    }
    meta = drawing_metadata(Drawing(points, polylines, parts={"x1": "platform"}), {q})
    assert meta["fixed"] == ["anchors"]
    assert meta["parts"] == {"ground": "base", "x1": "platform", "x2": "base"}
    assert drawing_metadata(Drawing(points, polylines), {q})["parts"]["x1"] == "leg"
    for bad in ({"x1": "wheel"}, {"nowhere": "leg"}):
        with pytest.raises(GenerationError, match="drawing parts"):
            drawing_metadata(Drawing(points, polylines, parts=bad), {q})
