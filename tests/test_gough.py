"""6-SPS with linearly related planar platforms: claims of Kong & Gosselin and checks.

Section 5.4's geometry (architecturally singular) is the named example ``section54_self_motion``
(``arch.SECTION_54``), passed explicitly; the defaults are a usable geometry (its A4 moved off the
conic, tests/test_gough.py::test_defaults_are_section54_with_a4_off_the_conic). Other usable
geometries are drawn at random: xA, yA in [-1, 1] m, |t11|, |t22| in [0.2, 2], t12 in [-1.5, 1.5],
bases within 1e-4 (relative singular value) of a conic rejected.
"""

import warnings

import gough_architecture as arch
import numpy as np
import pytest
import sympy as sp
from parakin.mechanisms import gough

import parakin
from parakin.errors import SingularConfigurationError
from parakin.solvers.continuation import SelfMotion

PRINTED = np.array(arch.PRINTED_LENGTHS)  # section 5.4, two decimals


@pytest.fixture(scope="module", params=["numpy", "compiled"])
def backend(request):
    return request.param


@pytest.fixture(scope="module")
def example(backend):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return parakin.load("gough", backend=backend, **arch.SECTION_54)


def random_geometry(rng: np.random.Generator) -> dict[str, float]:
    while True:
        xy = rng.uniform(-1, 1, (2, 5))
        t11, t22 = rng.choice([-1, 1], 2) * rng.uniform(0.2, 2, 2)
        params = {f"xA{i + 2}": xy[0, i] for i in range(5)} | {f"yA{i + 2}": xy[1, i] for i in range(5)}
        params |= {"t11": t11, "t12": rng.uniform(-1.5, 1.5), "t22": t22}
        if arch.conic_fit(params).measure > 1e-4:
            return params


def random_pose(rng: np.random.Generator) -> np.ndarray:
    q = rng.normal(size=4)
    w, x, y, z = q / np.linalg.norm(q)
    pose = np.eye(4)
    pose[:3, :3] = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]
    pose[:3, 3] = [*rng.uniform(-1, 1, 2), rng.choice([-1, 1]) * rng.uniform(0.2, 2.5)]
    return pose


# ------------------------------------------------------------------ section 4: the architecture
def test_eq14_determinant_is_the_conic_condition_eq15():
    """det M of system (8) (5x5, degree 8, 120 terms) is irreducible over Q and equals the 6-point
    conic determinant det[1, x, y, x^2, y^2, xy] with A1 = O: det M = 0 iff the base lies on a
    conic (eq 15, k0 = 0 since the conic passes through A1 = O). SymPy's factorisation draws
    random evaluation points from its own generator, and its time depends on them (0.4 s here;
    over five minutes with seed 2026, and an unseeded clean-clone run hung in it): seeded, every
    run takes the same path."""
    from sympy.core.random import seed

    seed(0)
    det_m = sp.expand(gough.system8_matrix().det(method="berkowitz"))
    assert len(det_m.as_ordered_terms()) == 120
    assert sp.Poly(det_m).total_degree() == 8
    _, factors = sp.factor_list(det_m)
    assert len(factors) == 1 and factors[0][1] == 1  # irreducible
    assert sp.expand(det_m - gough.conic_matrix().det(method="berkowitz")) == 0
    # the paper's frame (X through A2, yA2 = 0): det M = xA2 * (an irreducible factor), xA2 = 0
    # being A2 = A1
    _, in_frame = sp.factor_list(det_m.subs(gough.YA[0], 0))
    assert sorted(sp.Poly(f).total_degree() for f, _ in in_frame) == [1, 7]
    assert gough.XA[0] in [f for f, _ in in_frame]


def test_eq8_follows_from_eq6_on_so3():
    """(eq6_i - eq5) / 2 - eq8_i vanishes once i_P, j_P are orthonormal (eqs 2-4)."""
    ix, iy, iz, jx, jy, jz, x, y, z = sp.symbols("ix iy iz jx jy jz x y z", real=True)
    xa, ya, t11, t12, t22, l1, li = sp.symbols("xa ya t11 t12 t22 l1 li", real=True)
    p, i_p, j_p = sp.Matrix([x, y, z]), sp.Matrix([ix, iy, iz]), sp.Matrix([jx, jy, jz])
    xb, yb = t11 * xa + t12 * ya, t22 * ya
    leg = p + xb * i_p + yb * j_p - sp.Matrix([xa, ya, 0])
    u = [
        t11 * p.dot(i_p) - x,
        t12 * p.dot(i_p) + t22 * p.dot(j_p) - y,
        -t11 * ix,
        -t12 * iy - t22 * jy,
        -t12 * ix - t11 * iy - t22 * jx,
    ]
    big_l = (li**2 - xb**2 - yb**2 - xa**2 - ya**2 - l1**2) / 2
    eq8 = xa * u[0] + ya * u[1] + xa**2 * u[2] + ya**2 * u[3] + xa * ya * u[4] - big_l
    difference = ((leg.dot(leg) - li**2) - (p.dot(p) - l1**2)) / 2 - eq8
    on_so3 = xb**2 / 2 * (i_p.dot(i_p) - 1) + yb**2 / 2 * (j_p.dot(j_p) - 1) + xb * yb * i_p.dot(j_p)
    assert sp.expand(difference - on_so3) == 0


def test_section54_base_lies_on_the_printed_conic():
    """(x - 5)^2 + y^2 = 25, i.e. x - 0.1 x^2 - 0.1 y^2 = 0: det M = 0 exactly, and the fit."""
    base = gough.SECTION_54_BASE
    exact = sp.Matrix([[sp.Integer(int(a)), int(b), int(a) ** 2, int(b) ** 2, int(a * b)] for a, b in base])
    assert exact.det() == 0
    assert list(exact.nullspace()[0]) == [-10, 0, 1, 1, 0]  # -10 x + x^2 + y^2 = 0
    fit = arch.conic_fit(arch.SECTION_54)
    assert fit.singular and fit.measure < 1e-15
    np.testing.assert_allclose(fit.coefficients, arch.PRINTED_CONIC, atol=1e-12)


def test_architecture_check_and_warning():
    """parakin.load warns (generically: a declared architecture measure below its tolerance) on
    the section 5.4 geometry and not on a base off the conic; the example's conic fit decides the
    same for any geometry: 50 random usable bases, and the same bases moved onto an ellipse."""
    with pytest.warns(parakin.ArchitectureSingularityWarning, match="architecturally singular"):
        example = parakin.load("gough", backend="numpy", **arch.SECTION_54)
    assert arch.is_architecturally_singular(example) and example.is_architecturally_singular()
    with warnings.catch_warnings():
        warnings.simplefilter("error", parakin.ArchitectureSingularityWarning)
        usable = parakin.load("gough", backend="numpy", **arch.SECTION_54 | {"yA4": 1.0})  # A4 off the circle
    assert not arch.is_architecturally_singular(usable) and not usable.is_architecturally_singular()
    rng = np.random.default_rng(5)
    for _ in range(50):
        usable = random_geometry(rng)
        assert not arch.is_architecturally_singular(usable)
        # A2..A6 moved onto a random ellipse (x - a)^2 + (c y - b)^2 = a^2 + b^2 through A1 = O
        a, b, c = rng.normal(size=3)
        angles = rng.uniform(0, 2 * np.pi, 5)
        radius = np.hypot(a, b)
        xs, ys = a + radius * np.cos(angles), (b + radius * np.sin(angles)) / abs(c)
        on_conic = usable | {f"xA{i + 2}": xs[i] for i in range(5)} | {f"yA{i + 2}": ys[i] for i in range(5)}
        assert arch.is_architecturally_singular(on_conic)


# ------------------------------------------------------------------ section 3: forward pose
def _random_geometries(backend: str, cases: int) -> None:
    """`cases` random usable geometries and poses: every case has at most 8 real modes (mirror
    pairs), each reproducing the six leg lengths to 1e-9, and the pose that made the lengths is
    always among them (pose difference below 1e-8 x scale)."""
    rng = np.random.default_rng(20261121)
    counts, worst_leg, worst_pose, missing = [], 0.0, 0.0, 0
    for _ in range(cases):
        m = parakin.load("gough", backend=backend, **random_geometry(rng))
        pose = random_pose(rng)
        lengths = m.inverse_pose(pose).actuated[0]
        modes = m.forward_pose_all(lengths)
        poses = modes.poses[modes.valid]
        counts.append(len(poses))
        geometry = arch.Geometry.from_parameters(m.parameters)
        worst_leg = max(worst_leg, float(np.abs(geometry.leg_lengths(poses) - lengths).max()))
        distance = np.abs(poses - pose).max(axis=(-2, -1)).min() / (1 + np.abs(pose[:3, 3]).max())
        worst_pose = max(worst_pose, float(distance))
        missing += int(distance > 1e-8)
    assert len(counts) == cases and max(counts) <= 8 and min(counts) >= 1, f"counts {np.bincount(counts)}"
    assert worst_leg < 1e-9, f"worst leg residual {worst_leg:.3g} m > 1e-9"
    assert missing == 0, f"{missing} of {cases} generating poses missing (worst distance {worst_pose:.3g})"


def test_random_geometries_at_most_eight_solutions_containing_the_pose(backend):
    """1000 random geometries compiled; with NumPy (a load costs ~40 ms there) the first 250 of
    them, all 1000 in the next test."""
    _random_geometries(backend, 1000 if backend == "compiled" else 250)


@pytest.mark.slow
def test_random_geometries_at_most_eight_solutions_containing_the_pose_numpy_1000():
    _random_geometries("numpy", 1000)


def test_real_solutions_come_in_mirror_pairs(backend):
    """Real modes pair up by reflection in the base plane: (x, y, z) -> (x, y, -z) with
    R -> S R S, S = diag(1, 1, -1) (the planar platform is mapped onto itself)."""
    rng = np.random.default_rng(3)
    mirror = np.diag([1.0, 1.0, -1.0, 1.0])
    for _ in range(20):
        m = parakin.load("gough", backend=backend, **random_geometry(rng))
        modes = m.forward_pose_all(m.inverse_pose(random_pose(rng)).actuated[0])
        poses = modes.poses[modes.valid]
        reflected = mirror @ poses @ mirror
        gap = np.abs(reflected[:, None] - poses[None]).max(axis=(-2, -1)).min(-1)
        assert gap.max() < 1e-8 and len(poses) % 2 == 0


def test_newton_forward_pose_tracks_a_nearby_guess(backend):
    rng = np.random.default_rng(11)
    m = parakin.load("gough", backend=backend, **random_geometry(rng))
    pose = random_pose(rng)
    lengths = m.inverse_pose(pose).actuated[0]
    guess = parakin.pose_from_xyz_euler(parakin.xyz_euler_from_pose(pose) + 0.01)
    fk = m.forward_pose(lengths, guess=guess)
    assert fk.residual < 1e-12 and np.abs(fk.pose - pose).max() < 1e-9


@pytest.fixture(scope="module")
def printed_motion():
    """The example's forward_all with the printed lengths (section 5.4's geometry, as every
    backend's example has): the self-motion of the five independent legs, 300 samples. Shared:
    tracing it takes ~10 s."""
    return arch.forward_all(arch.load_example(), PRINTED, samples=300)


def test_singular_geometry_forward_pose_all_reports_the_degeneracy(example, printed_motion):
    with pytest.raises(SingularConfigurationError, match="base_points_on_a_conic"):
        example.forward_pose_all(PRINTED)
    assert arch.is_architecturally_singular(example)  # so forward_all traces the self-motion
    assert isinstance(printed_motion, arch.SelfMotion) and printed_motion.modes_per_ix == [8]


# ------------------------------------------------------------------ usable defaults
def test_defaults_are_section54_with_a4_off_the_conic(backend):
    """The defaults (mechanisms/gough.py docstring) are section 5.4's geometry with A4 moved from
    (10, 0) to (13, 0), off the conic: load does not warn, the conic fit of the example module
    calls the base regular, and the home pose {5, 2, 5, -0.3, -0.5, 0.3} is a regular
    configuration: its leg lengths are those of direct substitution, forward_pose_all there finds
    eight real modes (mirror pairs through the base plane) with the home among them, and
    forward_pose from the home lengths lands on the home."""
    defaults = parakin.metadata("gough").parameter_defaults
    assert defaults == arch.SECTION_54 | {"xA4": 13.0}
    with warnings.catch_warnings():
        warnings.simplefilter("error", parakin.ArchitectureSingularityWarning)
        m = parakin.load("gough", backend=backend)
    assert arch.conic_fit(defaults).measure > 1e-3 and not m.is_architecturally_singular()
    home = parakin.pose_from_xyz_euler(gough.HOME_POSE)
    geometry = arch.Geometry.from_parameters(defaults)
    np.testing.assert_allclose(m.home_actuated, geometry.leg_lengths(home), rtol=1e-14)
    assert np.abs(m.home_passive - np.array(gough.HOME_POSE)).max() == 0.0
    modes = m.forward_pose_all(m.home_actuated)
    assert modes.count == 8
    poses = modes.poses[modes.valid]
    assert np.abs(poses - home).max(axis=(-2, -1)).min() < 1e-10
    heights = np.sort(poses[:, 2, 3])
    np.testing.assert_allclose(heights, -heights[::-1], atol=1e-9)  # mirror pairs
    assert np.abs(geometry.leg_lengths(poses) - m.home_actuated).max() < 1e-9
    forward = m.forward_pose(m.home_actuated)
    assert forward.converged and np.abs(forward.pose - home).max() < 1e-10


def test_section54_example_pose_lies_on_the_self_motion_with_the_printed_lengths():
    """The named example ``section54_self_motion``: its pose is one of section 5's modes (at its
    own i_x = 0.044) of the compatible lengths nearest the printed ones, and its inverse pose gives
    the printed l1..l6 to 4.2e-3 m (printed to 0.01 m: within 5e-3)."""
    (example,) = [e for e in parakin.metadata("gough").examples if e.name == arch.EXAMPLE]
    assert example.parameters == arch.SECTION_54 and list(example.expected["actuated"]) == list(arch.PRINTED_LENGTHS)
    m = arch.load_example()
    nearest = arch.compatibility(m, PRINTED).nearest
    pose = np.array(example.pose)
    assert pose[0, 0] == pytest.approx(0.044, abs=1e-12)
    assert arch.distance_to_self_motion(m, nearest, pose)[0] < 1e-9
    lengths = m.inverse_pose(pose).actuated[0]
    assert np.abs(lengths - PRINTED).max() == pytest.approx(0.00419, abs=1e-5)
    assert np.abs(lengths - PRINTED).max() < example.tolerance


# ------------------------------------------------------------------ section 5: self-motion
def test_section54_self_motion_eight_modes_two_circuits_all_legs():
    """With the nearest compatible lengths, the self-motion has 8 modes for every i_x in one
    interval, on 2 circuits (mirror images in the base plane), and every traced mode satisfies
    all six legs to 1e-9."""
    example = arch.Geometry.from_parameters(arch.SECTION_54)
    compatible = arch.compatibility(example, PRINTED).nearest
    motion = arch.self_motion(example, compatible, samples=400)
    assert len(motion.intervals) == 1 and motion.modes_per_ix == [8]
    low, high = motion.intervals[0]
    assert low == pytest.approx(-0.55488, abs=1e-4) and high == pytest.approx(0.59098, abs=1e-4)
    assert len(motion.circuits) == 2 and sorted(len(c) for c in motion.circuits) == [4, 4]
    assert motion.residual.max() < 1e-9, f"leg residuals {motion.residual}"
    assert max(motion.fold_gaps) < 0.05
    heights = [np.concatenate(motion.circuit_positions(k))[:, 2] for k in range(2)]
    assert min(h.min() for h in heights) == pytest.approx(-max(h.max() for h in heights), rel=1e-6)


def test_section54_printed_lengths_five_legs_exact_sixth_constant_offset(printed_motion):
    """The paper's procedure with the printed l1..l5 (leg 6 dependent): 8 modes for i_x in
    (-0.53603, 0.62301); legs 1-5 to 1e-12, leg 6 off by a constant +0.033847 (its implied length
    38.3538 against the printed 38.32)."""
    example = arch.Geometry.from_parameters(arch.SECTION_54)
    motion = printed_motion  # arch.self_motion(example, PRINTED, samples=300) through forward_all
    assert motion.dependent == 6 and motion.modes_per_ix == [8] and len(motion.circuits) == 2
    assert motion.intervals[0][0] == pytest.approx(-0.53603, abs=1e-5)
    assert motion.intervals[0][1] == pytest.approx(0.62301, abs=1e-5)
    assert motion.residual[:5].max() < 1e-12
    offsets = np.concatenate([example.leg_lengths(poses)[..., 5].ravel() - PRINTED[5] for _, poses in motion.branches])
    assert offsets.min() == pytest.approx(0.033847, abs=1e-6) and np.ptp(offsets) < 1e-10
    modes = arch.self_motion_modes(example, PRINTED, 0.044)
    assert modes.poses.shape[0] == 8 and np.abs(modes.residual[:, :5]).max() < 1e-12


def test_section54_printed_inputs_consistent_only_within_rounding():
    """lambda . L(l) = 0 is the compatibility condition; the printed value is within what
    rounding to 0.005 can produce, but the lengths are not 'five inputs and the dependent sixth':
    l6 implied by l1..l5 is 38.3538 (printed 38.32). Nearest compatible lengths: 0.006014 away."""
    example = arch.Geometry.from_parameters(arch.SECTION_54)
    check = arch.compatibility(example, PRINTED)
    np.testing.assert_allclose(check.null_vector / check.null_vector[0], [1, -25 / 9, 4, -25 / 9, 1], rtol=1e-12)
    assert abs(check.value) <= 0.005 * np.abs(check.gradient).sum()
    np.testing.assert_allclose(check.implied, [33.0819, 32.0605, 35.1067, 37.5786, 38.9980, 38.3538], atol=1e-4)
    assert check.distance == pytest.approx(0.006014, abs=1e-6)
    assert abs(arch.compatibility(example, check.nearest).value) < 1e-10


def test_incompatible_locked_lengths_least_squares_residual():
    """Locked lengths that no pose reaches: the least-squares pose leaves a residual whose norm is
    the distance to the nearest compatible lengths (0.006014; largest leg error 0.0042, leg 4)."""
    example = arch.Geometry.from_parameters(arch.SECTION_54)
    start = arch.self_motion_modes(example, PRINTED, 0.044).poses[0]
    fit = arch.least_squares_pose(example, PRINTED, start)
    assert fit.norm == pytest.approx(arch.compatibility(example, PRINTED).distance, rel=1e-6)
    assert np.argmax(np.abs(fit.residual)) == 3 and abs(fit.residual[3]) == pytest.approx(0.0042, abs=1e-4)


# ------------------------------------------------------------------ Pluecker Jacobian
def test_pluecker_jacobian_matches_finite_differences(backend):
    """l_dot = B^-1 A twist, twist = (v of O_P, w) in {B}: against central differences of the
    inverse pose along exp(w dt) and p + v dt."""
    rng = np.random.default_rng(17)
    m = parakin.load("gough", backend=backend, **random_geometry(rng))
    worst = 0.0
    for _ in range(50):
        pose = random_pose(rng)
        state = m.inverse_pose(pose).branch(0)
        jac = m.rate_jacobians(state)
        rates = np.linalg.solve(jac["b"], jac["a"])
        twist = rng.normal(size=6)
        h = 1e-6

        def moved(s: float, pose=pose, twist=twist) -> np.ndarray:
            out = pose.copy()
            out[:3, 3] += s * twist[:3]
            out[:3, :3] = arch.rotation_from_vector(s * twist[3:]) @ pose[:3, :3]
            return m.inverse_pose(out).actuated[0]

        numeric = (moved(h) - moved(-h)) / (2 * h)
        worst = max(worst, float(np.abs(rates @ twist - numeric).max() / np.abs(numeric).max()))
    assert worst < 1e-7


def test_pluecker_determinant_flags_architecture_and_type2(backend):
    """det A (leg_lines_dependent, and det_A) through m.singularities: relative to the Hadamard
    bound it is ~1e-16 at every pose of the conic example and clearly nonzero for a usable base;
    at a pose where it changes sign, Newton reports a type II singularity."""
    rng = np.random.default_rng(23)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        example = parakin.load("gough", backend=backend, **arch.SECTION_54)
    usable = parakin.load("gough", backend=backend, **random_geometry(rng))
    for m, singular in ((example, True), (usable, False)):
        poses = np.stack([random_pose(rng) for _ in range(50)])
        if singular:
            poses[:, :3, 3] *= 15.0
        state = m.inverse_pose(poses).branch(0)
        factors = m.singularities(state)
        a = m.rate_jacobians(state)["a"]
        hadamard = np.prod(np.linalg.norm(a, axis=-1), axis=-1)
        ratio = np.abs(factors["leg_lines_dependent"]) / hadamard
        np.testing.assert_allclose(factors["det_A"], np.linalg.det(a), rtol=1e-6, atol=1e-12 * hadamard.max())
        if singular:
            assert ratio.max() < 1e-12
        else:
            assert np.median(ratio) > 1e-6
    # a type II singularity of the usable geometry: the platform in the base plane, k_P vertical,
    # puts all six leg lines in one plane
    flat = np.eye(4)
    flat[:3, 3] = [0.3, -0.2, 0.0]
    state = usable.inverse_pose(flat).branch(0)
    a = usable.rate_jacobians(state)["a"]
    hadamard = np.prod(np.linalg.norm(a, axis=-1))
    assert abs(float(usable.singularities(state)["leg_lines_dependent"])) < 1e-12 * hadamard


def test_mechanism_method_reports_architecture_singularity():
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        singular = parakin.load("gough", backend="numpy", **arch.SECTION_54)
    assert singular.is_architecturally_singular()
    usable = parakin.load("gough", backend="numpy", **arch.SECTION_54 | {"yA4": 1.0})
    assert not usable.is_architecturally_singular()
    assert not parakin.load("sam", backend="numpy").is_architecturally_singular()


def test_symbolic_architecture_condition_is_what_the_runtime_evaluates():
    """The declared architecture measure (``parakin.symbolic``: det M of eq 14, possibly
    normalised) vanishes on the section 5.4 base and not on a base off the conic, and the runtime's
    ``m.architecture()`` is its value at the loaded parameters."""
    objects = parakin.symbolic("gough")
    singular = arch.load_example()
    usable = parakin.load("gough", backend="numpy", **arch.SECTION_54 | {"yA4": 1.0})
    names = list(singular.architecture())
    assert names and names == list(usable.architecture())
    for name in names:
        expression = objects[f"architecture_{name}"]
        for m in (singular, usable):
            values = {s: m.parameters[s.name] for s in expression.free_symbols}
            assert float(expression.subs(values)) == pytest.approx(m.architecture()[name], rel=1e-9, abs=1e-12)
    tolerance = parakin.metadata("gough").capabilities.architecture.tolerance
    assert max(abs(v) for v in singular.architecture().values()) < tolerance
    assert min(abs(v) for v in usable.architecture().values()) > 1e3 * tolerance


@pytest.mark.parametrize(
    "stride", [10, pytest.param(1, marks=pytest.mark.slow)], ids=["every-10th-point", "every-point"]
)
def test_forward_pose_all_reports_the_self_motion_set(stride):
    """On an architecturally singular design with compatible locked legs (section 5.4's printed
    lengths moved by 0.006 m to the nearest compatible ones), forward pose neither fails silently
    nor returns a random point: it raises SelfMotionError carrying parakin's generic self-motion
    (continuation of the loop closure). Every traced point closes the loop (residual below 1e-9),
    its leg lengths are the locked ones, and it lies on the paper's self-motion: one of the
    section 5 modes at its own i_x, with i_x inside the interval (-0.55488, 0.59098) of
    test_section54_self_motion_eight_modes_two_circuits_all_legs. The section 5 modes are found
    point by point (~7 ms each): every `stride`-th traced point of 8000 is compared."""
    m = arch.load_example()
    locked = arch.compatibility(m, PRINTED).nearest
    with pytest.raises(parakin.SelfMotionError, match="solution set") as error:
        m.forward_pose_all(locked)
    assert isinstance(error.value, parakin.SingularConfigurationError)
    motion = error.value.solution_set
    assert isinstance(motion, SelfMotion) and motion.count > 100
    assert np.array_equal(motion.actuated, locked)
    assert motion.residual.max() < 1e-9, f"closure residual {motion.residual.max():.3g} >= 1e-9"
    legs = m.inverse_pose(motion.poses).actuated[:, 0]
    assert np.abs(legs - locked).max() < 2e-9
    # 1e-5 (poses ~30 m): at the folds the quartic (23) has a double root, so the section 5 modes
    # themselves are only sqrt(eps)-accurate there; away from them the distance is ~1e-11
    distance = arch.distance_to_self_motion(m, locked, motion.poses[::stride])
    assert distance.size >= 5000 // stride, distance.size
    assert distance.max() < 1e-5, f"largest distance to the section 5 modes {distance.max():.3g}"
    assert np.median(distance) < 1e-9
    ix = motion.poses[:, 0, 0]
    assert ix.min() > -0.55488 - 1e-4 and ix.max() < 0.59098 + 1e-4 and np.ptp(ix) > 0.5
