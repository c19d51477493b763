"""Figures written by ``parakin plot NAME`` (matplotlib, Agg backend, PNG)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

import parakin


def _axes_3d():  # matplotlib only when plotting: it is an optional dependency (extra 'plot')
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure = plt.figure(figsize=(7, 7))
    return plt, figure, figure.add_subplot(projection="3d")


def spm_modes_on_sphere(path: str, actuated_deg: list[float] | None = None) -> None:
    """The report's Fig. 3: every assembly mode of the SPM drawn on the unit sphere, each as the
    triangle of its platform axes v_i = R v0_i, with the actuated axes u_i (default inputs: the
    example of section 3.2.3)."""
    m = parakin.load("spm")
    theta = np.deg2rad(actuated_deg if actuated_deg else [105.0, 60.0, 105.0])
    modes = m.forward_pose_all(theta)
    plt, figure, ax = _axes_3d()
    u, v = np.mgrid[0 : 2 * np.pi : 40j, 0 : np.pi : 20j]
    ax.plot_wireframe(np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v), color="0.85", linewidth=0.5)
    beta, gamma = m.parameters["beta"], m.parameters["gamma"]
    eta = 2 * np.pi * np.arange(3) / 3
    base = np.stack([np.sin(gamma) * -np.sin(eta), np.sin(gamma) * np.cos(eta), -np.cos(gamma) * np.ones(3)], -1)
    platform = np.stack([np.sin(beta) * -np.sin(eta), np.sin(beta) * np.cos(eta), np.cos(beta) * np.ones(3)], -1)
    ax.scatter(*base.T, color="k", s=40, label="actuated axes u_i")
    colours = plt.cm.tab10(np.linspace(0, 1, 10))
    for number, k in enumerate(np.nonzero(modes.valid)[0]):
        axes = (modes.poses[k, :3, :3] @ platform.T).T
        loop = np.vstack([axes, axes[:1]])
        ax.plot(*loop.T, color=colours[number % 10], marker="o", label=f"mode {number + 1}")
    ax.set_box_aspect((1, 1, 1))
    ax.set_title(f"3-RRR SPM: {int(modes.count)} assembly modes at theta = {np.rad2deg(theta).round(2)} deg")
    ax.legend(loc="upper left", fontsize=8)
    figure.savefig(path, dpi=120)
    plt.close(figure)


def gough_self_motion(path: str, actuated_deg: list[float] | None = None) -> None:
    """Kong & Gosselin Fig. 2 (section 5.4 self-motion); the inputs are the paper's lengths."""
    from parakin import plots_gough

    plots_gough.plot(path)


def sps_closure_function(path: str, actuated_deg: list[float] | None = None) -> None:
    """Knapczyk & Tora section 5: F(v) over [-1, 1] with its roots, and the configurations."""
    from parakin import plots_sps

    plots_sps.plot(path)


PLOTS: dict[str, Callable[..., None]] = {
    "spm": spm_modes_on_sphere,
    "sps": sps_closure_function,
    "gough": gough_self_motion,
}
