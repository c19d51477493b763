"""Kong & Gosselin Fig. 2: the self-motion circuits of the section 5.4 example (matplotlib, Agg)."""

from __future__ import annotations

import warnings

import parakin
from parakin import architecture
from parakin.demos_gough import PRINTED_LENGTHS


def plot(path: str) -> None:
    """O_P along the two circuits of the self-motion (printed l1..l5, leg 6 dependent), with the
    eight assembly modes at one i_x drawn as platform triangles B1 B2 B6; right: z of O_P vs i_x."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", architecture.ArchitectureSingularityWarning)
        m = parakin.load("gough", backend="numpy")
    geometry = architecture.Geometry.from_parameters(m.parameters)
    motion = architecture.self_motion(m, PRINTED_LENGTHS, samples=500)
    figure = plt.figure(figsize=(12, 5.5))
    ax = figure.add_subplot(1, 2, 1, projection="3d")
    side = figure.add_subplot(1, 2, 2)
    colours = ["tab:blue", "tab:red", "tab:green", "tab:orange"]
    for number, circuit in enumerate(motion.circuits):
        colour = colours[number % len(colours)]
        for piece, (branch, mode) in enumerate(circuit):
            ixs, poses = motion.branches[branch]
            positions = poses[:, mode, :3, 3]
            label = f"circuit {number + 1}" if piece == 0 else None
            ax.plot(*positions.T, color=colour, linewidth=1.2, label=label)
            side.plot(ixs, positions[:, 2], color=colour, linewidth=1.2, label=label)
    modes = architecture.self_motion_modes(m, PRINTED_LENGTHS, 0.044)
    for pose in modes.poses:
        corners = pose[:3, 3] + geometry.platform[[0, 1, 5, 0]] @ pose[:3, :3].T
        ax.plot(*corners.T, color="k", linewidth=0.8)
        ax.scatter(*pose[:3, 3], color="k", s=10)
    ax.scatter(*geometry.base.T, color="k", marker="^", s=30, label="base joints A_i")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    ax.set_title(f"O_P on {len(motion.circuits)} circuits; {modes.poses.shape[0]} modes at i_x = 0.044")
    ax.legend(loc="upper left", fontsize=8)
    side.axvline(0.044, color="0.6", linewidth=0.8)
    side.set_xlabel("i_x")
    side.set_ylabel("z of O_P")
    side.set_title("Kong & Gosselin 5.4: self-motion, leg 6 dependent")
    side.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


if __name__ == "__main__":
    plot("gough.png")
