"""Grids of many modes people can read (issue 36's review: ``parakin plot stewart`` drew 40 panels
of 2.7 in). The default grid draws the first MAX_PANELS modes on larger panels with shared limits
and names the others (and which of them are near-singular) in its title; ``all_modes=True`` draws
every one (tests/test_plot.py: one panel per mode, stewart's 40 included); each panel says its
mode number, and near a type II singularity it says so in red. Grids of up to MAX_PANELS modes
keep their layout. Near-singular is decided here from NumPy's ``cond`` of the generated closure
Jacobian (1/cond below NEAR_SINGULAR)."""

import re

import matplotlib
import numpy as np
import pytest

import parakin
from parakin.interfaces.plot import MAX_PANELS, NEAR_COLOUR, numbers_text
from parakin.singularity import NEAR_SINGULAR

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import same_color  # noqa: E402


def near_by_numpy(m, modes) -> list[bool]:
    """Per mode: 1/numpy.linalg.cond of the closure Jacobian below NEAR_SINGULAR."""
    flags = []
    for k in range(int(modes.count)):
        c = modes.mode(k)
        flags.append(1.0 / np.linalg.cond(m.loop_closure(c.actuated, c.passive)["jacobian"]) < NEAR_SINGULAR)
    return flags


@pytest.fixture(scope="module")
def stewart():
    m = parakin.load("stewart")
    return m, m.forward_pose_all(m.home_actuated)


def test_the_default_grid_of_40_modes_draws_12_and_names_the_rest(stewart):
    m, modes = stewart
    near = near_by_numpy(m, modes)
    assert int(modes.count) == 40 and MAX_PANELS == 12
    axes = m.plot(modes)
    figure = axes[0].figure
    try:
        assert len(axes) == 12
        assert [ax.get_title().split("\n")[0] for ax in axes] == [f"mode {k}" for k in range(12)]
        # shared limits and view
        assert len({(ax.get_xlim(), ax.get_ylim(), ax.get_zlim(), ax.elev, ax.azim) for ax in axes}) == 1
        # near-singular panels: red and marked, exactly where numpy's cond says so
        for k, ax in enumerate(axes):
            red = same_color(ax.title.get_color(), NEAR_COLOUR)
            assert red == near[k] == ("near-singular" in ax.get_title()), (k, ax.get_title())
        title = figure.get_suptitle().replace("\n", " ")
        assert "40 assembly modes at" in title and "the first 12 drawn" in title
        listed = re.search(r"not drawn: modes 12-39 \(near-singular: ([0-9, -]+)\)", title)
        assert listed is not None, title
        assert listed.group(1) == numbers_text([k for k in range(12, 40) if near[k]])
        assert "--all-modes" in title and "draws all 40" in title
        # larger panels: 4 columns of 3.4 in (the 40-panel grid had 7 of 2.7 in)
        assert figure.get_figwidth() == pytest.approx(4 * 3.4)
        assert sum(near[12:]) >= 10 and sum(near[:12]) >= 5  # the premise: both kinds are listed
    finally:
        plt.close(figure)


def test_a_grid_of_six_modes_keeps_its_layout():
    """planar_3rpr's six modes: every one drawn, 3 columns of 2.7 in, nothing 'not drawn'."""
    m = parakin.load("planar_3rpr", backend="numpy")
    modes = m.forward_pose_all(m.home_actuated)
    axes = m.plot(modes)
    figure = axes[0].figure
    try:
        assert len(axes) == int(modes.count) == 6
        assert figure.get_figwidth() == pytest.approx(3 * 2.7)
        assert "not drawn" not in figure.get_suptitle()
        near = near_by_numpy(m, modes)
        assert [same_color(ax.title.get_color(), NEAR_COLOUR) for ax in axes] == near
    finally:
        plt.close(figure)


def test_numbers_as_runs():
    assert numbers_text([0, 1, 2, 5, 7, 8]) == "0-2, 5, 7-8"
    assert numbers_text([39]) == "39" and numbers_text([]) == ""
    assert numbers_text([3, 1, 2]) == "1-3"


def test_the_help_and_the_readme_say_what_the_default_grid_draws():
    """``parakin plot --help`` and the README's plot row once said the default grid is every mode:
    they name the first MAX_PANELS modes and --all-modes for every one."""
    from pathlib import Path

    from parakin.interfaces import cli

    plot = next(a for a in cli._parser()._actions if a.dest == "command").choices["plot"]
    all_modes = next(a for a in plot._actions if "--all-modes" in a.option_strings)
    assert f"the first {MAX_PANELS}," in all_modes.help and "named in the title" in all_modes.help
    description = " ".join(plot.description.split())
    assert f"a grid of the first {MAX_PANELS} assembly modes" in description
    assert "--all-modes draws every mode" in description and "the title names the modes left out" in description
    readme = (Path(__file__).resolve().parent.parent / "README.md").read_text()
    (row,) = [line for line in readme.splitlines() if line.startswith("| `parakin plot ")]
    assert f"default: the first {MAX_PANELS}, the others named in the title" in row and "`--all-modes`" in row
