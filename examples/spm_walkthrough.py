"""ED5314 report, section 3: the 3-RRR spherical parallel manipulator (SPM), its example of
section 3.2.3 on parakin's public API.

    python examples/spm_walkthrough.py [figure.png]

prints every assembly mode of the example (the report's eight), the count with the link labels as
printed, and the Agile Eye's input-independent (folded) solutions; given a path, draws the modes on
the unit sphere (the report's Fig. 3).

Geometry (``mechanisms/spm.py``, Bai-Hansen-Angeles): base and platform half-angles gamma, beta;
the actuated axes u_i and the platform axes v_i = R v0_i lie on cones about the vertical, at
azimuths eta_i = 2 pi (i - 1) / 3.
"""

from __future__ import annotations

import sys

import numpy as np

import parakin

#: section 3.2.3: the inputs theta1..theta3 (deg)
EXAMPLE_DEG = [105.0, 60.0, 105.0]
#: the report's count of real assembly modes for the example
EXAMPLE_MODES = 8
#: the link angles as printed (alpha1 = 90, alpha2 = 45 deg; the defaults read them swapped)
PRINTED_LINKS = {"alpha1": np.pi / 2, "alpha2": np.pi / 4}
#: the Agile Eye: alpha1 = alpha2 = 90 deg, beta = gamma = atan(sqrt(2)), and an input of it (deg)
AGILE_EYE = {
    "alpha1": np.pi / 2,
    "alpha2": np.pi / 2,
    "beta": float(np.arctan(np.sqrt(2))),
    "gamma": float(np.arctan(np.sqrt(2))),
}
AGILE_EYE_DEG = [10.0, 20.0, -15.0]


def axis_angle(rotation: np.ndarray) -> tuple[float, np.ndarray]:
    """(angle in degrees, unit axis) of a rotation matrix."""
    angle = float(np.rad2deg(np.arccos(np.clip((np.trace(rotation) - 1) / 2, -1, 1))))
    axis = np.array([rotation[2, 1] - rotation[1, 2], rotation[0, 2] - rotation[2, 0], rotation[1, 0] - rotation[0, 1]])
    return angle, axis / max(float(np.linalg.norm(axis)), 1e-300)


def cone_axes(half_angle: float, z_sign: float) -> np.ndarray:
    """(3, 3) unit axes at azimuths 0, 120, 240 deg on the cone of ``half_angle`` about z_sign z."""
    eta = 2 * np.pi * np.arange(3) / 3
    return np.stack(
        [np.sin(half_angle) * -np.sin(eta), np.sin(half_angle) * np.cos(eta), z_sign * np.cos(half_angle) * np.ones(3)],
        -1,
    )


def demo() -> None:
    m = parakin.load("spm")
    np.set_printoptions(precision=5, suppress=True, linewidth=120)
    forward = m.manifest.capabilities.forward
    degree = forward.degree if forward else None
    print(f"{m!r}")
    print("section 3.2.3 example, read as proximal alpha1 = 45 deg, distal alpha2 = 90 deg (the printed")
    print(f"labels swap them), beta = 60, gamma = 45 deg; theta = {EXAMPLE_DEG} deg")
    theta = np.deg2rad(EXAMPLE_DEG)
    modes = m.forward_pose_all(theta)
    print(f"  forward polynomial degree {degree}: {int(modes.count)} real assembly modes (report: {EXAMPLE_MODES})")
    for number, k in enumerate(np.nonzero(modes.valid)[0]):
        angle, axis = axis_angle(modes.poses[k, :3, :3])
        print(
            f"  mode {number}: x = tan((phi1 - 1/2) / 2) = {modes.root[k]: .5f}  rotation {angle:7.3f} deg about {axis}"
            f"  quaternion (q0..q3) {modes.passive[k].round(5)}  residual {modes.residual[k]:.1e}"
        )
    printed = parakin.load("spm", **PRINTED_LINKS)
    print(
        f"  with the labels as printed (alpha1 = 90, alpha2 = 45 deg): {int(printed.forward_pose_all(theta).count)} modes"
    )
    eye = parakin.load("spm", **AGILE_EYE)
    agile = eye.forward_pose_all(np.deg2rad(AGILE_EYE_DEG))
    print(
        f"  Agile Eye at theta = {tuple(AGILE_EYE_DEG)} deg: {int(agile.count)} genuine modes, "
        f"{int(agile.input_independent.sum())} input-independent (folded) solutions flagged"
    )


def modes_on_sphere(path: str, actuated_deg: list[float] | None = None) -> None:
    """The report's Fig. 3: every assembly mode drawn on the unit sphere, each as the triangle of
    its platform axes v_i = R v0_i, with the actuated axes u_i (default inputs: section 3.2.3's).
    Needs matplotlib."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    m = parakin.load("spm")
    theta = np.deg2rad(actuated_deg if actuated_deg else EXAMPLE_DEG)
    modes = m.forward_pose_all(theta)
    figure = plt.figure(figsize=(7, 7))
    ax = figure.add_subplot(projection="3d")
    u, v = np.mgrid[0 : 2 * np.pi : 40j, 0 : np.pi : 20j]
    ax.plot_wireframe(np.cos(u) * np.sin(v), np.sin(u) * np.sin(v), np.cos(v), color="0.85", linewidth=0.5)
    base = cone_axes(m.parameters["gamma"], -1.0)
    platform = cone_axes(m.parameters["beta"], 1.0)
    ax.scatter(*base.T, color="k", s=40, label="actuated axes u_i")
    colours = plt.cm.tab10(np.linspace(0, 1, 10))
    for number, k in enumerate(np.nonzero(modes.valid)[0]):
        axes = (modes.poses[k, :3, :3] @ platform.T).T
        loop = np.vstack([axes, axes[:1]])
        ax.plot(*loop.T, color=colours[number % 10], marker="o", label=f"mode {number}")
    ax.set_box_aspect((1, 1, 1))
    ax.set_title(f"3-RRR SPM: {int(modes.count)} assembly modes at theta = {np.rad2deg(theta).round(2)} deg")
    ax.legend(loc="upper left", fontsize=8)
    figure.savefig(path, dpi=120)
    plt.close(figure)


def main(argv: list[str]) -> None:
    demo()
    if argv:
        modes_on_sphere(argv[0])
        print(f"\nwrote {argv[0]}")


if __name__ == "__main__":
    main(sys.argv[1:])
