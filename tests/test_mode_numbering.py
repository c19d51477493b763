"""Modes are numbered as modes everywhere a user sees them (issue 18, item 4): the CLI's ``fk``,
the demo's mode table and the plot legend number them 0 .. count - 1, the numbers
``AssemblyModes.mode(n)`` takes, never by slot (``slot`` stays in the CLI's JSON record)."""

import io
import json
from contextlib import redirect_stdout

import matplotlib
import numpy as np
import pytest

import parakin
from parakin.interfaces.cli import main
from parakin.interfaces.demo import mode_table

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def _with_modes_in_sparse_slots() -> tuple[str, np.ndarray]:
    """A mechanism and an example input whose modes do not sit in slots 0 .. count - 1 (so slot
    numbering and mode numbering differ), chosen from the manifests' examples."""
    for name in parakin.available():
        manifest = parakin.metadata(name)
        if manifest.capabilities.forward is None or manifest.capabilities.drawing is None:
            continue
        for example in manifest.examples:
            if example.actuated is None:
                continue
            m = parakin.load(name, backend="numpy", **example.parameters)
            modes = m.forward_pose_all(np.asarray(example.actuated))
            slots = np.nonzero(modes.valid)[0]
            if modes.count >= 2 and not np.array_equal(slots, np.arange(modes.count)):
                return name, np.asarray(example.actuated)
    pytest.skip("no example whose modes sit in sparse slots")


def test_cli_fk_numbers_modes_as_mode_n_does():
    name, actuated = _with_modes_in_sparse_slots()
    out = io.StringIO()
    with redirect_stdout(out):
        assert main(["fk", name, "--backend", "numpy", "--json", "--actuated", *map(repr, actuated.tolist())]) == 0
    records = [json.loads(line) for line in out.getvalue().splitlines()]
    modes = parakin.load(name, backend="numpy").forward_pose_all(actuated)
    assert [r["mode"] for r in records] == list(range(int(modes.count)))
    assert [r["slot"] for r in records] == np.nonzero(modes.valid)[0].tolist()
    for record in records:
        mode = modes.mode(record["mode"])
        assert record["residual"] == pytest.approx(float(modes.residual[record["slot"]]))
        assert np.allclose(mode.pose, modes.slot(record["slot"]).pose)


def test_demo_table_and_plot_legend_number_modes_from_zero():
    name, actuated = _with_modes_in_sparse_slots()
    m = parakin.load(name, backend="numpy")
    modes = m.forward_pose_all(actuated)
    rows = mode_table(modes)[3:]  # below the convention line, the header and its rule
    assert [int(row.split()[0]) for row in rows] == list(range(int(modes.count)))
    for row, mode in zip(rows, modes, strict=True):
        assert float(row.split()[1]) == pytest.approx(mode.pose[0, 3], abs=1e-6)
    figure = plt.figure()
    try:
        ax = figure.add_subplot(projection="3d")
        m.plot(modes, ax=ax)
        labels = [t.get_text() for t in ax.get_legend().get_texts()] if ax.get_legend() else []
    finally:
        plt.close(figure)
    assert labels == [f"mode {n}" for n in range(int(modes.count))]
