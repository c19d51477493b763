"""Kong & Gosselin: the architecture singularity and self-motion of the 6-SPS platform with
linearly related planar platforms (``mechanisms/gough.py``), section 5.4's example, on parakin's
public API.

    python examples/gough_architecture.py [figure.png]

prints the walkthrough and, given a path, draws Fig. 2 (the self-motion circuits).

Frames are those of the mechanism: A1 = O, A_i = (xA_i, yA_i, 0), B_i^(P) = (t11 xA_i + t12 yA_i,
t22 yA_i, 0) (eq 1), pose ^B_P T with O_P = B1, lengths in metres. NumPy only.

* The mechanism's defaults are a usable geometry (section 5.4's base with A4 moved off the conic);
  section 5.4's own geometry is its named example ``section54_self_motion`` (``SECTION_54``).
* parakin itself, generically: ``parakin.load`` warns (ArchitectureSingularityWarning) when the
  mechanism's declared architecture measure vanishes, ``m.forward_pose_all`` reports the
  degenerate elimination and, where the locked legs leave a curve of poses, raises SelfMotionError
  with the curve traced by continuation (``parakin.solvers.continuation.SelfMotion``).
* This module, the paper's section 5: ``conic_fit``, the conic through the six base points (eq 15,
  with A1 = O), fitted by the SVD of the scaled 6-point conic matrix [1, x, y, x^2, y^2, xy];
  ``compatibility``: on a singular geometry M u = L (8) is solvable iff lambda . L(l) = 0 (lambda
  the left null vector of M), the nearest compatible lengths and, for each leg, the length the
  other five imply; ``self_motion_modes`` / ``self_motion``: with i_x as the free coordinate, four
  equations of (8) solved for u1, u2, u4, u5 = i_x C + D (eqs 16-18), then the quartic (23) and the
  back-substitution of the forward pose, every assembly mode for one i_x and the circuits traced
  as i_x varies; ``least_squares_pose``: Levenberg-Marquardt on the six leg residuals, the answer
  for locked lengths that are not exactly compatible; ``forward_all``: the closed form on a usable
  geometry, the self-motion on an architecturally singular one.
"""

from __future__ import annotations

import sys
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

import parakin
from parakin.solvers.polynomial import isolate_real_roots

Array = NDArray[np.float64]

#: section 5.4: the locked inputs l1..l6 as printed (two decimals), metres
PRINTED_LENGTHS = [33.17, 32.02, 35.12, 37.57, 39.01, 38.32]
#: section 5.4: the base lies on (x - 5)^2 + y^2 = 25, i.e. x - 0.1 x^2 - 0.1 y^2 = 0
PRINTED_CONIC = [0.0, 1.0, 0.0, -0.1, -0.1, 0.0]
#: the i_x at which the walkthrough and the figure list the eight assembly modes
SAMPLE_IX = 0.044
#: relative smallest singular value below which a base counts as lying on a conic
CONIC_TOLERANCE = 1e-9


#: the named example of the mechanism's manifest that holds section 5.4's geometry
EXAMPLE = "section54_self_motion"


def section54_parameters() -> dict[str, float]:
    """Section 5.4's (architecturally singular) geometry, the parameters of the manifest's named
    example ``EXAMPLE`` (the mechanism's defaults are a usable, non-conic geometry)."""
    for example in parakin.metadata("gough").examples:
        if example.name == EXAMPLE:
            return dict(example.parameters)
    raise parakin.UnknownMechanismError(f"gough has no named example {EXAMPLE!r}; regenerate it")


#: section 5.4: A2..A6 = (5,-5) (9,-3) (10,0) (9,3) (5,5), t11 = t12 = t22 = 1 (names -> values)
SECTION_54 = section54_parameters()


def load_example(backend: str = "numpy", **parameters: float) -> parakin.Mechanism:
    """``parakin.load("gough")`` with section 5.4's (singular) geometry, overridden by
    ``parameters``, its warning silenced."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        return parakin.load("gough", backend=backend, **(SECTION_54 | parameters))


# ---------------------------------------------------------------------------------- geometry
@dataclass(frozen=True)
class Geometry:
    """Base points A (6, 3), platform points B^(P) (6, 3) and (t11, t12, t22)."""

    base: Array
    platform: Array
    t: tuple[float, float, float]

    @classmethod
    def from_parameters(cls, parameters: dict[str, float]) -> Geometry:
        try:
            xa = np.array([0.0] + [parameters[f"xA{i}"] for i in range(2, 7)])
            ya = np.array([0.0] + [parameters[f"yA{i}"] for i in range(2, 7)])
            t11, t12, t22 = (float(parameters[k]) for k in ("t11", "t12", "t22"))
        except KeyError as error:
            raise parakin.BadInputError(
                f"not a linearly-related-platform geometry: missing parameter {error}"
            ) from error
        if t11 * t22 == 0:
            raise parakin.BadInputError(f"t11 t22 must not vanish (eq 1), got t11={t11}, t22={t22}")
        base = np.column_stack([xa, ya, np.zeros(6)])
        platform = np.column_stack([t11 * xa + t12 * ya, t22 * ya, np.zeros(6)])
        return cls(base, platform, (t11, t12, t22))

    @property
    def x(self) -> Array:
        return self.base[:, 0]

    @property
    def y(self) -> Array:
        return self.base[:, 1]

    def leg_lengths(self, pose: ArrayLike) -> Array:
        """l_i = |p + R B_i^(P) - A_i| for poses (..., 4, 4)."""
        pose = np.asarray(pose, dtype=float)
        points = pose[..., None, :3, 3] + np.einsum("...jk,ik->...ij", pose[..., :3, :3], self.platform)
        return np.asarray(np.linalg.norm(points - self.base, axis=-1), dtype=np.float64)

    def system8(self, lengths: ArrayLike) -> tuple[Array, Array]:
        """M (5, 5) and L (..., 5) of eq (8): rows [x, y, x^2, y^2, x y] of A2..A6."""
        lengths = np.asarray(lengths, dtype=float)
        x, y = self.x[1:], self.y[1:]
        matrix = np.column_stack([x, y, x * x, y * y, x * y])
        b = self.platform[1:]
        rhs = 0.5 * (lengths[..., 1:] ** 2 - b[:, 0] ** 2 - b[:, 1] ** 2 - x * x - y * y - lengths[..., :1] ** 2)
        return matrix, rhs


def geometry(m: Any) -> Geometry:
    """A Geometry from a loaded mechanism, a parameter dict or a Geometry."""
    if isinstance(m, Geometry):
        return m
    if isinstance(m, dict):
        return Geometry.from_parameters(m)
    return Geometry.from_parameters(m.parameters)


# ---------------------------------------------------------------------------------- the conic
@dataclass(frozen=True)
class ConicFit:
    """k0 + k1 x + k2 y + k3 x^2 + k4 y^2 + k5 x y = 0 through the base points (max |k| = 1).

    ``measure``: smallest / largest singular value of the conic matrix in coordinates scaled by
    the largest |coordinate| (0 on a conic); ``det_m``: det of system (8), eq (14);
    ``distances``: each base point's residual of the fitted conic divided by its gradient norm
    (an approximate distance to the conic, metres)."""

    singular: bool
    measure: float
    coefficients: Array
    det_m: float
    distances: Array

    def describe(self) -> str:
        k = self.coefficients
        terms = " ".join(
            f"{c:+.6g}{t}" for c, t in zip(k, ["", " x", " y", " x^2", " y^2", " x y"], strict=True) if abs(c) > 1e-12
        )
        state = "architecturally singular" if self.singular else "not on a conic"
        return f"{state}: nearest conic {terms} = 0 (measure {self.measure:.3g}, det M = {self.det_m:.6g})"


def conic_fit(m: Any, tolerance: float = CONIC_TOLERANCE) -> ConicFit:
    """Fit the conic through A1..A6 (eq 15 with A1 = O) and test the architecture singularity."""
    g = geometry(m)
    scale = max(float(np.abs(g.base[:, :2]).max()), 1e-300)
    xs, ys = g.x / scale, g.y / scale
    conic = np.column_stack([np.ones(6), xs, ys, xs * xs, ys * ys, xs * ys])
    _, singular_values, vt = np.linalg.svd(conic)
    k = vt[-1] * np.array([1.0, 1 / scale, 1 / scale, scale**-2, scale**-2, scale**-2])
    k = k / np.abs(k).max()
    if k[np.argmax(np.abs(k))] < 0:
        k = -k
    value = k[0] + k[1] * g.x + k[2] * g.y + k[3] * g.x**2 + k[4] * g.y**2 + k[5] * g.x * g.y
    gradient = np.hypot(k[1] + 2 * k[3] * g.x + k[5] * g.y, k[2] + 2 * k[4] * g.y + k[5] * g.x)
    measure = float(singular_values[-1] / singular_values[0])
    det_m = float(np.linalg.det(g.system8(np.zeros(6))[0]))
    return ConicFit(measure < tolerance, measure, k, det_m, np.abs(value) / np.maximum(gradient, 1e-300))


def is_architecturally_singular(m: Any, tolerance: float = CONIC_TOLERANCE) -> bool:
    """Whether the base points lie on a conic (eq 15): then det J = 0 at every pose."""
    return conic_fit(m, tolerance).singular


# ---------------------------------------------------------------------------------- compatibility
@dataclass(frozen=True)
class Compatibility:
    """Locked lengths on a singular geometry: ``value`` = lambda . L(l) (0 when compatible), with
    lambda the unit left null vector of M; ``implied[k]`` = the length of leg k + 1 that the
    other five imply (nan for a leg whose square does not enter lambda . L); ``nearest``: the
    compatible lengths nearest in the 2-norm, ``distance`` = |nearest - l|."""

    value: float
    null_vector: Array
    gradient: Array
    implied: Array
    nearest: Array
    distance: float


def _compatibility_value(g: Geometry, null: Array, lengths: Array) -> tuple[float, Array]:
    _, rhs = g.system8(lengths)
    gradient = np.zeros(6)
    gradient[0] = -lengths[0] * null.sum()
    gradient[1:] = null * lengths[1:]
    return float(null @ rhs), gradient


def compatibility(m: Any, lengths: ArrayLike) -> Compatibility:
    """How far locked lengths are from a self-motion of a singular geometry (section 5)."""
    g = geometry(m)
    lengths = np.asarray(lengths, dtype=float)
    matrix, _ = g.system8(lengths)
    u, _, _ = np.linalg.svd(matrix)
    null = u[:, -1]
    null = null * np.sign(null[np.argmax(np.abs(null))])
    value, gradient = _compatibility_value(g, null, lengths)
    implied = np.full(6, np.nan)
    for k in range(6):
        # lambda . L is (lambda_{k-1} / 2) l_k^2 + const in l_k (k >= 1), -(sum lambda / 2) l_1^2 + const
        quadratic = -null.sum() / 2 if k == 0 else null[k - 1] / 2
        if abs(quadratic) < 1e-9:
            continue
        others = lengths.copy()
        others[k] = 0.0
        constant, _ = _compatibility_value(g, null, others)
        square = -constant / quadratic
        implied[k] = np.sqrt(square) if square >= 0 else np.nan
    nearest = lengths.copy()
    for _ in range(50):  # nearest point of {lambda . L = 0}: project on the tangent plane, repeat
        value_n, gradient_n = _compatibility_value(g, null, nearest)
        updated = lengths - gradient_n * (value_n + gradient_n @ (lengths - nearest)) / (gradient_n @ gradient_n)
        converged = np.abs(updated - nearest).max() < 1e-15 * (1 + np.abs(lengths).max())
        nearest = updated
        if converged:
            break
    return Compatibility(value, null, gradient, implied, nearest, float(np.linalg.norm(nearest - lengths)))


# ---------------------------------------------------------------------------------- back-substitution
def _real_roots(coefficients: Array) -> list[float]:
    """Real roots of a polynomial (highest power first) by parakin's one root finder (near-real
    candidates included: the checks below decide what closes)."""
    isolated = isolate_real_roots(np.asarray(coefficients, dtype=float)[::-1])
    return [float(x) for x in isolated.roots[: int(isolated.count)]]


def quartic(ix: float, e1: float, e2: float, a1: float, a2: float) -> Array:
    """Eq (23), highest power first: (1 - i_x^2 - i_y^2)(1 - j_x^2 - j_y^2) - (i_x j_x + i_y j_y)^2
    with j_x = e1 i_y + a1, j_y = e2 i_y + a2."""
    s = 1.0 - ix * ix
    b0, b1, b2 = 1.0 - a1 * a1 - a2 * a2, -2.0 * (e1 * a1 + e2 * a2), -(e1 * e1 + e2 * e2)
    k2, k1, k0 = e2, ix * e1 + a2, ix * a1
    return np.array(
        [
            -b2 - k2 * k2,
            -b1 - 2 * k2 * k1,
            s * b2 - b0 - (k1 * k1 + 2 * k2 * k0),
            s * b1 - 2 * k1 * k0,
            s * b0 - k0 * k0,
        ]
    )


def poses_from_u(g: Geometry, u: Array, l1: float, ix: float, tolerance: float = 1e-9) -> list[Array]:
    """Every real pose (4x4) from u1..u5 and i_x: eqs (19)-(25), then (9), (10), (5) as a
    line-sphere intersection (eqs (26)-(27) without Q^-1). Duplicates are removed."""
    t11, t12, t22 = g.t
    if abs(ix) > 1 + tolerance:
        return []
    e1, e2 = -t11 / t22, -t12 / t22
    a1, a2 = -(u[4] + t12 * ix) / t22, -u[3] / t22
    poses: list[Array] = []
    for iy in _real_roots(quartic(ix, e1, e2, a1, a2)):
        jx, jy = e1 * iy + a1, e2 * iy + a2
        wi, wj = 1.0 - ix * ix - iy * iy, 1.0 - jx * jx - jy * jy
        if wi < -tolerance or wj < -tolerance:
            continue
        dot = ix * jx + iy * jy
        for sign in (1.0, -1.0):
            if wi >= wj:
                iz = sign * np.sqrt(max(wi, 0.0))
                jz = -dot / iz if iz != 0 else 0.0
            else:
                jz = sign * np.sqrt(max(wj, 0.0))
                iz = -dot / jz
            i_p, j_p = np.array([ix, iy, iz]), np.array([jx, jy, jz])
            n1 = t11 * i_p - np.array([1.0, 0.0, 0.0])
            n2 = t12 * i_p + t22 * j_p - np.array([0.0, 1.0, 0.0])
            g11, g12, g22 = n1 @ n1, n1 @ n2, n2 @ n2
            det = g11 * g22 - g12 * g12
            if det <= 1e-300:
                continue
            p0 = (g22 * u[0] - g12 * u[1]) / det * n1 + (g11 * u[1] - g12 * u[0]) / det * n2
            h2 = l1 * l1 - p0 @ p0
            if h2 < -tolerance * l1 * l1:
                continue
            d = np.cross(n1, n2)
            for tau in (1.0, -1.0):
                pose = np.eye(4)
                pose[:3, :3] = np.column_stack([i_p, j_p, np.cross(i_p, j_p)])
                pose[:3, 3] = p0 + tau * np.sqrt(max(h2, 0.0) / det) * d
                if all(np.abs(pose - q).max() > 1e-9 * (1 + np.abs(q).max()) for q in poses):
                    poses.append(pose)
    return poses


# ---------------------------------------------------------------------------------- self-motion
def dependent_leg(m: Any) -> int:
    """The leg (1-based) whose length section 5 treats as dependent: 6 as in the paper, unless
    equation 6 of (8) does not enter the dependency (then the leg with the largest |lambda|)."""
    g = geometry(m)
    u, _, _ = np.linalg.svd(g.system8(np.zeros(6))[0])
    null = np.abs(u[:, -1])
    return 6 if null[4] > 1e-6 * null.max() else int(np.argmax(null)) + 2


def _self_motion_cd(g: Geometry, lengths: Array, dependent: int) -> tuple[Array, Array]:
    """Eqs (16)-(18): (u1, u2, u4, u5) = i_x C + D from the four equations of (8) without the
    dependent leg."""
    matrix, rhs = g.system8(lengths)
    rows = [k for k in range(5) if k != dependent - 2]
    j = matrix[rows][:, [0, 1, 3, 4]]
    c = np.asarray(np.linalg.solve(j, g.t[0] * matrix[rows, 2]), dtype=np.float64)
    return c, np.asarray(np.linalg.solve(j, rhs[rows]), dtype=np.float64)


@dataclass(frozen=True)
class SelfMotionModes:
    """Every assembly mode for one i_x: poses (n, 4, 4) and leg residuals (n, 6) (metres)."""

    ix: float
    poses: Array
    residual: Array
    dependent: int


def self_motion_modes(m: Any, lengths: ArrayLike, ix: float, dependent: int | None = None) -> SelfMotionModes:
    """Section 5.1-5.3 for one value of i_x, the five independent legs imposed."""
    g = geometry(m)
    lengths = np.asarray(lengths, dtype=float)
    dependent = dependent_leg(g) if dependent is None else dependent
    c, d = _self_motion_cd(g, lengths, dependent)
    values = ix * c + d
    u = np.array([values[0], values[1], -g.t[0] * ix, values[2], values[3]])
    poses = poses_from_u(g, u, float(lengths[0]), ix)
    stacked = np.array(poses) if poses else np.zeros((0, 4, 4))
    residual = g.leg_lengths(stacked) - lengths if poses else np.zeros((0, 6))
    return SelfMotionModes(ix, stacked, residual, dependent)


def distance_to_self_motion(m: Any, lengths: ArrayLike, poses: ArrayLike) -> Array:
    """For poses (k, 4, 4) on a self-motion: the max-norm distance of each to the nearest of the
    section 5 modes at its own i_x (= R[0, 0]); inf where there is none."""
    poses = np.asarray(poses, dtype=float).reshape(-1, 4, 4)
    distances = np.full(poses.shape[0], np.inf)
    for n, pose in enumerate(poses):
        modes = self_motion_modes(m, lengths, float(pose[0, 0])).poses
        if modes.shape[0]:
            distances[n] = float(np.abs(modes - pose).max(axis=(-2, -1)).min())
    return distances


@dataclass
class SelfMotion:
    """The self-motion of a singular geometry with locked lengths (section 5, Fig. 2).

    ``intervals``: the i_x ranges with real modes; ``branches``: per interval, (i_x grid (k,),
    poses (k, n, 4, 4)) with the n modes tracked continuously; ``circuits``: lists of (interval,
    mode) pairs joined at the folds; ``residual``: max leg residual (6,) over all traced poses;
    ``fold_gaps``: the pose distance of every fold join (small when the join is sound)."""

    dependent: int
    intervals: list[tuple[float, float]]
    branches: list[tuple[Array, Array]]
    circuits: list[list[tuple[int, int]]]
    residual: Array
    fold_gaps: list[float] = field(default_factory=list)

    @property
    def modes_per_ix(self) -> list[int]:
        return [int(poses.shape[1]) for _, poses in self.branches]

    def circuit_positions(self, index: int) -> list[Array]:
        """O_P along each piece of circuit ``index``: arrays (k, 3)."""
        return [self.branches[b][1][:, k, :3, 3] for b, k in self.circuits[index]]


def _count(g: Geometry, lengths: Array, ix: float, dependent: int) -> int:
    return int(self_motion_modes(g, lengths, ix, dependent).poses.shape[0])


def _intervals(g: Geometry, lengths: Array, dependent: int, grid: int) -> list[tuple[float, float]]:
    samples = np.linspace(-1.0, 1.0, grid)
    inside = np.array([_count(g, lengths, v, dependent) > 0 for v in samples])
    edges = []
    for k in np.flatnonzero(np.diff(inside.astype(int))):
        low, high = samples[k], samples[k + 1]
        low_inside = bool(inside[k])
        for _ in range(60):
            middle = 0.5 * (low + high)
            if (_count(g, lengths, middle, dependent) > 0) == low_inside:
                low = middle
            else:
                high = middle
        edges.append(low if low_inside else high)
    bounds = ([-1.0] if inside[0] else []) + edges + ([1.0] if inside[-1] else [])
    return [(bounds[2 * k], bounds[2 * k + 1]) for k in range(len(bounds) // 2)]


def _pose_vector(poses: Array) -> Array:
    return np.concatenate([poses[..., :3, 3], poses[..., :3, 0], poses[..., :3, 1]], axis=-1)


def self_motion(
    m: Any, lengths: ArrayLike, samples: int = 600, dependent: int | None = None, grid: int = 2001
) -> SelfMotion:
    """Trace every circuit of the self-motion: i_x on a cosine-spaced grid in each interval
    (dense at the folds), modes matched between neighbouring samples by nearest pose, the ends of
    the pieces paired at each fold by nearest pose, and pieces joined into circuits."""
    g = geometry(m)
    lengths = np.asarray(lengths, dtype=float)
    dependent = dependent_leg(g) if dependent is None else dependent
    intervals = _intervals(g, lengths, dependent, grid)
    branches: list[tuple[Array, Array]] = []
    worst = np.zeros(6)
    for low, high in intervals:
        angles = np.linspace(1e-4, np.pi - 1e-4, samples)
        ixs = low + (high - low) * (1 - np.cos(angles)) / 2
        modes = [self_motion_modes(g, lengths, v, dependent) for v in ixs]
        count = min(mode.poses.shape[0] for mode in modes)
        track = [modes[0].poses[:count]]
        for mode in modes[1:]:
            previous = _pose_vector(track[-1])
            current = _pose_vector(mode.poses)
            cost = np.linalg.norm(previous[:, None, :] - current[None, :, :], axis=-1)
            order = np.full(count, -1)
            for _ in range(count):  # greedy assignment, cheapest pair first
                i, j = np.unravel_index(np.argmin(cost), cost.shape)
                order[i] = j
                cost[i, :] = np.inf
                cost[:, j] = np.inf
            track.append(mode.poses[order])
            worst = np.maximum(worst, np.abs(mode.residual).max(0, initial=0.0))
        branches.append((ixs, np.stack(track)))
    parent: dict[tuple[int, int], tuple[int, int]] = {}

    def find(key: tuple[int, int]) -> tuple[int, int]:
        while parent.setdefault(key, key) != key:
            key = parent[key]
        return key

    gaps: list[float] = []
    for b, (ixs, poses) in enumerate(branches):
        for end in (0, -1):
            if abs(ixs[end]) >= 1.0 - 1e-3:
                continue  # the interval reaches |i_x| = 1: no fold there
            ends = _pose_vector(poses[end])
            n = ends.shape[0]
            cost = np.linalg.norm(ends[:, None] - ends[None], axis=-1)
            np.fill_diagonal(cost, np.inf)
            for _ in range(n // 2):
                i, j = np.unravel_index(np.argmin(cost), cost.shape)
                gaps.append(float(cost[i, j]))
                parent[find((b, int(i)))] = find((b, int(j)))
                cost[[i, j], :] = np.inf
                cost[:, [i, j]] = np.inf
    circuits: dict[tuple[int, int], list[tuple[int, int]]] = {}
    for b, (_, poses) in enumerate(branches):
        for k in range(poses.shape[1]):
            circuits.setdefault(find((b, k)), []).append((b, k))
    return SelfMotion(dependent, intervals, branches, list(circuits.values()), worst, gaps)


# ---------------------------------------------------------------------------------- least squares
@dataclass(frozen=True)
class LeastSquaresPose:
    """The pose whose leg lengths are nearest (2-norm) the locked ones; ``residual`` (6,) =
    l_i(pose) - l_i, metres. Nonzero exactly when the lengths are incompatible."""

    pose: Array
    residual: Array
    iterations: int

    @property
    def norm(self) -> float:
        return float(np.linalg.norm(self.residual))


def rotation_from_vector(w: ArrayLike) -> Array:
    """exp([w]x): the rotation by |w| about w (Rodrigues)."""
    w = np.asarray(w, dtype=float)
    angle = float(np.linalg.norm(w))
    if angle < 1e-300:
        return np.eye(3)
    k = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]) / angle
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)


def least_squares_pose(m: Any, lengths: ArrayLike, start: ArrayLike, iterations: int = 200) -> LeastSquaresPose:
    """Levenberg-Marquardt from ``start`` (4x4) on the leg residuals, in the twist (v of O_P, w)
    of the platform (R updated as exp(w) R): handles the rank-deficient Jacobian of a self-motion."""
    g = geometry(m)
    lengths = np.asarray(lengths, dtype=float)
    pose = np.array(start, dtype=float)
    damping = 1e-3

    def residual_and_jacobian(current: Array) -> tuple[Array, Array]:
        arm = current[:3, :3] @ g.platform.T  # R B_i^(P), (3, 6)
        legs = current[:3, 3][:, None] + arm - g.base.T
        norm = np.linalg.norm(legs, axis=0)
        unit = legs / norm
        return norm - lengths, np.hstack([unit.T, np.cross(arm.T, unit.T)])

    residual, jacobian = residual_and_jacobian(pose)
    done = 0
    while done < iterations:
        done += 1
        gradient = jacobian.T @ residual
        if np.abs(gradient).max() < 1e-15 * max(1.0, float(np.abs(lengths).max()) ** 2):
            break
        normal = jacobian.T @ jacobian
        step = np.asarray(-np.linalg.solve(normal + damping * np.diag(np.diag(normal) + 1e-12), gradient))
        trial = pose.copy()
        trial[:3, 3] += step[:3]
        trial[:3, :3] = rotation_from_vector(step[3:]) @ pose[:3, :3]
        trial_residual, trial_jacobian = residual_and_jacobian(trial)
        if trial_residual @ trial_residual < residual @ residual:
            pose, residual, jacobian = trial, trial_residual, trial_jacobian
            damping = max(damping / 3, 1e-12)
            if np.abs(step).max() < 1e-14 * (1 + np.abs(pose[:3, 3]).max()):
                break
        else:
            damping *= 4
            if damping > 1e12:
                break
    return LeastSquaresPose(pose, residual, done)


# ---------------------------------------------------------------------------------- dispatch
def forward_all(m: parakin.Mechanism, lengths: ArrayLike, samples: int = 600) -> Any:
    """Every solution of the forward pose for a loaded gough mechanism: ``m.forward_pose_all``
    (isolated modes, at most 8) on a usable geometry; on an architecturally singular one, the
    SelfMotion of section 5 (a one-parameter family) for compatible lengths, or, for incompatible
    lengths, the SelfMotion of the five independent legs (the dependent leg then has a constant
    error)."""
    if not is_architecturally_singular(m):
        return m.forward_pose_all(lengths)
    return self_motion(m, lengths, samples)


# ---------------------------------------------------------------------------------- the walkthrough
def demo() -> None:
    np.set_printoptions(precision=5, suppress=True, linewidth=120)
    usable = parakin.load("gough", backend="numpy")
    home = usable.forward_pose(usable.home_actuated)
    print(f"the defaults, a base off the conic: {usable!r}")
    print(f"  architecture measure {usable.architecture()}, home pose {parakin.xyz_euler_from_pose(home.pose)}")
    print(f"  {usable.forward_pose_all(usable.home_actuated).count} assembly modes at the home lengths\n")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", parakin.ArchitectureSingularityWarning)
        m = parakin.load("gough", backend="numpy", **SECTION_54)
    print(f"section 5.4, the named example {EXAMPLE!r}: {m!r}\n")
    for warning in caught:
        print(f"parakin.load warns: {warning.category.__name__}: {warning.message}\n")
    print("section 5.4: base A2..A6 = (5,-5) (9,-3) (10,0) (9,3) (5,5), t11 = t12 = t22 = 1")
    fit = conic_fit(m)
    print(f"  architecture (eq 14-15): {fit.describe()}")
    print("  paper: on (x - 5)^2 + y^2 - 25 = 0, i.e. x - 0.1 x^2 - 0.1 y^2 = 0")
    lengths = np.array(PRINTED_LENGTHS)
    try:
        m.forward_pose_all(lengths)
    except parakin.SingularConfigurationError as error:
        print(f"  forward_pose_all: {type(error).__name__}: {error}")

    check = compatibility(m, lengths)
    print(f"\nprinted inputs l1..l6 = {PRINTED_LENGTHS}")
    scale = check.null_vector[0]
    print(f"  compatibility lambda . L(l) = {check.value / scale:.5f} (lambda = {check.null_vector / scale})")
    bound = 0.005 * np.abs(check.gradient / scale).sum()
    print(f"  rounding to 0.005 can move it by up to {bound:.3f}: consistent with rounding")
    print(f"  each leg implied by the other five: {check.implied}")
    print(f"  nearest compatible lengths {check.nearest}, 2-norm change {check.distance:.5f}")

    motion = self_motion(m, lengths, samples=300)
    low, high = motion.intervals[0]
    print(f"\nself-motion (section 5, legs 1-5 imposed, leg {motion.dependent} dependent):")
    print(f"  {motion.modes_per_ix[0]} assembly modes for every i_x in ({low:.5f}, {high:.5f}), none outside")
    print(f"  {len(motion.circuits)} circuits, each joined from {[len(c) for c in motion.circuits]} i_x-branches")
    print(f"  max leg residual along the motion (l_i(pose) - l_i): {motion.residual}")
    print("  (leg 6 keeps the constant length the other five imply: the printed l6 is 0.0338 short)")
    modes = self_motion_modes(m, lengths, SAMPLE_IX)
    print(
        f"\nthe {modes.poses.shape[0]} assembly modes at i_x = {SAMPLE_IX} ({{x y z alpha beta gamma}}, leg residuals):"
    )
    for pose, residual in zip(modes.poses, modes.residual, strict=True):
        print(f"  {parakin.xyz_euler_from_pose(pose)}  {np.abs(residual[:5]).max():.1e} / leg 6 {residual[5]:+.6f}")

    compatible = self_motion(m, check.nearest, samples=300)
    print(
        f"\nwith the nearest compatible lengths: {compatible.modes_per_ix[0]} modes per i_x on "
        f"({compatible.intervals[0][0]:.5f}, {compatible.intervals[0][1]:.5f}), {len(compatible.circuits)} circuits, "
        f"all six legs within {compatible.residual.max():.1e}"
    )
    fit_ls = least_squares_pose(m, lengths, modes.poses[0])
    print(
        f"least-squares pose for the printed (incompatible) lengths: residuals {fit_ls.residual}, "
        f"2-norm {fit_ls.norm:.5f} (= the distance to compatible lengths)"
    )


# ---------------------------------------------------------------------------------- Fig. 2
def plot(path: str) -> None:
    """O_P along the two circuits of the self-motion (printed l1..l5, leg 6 dependent), with the
    eight assembly modes at one i_x drawn as platform triangles B1 B2 B6; right: z of O_P vs i_x.
    Needs matplotlib."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    m = load_example()
    g = geometry(m)
    motion = self_motion(m, PRINTED_LENGTHS, samples=500)
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
    modes = self_motion_modes(m, PRINTED_LENGTHS, SAMPLE_IX)
    for pose in modes.poses:
        corners = pose[:3, 3] + g.platform[[0, 1, 5, 0]] @ pose[:3, :3].T
        ax.plot(*corners.T, color="k", linewidth=0.8)
        ax.scatter(*pose[:3, 3], color="k", s=10)
    ax.scatter(*g.base.T, color="k", marker="^", s=30, label="base joints A_i")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    ax.set_title(f"O_P on {len(motion.circuits)} circuits; {modes.poses.shape[0]} modes at i_x = {SAMPLE_IX}")
    ax.legend(loc="upper left", fontsize=8)
    side.axvline(SAMPLE_IX, color="0.6", linewidth=0.8)
    side.set_xlabel("i_x")
    side.set_ylabel("z of O_P")
    side.set_title("Kong & Gosselin 5.4: self-motion, leg 6 dependent")
    side.legend(fontsize=8)
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
