"""``parakin plot sps``: the closure function F(v) of eq (6) over [-1, 1] on the four branches of
eqs (3), (4), with the roots found by the forward polynomial, and the four configurations of
section 5 (Knapczyk & Tora). Needs matplotlib (the ``plot`` extra); drawn with the Agg backend."""

from __future__ import annotations

import numpy as np

import parakin
from parakin import demos_sps as s5

COLOURS = ["tab:blue", "tab:orange", "tab:green", "tab:red"]


def plot(path: str, lengths: np.ndarray = s5.LENGTHS, backend: str = "auto") -> None:
    """Write the figure to ``path`` (any format matplotlib knows from the suffix)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    m = parakin.load("sps", backend=backend)
    found = s5.configurations(m, lengths)
    figure = plt.figure(figsize=(13, 5.5))
    left = figure.add_subplot(1, 2, 1)
    v = np.linspace(-1, 1, 20001)[1:-1]
    for colour, (s1, s2) in zip(COLOURS, s5.PAPER_BRANCHES, strict=True):
        left.plot(v, s5.closure_function(m, lengths, v, s1, s2), color=colour, label=f"(s1, s2) = ({s1:+d}, {s2:+d})")
    for n, (root, s1, s2, _) in enumerate(found):
        colour = COLOURS[s5.PAPER_BRANCHES.index((s1, s2))]
        left.plot([root], [0.0], "o", color=colour, markeredgecolor="black", label=f"v{n + 1} = {root:.6f}")
    left.axhline(0.0, color="black", linewidth=0.6)
    left.set_xlim(-1, 1)
    left.set_xlabel("v = a2o . b1o (eq 2)")
    left.set_ylabel("F(v) (eq 6)")
    left.set_title(f"closure function, d = {np.round(lengths, 4)} m")
    left.legend(loc="lower left", fontsize=8, title="F is real where D1, D2 >= 0", title_fontsize=8)
    inset = left.inset_axes((0.08, 0.55, 0.42, 0.4))
    if found:
        roots = np.array([root for root, *_ in found])
        zoom = np.linspace(max(roots.min() - 0.02, -1 + 1e-9), min(roots.max() + 0.02, 1 - 1e-9), 4001)
        for colour, (s1, s2) in zip(COLOURS, s5.PAPER_BRANCHES, strict=True):
            inset.plot(zoom, s5.closure_function(m, lengths, zoom, s1, s2), color=colour)
        inset.plot(roots, np.zeros_like(roots), "ko", markersize=3)
        inset.axhline(0.0, color="black", linewidth=0.6)
        inset.set_ylim(-0.05, 0.05)
        inset.tick_params(labelsize=7)

    right = figure.add_subplot(1, 2, 2, projection="3d")
    base, _ = s5.geometry(m)
    right.scatter(*base.T, color="black", marker="s")
    right.scatter([0], [0], [0], color="black", marker="*", s=80)
    for i, point in enumerate(base):
        right.text(*point, f"A{i + 1}")
    for n, (_, s1, s2, config) in enumerate(found):
        colour = COLOURS[s5.PAPER_BRANCHES.index((s1, s2))]
        points = s5.platform_points(m, config.rotation)
        triangle = np.vstack([points, points[:1]])
        right.plot(*triangle.T, color=colour, linewidth=2, label=f"v{n + 1}")
        for a, b in zip(base, points, strict=True):
            right.plot(*np.array([a, b]).T, color=colour, linestyle="--", linewidth=1)
        for point in points:
            right.plot(*np.array([np.zeros(3), point]).T, color=colour, linewidth=0.5, alpha=0.5)
    right.set_xlabel("x_b (m)")
    right.set_ylabel("y_b (m)")
    right.set_zlabel("z_b (m)")
    right.set_title("configurations: platform B1 B2 B3 (solid), legs (dashed), Q at the origin")
    right.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)
