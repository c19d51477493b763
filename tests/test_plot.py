"""Drawings on given axes: 2-D axes draw planar mechanisms in the x-y plane; a drawing that
leaves the plane z = const needs 3-D axes and says so (issue 18, item 17)."""

import matplotlib
import numpy as np
import pytest

import parakin

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def planar_names() -> list[str]:
    """Mechanisms whose pose kind keeps the platform in the plane z = 0 (and that can draw)."""
    kinds = ("planar", "planar_translation")
    return [
        n
        for n in parakin.available()
        if parakin.metadata(n).pose_kind in kinds and parakin.metadata(n).capabilities.drawing is not None
    ]


@pytest.mark.parametrize("name", planar_names())
def test_planar_mechanisms_draw_on_2d_axes(name):
    """`m.plot(state, ax=<2-D axes>)` once raised AttributeError (set_zlabel); each polyline is
    drawn with the x and y of the drawing kernel's points."""
    m = parakin.load(name, backend="numpy")
    state = m.forward_pose(m.home_actuated)
    figure, ax = plt.subplots()
    try:
        assert m.plot(state, ax=ax) is ax
        lines = ax.get_lines()
        drawing = m.capabilities.drawing
        assert len(lines) == len(drawing.polylines)
        points = m.drawing(state)
        for line, vertices in zip(lines, drawing.polylines.values(), strict=True):
            expected = np.stack([points[s][:, i] for s, i in vertices], axis=-1)
            np.testing.assert_allclose(line.get_xdata(), expected[0])
            np.testing.assert_allclose(line.get_ydata(), expected[1])
        assert ax.get_xlabel() == "x [m]" and ax.get_ylabel() == "y [m]"
    finally:
        plt.close(figure)


def test_a_spatial_drawing_on_2d_axes_is_refused_naming_3d_axes():
    m = parakin.load("spm", backend="numpy")
    state = m.forward_pose(m.home_actuated)
    figure, ax = plt.subplots()
    try:
        with pytest.raises(parakin.BadInputError, match=r"the drawing of spm spans .* m in z: it needs 3-D axes"):
            m.plot(state, ax=ax)
        assert ax.get_lines() == []  # refused before drawing anything
    finally:
        plt.close(figure)
    figure = plt.figure()
    try:
        ax3 = figure.add_subplot(projection="3d")
        assert m.plot(state, ax=ax3) is ax3 and len(ax3.get_lines()) == len(m.capabilities.drawing.polylines)
    finally:
        plt.close(figure)


# ---------------------------------------------------------------- pictures people can read (issue 21, item 2)
import io  # noqa: E402
import time  # noqa: E402
from contextlib import redirect_stdout  # noqa: E402

from PIL import Image  # noqa: E402

from parakin.interfaces.cli import main  # noqa: E402
from parakin.interfaces.plot import PART_LABEL, PART_STYLE, actuated_line, actuated_loop, animate, plot, track  # noqa: E402


def drawable_names() -> list[str]:
    return [n for n in parakin.available() if parakin.metadata(n).capabilities.drawing is not None]


def forward_names() -> list[str]:
    return [n for n in drawable_names() if parakin.metadata(n).capabilities.forward is not None]


def home(m):
    """The home configuration (Newton from the home passive values: no all-modes solve)."""
    return m.forward_pose(m.home_actuated, guess=m.home_passive)


def points_of(m, state):
    """Every polyline vertex of the drawing (3, n) in {B}."""
    points = m.drawing(state)
    return np.concatenate(
        [np.stack([points[s][:, i] for s, i in v], -1) for v in m.capabilities.drawing.polylines.values()], -1
    )


@pytest.mark.parametrize("name", drawable_names())
def test_planar_drawings_get_2d_axes_and_the_others_3d(name):
    """ax=None: 2-D axes exactly when every drawn point has the same z (a planar mechanism)."""
    m = parakin.load(name)
    state = home(m)
    z = points_of(m, state)[2]
    ax = plot(m, state)
    try:
        planar = np.ptp(z) <= 1e-9 * max(1.0, np.abs(points_of(m, state)).max())
        assert hasattr(ax, "set_zlim") is not planar, (name, np.ptp(z))
        if parakin.metadata(name).pose_kind in ("planar", "planar_translation"):
            assert planar and ax.get_xlabel() == "x [m]" and ax.get_ylabel() == "y [m]"
    finally:
        plt.close(ax.figure)


@pytest.mark.parametrize("name", forward_names())
def test_all_modes_grid_has_one_panel_per_mode_titled_and_with_common_limits(name):
    m = parakin.load(name)
    modes = m.forward_pose_all(m.home_actuated)
    axes = plot(m, modes, all_modes=True)
    try:
        assert len(axes) == int(modes.count)
        assert [ax.get_title().split("\n")[0] for ax in axes] == [f"mode {k}" for k in range(int(modes.count))]
        limits = {(ax.get_xlim(), ax.get_ylim(), getattr(ax, "get_zlim", lambda: None)()) for ax in axes}
        assert len(limits) == 1, limits
        # every mode drawn inside the common limits
        low, high = np.array([lim[0] for lim in next(iter(limits)) if lim]), None
        high = np.array([lim[1] for lim in next(iter(limits)) if lim])
        for mode in modes:
            xyz = points_of(m, mode)[: low.size]
            assert (xyz >= low[:, None] - 1e-12).all() and (xyz <= high[:, None] + 1e-12).all()
    finally:
        plt.close(axes[0].figure)


def test_default_plot_of_modes_is_the_grid_and_mode_k_draws_mode_k_alone():
    m = parakin.load("spm")
    modes = m.forward_pose_all(m.home_actuated)
    axes = plot(m, modes)
    plt.close(axes[0].figure)
    assert len(axes) == int(modes.count) == 8
    ax = plot(m, modes, mode=3)
    try:
        assert ax.get_title().split("\n")[1].startswith("mode 3 · type II")
        arcs = [np.array(line.get_data_3d()) for line in ax.get_lines()]
        expected = points_of(m, modes.mode(3))
        drawn = np.concatenate(arcs, -1)
        for point in expected.T:  # every joint of mode 3 is on a drawn arc
            assert np.min(np.linalg.norm(drawn - point[:, None], axis=0)) < 1e-12
    finally:
        plt.close(ax.figure)


def test_a_bad_mode_index_is_refused_naming_the_valid_range():
    m = parakin.load("five_bar")
    modes = m.forward_pose_all(m.home_actuated)
    count = int(modes.count)
    for bad in (count, -1, 1.0, True):
        with pytest.raises(parakin.errors.NoSuchModeError, match=r"mode"):
            plot(m, modes, mode=bad)
    with pytest.raises(parakin.errors.NoSuchModeError, match=rf"there are {count} modes \(indexed 0 to {count - 1}\)"):
        plot(m, modes, mode=count)
    with pytest.raises(parakin.BadInputError, match="not both"):
        plot(m, modes, mode=0, all_modes=True)
    figure, ax = plt.subplots()
    try:
        with pytest.raises(parakin.BadInputError, match="leave ax None"):
            plot(m, modes, ax=ax, all_modes=True)
    finally:
        plt.close(figure)


def spherical_names() -> list[str]:
    """Rotation-kind mechanisms whose every drawn point is at one distance from the centre."""
    names = []
    for name in drawable_names():
        if parakin.metadata(name).pose_kind != "rotation":
            continue
        m = parakin.load(name)
        state = home(m)
        radii = np.linalg.norm(points_of(m, state) - np.asarray(state.pose)[:3, 3:4], axis=0)
        if np.ptp(radii) < 1e-9:
            names.append(name)
    return names


def test_spm_and_sphere2r_are_the_spherical_drawings():
    assert {"spm", "sphere2r"} <= set(spherical_names()) and "sps" not in spherical_names()


@pytest.mark.parametrize("name", spherical_names())
def test_spherical_drawings_are_great_circle_arcs_on_the_sphere(name):
    """Every drawn vertex lies on the sphere about the fixed centre to 1e-9 (arcs, not chords),
    and each arc lies in the plane through the centre and its end points (a great circle)."""
    m = parakin.load(name)
    state = home(m)
    centre = np.asarray(state.pose)[:3, 3]
    radius = float(np.linalg.norm(points_of(m, state)[:, 0] - centre))
    ax = plot(m, state)
    try:
        lines = [np.array(line.get_data_3d()) for line in ax.get_lines()]
        assert len(lines) == len(m.capabilities.drawing.polylines)
        for arc in lines:
            assert np.abs(np.linalg.norm(arc - centre[:, None], axis=0) - radius).max() < 1e-9
        for arc, vertices in zip(lines, m.capabilities.drawing.polylines.values(), strict=True):
            assert arc.shape[1] > len(vertices)  # densified: not the chords
            a, b = arc[:, 0] - centre, arc[:, 1] - centre  # the first segment's plane
            normal = np.cross(a, b) / np.linalg.norm(np.cross(a, b))
            head = arc[:, :10] - centre[:, None]
            assert np.abs(normal @ head).max() < 1e-9
        assert ax.collections  # the translucent sphere (a surface and its wireframe) is drawn
    finally:
        plt.close(ax.figure)


@pytest.mark.parametrize("name", drawable_names())
def test_parts_are_styled_apart_and_named_in_the_legend(name):
    m = parakin.load(name)
    ax = plot(m, home(m))
    try:
        names = list(m.capabilities.drawing.polylines)
        lines = ax.get_lines()
        for polyline, line in zip(names, lines, strict=True):
            if polyline.startswith("base"):
                assert line.get_color() == PART_STYLE["base"]["color"]
                assert line.get_linewidth() == PART_STYLE["base"]["linewidth"]
            if polyline.startswith("leg"):
                assert line.get_color() == PART_STYLE["leg"]["color"]
            if polyline.startswith("platform"):
                assert line.get_color() == PART_STYLE["platform"]["color"]
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
        assert "fixed joints" in labels and "moving joints" in labels
        colours = {style["color"]: PART_LABEL[part] for part, style in PART_STYLE.items()}
        assert sorted(set(labels) - {"fixed joints", "moving joints"}) == sorted(
            {colours[li.get_color()] for li in lines}
        )
    finally:
        plt.close(ax.figure)


@pytest.mark.parametrize("name", drawable_names())
def test_the_manifests_fixed_point_sets_stay_and_the_others_move(name):
    """The generator's symbolic fact (no actuated or passive variable in the expressions) against
    the kernel: at configurations tracked to other inputs, fixed sets are unchanged and every other
    set moves; each polyline's part in the manifest is the part it is drawn as."""
    m = parakin.load(name)
    drawing = m.capabilities.drawing
    start = home(m)
    step = np.where(np.isfinite(start.actuated), 0.02 * np.maximum(abs(start.actuated), 0.1), 0.0)
    others = [m.forward_pose(start.actuated + k * step, guess=start.passive) for k in (1, -1)]
    at_home = m.drawing(start)
    moved = {s: max(abs(m.drawing(c)[s] - at_home[s]).max() for c in others) for s in drawing.points}
    assert drawing.fixed and set(drawing.fixed) < set(drawing.points)
    for s, distance in moved.items():
        assert (distance == 0.0) == (s in drawing.fixed), (s, distance)
    ax = plot(m, start)
    try:
        for polyline, line in zip(drawing.polylines, ax.get_lines(), strict=True):
            assert line.get_color() == PART_STYLE[drawing.parts[polyline]]["color"]
    finally:
        plt.close(ax.figure)


@pytest.mark.parametrize("name", [n for n in drawable_names() if parakin.metadata(n).capabilities.forward])
def test_the_title_shows_the_distance_to_a_type_ii_singularity(name):
    """'type II d' in the title: d = 1/cond of the loop-closure Jacobian (0 at a singularity)."""
    m = parakin.load(name)
    state = home(m)
    ax = plot(m, state)
    try:
        shown = float(ax.get_title().split("type II ")[1].split()[0])
        jacobian = m.loop_closure(state.actuated, state.passive)["jacobian"]
        assert shown == pytest.approx(1 / np.linalg.cond(jacobian), rel=0.05)
    finally:
        plt.close(ax.figure)


@pytest.mark.parametrize("name", drawable_names())
def test_tracking_a_loop_reproduces_the_inputs_and_keeps_the_mode(name):
    """Every tracked configuration closes the loop at its frame's inputs (residual < 1e-9), and
    after the closed loop the mechanism is back in its starting configuration (the same mode)."""
    m = parakin.load(name)
    path = actuated_loop(m, m.home_actuated, 12, 0.1)
    tracked = track(m, path)
    assert np.array_equal(tracked.actuated, path)
    if m.passive_names:
        residual = np.abs(m.loop_closure(tracked.actuated, tracked.passive)["residual"]).max()
        assert residual < 1e-9, residual
    np.testing.assert_allclose(tracked.pose[-1], tracked.pose[0], atol=1e-8)
    np.testing.assert_allclose(tracked.pose[0], home(m).pose, atol=1e-9)


def test_animation_tracks_a_chosen_mode_and_writes_a_gif_of_every_frame(tmp_path):
    m = parakin.load("planar_3rpr")
    modes = m.forward_pose_all(m.home_actuated)
    start = modes.mode(2)
    target = tmp_path / "p.gif"
    done = animate(m, actuated_loop(m, m.home_actuated, 6), str(target), start=start)
    assert len(done) == 6 and np.allclose(done.configurations.pose[0], start.pose)
    assert set(done.distance) == {"type I", "type II"} and (done.distance["type II"] > 0).all()
    with Image.open(target) as gif:
        assert (
            gif.format == "GIF" and gif.n_frames == 6 and gif.size == (600, 650)
        )  # 6 x 6.5 in at 100 dpi (was 400 px)


def test_a_path_across_a_singularity_or_out_of_range_is_a_named_error_with_its_frame():
    m = parakin.load("stewart")
    with pytest.raises(
        parakin.errors.AssemblyModeChangeError, match=r"animation frame \d+ of 12 .*type II singularity"
    ):
        track(m, actuated_loop(m, m.home_actuated, 12))
    low, _ = m.actuated_bounds
    with pytest.raises(
        parakin.BadInputError, match=r"leaves the workspace at frame 3: l1 = -0.2 is outside its range \[0, "
    ):
        actuated_line(m, m.home_actuated, np.r_[low[0] - 1.0, m.home_actuated[1:]], 6)
    with pytest.raises(parakin.BadInputError, match=r"start is at actuated .* the path begins at"):
        track(m, actuated_loop(m, m.home_actuated * 1.01, 4, 0.1), start=home(m))
    with pytest.raises(parakin.BadInputError, match=r"shape \(N >= 2, 6\)"):
        track(m, m.home_actuated)


def cli(*arguments: str) -> tuple[int, str]:
    out = io.StringIO()
    with redirect_stdout(out):
        status = main(list(arguments))
    return status, out.getvalue()


def test_cli_mode_all_modes_and_animate(tmp_path):
    status, text = cli("plot", "five_bar", "--mode", "1", "--output", str(tmp_path / "one.png"))
    assert status == 0 and (tmp_path / "one.png").stat().st_size > 10_000
    status, text = cli("plot", "five_bar", "--all-modes", "--output", str(tmp_path / "all.png"))
    with Image.open(tmp_path / "all.png") as grid, Image.open(tmp_path / "one.png") as one:
        assert grid.size[0] > one.size[0]  # two panels side by side
    assert cli("plot", "five_bar", "--mode", "2")[0] == 2  # five_bar has 2 modes here
    assert cli("plot", "five_bar", "--frames", "3")[0] == 2  # --frames without --animate
    gif = tmp_path / "f.gif"
    status, text = cli("plot", "five_bar", "--animate", str(gif), "--frames", "5", "--mode", "1")
    assert status == 0 and "wrote" in text
    with Image.open(gif) as image:
        assert image.n_frames == 5
    status, text = cli("plot", "five_bar", "--animate", str(gif), "--frames", "4", "--to", "1.9", "1.3")
    assert status == 0
    with Image.open(gif) as image:
        assert image.n_frames == 4


@pytest.mark.slow
def test_a_3d_animation_of_the_spm_on_its_sphere(tmp_path):
    m = parakin.load("spm")
    begin = time.perf_counter()
    animate(m, actuated_loop(m, m.home_actuated, 12), str(tmp_path / "s.gif"))
    assert time.perf_counter() - begin < 30
    with Image.open(tmp_path / "s.gif") as gif:
        assert gif.n_frames == 12
