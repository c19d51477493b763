"""Every body visible (issue 36's review: the delta's platform, 0.1 m across beside 1.3 m legs, was
hidden under its joints' markers in ``parakin plot delta``). Checked on the rendered pixels: each
panel shows the platform's own colour; joint markers never grow wider than a share of the
segments they end, and markers of joints that are far apart keep their full size."""

import matplotlib
import numpy as np
import pytest

import parakin
from parakin.interfaces.plot import JOINT_STYLE, MARKER_SHARE, PART_STYLE

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import to_rgb  # noqa: E402

#: a rendered pixel counts as platform where each RGB channel is within this of the platform's colour
CLOSE = 0.12
#: the fewest platform pixels a panel must show (0 before the fix, ~40 after at the grid's size)
FEWEST = 20


def platform_pixels(figure, axes) -> list[int]:
    """Per axes, the rendered pixels of the platform's colour inside its window."""
    figure.canvas.draw()
    image = np.asarray(figure.canvas.buffer_rgba())[..., :3] / 255.0
    colour = np.array(to_rgb(PART_STYLE["platform"]["color"]))
    close = (np.abs(image - colour) < CLOSE).all(-1)
    height = image.shape[0]
    counts = []
    for ax in axes:
        box = ax.get_window_extent()
        rows = slice(int(height - box.y1), int(height - box.y0))
        counts.append(int(close[rows, int(box.x0) : int(box.x1)].sum()))
    return counts


@pytest.fixture(scope="module")
def delta():
    m = parakin.load("delta", backend="numpy")
    return m, m.forward_pose_all(m.home_actuated)


def test_the_delta_platform_shows_in_every_panel_of_its_grid(delta):
    m, modes = delta
    axes = m.plot(modes)
    try:
        counts = platform_pixels(axes[0].figure, axes)
        assert len(counts) == int(modes.count) == 2
        assert min(counts) >= FEWEST, counts
    finally:
        plt.close(axes[0].figure)


def test_the_delta_platform_shows_alone_and_its_markers_leave_room(delta):
    """Mode 0 alone: the platform shows (~150 pixels at 100 dpi), and the markers of its four
    points are at most MARKER_SHARE (x 1.2) of its centre-to-corner distance r = 0.05 m at the
    panel's scale (matplotlib's own projection of 0.1 m along x; the full-size markers were 4.5 pt,
    1.6 times that)."""
    from mpl_toolkits.mplot3d import proj3d

    m, modes = delta
    ax = m.plot(modes, mode=0)
    try:
        (count,) = platform_pixels(ax.figure, [ax])
        assert count >= 5 * FEWEST, count
        centre = np.asarray(m.drawing(modes.mode(0))["platform"])[:, 3]
        segment = np.stack([centre, centre + [0.1, 0.0, 0.0]], axis=1)
        x, y, _ = proj3d.proj_transform(*segment, ax.get_proj())
        ends = ax.transData.transform(np.column_stack([x, y])) * 72 / ax.figure.dpi  # points
        radius = 0.05 * np.linalg.norm(ends[1] - ends[0]) / 0.1  # r on screen, points
        moving = max((np.sqrt(c.get_sizes()) for c in ax.collections), key=len)  # 3 elbows, 4 platform points
        assert moving.size == 7
        smallest = np.sort(moving)[:4]
        assert smallest.max() <= MARKER_SHARE * radius * 1.2, (smallest, radius)
        assert np.sqrt(JOINT_STYLE["moving"]["s"]) > MARKER_SHARE * radius * 1.2  # the premise: it was too large
        assert np.sort(moving)[4:].min() == np.sqrt(JOINT_STYLE["moving"]["s"])  # the elbows keep full size
    finally:
        plt.close(ax.figure)


def test_joints_far_apart_keep_the_full_marker_size():
    """planar_3rpr's joints are metres apart: every marker has its style's full size."""
    m = parakin.load("planar_3rpr", backend="numpy")
    ax = m.plot(m.forward_pose(m.home_actuated))
    try:
        sizes = sorted({float(s) for c in ax.collections for s in c.get_sizes()})
        assert sizes == sorted({float(JOINT_STYLE["fixed"]["s"]), float(JOINT_STYLE["moving"]["s"])}), sizes
    finally:
        plt.close(ax.figure)
