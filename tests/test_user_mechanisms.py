"""A new user's mechanisms, written only as joints, through ``parakin generate`` (issue 32, Done when).

Seven kinds, each a mechanism file a user writes with the documented calls of
``parakin.generator.joints`` (no hand derivation), generated into a temporary folder as a user
runs it (``python -m parakin generate FILE --out DIR``) and checked against sources independent
of the generated code:

* the 2-PRR biglide (``fixtures/biglide.py``): two circles about the sliders meet in the output
  point; the forward modes, the inverse branches, the rates and the type II factor against
  their closed forms derived here, the root count 2 (two circles meet in two points);
* the 3-UPU (``fixtures/upu3.py``) and the 3-PUU linear delta (``fixtures/linear_delta.py``):
  three spheres meet in two points, the modes against that intersection computed here;
* the 3-RPS and 3-RRS (``fixtures/rps3.py``, ``fixtures/rrs3.py``): 16 poses (Lee and Shah 1988;
  the 3-RRS at locked cranks is the same problem, each platform joint on a circle in its leg's
  plane), 32 roots with the two quaternion signs;
* the Tricept, as shipped (``mechanisms/tricept.py``: its platform written in the passive leg's
  coordinates) and only as joints (``fixtures/tricept_joints.py``: a spatial platform and
  ``passive_leg``): 24 poses, counted here independently as the dimension of the quotient ring of
  the closure (a Groebner basis over the rationals), 48 roots in the quaternion form; the two
  packages give the same modes, pose by pose;
* the Hexaglide (6-PUS, ``fixtures/hexaglide.py``): at locked sliders a 6-6 Gough-Stewart
  platform, 40 poses (Raghavan 1993, Dietmaier 1998), 80 roots generically, 72 with its sliders on shared rails.

For each: the proven root count equals the independent one, every assembly mode's pose gives its
input back through the inverse, Newton from each mode's passive values moved by 1e-3 returns to
that mode, the certificate is complete (every root found and certified) at the home and at inputs
near it, the command line answers (``fk --json``, ``plot``, ``export``, and the exported C example
compiled and run). The Hexaglide's count is 72, proven where its sliders share rails (8 of the
family's 80 roots are at infinity there); loaded with the rails apart it is not called complete. The
biglide runs by default (its generation takes about two seconds of CPU); the others are marked
slow (generation 2 s to 1 min of CPU each).
"""

from __future__ import annotations

import itertools
import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import parakin

FIXTURES = Path(__file__).parent / "fixtures"
MECHANISMS = Path(__file__).parents[1] / "mechanisms"

#: the seven kinds (the Tricept from two files): the file a user writes, and the number of complex solutions of its forward
#: problem at generic inputs, known without the generator (module docstring)
KINDS = {
    "biglide": (FIXTURES / "biglide.py", 2),
    "upu3": (FIXTURES / "upu3.py", 2),
    "linear_delta": (FIXTURES / "linear_delta.py", 2),
    "rps3": (FIXTURES / "rps3.py", 32),
    "rrs3": (FIXTURES / "rrs3.py", 32),
    "tricept": (MECHANISMS / "tricept.py", 24),
    "tricept_joints": (FIXTURES / "tricept_joints.py", 48),
    # 40 poses x 2 generically; its sliders share rails, where 8 of the 80 are at infinity
    # (tests/test_family_coincidences.py follows the generic 80 there: 72 stay finite)
    "hexaglide": (FIXTURES / "hexaglide.py", 72),
}
#: closure and pose agreement of double-precision solutions (metres at unit scale)
CLOSE = 1e-10


def generate(source: Path, folder: Path) -> Path:
    """``parakin generate SOURCE --out FOLDER`` as a user runs it."""
    done = subprocess.run(
        [sys.executable, "-m", "parakin", "generate", str(source), "--out", str(folder)],
        capture_output=True,
        text=True,
        timeout=1800,
    )
    assert done.returncode == 0, done.stderr
    return folder


def cli(*arguments: str) -> subprocess.CompletedProcess:
    """``parakin ARGUMENTS``, its exit status asserted 0."""
    done = subprocess.run([sys.executable, "-m", "parakin", *arguments], capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, f"parakin {' '.join(arguments)}: {done.stderr}"
    return done


# ---------------------------------------------------------------------------- the biglide (default)
@pytest.fixture(scope="module")
def biglide_folder(tmp_path_factory) -> Path:
    return generate(KINDS["biglide"][0], tmp_path_factory.mktemp("biglide") / "package")


def two_circles(s1: float, s2: float, l1: float, l2: float) -> list[tuple[float, float]]:
    """The points at distance l1 from (s1, 0) and l2 from (s2, 0): subtracting the circles'
    equations gives x = (s1 + s2) / 2 + (l1^2 - l2^2) / (2 (s2 - s1)), then y = +-sqrt(l1^2 -
    (x - s1)^2); none where that is negative."""
    x = (s1 + s2) / 2 + (l1**2 - l2**2) / (2 * (s2 - s1))
    square = l1**2 - (x - s1) ** 2
    return [] if square < 0 else [(x, -np.sqrt(square)), (x, np.sqrt(square))]


@pytest.mark.parametrize("links", [(0.5, 0.4), (0.3, 0.45)])
def test_biglide_modes_are_the_two_circles_meeting_and_certified_complete(biglide_folder: Path, links) -> None:
    l1, l2 = links
    m = parakin.load(biglide_folder, backend="numpy", L1=l1, L2=l2)
    homotopy = m.capabilities.forward_methods["automatic"].homotopy
    assert homotopy is not None and homotopy.root_count is not None
    assert homotopy.root_count.count == 2 and homotopy.root_count.proven  # two circles meet in two points
    rng = np.random.default_rng(7)
    inputs = rng.uniform(-0.9, 0.9, (40, 2))
    modes = m.forward_pose_all(inputs)
    certificate = modes.certificate()
    assert certificate["complete"].all()  # every root found and certified, at every input
    meeting = 0
    for k, (s1, s2) in enumerate(inputs):
        expected = two_circles(s1, s2, l1, l2)
        found = sorted(tuple(modes.poses[k, j, :2, 3]) for j in np.flatnonzero(modes.valid[k]))
        assert len(found) == len(expected), (s1, s2, found, expected)
        for (x, y), (ex, ey) in zip(sorted(found, key=lambda p: p[1]), expected, strict=True):
            assert abs(x - ex) < CLOSE and abs(y - ey) < CLOSE
        meeting += bool(expected)
    assert 10 <= meeting <= 30  # both cases drawn: circles that meet, circles that do not


def test_biglide_inverse_branches_are_the_sliders_either_side(biglide_folder: Path) -> None:
    # slider i at x -+ sqrt(L_i^2 - y^2); branch 0 (the file's convention): slider 1 left of P,
    # slider 2 right of it; every branch is a combination of the two sides, and forward_pose from
    # the branch's configuration nudged returns the pose
    m = parakin.load(biglide_folder, backend="numpy")
    l1, l2 = m.parameters["L1"], m.parameters["L2"]
    checked = 0
    for x, y in [(0.0, 0.3), (0.12, -0.2), (-0.3, 0.05)]:
        ik = m.inverse_pose([x, y])
        reach1, reach2 = np.sqrt(l1**2 - y**2), np.sqrt(l2**2 - y**2)
        assert np.allclose(ik.actuated[0], [x - reach1, x + reach2], atol=CLOSE)
        sides = {(x + a * reach1, x + b * reach2) for a, b in itertools.product((-1, 1), repeat=2)}
        found = {tuple(np.round(v, 12)) for v in ik.actuated[ik.valid]}
        assert found == {tuple(np.round(v, 12)) for v in sides}
        for branch in np.flatnonzero(ik.valid):
            fk = m.forward_pose(ik.actuated[branch], guess=ik.passive[branch] + 0.01)
            assert fk.converged and np.allclose(fk.pose[:2, 3], [x, y], atol=CLOSE)
            checked += 1
    assert checked == 12


def test_biglide_rates_and_type_ii_factor_match_the_closed_form(biglide_folder: Path) -> None:
    m = parakin.load(biglide_folder, backend="numpy")
    l1, l2 = m.parameters["L1"], m.parameters["L2"]
    step = 1e-6
    ratios = []
    for s1, s2 in [(-0.4, 0.2645751311), (-0.2, 0.3), (0.1, 0.5)]:
        modes = m.forward_pose_all([s1, s2])
        assert int(modes.count) == 2
        for k in range(2):
            state = modes.mode(k)
            x, y = state.pose[:2, 3]
            side = np.sign(y)
            for rate in ([1.0, 0.0], [0.0, 1.0], [0.3, -0.7]):
                # central differences of the closed-form forward along the actuated rates
                ahead = two_circles(s1 + step * rate[0], s2 + step * rate[1], l1, l2)
                behind = two_circles(s1 - step * rate[0], s2 - step * rate[1], l1, l2)
                pick = 1 if side > 0 else 0
                velocity = (np.array(ahead[pick]) - np.array(behind[pick])) / (2 * step)
                assert np.allclose(m.forward_rate(state, rate), velocity, atol=1e-7)
            # det A of the rows (x - s_i, y) is y (s2 - s1): the generated factor up to a constant
            ratios.append(float(m.singularities(state)["links_aligned"]) / (y * (s2 - s1)))
    assert np.ptp(ratios) < 1e-9 * np.abs(ratios).max() and abs(ratios[0]) > 0.1


# ---------------------------------------------------------------------------- the seven (slow)
@pytest.fixture(scope="module")
def packages(tmp_path_factory):
    """name -> its generated package folder, generated on first use."""
    made: dict[str, Path] = {}

    def get(name: str) -> Path:
        if name not in made:
            made[name] = generate(KINDS[name][0], tmp_path_factory.mktemp(name) / "package")
        return made[name]

    return get


def near_home(m: parakin.Mechanism, count: int, spread: float, seed: int) -> np.ndarray:
    """The home's actuated values and ``count - 1`` inputs moved from it by up to ``spread``
    (relative)."""
    home = np.array([v.home for v in m.manifest.actuated])
    rng = np.random.default_rng(seed)
    moved = home * (1 + spread * rng.uniform(-1, 1, (count - 1, home.size)))
    return np.vstack([home, moved])


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(KINDS))
def test_root_count_is_proven_and_equals_the_independent_count(packages, name: str) -> None:
    manifest = json.loads((packages(name) / "manifest.json").read_text())
    proof = manifest["capabilities"]["forward"]["methods"]["automatic"]["root_count"]
    assert proof["proven"] and proof["count"] == KINDS[name][1], proof


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(KINDS))
def test_every_mode_gives_its_input_back_and_newton_returns_to_it(packages, name: str) -> None:
    m = parakin.load(packages(name), backend="compiled")
    revolute = np.array([v.revolute for v in m.manifest.actuated])
    checked = 0
    for actuated in near_home(m, 2, 0.02, 11):
        modes = m.forward_pose_all(actuated)
        assert int(modes.count) >= 1
        for k in range(int(modes.count)):
            state = modes.mode(k)
            ik = m.inverse_pose(state.pose)
            difference = ik.actuated[ik.valid] - actuated
            difference = np.where(revolute, (difference + np.pi) % (2 * np.pi) - np.pi, difference)
            assert np.abs(difference).max(axis=1).min() < 1e-9, (name, k)
            checked += 1
        # Newton from each mode's passive values moved by up to 1e-3 (m, rad, quaternion units)
        # returns to that mode (its pose)
        rng = np.random.default_rng(checked)
        for k in range(int(modes.count)):
            state = modes.mode(k)
            fk = m.forward_pose(actuated, guess=state.passive + 1e-3 * rng.uniform(-1, 1, state.passive.shape))
            assert fk.converged and np.abs(fk.pose - state.pose).max() < 1e-9, (name, k)
    assert checked >= 2


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(KINDS))
def test_certificate_is_complete_at_the_home_and_near_it(packages, name: str) -> None:
    m = parakin.load(packages(name), backend="compiled")
    certificate = m.forward_pose_all(near_home(m, 3, 0.03, 5)).certificate()
    assert (certificate["root_count"] == KINDS[name][1]).all()
    assert (certificate["certified_roots"] == KINDS[name][1]).all(), certificate
    assert certificate["complete"].all()


@pytest.mark.slow
def test_the_hexaglide_with_its_rails_apart_finds_its_poses_and_is_not_called_complete(packages) -> None:
    # the default geometry puts two sliders on each rail (y1 = y2, y3 = y6, y4 = y5), where 8 of
    # the family's 80 solutions are at infinity: its count, 72, is proven there. Loaded with every
    # slider on a rail of its own, those 8 come back, so the 72 paths still find each input's pose
    # but the certificate may not say complete
    m = parakin.load(packages("hexaglide"), backend="compiled", y2=-0.25, y5=0.2, y6=0.08)
    rng = np.random.default_rng(9)
    checked = 0
    for _ in range(3):
        pose = parakin.pose_from_xyz_euler(np.array([0.0, 0.0, -0.44, 0.0, 0.0, 0.0]) + 0.03 * rng.uniform(-1, 1, 6))
        ik = m.inverse_pose(pose)
        branch = int(np.flatnonzero(ik.valid)[0])
        modes = m.forward_pose_all(ik.actuated[branch])
        certificate = modes.certificate()
        assert not certificate["complete"] and not certificate["root_count_proven"]
        assert np.abs(modes.poses[modes.valid] - pose).max(axis=(1, 2)).min() < 1e-9
        checked += 1
    assert checked == 3


@pytest.mark.slow
@pytest.mark.parametrize(
    "name",
    [name for name in sorted(KINDS) if name != "hexaglide"],  # its home is 1/cond 0.01 from a type II singularity
)
def test_forward_pose_from_the_homes_inputs_returns_the_home(packages, name: str) -> None:
    m = parakin.load(packages(name), backend="compiled")
    fk = m.forward_pose(m.home_actuated)
    revolute = np.array([v.revolute for v in m.manifest.passive])
    difference = fk.passive - m.home_passive
    difference = np.where(revolute, (difference + np.pi) % (2 * np.pi) - np.pi, difference)
    assert fk.converged and np.abs(difference).max() < 1e-9, (fk.passive, m.home_passive)


def three_spheres(centres: np.ndarray, radius: np.ndarray) -> list[np.ndarray]:
    """The points at the distances ``radius`` from the three ``centres``: subtracting the first
    sphere from the others leaves two planes, whose line p0 + t n (n normal to both) meets the
    first sphere where a quadratic in t vanishes."""
    rows = 2 * (centres[1:] - centres[0])
    right = (centres[1:] ** 2).sum(axis=1) - (centres[0] ** 2).sum() - radius[1:] ** 2 + radius[0] ** 2
    normal = np.cross(rows[0], rows[1])
    p0 = np.linalg.lstsq(rows, right, rcond=None)[0]  # the point of the line nearest the origin
    offset = p0 - centres[0]
    a, b, c = normal @ normal, 2 * normal @ offset, offset @ offset - radius[0] ** 2
    disc = b * b - 4 * a * c
    return (
        [] if disc < 0 else [p0 + t * normal for t in ((-b - np.sqrt(disc)) / (2 * a), (-b + np.sqrt(disc)) / (2 * a))]
    )


def sphere_centres(name: str, m: parakin.Mechanism, actuated: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Where the translating platform's origin is: at the distance of each leg from the centre
    (base joint or slider) moved back by the platform joint, c_i in {P} (R = I)."""
    angles = np.deg2rad([0.0, 120.0, 240.0])
    radial = np.stack([np.cos(angles), np.sin(angles), np.zeros(3)], axis=1)
    if name == "upu3":
        shift = m.parameters["r_b"] - m.parameters["r_p"]
        return shift * radial, actuated
    shift = m.parameters["R"] - m.parameters["r"]
    centres = shift * radial + actuated[:, None] * np.array([0.0, 0.0, 1.0])
    return centres, np.full(3, m.parameters["l"])


@pytest.mark.slow
@pytest.mark.parametrize("name", ["upu3", "linear_delta"])
def test_translating_platforms_are_three_spheres_meeting(packages, name: str) -> None:
    m = parakin.load(packages(name), backend="compiled")
    inputs = near_home(m, 12, 0.1, 3)
    modes = m.forward_pose_all(inputs)
    assert modes.certificate()["complete"].all()
    for k, actuated in enumerate(inputs):
        expected = sorted(three_spheres(*sphere_centres(name, m, actuated)), key=lambda p: p[2])
        found = sorted((modes.poses[k, j, :3, 3] for j in np.flatnonzero(modes.valid[k])), key=lambda p: p[2])
        assert len(found) == len(expected) == 2
        assert np.allclose(found, expected, atol=CLOSE)


@pytest.mark.slow
def test_the_tricept_count_is_the_quotient_ring_dimension_of_its_closure() -> None:
    # R = Rot_x(a) Rot_y(b), p = s R z_P (mechanisms/tricept.py); each actuated leg |p + R c_i -
    # A_i|^2 = l_i^2 with A_i = r_b e_i, c_i = r_p e_i; (cos, sin) of a and b on circles. A
    # Groebner basis over the rationals (directions e_i near 0, 120, 240 degrees with rational
    # cosines: the count is the family's, as for the exact 120 degrees) gives the number of
    # solutions as the number of monomials outside its leading-term ideal
    ca, sa, cb, sb, s = sp.symbols("ca sa cb sb s")
    turn = sp.Matrix([[1, 0, 0], [0, ca, -sa], [0, sa, ca]]) * sp.Matrix([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    directions = [
        sp.Matrix(v)
        for v in ([1, 0, 0], [sp.Rational(-7, 25), sp.Rational(24, 25), 0], [sp.Rational(-3, 5), sp.Rational(-4, 5), 0])
    ]
    r_b, r_p = sp.Rational(3, 10), sp.Rational(1, 10)
    squares = [sp.Rational(29, 100), sp.Rational(31, 100), sp.Rational(27, 100)]
    position = s * turn[:, 2]
    legs = [position + turn * (r_p * e) - r_b * e for e in directions]
    equations = [ca**2 + sa**2 - 1, cb**2 + sb**2 - 1] + [
        sp.expand(leg.dot(leg) - q) for leg, q in zip(legs, squares, strict=True)
    ]
    unknowns = (s, ca, sa, cb, sb)
    basis = sp.groebner(equations, *unknowns, order="grevlex")
    leading = [sp.Poly(g, *unknowns).monoms(order="grevlex")[0] for g in basis.exprs]
    standard = 0
    for degree in itertools.count():
        new = sum(
            1
            for powers in itertools.product(range(degree + 1), repeat=5)
            if sum(powers) == degree
            and not any(all(p >= q for p, q in zip(powers, lead, strict=True)) for lead in leading)
        )
        standard += new
        if new == 0:
            break
    assert standard == KINDS["tricept"][1] == KINDS["tricept_joints"][1] // 2 == 24


@pytest.mark.slow
def test_the_tricept_only_as_joints_has_the_shipped_tricepts_modes(packages) -> None:
    # the same robot from two files: the user's (a spatial platform, the passive leg's constraints
    # derived) and the shipped one (the platform in the passive leg's coordinates, read by hand)
    joints_only = parakin.load(packages("tricept_joints"), backend="compiled")
    shipped = parakin.load(packages("tricept"), backend="compiled")
    inputs = near_home(shipped, 20, 0.05, 2)
    ours, theirs = joints_only.forward_pose_all(inputs), shipped.forward_pose_all(inputs)
    assert ours.certificate()["complete"].all() and theirs.certificate()["complete"].all()
    assert (ours.count == theirs.count).all() and ours.count.min() >= 2
    for k in range(len(inputs)):
        mine, other = ours.poses[k][ours.valid[k]], theirs.poses[k][theirs.valid[k]]
        distance = np.abs(mine[:, None] - other[None]).max(axis=(2, 3))
        assert distance.min(axis=1).max() < 1e-9 and distance.min(axis=0).max() < 1e-9
    for pose, failing in (
        ([0, 0, 0.5, 0.1, 0, 0], "leg4_u_joint_reachable"),
        ([0.05, 0, 0.5, 0, 0, 0], "leg4_line_reachable"),
    ):
        # turned about the passive leg, or off its line: out of reach, the failing condition named
        ik = joints_only.inverse_pose(parakin.pose_from_xyz_euler(pose), strict=False)
        assert not ik.valid.any() and ik.failures[failing].all()


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(KINDS))
def test_the_command_line_answers_and_the_exported_c_runs(packages, name: str, tmp_path: Path) -> None:
    folder = packages(name)
    m = parakin.load(folder, backend="numpy")
    home = [f"{v.home:.12f}" for v in m.manifest.actuated]
    lines = cli("fk", str(folder), "--actuated", *home, "--json").stdout.splitlines()
    modes = m.forward_pose_all([float(v) for v in home])
    assert [json.loads(line)["mode"] for line in lines] == list(range(int(modes.count)))
    png = tmp_path / "modes.png"
    cli("plot", str(folder), "--actuated", *home, "--output", str(png))
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    cli("export", str(folder), "--out", str(tmp_path / "c"))
    compiler = shutil.which("cc")
    if compiler is None:
        pytest.skip("no C compiler")
    prefix = next((tmp_path / "c").glob("*_example_main.c")).name.removesuffix("_example_main.c")
    sources = [f"{prefix}_example_main.c", f"{prefix}_driver.c", f"{prefix}_kernels.c"]
    build = [compiler, "-std=c99", "-O2", "-I.", *sources, "-lm", "-o", "example"]
    subprocess.run(build, cwd=tmp_path / "c", check=True, capture_output=True, timeout=600)
    run = subprocess.run(["./example"], cwd=tmp_path / "c", capture_output=True, text=True, timeout=600)
    assert run.returncode == 0 and "assembly mode" in run.stdout, run.stdout + run.stderr
