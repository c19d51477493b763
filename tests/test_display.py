"""Results that explain themselves: ``print(m)`` tables every parameter with its value and unit
and every variable with its kind, unit and limits; an AssemblyModes repr is a summary line and
one row per mode (numbered 0 .. count - 1) whose pose columns are the mode's pose in the stated
convention (checked against SciPy's Z-Y-X Euler angles); the HTML forms hold the same tables."""

from __future__ import annotations

from html.parser import HTMLParser

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import parakin


class _Cells(HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.rows: list[list[str]] = []
        self._cell: list[str] | None = None

    def handle_starttag(self, tag, attrs):
        if tag == "tr":
            self.rows.append([])
        elif tag in ("td", "th"):
            self._cell = []

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self.rows[-1].append("".join(self._cell))
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


@pytest.mark.parametrize("name", ["five_bar", "spm", "stewart", "prs3"])
def test_print_mechanism_tables_parameters_variables_and_examples(name):
    m = parakin.load(name)
    text = str(m)
    assert text.splitlines()[0].startswith(f"{name}: {m.manifest.title}")
    lines = text.splitlines()
    for p in m.manifest.parameters:
        assert any(
            line.split()[:3] == [p.name, f"{m.parameters[p.name]:.6g}", p.unit] for line in lines if line.strip()
        )
    for v in (*m.manifest.actuated, *m.manifest.passive):
        assert any(line.split()[:3] == [v.name, v.kind, v.unit or "1"] for line in lines if line.strip())
    for example in m.manifest.examples:
        assert any(line.split()[:1] == [example.name] for line in lines if line.strip())
    cells = _Cells()
    cells.feed(m._repr_html_())
    assert [p.name for p in m.manifest.parameters] == [row[0] for row in cells.rows[1 : 1 + len(m.manifest.parameters)]]


def test_assembly_modes_repr_is_a_table_of_modes_in_the_stated_convention():
    m = parakin.load("stewart")
    modes = m.forward_pose_all(m.home_actuated)
    lines = repr(modes).splitlines()
    assert lines[0] == f"AssemblyModes: {int(modes.count)} assembly modes by homotopy; certified complete"
    assert "Z-Y-X Euler angles" in lines[1] and "alpha [rad]" in lines[2] and len(lines) == 4 + int(modes.count)
    checked = 0
    for k, line in enumerate(lines[4:]):
        fields = line.split()
        assert int(fields[0]) == k
        pose = modes.mode(k).pose
        euler = Rotation.from_matrix(pose[:3, :3]).as_euler("ZYX")  # intrinsic z, y', x'', radians
        assert np.allclose([float(v) for v in fields[1:4]], pose[:3, 3], rtol=1e-5, atol=1e-6)
        assert np.allclose([float(v) for v in fields[4:7]], euler, rtol=1e-5, atol=1e-4)
        checked += 1
    assert checked == 40
    cells = _Cells()
    cells.feed(modes._repr_html_())
    assert len(cells.rows) == 41 and cells.rows[0][0] == "mode"
    batch = repr(m.forward_pose_all(np.stack([m.home_actuated] * 3)))
    assert batch.splitlines()[0].startswith("AssemblyModes: a batch of 3 inputs") and len(batch.splitlines()) == 2


def test_an_incomplete_certificate_of_one_input_says_how_far_it_got():
    """planar_3rrr at its symmetric home is a degenerate input: 4 of its 6 paths head to infinity
    (tests/test_degenerate_home.py shows the roots growing as the input nears home); the summary
    line counts the certified roots and says what the others are, instead of 'complete for 0 of
    1'."""
    m = parakin.load("planar_3rrr")
    modes = m.forward_pose_all(m.home_actuated)
    certificate = modes.certificate()
    certified, total = int(certificate["certified_roots"]), int(certificate["root_count"])
    assert not certificate["complete"] and certified < total
    assert (
        repr(modes)
        .splitlines()[0]
        .endswith(
            f"; not certified complete: {certified} of {total} roots certified, the other {total - certified} paths "
            "head to infinity (roots at infinity: the input is degenerate; "
            "no finite root beyond the certified ones is proven absent) (modes.path_certified says which paths)"
        )
    )
    assert int((~modes.path_certified).sum()) == total - certified
