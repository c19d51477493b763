"""Sweep inputs and sentinels (issue 18 item 10): a mode count the elimination cannot give is a
missing value (NaN) with a status variable of its own, never the number -1; every name that is
not swept can be fixed (pose coordinates, actuated inputs, parameters), from the API and from
the CLI; a fixed value for a swept, unknown or unread name, or one that is not one finite real
number, is a BadInputError naming it."""

from __future__ import annotations

import json

import numpy as np
import pytest

xr = pytest.importorskip("xarray")
pytest.importorskip("dask")

from test_sweep import _five_bar_reachable  # noqa: E402

import parakin  # noqa: E402
from parakin.interfaces.cli import main  # noqa: E402
from parakin.studies.sweep import sweep  # noqa: E402

# SAM's inputs other than the two swept, fixed explicitly (the values of its home at 6bfa97b),
# so that the claims below do not depend on the default home
SAM_OTHERS = {"theta2": -np.pi / 12, "theta3": 0.0, "theta5": np.pi / 12, "theta6": 0.0}


def _sam_inputs(m, grid: dict[str, np.ndarray], fixed: dict[str, float]) -> np.ndarray:
    """(n1, n2, 6) actuated inputs of a 2-axis grid, for ``count_modes`` (the independent source)."""
    mesh = np.meshgrid(*grid.values(), indexing="ij")
    theta = np.empty(mesh[0].shape + (6,))
    for k, name in enumerate(m.actuated_names):
        theta[..., k] = mesh[list(grid).index(name)] if name in grid else fixed[name]
    return theta


def test_a_degenerate_mode_count_is_missing_and_flagged_not_minus_one():
    """SAM with theta1 = theta4 (parallel U-joint axes): the elimination degenerates on the
    diagonal. At 6bfa97b 'modes' held -1 there (an int32 'count'); now NaN, and modes_status
    holds the manifest's code 'degenerate', named in its attributes."""
    m = parakin.load("sam")
    grid = {"theta1": np.linspace(-0.3, 0.3, 5), "theta4": np.linspace(-0.3, 0.3, 5)}
    result = sweep(m, ["modes"], grid, fixed=SAM_OTHERS)
    counted = m.count_modes(_sam_inputs(m, grid, SAM_OTHERS))
    codes = list(m.manifest.abi.input_status)
    status = result.modes_status.values
    np.testing.assert_array_equal(status, counted["status"])
    np.testing.assert_array_equal(status == codes.index("degenerate"), np.eye(5, dtype=bool))
    modes = result.modes.values
    assert modes.dtype == float
    np.testing.assert_array_equal(np.isnan(modes), np.eye(5, dtype=bool))
    np.testing.assert_array_equal(modes[~np.eye(5, dtype=bool)], counted["count"][~np.eye(5, dtype=bool)])
    attributes = result.modes_status.attrs
    assert attributes["flag_meanings"].split() == codes and list(attributes["flag_values"]) == [0, 1, 2]


def test_a_plot_marks_the_flag_as_its_own_region(tmp_path):
    """plot_sweep draws 'modes' with its degenerate cells left out of the colour map and covered
    by a hatched region named in the legend (one cell per degenerate input)."""
    pytest.importorskip("matplotlib")
    from parakin.studies.atlas import plot_sweep

    grid = {"theta1": np.linspace(-0.3, 0.3, 5), "theta4": np.linspace(-0.3, 0.3, 5)}
    result = sweep("sam", ["modes"], grid, fixed=SAM_OTHERS)
    ax = plot_sweep(result, "modes", str(tmp_path / "modes.png"))
    flagged = [c for c in ax.collections if c.get_gid() == "flag degenerate"]
    assert len(flagged) == 1 and flagged[0].get_hatch()
    cells = flagged[0].get_array()
    assert int(np.ma.count(cells)) == 5  # the diagonal, nothing else
    mesh = next(
        c for c in ax.collections if c.get_gid() is None and hasattr(c, "get_array") and c.get_array() is not None
    )
    assert int(np.ma.count_masked(mesh.get_array())) == 5
    assert any("degenerate" in text.get_text() for text in ax.get_legend().get_texts())
    assert (tmp_path / "modes.png").stat().st_size > 5_000
    status_ax = plot_sweep(result, "modes_status")
    labels = [t.get_text() for t in status_ax.figure.axes[-1].get_yticklabels()]
    assert labels == ["ok", "nonfinite", "degenerate"]
    line = sweep("sam", ["modes"], {"theta1": np.linspace(-0.3, 0.3, 7)}, fixed={**SAM_OTHERS, "theta4": 0.0})
    assert int(np.isnan(line.modes.values).sum()) == 1  # theta1 = theta4 = 0
    curve_ax = plot_sweep(line, "modes")
    assert [c.get_gid() for c in curve_ax.collections] == ["flag degenerate"]


def test_actuated_inputs_not_swept_can_be_fixed():
    """At 6bfa97b only pose coordinates could be fixed: theta1 stayed at its home value."""
    m = parakin.load("sam")
    grid = {"theta2": np.linspace(-0.6, 0.6, 3), "theta5": np.linspace(-0.6, 0.6, 3)}
    fixed = {"theta1": 0.1, "theta3": 0.0, "theta4": -0.05, "theta6": 0.0}
    result = sweep(m, ["modes"], grid, fixed=fixed)
    counted = m.count_modes(_sam_inputs(m, grid, fixed))
    assert (counted["status"] == 0).all() and counted["count"].max() > 0
    np.testing.assert_array_equal(result.modes.values, counted["count"])
    assert json.loads(result.attrs["fixed"]) == fixed


def test_a_fixed_pose_coordinate_and_a_fixed_parameter_are_used():
    """five_bar along x at the fixed height y = 0.3, with a1 = 0.25 fixed instead of loaded:
    reachable matches the analytic workspace of that design at that height."""
    xs = np.linspace(-0.6, 0.6, 121)
    result = sweep("five_bar", ["reachable"], {"x": xs}, fixed={"y": 0.3, "a1": 0.25})
    parameters = {**parakin.load("five_bar").parameters, "a1": 0.25}
    expected, margin = _five_bar_reachable(xs, np.full_like(xs, 0.3), parameters)
    clear = margin > 1e-9
    assert expected[clear].any() and (~expected[clear]).any()
    np.testing.assert_array_equal(result.reachable.values[clear], expected[clear])
    assert not np.array_equal(result.reachable.values, sweep("five_bar", ["reachable"], {"x": xs}).reachable.values)


@pytest.mark.parametrize(
    ("fixed", "message"),
    [
        ({"theta2": 0.1}, "fixed 'theta2' is swept"),
        ({"nonsense": 0.1}, "fixed 'nonsense' is not a name"),
        ({"theta1": [0.1, 0.2]}, "fixed 'theta1' must be one number"),
        ({"theta1": float("nan")}, "fixed 'theta1' must be finite"),
        ({"theta1": float("inf")}, "fixed 'theta1' must be finite"),
        ({"theta1": "0.1"}, "fixed 'theta1' must be numeric"),
        ({"theta1": True}, "fixed 'theta1' must be real numbers"),
        ({"theta1": 1e12}, r"fixed .theta1. = 1e\+12 exceeds"),
        ({"x": 0.1}, "fixed 'x': a pose coordinate, which none of the quantities"),
    ],
)
def test_bad_fixed_values_are_refused_naming_them(fixed, message):
    grid = {"theta2": [0.0, 0.1], "theta5": [0.0]}
    with pytest.raises(parakin.BadInputError, match=message):
        sweep("sam", ["modes"], grid, fixed=fixed)


def test_bad_fixed_pose_values_and_unread_axes_are_refused():
    """The issue's cases on a pose sweep: a list for a pose coordinate (a raw TypeError at
    6bfa97b), a fixed value for a swept coordinate (silently ignored at 6bfa97b); and an axis
    that no requested quantity reads."""
    with pytest.raises(parakin.BadInputError, match="fixed 'beta' must be one number"):
        sweep("spm", ["reachable"], {"alpha": [0.0, 0.1]}, fixed={"beta": [0.1, 0.2]})
    with pytest.raises(parakin.BadInputError, match="fixed 'alpha' is swept"):
        sweep("spm", ["reachable"], {"alpha": [0.0, 0.1]}, fixed={"alpha": 0.3})
    with pytest.raises(parakin.BadInputError, match="axis 'x': a pose coordinate, which none"):
        sweep("sam", ["modes"], {"x": [0.0, 0.1]})
    with pytest.raises(parakin.BadInputError, match="fixed must be a mapping"):
        sweep("spm", ["reachable"], {"alpha": [0.0, 0.1]}, fixed=[("beta", 0.1)])


def test_the_cli_fixes_and_refuses_the_same(tmp_path, capsys):
    """`parakin sweep sam modes --axis theta2=... --axis theta5=...` printed "mean -1 (121/121
    defined)" at 6bfa97b and refused `--fixed theta1=0.1`."""
    axes = ["--axis", "theta2=-0.6:0.6:3", "--axis", "theta5=-0.6:0.6:3"]
    others = [f"--fixed={name}=0" for name in ("theta3", "theta6")]
    assert main(["sweep", "sam", "modes", *axes, *others, "--fixed", "theta1=0", "--fixed", "theta4=0"]) == 0
    printed = capsys.readouterr().out
    assert "modes " in printed and "all NaN  (0/9 defined)" in printed and "-1" not in printed
    path = tmp_path / "s.nc"
    fixed = ["--fixed", "theta1=0.1", "--fixed", "theta4=-0.05", *others]
    assert main(["sweep", "sam", "modes", *axes, *fixed, "--netcdf", str(path)]) == 0
    grid = {"theta2": np.linspace(-0.6, 0.6, 3), "theta5": np.linspace(-0.6, 0.6, 3)}
    direct = sweep("sam", ["modes"], grid, fixed={"theta1": 0.1, "theta4": -0.05, "theta3": 0.0, "theta6": 0.0})
    np.testing.assert_array_equal(xr.load_dataset(path).modes.values, direct.modes.values)
    capsys.readouterr()
    assert main(["sweep", "sam", "modes", *axes, "--fixed", "theta2=0.1"]) == 2
    assert "fixed 'theta2' is swept" in capsys.readouterr().err
    assert main(["sweep", "sam", "modes", *axes, "--fixed", "theta1=nan"]) == 2
    assert "fixed 'theta1' must be finite" in capsys.readouterr().err


def test_planar_translation_pose_coordinates():
    """pose kind 'planar_translation': ^B_P T = [I, (x, y, 0)] from the sweep's (x, y)."""
    from parakin.studies.sweep import POSE_COORDINATES, _pose_from

    assert POSE_COORDINATES["planar_translation"] == ("x", "y")
    x, y = np.array([0.1, -0.2]), np.array([0.3, 0.4])
    pose = _pose_from("planar_translation", {"x": x, "y": y})
    expected = np.broadcast_to(np.eye(4), (2, 4, 4)).copy()
    expected[:, 0, 3], expected[:, 1, 3] = x, y
    np.testing.assert_array_equal(pose, expected)


def test_a_planar_translation_mechanism_sweeps_over_x_and_y():
    m = parakin.load("five_bar")
    if m.manifest.pose_kind != "planar_translation":
        pytest.skip(f"five_bar's manifest says pose_kind {m.manifest.pose_kind!r}: regenerate it (make generate)")
    xs, ys = np.linspace(-0.5, 0.5, 21), np.linspace(-0.3, 0.6, 19)
    result = sweep(m, ["reachable"], {"x": xs, "y": ys})
    expected, margin = _five_bar_reachable(*np.meshgrid(xs, ys, indexing="ij"), m.parameters)
    clear = margin > 1e-9
    np.testing.assert_array_equal(result.reachable.values[clear], expected[clear])
    with pytest.raises(parakin.BadInputError, match="axis 'z' is not a pose coordinate"):
        sweep(m, ["reachable"], {"x": xs, "z": [0.0]})


def test_a_planar_translation_package_sweeps_over_x_and_y(tmp_path):
    """The five-bar's package with its manifest's pose kind set to 'planar_translation' (what the
    regenerated five-bar declares; its kernels do not change): the sweep takes (x, y), no z, and
    gives the same map as the five-bar swept over x, y at z = 0."""
    import shutil

    source = parakin.load("five_bar").package.path
    package = tmp_path / "five_bar"
    shutil.copytree(source, package, ignore=shutil.ignore_patterns("__pycache__"))
    manifest = json.loads((package / "manifest.json").read_text())
    manifest["pose_kind"] = "planar_translation"
    (package / "manifest.json").write_text(json.dumps(manifest))
    m = parakin.load(str(package), backend="numpy")
    assert m.manifest.pose_kind == "planar_translation"
    axes = {"x": np.linspace(-0.5, 0.5, 21), "y": np.linspace(-0.3, 0.6, 19)}
    quantities = ["reachable", "type_ii_distance", "type_i_distance"]
    planar = sweep(m, quantities, axes)
    reference = sweep("five_bar", quantities, axes, backend="numpy")
    for name in quantities:
        np.testing.assert_array_equal(planar[name].values, reference[name].values, err_msg=name)
    assert json.loads(planar.attrs["fixed"]) == {}  # nothing left to fix: (x, y) is the whole pose
    with pytest.raises(parakin.BadInputError, match="axis 'z' is not a pose coordinate"):
        sweep(m, ["reachable"], {"x": axes["x"], "z": [0.0]})
    line = sweep(m, ["reachable"], {"x": axes["x"]}, fixed={"y": 0.3})
    expected, margin = _five_bar_reachable(axes["x"], np.full(21, 0.3), m.parameters)
    assert (margin > 1e-9).all() and expected.any() and (~expected).any()
    np.testing.assert_array_equal(line.reachable.values, expected)
