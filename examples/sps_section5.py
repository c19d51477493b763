"""Knapczyk & Tora, section 5: the 3(SPS)-S spherical platform's printed example, on parakin's
public API (``parakin.load("sps")`` and ``parakin.solvers.statics``).

    python examples/sps_section5.py [figure.png]

prints the walkthrough (the four configurations, the machine's, its Jacobians, the equilibrium
under load and the stiffness) and, given a path, draws the closure function F(v) of eq (6) with its
roots and the four configurations.

Conventions (``mechanisms/sps.py``): {B} and {P} at the centre Q of the spherical joint; leg force
f_i > 0 is a compression, acting on the platform at B_i along u_i = (B_i - A_i) / d_i; actuator
compliance delta f_i = k_i delta d_i (the paper's k_i < 0: the compression drops when the leg
extends), i.e. parakin's actuator stiffness K_q = -diag(k). The external force F (in {B}) acts at
the platform point P, p_p in {P}, p_b = R p_p in {B}.

Statics used instead of the paper's eqs (19c)-(23), which cannot hold as printed (J_p^-1 is
singular, see ``jacobians``): the generic virtual-work statics of ``parakin.solvers.statics`` with the
moment p_b x F about Q as the wrench, f = -(J_p^-1)^T F, and the joint Q carries
R_Q = -(F + sum_i f_i u_i).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass

import numpy as np

import parakin
from parakin.results import Configuration
from parakin.solvers import statics

# ---------------------------------------------------------------------------- section 5, as printed
A3_PRINTED = np.array([-2.720, 0.130, -0.460])  # m; typo: a3x is +2.720 (tests/test_sps.py)
LENGTHS = np.array([0.780, 0.570, 1.320])  # m, the starting point d
V_PRINTED = np.array([0.98004, 0.83904, 0.91463, 0.96707])
MACHINE_ROOT = 2  # v3: "the actual configuration of the machine manipulator"
#: b_1, b_2 and the vector printed a second time as "b_2" (it is b_3), m, in {B}
B_PRINTED = np.array([[2.278, 0.290, -0.698], [2.000, 1.250, -0.454], [2.200, 1.345, -0.541]])
LOAD = np.array([-500.0, -500.0, -5000.0])  # N, in {B}
LOAD_POINT = np.array([1.8, 1.9, -0.5])  # m, p_p in {P}
FORCES_PRINTED = np.array([5378.0, -11584.0, 4170.0])  # N
STIFFNESS_PRINTED = np.array(
    [[-8.614e6, 1.861e7, -6.401e6], [1.861e7, -4.041e7, 1.263e7], [-6.401e7, 1.263e7, -1.137e7]]
)  # N/m; S31 = -6.401e7 is a typo for -6.401e6 (then S is symmetric)
#: the paper's order of the roots v1..v4 is the branch order (s1, s2) of eqs (3), (4)
PAPER_BRANCHES = [(1, 1), (1, -1), (-1, 1), (-1, -1)]
COLOURS = ["tab:blue", "tab:orange", "tab:green", "tab:red"]


# ---------------------------------------------------------------------------- geometry
def geometry(m: parakin.Mechanism) -> tuple[np.ndarray, np.ndarray]:
    """Base points a_i (rows, {B}) and platform points b_ip (rows, {P}) from the parameters."""
    p = m.parameters
    base = np.array([[p["a1x"], 0.0, 0.0], [p["a2x"], p["a2y"], 0.0], [p["a3x"], p["a3y"], p["a3z"]]])
    b = np.array([p["b1"], p["b2"], p["b3"]])
    q12 = (b[0] ** 2 + b[1] ** 2 - p["b12"] ** 2) / (2 * b[0] * b[1])
    q13 = (b[0] ** 2 + b[2] ** 2 - p["b13"] ** 2) / (2 * b[0] * b[2])
    q23 = (b[1] ** 2 + b[2] ** 2 - p["b23"] ** 2) / (2 * b[1] * b[2])
    s = np.sqrt(1 - q12**2)
    gram = max(1 - q12**2 - q13**2 - q23**2 + 2 * q12 * q13 * q23, 0.0)
    platform = np.array(
        [
            [b[0], 0.0, 0.0],
            [b[1] * q12, b[1] * s, 0.0],
            [b[2] * q13, b[2] * (q23 - q12 * q13) / s, b[2] * p["chi"] * np.sqrt(gram) / s],
        ]
    )
    return base, platform


def stiffnesses(m: parakin.Mechanism) -> np.ndarray:
    """The paper's k_i (N/m, negative: delta f_i = k_i delta d_i with f_i a compression)."""
    return np.array([m.parameters[f"k{i}"] for i in (1, 2, 3)])


def strokes(m: parakin.Mechanism) -> np.ndarray:
    """(3, 2): d_i_min, d_i_max, the actuated ranges of the manifest (every solver refuses
    lengths outside them)."""
    return np.array([m.manifest.actuated[i].limits for i in range(3)])


def platform_points(m: parakin.Mechanism, rotation: np.ndarray) -> np.ndarray:
    """b_i = R b_ip (rows, {B}) for R (..., 3, 3) -> (..., 3, 3)."""
    return np.einsum("...jk,ik->...ij", rotation, geometry(m)[1])


def leg_units(m: parakin.Mechanism, config: Configuration) -> np.ndarray:
    """u_i = (B_i - A_i) / d_i (rows, {B})."""
    base, _ = geometry(m)
    return (platform_points(m, config.rotation) - base) / np.asarray(config.actuated)[:, None]


# ---------------------------------------------------------------------------- the vector method, eqs (1)-(6)
def three_unit(
    u: np.ndarray, w: np.ndarray, cuw: float | np.ndarray, p: float, q: np.ndarray, sign: float
) -> np.ndarray:
    """x with x.u = p, x.w = q (u, w unit, u.w = cuw): eqs (3)-(5) with +-sqrt(D); nan where D < 0."""
    q = np.asarray(q, dtype=float)[..., None]
    cuw_ = np.asarray(cuw, dtype=float)[..., None] if np.ndim(cuw) else cuw
    discriminant = 1 - cuw_**2 - p**2 - q**2 + 2 * p * q * cuw_
    with np.errstate(invalid="ignore"):
        root = sign * np.sqrt(np.where(discriminant >= 0, discriminant, np.nan))
    return ((p - q * cuw_) * u + (q - p * cuw_) * w + root * np.cross(u, w)) / (1 - cuw_**2)


def closure_function(m: parakin.Mechanism, lengths: np.ndarray, v: np.ndarray, s1: int, s2: int) -> np.ndarray:
    """F(v) of eq (6) on the branch (s1, s2) of eqs (3), (4), for an array of v; nan where D1 or D2 < 0."""
    base, platform = geometry(m)
    a, b = np.linalg.norm(base, axis=1), np.linalg.norm(platform, axis=1)
    ao, bo = base / a[:, None], platform / b[:, None]
    p = (a**2 + b**2 - np.asarray(lengths) ** 2) / (2 * a * b)  # eq (1b)
    q12, q13, q23 = bo[0] @ bo[1], bo[0] @ bo[2], bo[1] @ bo[2]  # eq (1c)
    chi = np.sign(np.linalg.det(platform))
    v = np.asarray(v, dtype=float)
    b1o = three_unit(ao[0], ao[1], float(ao[0] @ ao[1]), p[0], v, s1)  # eq (3)
    b2o = three_unit(ao[1], b1o, v, p[1], np.full_like(v, q12), s2)  # eq (4)
    b3o = three_unit(b1o, b2o, q12, q13, np.full_like(v, q23), chi)  # eq (5): the sign is chi
    return np.asarray(b3o @ ao[2] - p[2])  # eq (6)


def polynomial_roots(m: parakin.Mechanism, lengths: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """All 8 complex roots t = tan(phi / 2) of the forward polynomial (phi: the angle of b1o about a1o
    from the plane z_b = 0, mechanisms/sps.py) and the paper's v = a2o . b1o at each (eq 2):
    v = c12 p1 + s12 sqrt(1 - p1^2) cos(phi), cos(phi) = (1 - t^2) / (1 + t^2).

    The complex roots are not part of ``forward_pose_all``'s answer (it keeps the real ones), so
    the coefficients come from the generated kernel through the backend."""
    lengths = np.asarray(lengths, dtype=float)
    coefficients = m.backend.call("forward_polynomial", lengths, m.params)["coefficients"]
    t = np.roots(np.asarray(coefficients)[::-1])
    base, platform = geometry(m)
    a, b = np.linalg.norm(base, axis=1), np.linalg.norm(platform, axis=1)
    p1 = (a[0] ** 2 + b[0] ** 2 - lengths[0] ** 2) / (2 * a[0] * b[0])
    c12, s12 = base[1, :2] / a[1]
    return t, c12 * p1 + s12 * np.sqrt(1 - p1**2) * (1 - t**2) / (1 + t**2)


def paper_labels(m: parakin.Mechanism, rotation: np.ndarray) -> tuple[float, int, int]:
    """(v, s1, s2) of a configuration: v = a2o . b1o (eq 2), s1 the sign of (a1o x a2o) . b1o
    (the root in eq 3) and s2 that of (a2o x b1o) . b2o (eq 4)."""
    base, _ = geometry(m)
    ao = base / np.linalg.norm(base, axis=1)[:, None]
    points = platform_points(m, rotation)
    bo = points / np.linalg.norm(points, axis=1)[:, None]
    s1 = int(np.sign(np.cross(ao[0], ao[1]) @ bo[0]))
    s2 = int(np.sign(np.cross(ao[1], bo[0]) @ bo[1]))
    return float(ao[1] @ bo[0]), s1, s2


def configurations(m: parakin.Mechanism, lengths: np.ndarray) -> list[tuple[float, int, int, Configuration]]:
    """Every configuration for the leg lengths, in the paper's order (branch (s1, s2) as v1..v4)."""
    modes = m.forward_pose_all(lengths)
    found = []
    for k in np.nonzero(modes.valid)[0]:  # the valid slots, each one mode
        config = Configuration(modes.actuated, modes.passive[k], modes.poses[k])
        v, s1, s2 = paper_labels(m, config.rotation)
        found.append((v, s1, s2, config))
    order = {branch: n for n, branch in enumerate(PAPER_BRANCHES)}
    return sorted(found, key=lambda item: (order.get((item[1], item[2]), 4), item[0]))


def machine_configuration(m: parakin.Mechanism) -> Configuration:
    """v3 of section 5: the machine's configuration at the starting point d."""
    return configurations(m, LENGTHS)[MACHINE_ROOT][3]


# ---------------------------------------------------------------------------- Jacobians (eqs 10-19)
def euler_rate_matrix(alpha: float, beta: float) -> np.ndarray:
    """E of eq (15): omega = E (alpha_dot, beta_dot, gamma_dot)."""
    ca, sa, cb, sb = np.cos(alpha), np.sin(alpha), np.cos(beta), np.sin(beta)
    return np.array([[1.0, 0.0, cb], [0.0, ca, sa * sb], [0.0, sa, -ca * sb]])


def skew(p: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -p[2], p[1]], [p[2], 0.0, -p[0]], [-p[1], p[0], 0.0]])


@dataclass(frozen=True)
class Jacobians:
    """U_omega (eq 11a), J_omega^-1 = -U_omega^-1 W (eqs 16, 17 with the sign fixed; the closure's
    passive rates per leg rate), E (eq 15), J_p^-1 (eq 19a, b; rank 2: p_b^T J_p^-1 = 0, so J_p
    does not exist) and M_T, whose columns b_i x u_i give d_dot = M_T^T omega (the paper's form of
    parakin's G = B^-1 A)."""

    u_omega: np.ndarray
    j_omega_inv: np.ndarray
    e: np.ndarray
    j_p_inv: np.ndarray
    moment_arms: np.ndarray
    point: np.ndarray


def jacobians(m: parakin.Mechanism, config: Configuration, point: np.ndarray = LOAD_POINT) -> Jacobians:
    u_omega = m.loop_closure(config.actuated, config.passive)["jacobian"]
    j_omega_inv = m.passive_rates(config, np.eye(3)).T
    e = euler_rate_matrix(config.passive[0], config.passive[1])
    p_b = config.rotation @ point
    arms = np.cross(platform_points(m, config.rotation), leg_units(m, config)).T
    return Jacobians(u_omega, j_omega_inv, e, -skew(p_b) @ e @ j_omega_inv, arms, p_b)


# ---------------------------------------------------------------------------- statics (section 4)
def load_wrench(m: parakin.Mechanism, force: np.ndarray = LOAD, point: np.ndarray = LOAD_POINT):
    """The wrench of F at P as a function of the configuration (the moment p_b x F about Q)."""
    return lambda config: statics.point_force_wrench(m, config, force, point)


def leg_forces(
    m: parakin.Mechanism, config: Configuration, force: np.ndarray = LOAD, point: np.ndarray = LOAD_POINT
) -> tuple[np.ndarray, np.ndarray]:
    """Leg forces f (compression > 0) balancing F at P about Q (``parakin.solvers.statics``), and the
    reaction R_Q at Q (N)."""
    forces = statics.actuator_forces(m, config, statics.point_force_wrench(m, config, force, point))
    return forces, -(force + leg_units(m, config).T @ forces)


@dataclass(frozen=True)
class Equilibrium:
    """The platform's equilibrium with compliant actuators: ``config`` (loaded leg lengths d, the
    rotation), leg ``forces`` f, ``reaction`` at Q, and the generic result (``solution``: update
    sizes, iterations, residual)."""

    config: Configuration
    forces: np.ndarray
    reaction: np.ndarray
    solution: statics.Equilibrium

    @property
    def iterations(self) -> int:
        return self.solution.iterations


def equilibrium(
    m: parakin.Mechanism,
    unloaded: Configuration,
    force: np.ndarray = LOAD,
    point: np.ndarray = LOAD_POINT,
    method: str = "successive",
    tolerance: float = 1e-13,
) -> Equilibrium:
    """Static equilibrium under F at P with compliant actuators, d = d0 + f(d) / k (section 4):
    the lengths d0 of ``unloaded`` are commanded, the assembly mode is tracked from it.
    ``method`` 'successive' is the paper's successive approximation (``parakin.solvers.statics``'
    'fixed_point'), 'newton' Newton with a finite-difference Jacobian."""
    generic = {"successive": "fixed_point", "newton": "newton"}.get(method)
    if generic is None:
        raise parakin.BadInputError(f"method must be 'successive' or 'newton', got {method!r}")
    solution = statics.equilibrium(
        m,
        unloaded.actuated,
        load_wrench(m, force, point),
        -stiffnesses(m),  # K_q = -k: parakin's efforts pull back toward the command
        guess=unloaded,
        method=generic,
        tolerance=tolerance,
    )
    config = solution.configuration
    _, reaction = leg_forces(m, config, force, point)
    return Equilibrium(Configuration(config.actuated, config.passive, config.pose), solution.forces, reaction, solution)


@dataclass(frozen=True)
class Stiffness:
    """Stiffness of the platform held by compliant actuators (the legs' geometric stiffness under
    preload is neglected): ``rotational`` S_omega = G^T K_q G = -M_T K M_T^T (N m/rad: the applied
    moment per rotation, positive definite; ``parakin.solvers.statics.stiffness``); ``compliance_point``
    C = -[p_b]x S_omega^-1 [p_b]x (m/N: delta p = C delta F) of P, rank 2 (P moves on a sphere
    about Q; the paper's -H K^-1 H^T with H = J_p^-1); ``point`` = pinv(C) (N/m), the stiffness
    of P across p_b."""

    rotational: np.ndarray
    compliance_point: np.ndarray
    point: np.ndarray


def stiffness(m: parakin.Mechanism, config: Configuration, point: np.ndarray = LOAD_POINT) -> Stiffness:
    rotational = statics.stiffness(m, config, -stiffnesses(m))
    arm = skew(config.rotation @ point)
    compliance = -arm @ np.linalg.solve(rotational, arm)
    return Stiffness(rotational, compliance, np.linalg.pinv(compliance, rcond=1e-10))


def paper_rotational_stiffness(m: parakin.Mechanism, config: Configuration) -> np.ndarray:
    """S_omega from the paper's moment arms: -M_T diag(k) M_T^T (M_T's columns b_i x u_i)."""
    arms = jacobians(m, config).moment_arms
    return -arms @ np.diag(stiffnesses(m)) @ arms.T


def significant_digits(value: float, printed: float) -> int:
    """The number of significant digits (up to 8) to which ``value`` rounds to ``printed``."""
    for n in range(8, 0, -1):
        if float(f"{value:.{n}g}") == float(f"{printed:.{n}g}"):
            return n
    return 0


# ---------------------------------------------------------------------------- the walkthrough
def demo(backend: str = "auto") -> None:
    """Print section 5's results."""
    m = parakin.load("sps", backend=backend)
    np.set_printoptions(precision=5, suppress=True, linewidth=120)
    print(f"{m!r}\n")
    print("Section 5 (Knapczyk & Tora), a3 = (+2.720, 0.130, -0.460) m (printed -2.720: a typo), chi = -1")
    printed = parakin.load("sps", backend=m.backend.name, a3x=float(A3_PRINTED[0]))
    count = int(printed.forward_pose_all(LENGTHS).count)
    print(f"  with the printed a3x = -2.720 the lengths d = {LENGTHS} m have {count} configurations")
    t_roots, v_roots = polynomial_roots(m, LENGTHS)
    print(f"  degree-8 forward polynomial in t = tan(phi / 2): roots {np.sort_complex(t_roots)}")
    print(f"    v = a2o . b1o at those roots (eq 2): {np.sort_complex(v_roots)}")
    found = configurations(m, LENGTHS)
    print(f"  {len(found)} configurations (paper: four real roots), in the paper's order:")
    for n, (v, s1, s2, config) in enumerate(found):
        error = np.abs(m.inverse_pose(config.rotation).actuated[0] - LENGTHS).max()
        euler = np.rad2deg(config.passive)
        print(
            f"    v{n + 1} = {v:.8f} (printed {V_PRINTED[n]:.5f}, {significant_digits(v, V_PRINTED[n])} digits)"
            f"  (s1, s2) = ({s1:+d}, {s2:+d})  (alpha, beta, gamma) = {euler} deg  |d error| {error:.1e} m"
        )
    machine = found[MACHINE_ROOT][3]
    points = platform_points(m, machine.rotation)
    print("  the machine's configuration v3: b_i (m, {B})")
    for i in range(3):
        digits = [significant_digits(x, y) for x, y in zip(points[i], B_PRINTED[i], strict=True)]
        label = " (printed as 'b2')" if i == 2 else ""
        print(f"    b{i + 1} = {points[i]}  printed {B_PRINTED[i]}{label}  digits {digits}")
    jac = jacobians(m, machine)
    factors = m.singularities(machine)
    print("\n  J_omega^-1 = -U_omega^-1 W (Euler rates per leg rate):")
    print("   ", str(jac.j_omega_inv).replace("\n", "\n    "))
    print(
        f"  det U_omega = {np.linalg.det(jac.u_omega):.6g} = 8 sin(beta) det[b_i x a_i];"
        f" leg_moments_coplanar = {float(factors['leg_moments_coplanar']):.6g}"
    )
    print(f"  J_p^-1 singular values {np.linalg.svd(jac.j_p_inv, compute_uv=False)} (rank 2: J_p does not exist)")

    rigid, _ = leg_forces(m, machine)
    loaded = equilibrium(m, machine)
    newton = equilibrium(m, machine, method="newton")
    print(f"\n  load F = {LOAD} N at p_p = {LOAD_POINT} m; k = {stiffnesses(m)} N/m (parakin.solvers.statics)")
    print(f"  rigid legs (unloaded pose): f = {rigid} N")
    updates = ", ".join(f"{h:.1e}" for h in loaded.solution.history)
    print(f"  compliant equilibrium, successive approximation ({loaded.iterations} iterations, updates {updates}):")
    print(f"    d = {loaded.config.actuated} m, f = {loaded.forces} N, R_Q = {loaded.reaction} N")
    print(
        f"    Newton: {newton.iterations} iterations, |f - f_successive| = {np.abs(newton.forces - loaded.forces).max():.1e} N"
    )
    digits = [significant_digits(x, y) for x, y in zip(loaded.forces, FORCES_PRINTED, strict=True)]
    print(f"    printed f = {FORCES_PRINTED} N: digits reproduced {digits}")
    stiff = stiffness(m, loaded.config)
    print("  rotational stiffness S_omega = G^T K_q G (N m/rad):")
    print("   ", str(stiff.rotational).replace("\n", "\n    "))
    print("  stiffness of P (N/m, rank 2; the printed S is not reproduced: eq (23) needs J_p, which does not exist):")
    print("   ", str(stiff.point).replace("\n", "\n    "))
    corrected = STIFFNESS_PRINTED.copy()
    corrected[2, 0] = -6.401e6
    print(f"  printed S with S31 = -6.401e6 (symmetric): singular values {np.linalg.svd(corrected, compute_uv=False)}")


# ---------------------------------------------------------------------------- the figure
def plot(path: str, lengths: np.ndarray = LENGTHS, backend: str = "auto") -> None:
    """F(v) over [-1, 1] on the four branches of eqs (3), (4), with the roots found by the forward
    polynomial, and the configurations (platform B1 B2 B3, legs, Q). Needs matplotlib."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    m = parakin.load("sps", backend=backend)
    found = configurations(m, lengths)
    figure = plt.figure(figsize=(13, 5.5))
    left = figure.add_subplot(1, 2, 1)
    v = np.linspace(-1, 1, 20001)[1:-1]
    for colour, (s1, s2) in zip(COLOURS, PAPER_BRANCHES, strict=True):
        left.plot(v, closure_function(m, lengths, v, s1, s2), color=colour, label=f"(s1, s2) = ({s1:+d}, {s2:+d})")
    for n, (root, s1, s2, _) in enumerate(found):
        colour = COLOURS[PAPER_BRANCHES.index((s1, s2))]
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
        for colour, (s1, s2) in zip(COLOURS, PAPER_BRANCHES, strict=True):
            inset.plot(zoom, closure_function(m, lengths, zoom, s1, s2), color=colour)
        inset.plot(roots, np.zeros_like(roots), "ko", markersize=3)
        inset.axhline(0.0, color="black", linewidth=0.6)
        inset.set_ylim(-0.05, 0.05)
        inset.tick_params(labelsize=7)

    right = figure.add_subplot(1, 2, 2, projection="3d")
    base, _ = geometry(m)
    right.scatter(*base.T, color="black", marker="s")
    right.scatter([0], [0], [0], color="black", marker="*", s=80)
    for i, point in enumerate(base):
        right.text(*point, f"A{i + 1}")
    for n, (_, s1, s2, config) in enumerate(found):
        colour = COLOURS[PAPER_BRANCHES.index((s1, s2))]
        points = platform_points(m, config.rotation)
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


def main(argv: list[str]) -> None:
    demo()
    if argv:
        plot(argv[0])
        print(f"\nwrote {argv[0]}")


if __name__ == "__main__":
    main(sys.argv[1:])
