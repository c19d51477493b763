"""The generic builders of ``generator/blocks.py`` that mechanism files use instead of hand
boilerplate (issue 32, item 4), each against an independent fact: layouts by their radius and
angles, exact directions by their norm and spacing, declarations by what they declare, example
poses by their structure, and ``home_from_pose`` by closing the loop at the pose."""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import (
    circle_points,
    crank_bases,
    distance_cosines,
    distance_points,
    euler_platform,
    euler_pose,
    euler_pose_values,
    frame_pose_values,
    home_from_pose,
    leg_parameters,
    pair_sides,
    paired_circle_points,
    parameter_fields,
    planar_pose_values,
    point_group,
    pose_values,
    radial_directions,
    scalar_parameter,
    universal_prismatic_platform,
)
from parakin.generator.model import POSE_POSITION, POSE_ROTATION


def test_circle_points_lie_on_the_circle_at_their_angles():
    points = circle_points(0.5, angles_deg=[210.0, 330.0, 90.0])
    for (x, y, z), angle in zip(points, [210.0, 330.0, 90.0], strict=True):
        assert math.hypot(x, y) == pytest.approx(0.5, abs=1e-15) and z == 0.0
        assert math.degrees(math.atan2(y, x)) % 360 == pytest.approx(angle, abs=1e-12)
    assert [len(p) for p in circle_points(0.5, angles_deg=[0.0], dims=2)] == [2]
    with pytest.raises(ValueError, match="dims"):
        circle_points(1.0, angles_deg=[0.0], dims=1)


def test_paired_points_straddle_their_centres():
    """Six points on a 0.4 m circle, pairs at 0, 120, 240 deg +- 10 deg: each at the radius, the
    first of a pair 10 deg clockwise of its centre, the second 10 deg counter-clockwise, so that
    consecutive pairs are 100 deg apart (the hexapod's alternating 20 / 100 deg gaps)."""
    points = paired_circle_points(0.4, centres_deg=[0.0, 120.0, 240.0], offset_deg=10.0)
    angles = [math.degrees(math.atan2(y, x)) % 360 for x, y, _ in points]
    assert np.allclose([math.hypot(x, y) for x, y, _ in points], 0.4, atol=1e-15)
    assert np.allclose(angles, [350.0, 10.0, 110.0, 130.0, 230.0, 250.0], atol=1e-12)
    assert [side for _, side in pair_sides(centres_deg=[0.0, 120.0])] == [-1, 1, -1, 1]


def test_layout_angles_are_degrees_by_name_never_by_position():
    """The layout builders take degrees (as a paper prints a layout) and the API's unit is the
    radian: the degree arguments are keyword-only and named ``..._deg``, so radians passed by
    position (what a new user wrote: joints 2 deg apart, a near-singular home) are refused, and
    the same layout in radians converted by ``math.degrees`` gives the points 120 deg apart."""
    radians = [0.0, 2 * math.pi / 3, 4 * math.pi / 3]
    with pytest.raises(TypeError):
        circle_points(1.0, radians)  # type: ignore[misc]
    with pytest.raises(TypeError):
        paired_circle_points(1.0, radians, 0.1)  # type: ignore[misc]
    with pytest.raises(TypeError):
        pair_sides(radians)  # type: ignore[misc]
    points = np.array(circle_points(1.0, angles_deg=[math.degrees(t) for t in radians]))
    gaps = [np.linalg.norm(points[k] - points[(k + 1) % 3]) for k in range(3)]
    assert gaps == pytest.approx([math.sqrt(3)] * 3, abs=1e-15)  # the side of an inscribed equilateral triangle


def test_radial_directions_are_exact_unit_vectors_evenly_spaced():
    directions = radial_directions(3)
    assert directions[0].T.tolist() == [[1, 0, 0]]
    assert directions[2].T.tolist() == [[-sp.Rational(1, 2), -sp.sqrt(3) / 2, 0]]
    for k, e in enumerate(directions):
        assert sp.simplify(e.dot(e)) == 1
        assert sp.simplify(e.dot(directions[(k + 1) % 3]) - sp.cos(2 * sp.pi / 3)) == 0
    turned = radial_directions(3, start=sp.pi / 2)  # 90, 210, 330 deg
    assert turned[0].T.tolist() == [[0, 1, 0]] and turned[2].T.tolist() == [[sp.sqrt(3) / 2, -sp.Rational(1, 2), 0]]
    with pytest.raises(ValueError, match="count"):
        radial_directions(0)


def test_declarations_give_defaults_meaning_and_groups_in_order():
    lengths = sp.symbols("a1:4", positive=True)
    base = point_group("base", [(0.0, 1.0), (2.0, 3.0), (4.0, 5.0)], "base joint A{k}, in {B}")
    fields = parameter_fields(base, leg_parameters(lengths, 0.3, "crank {k} length"))
    names = [str(s) for s in fields["parameters"]]
    assert names == ["base_x1", "base_y1", "base_x2", "base_y2", "base_x3", "base_y3", "a1", "a2", "a3"]
    assert list(fields["parameters"].values()) == [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 0.3, 0.3, 0.3]
    info = fields["parameter_info"]
    assert info[base.symbols[2, 1]].description == "y of base joint A3, in {B}"
    assert (info[lengths[1]].unit, info[lengths[1]].domain) == ("m", "positive")
    assert fields["parameter_groups"] == {"base": base.symbols}
    assert base.points[1].T.tolist() == [[base.symbols[1, 0], base.symbols[1, 1], 0]]
    with pytest.raises(ValueError, match="twice"):
        parameter_fields(base, base)
    r = sp.Symbol("r", positive=True)
    scalar = parameter_fields(scalar_parameter(r, 0.05, "platform radius", domain="positive"), base)
    assert list(scalar["parameters"].items())[0] == (r, 0.05) and scalar["parameter_info"][r].domain == "positive"
    with pytest.raises(ValueError, match="equal length"):
        point_group("bad", [(0.0, 1.0), (2.0,)], "p{k}")


def test_a_description_of_several_items_must_number_them():
    """Without ``{k}`` every point (or every leg's parameter) would be described by the same text:
    refused, naming the count and the remedy; a single point needs no number."""
    with pytest.raises(ValueError, match=r"has no \{k\}, so all 3 would read the same"):
        point_group("base", [(0.0, 1.0), (2.0, 3.0), (4.0, 5.0)], "base joint, in {B}")
    with pytest.raises(ValueError, match=r"no \{k\}, so all 2 would read the same"):
        leg_parameters(sp.symbols("a1:3", positive=True), 0.3, "crank length")
    single = point_group("tool", [(0.0, 0.0, 0.1)], "tool centre point, in {P}")
    assert single.info[single.symbols[0, 2]].description == "z of tool centre point, in {P}"


def test_pose_values_is_the_homogeneous_transform():
    rotation = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    pose = np.array(pose_values(rotation, [0.1, 0.2, 0.3]))
    point = np.array([1.0, 0.0, 0.0, 1.0])
    assert np.allclose(pose @ point, [0.1, 1.2, 0.3, 1.0], atol=0)  # Rot_z(90 deg) x + p
    planar = np.array(planar_pose_values(0.1, 0.2, math.pi / 2))
    assert np.allclose(planar, pose_values(rotation, [0.1, 0.2, 0.0]), rtol=0, atol=1e-16)
    assert all(isinstance(v, float) for row in pose_values(sp.eye(3), [0, 0, 1]) for v in row)


def test_home_from_pose_closes_the_loop_at_the_pose():
    """A planar 3-RPR (prismatic legs between two triangles): the home read at a tilted pose has
    leg lengths equal to the distances |p + R c_i - A_i| computed here with NumPy, and passive
    values equal to the pose's (x, y, phi)."""
    base = point_group("base", circle_points(0.5, angles_deg=[210.0, 330.0, 90.0], dims=2), "A{k}")
    platform = point_group("platform", circle_points(0.2, angles_deg=[200.0, 320.0, 80.0], dims=2), "c{k}")
    lengths = sp.symbols("l1:4", positive=True)
    model = joints.DistanceMechanism(
        joints.platform("planar"),
        [joints.prismatic_leg(a, c, n) for a, c, n in zip(base.points, platform.points, lengths, strict=True)],
    )
    defaults = parameter_fields(base, platform)["parameters"]
    x, y, phi = 0.05, -0.02, 0.3
    home = home_from_pose(model, planar_pose_values(x, y, phi), 0, defaults)
    rotation = np.array([[math.cos(phi), -math.sin(phi)], [math.sin(phi), math.cos(phi)]])
    for k in range(3):
        a = np.array(circle_points(0.5, angles_deg=[210.0, 330.0, 90.0], dims=2)[k])
        c = np.array(circle_points(0.2, angles_deg=[200.0, 320.0, 80.0], dims=2)[k])
        assert home[lengths[k]] == pytest.approx(np.linalg.norm([x, y] + rotation @ c - a), abs=1e-14)
    assert [home[s] for s in model.motion.coordinates] == pytest.approx([x, y, phi], abs=1e-14)


def test_home_from_pose_refuses_a_branch_the_inverse_does_not_have():
    """The inverse's branch numbers only its sign choices: a planar 3-RPR (leg lengths are
    distances) has one inverse branch, three R-R-R legs two elbows each, 2^3 = 8 branches. Branch
    1 of the 3-RPR and branches 8 and -1 of the 3-RRR were read as branches 0 and 7 (low bits
    only); they are refused with the count, and branch 7 of the 3-RRR (every elbow flipped) is a
    different home from branch 0 with the same pose."""
    base = point_group("base", circle_points(0.5, angles_deg=[210.0, 330.0, 90.0], dims=2), "A{k}")
    platform = point_group("platform", circle_points(0.2, angles_deg=[210.0, 330.0, 90.0], dims=2), "c{k}")
    lengths = sp.symbols("l1:4", positive=True)
    rpr = joints.DistanceMechanism(
        joints.platform("planar"),
        [joints.prismatic_leg(a, c, n) for a, c, n in zip(base.points, platform.points, lengths, strict=True)],
    )
    defaults = parameter_fields(base, platform)["parameters"]
    pose = planar_pose_values(0.0, 0.0, 0.0)
    from parakin.errors import BadInputError

    with pytest.raises(BadInputError, match=r"branch 1 is not one of this inverse's 1 branch \(0 \.\. 0\)"):
        home_from_pose(rpr, pose, 1, defaults)
    with pytest.raises(BadInputError, match="1 branch"):
        rpr.home_at(sp.eye(3), sp.Matrix([0, 0, 0]), 1, defaults)
    from parakin.mechanisms import planar_3rrr

    rrr_defaults = planar_3rrr.defaults()
    for bad in (8, -1):
        with pytest.raises(BadInputError, match=rf"branch {bad} is not one of this inverse's 8 branches \(0 \.\. 7\)"):
            home_from_pose(planar_3rrr.MODEL, pose, bad, rrr_defaults)
    first, last = (home_from_pose(planar_3rrr.MODEL, pose, b, rrr_defaults) for b in (0, 7))
    cranks = planar_3rrr.MODEL.actuated
    assert all(abs(first[t] - last[t]) > 0.1 for t in cranks)


@pytest.mark.parametrize(
    "sequence", ["xyz", "xzy", "yxz", "yzx", "zxy", "zyx", "xyx", "xzx", "yxy", "yzy", "zxz", "zyz"]
)
def test_euler_platform_reads_back_the_angles_of_its_rotation(sequence):
    """Every Euler sequence: the rotation built from seeded angles (beta within the reading's
    range: (-pi/2, pi/2) Tait-Bryan, (0, pi) or (-pi, 0) proper) is a rotation, and the reading
    evaluated at it, with the branch sign sign(sin beta) for a proper set, returns the angles and
    position; the proper set's validity is sin^2 beta."""
    from parakin.generator.model import POSE_POSITION, POSE_ROTATION

    angles, position = sp.symbols("alpha beta gamma", real=True), sp.symbols("x y z", real=True)
    platform = euler_platform(sequence, angles, position)
    assert platform.kind == "transform" and platform.coordinates == (*position, *angles)
    rng = np.random.default_rng(32)
    checked = 0
    for _ in range(3):
        tait_bryan = sequence[0] != sequence[2]
        beta = rng.uniform(-1.5, 1.5) if tait_bryan else rng.choice([-1, 1]) * rng.uniform(0.05, 3.1)
        values = dict(zip(angles, [rng.uniform(-3.1, 3.1), beta, rng.uniform(-3.1, 3.1)], strict=True))
        values |= dict(zip(position, rng.uniform(-1, 1, 3), strict=True))
        rotation = np.array(sp.lambdify(angles, platform.rotation)(*(values[a] for a in angles)), dtype=float)
        assert np.allclose(rotation @ rotation.T, np.eye(3), atol=1e-14) and np.linalg.det(rotation) > 0
        known = {POSE_ROTATION[i, j]: rotation[i, j] for i in range(3) for j in range(3)}
        known |= {POSE_POSITION[i]: values[position[i]] for i in range(3)}
        known |= {sign: float(np.sign(np.sin(beta))) for sign in platform.branches}
        for symbol, expression in platform.read:
            known[symbol] = float(expression.subs(known))
        assert [known[s] for s in (*position, *angles)] == pytest.approx(
            [values[s] for s in (*position, *angles)], abs=1e-12
        )
        for _, condition in platform.validity:
            assert float(condition.subs(known)) == pytest.approx(np.sin(beta) ** 2, abs=1e-12)
        checked += 1
    assert checked == 3
    assert euler_platform(sequence, angles).kind == "rotation"


def test_euler_platform_refuses_what_is_no_euler_sequence():
    angles = sp.symbols("alpha beta gamma", real=True)
    for sequence in ("xxy", "xyy", "xy", "xyw"):
        with pytest.raises(ValueError, match="not an Euler sequence"):
            euler_platform(sequence, angles)


@pytest.mark.parametrize("sequence", ["zyx", "xyx", "zyz", "xzy"])
def test_euler_pose_agrees_with_scipys_intrinsic_euler_angles(sequence):
    """``euler_pose`` (and ``euler_pose_values``) against SciPy's intrinsic Euler rotation
    (upper-case sequence): R_i(alpha) R_j(beta) R_k(gamma), the position in the last column."""
    from scipy.spatial.transform import Rotation

    angles, position = (0.4, -0.7, 1.9), (0.1, -0.2, 0.3)
    expected = Rotation.from_euler(sequence.upper(), angles).as_matrix()
    pose = np.array(euler_pose(sequence, angles, position), dtype=float)
    assert np.allclose(pose[:3, :3], expected, rtol=0, atol=1e-15)
    assert pose[:3, 3].tolist() == list(position) and pose[3].tolist() == [0.0, 0.0, 0.0, 1.0]
    assert np.array(euler_pose_values(sequence, angles, position)).tolist() == pose.tolist()


def test_crank_bases_put_the_crank_tips_on_the_given_points():
    """Shafts from ``crank_bases`` with seeded unit axes u_i and directions e1_i normal to them:
    the tip A_i + a (cos t e1_i + sin t u_i x e1_i), computed here with NumPy's cross product,
    is the given point, and the shaft lies the crank length from it."""
    rng = np.random.default_rng(32)
    axes = [v / np.linalg.norm(v) for v in rng.normal(size=(4, 3))]
    zeros = [np.cross(u, rng.normal(size=3)) for u in axes]
    zeros = [e / np.linalg.norm(e) for e in zeros]
    tips = rng.uniform(-1, 1, (4, 3))
    shafts = crank_bases(tips.tolist(), [u.tolist() for u in axes], [e.tolist() for e in zeros], 0.15, 0.4)
    for shaft, tip, u, e1 in zip(shafts, tips, axes, zeros, strict=True):
        reached = np.array(shaft) + 0.15 * (math.cos(0.4) * e1 + math.sin(0.4) * np.cross(u, e1))
        assert np.allclose(reached, tip, rtol=0, atol=1e-15)
        assert np.linalg.norm(np.array(shaft) - tip) == pytest.approx(0.15, abs=1e-15)


def test_frame_pose_values_is_the_orthonormal_frame_through_the_points():
    pose = np.array(frame_pose_values([2.278, 0.290, -0.698], [2.000, 1.250, -0.454], (0.1, 0.0, 0.0)))
    rotation = pose[:3, :3]
    assert np.allclose(rotation.T @ rotation, np.eye(3), atol=1e-15) and np.linalg.det(rotation) == pytest.approx(1)
    x_toward, y_toward = np.array([2.278, 0.290, -0.698]), np.array([2.000, 1.250, -0.454])
    assert np.allclose(rotation[:, 0], x_toward / np.linalg.norm(x_toward), atol=1e-15)
    assert rotation[:, 1] @ y_toward > 0 and abs(rotation[:, 2] @ y_toward) < 1e-15  # y toward, z across
    assert pose[:3, 3].tolist() == [0.1, 0.0, 0.0]


def test_leg_parameters_take_one_default_per_leg():
    k = sp.symbols("k1:4", real=True)
    group = leg_parameters(k, (1.0, 2.0, 3.0), "stiffness {k}", "N/m", "nonzero")
    assert list(group.defaults.values()) == [1.0, 2.0, 3.0] and group.info[k[2]].unit == "N/m"
    with pytest.raises(ValueError, match="3 parameters but 2 defaults"):
        leg_parameters(k, (1.0, 2.0), "stiffness {k}")


def test_every_inverse_refuses_a_branch_it_does_not_have():
    """InverseSolution.at, under every home (a chain mechanism's home_at too): x = sigma sqrt(p)
    has branches 0 (sigma = +1) and 1 (sigma = -1) only; 2 and -1 were read as 0 and 1."""
    from parakin.generator.model import InverseSolution

    from parakin.errors import BadInputError

    sigma, p, x = sp.symbols("sigma p x")
    inverse = InverseSolution(steps=[(x, sigma * sp.sqrt(p))], branches=[sigma])
    assert inverse.at(sp.eye(3), None, 0, {p: 4.0})[x] == 2.0
    assert inverse.at(sp.eye(3), None, 1, {p: 4.0})[x] == -2.0
    for branch in (2, -1, True, 0.0):
        with pytest.raises(BadInputError, match=r"inverse: branch .* 2 branches \(0 \.\. 1\)"):
            inverse.at(sp.eye(3), None, branch, {p: 4.0})


def test_distance_points_are_congruent_to_the_points_they_are_measured_from():
    """Three random points measured (their distances to the origin and to one another, the sign of
    their determinant), then built from those numbers: the points built have the same distances and
    handedness (congruent: a rotation of the measured ones), B_1 on x, B_2 in the x y plane on its
    +y side; the cosines' determinant is det[B_1 B_2 B_3]^2 / (r_1 r_2 r_3)^2, a volume."""
    rng = np.random.default_rng(32)
    checked = 0
    for _ in range(20):
        points = rng.normal(size=(3, 3))
        radii = [sp.Float(v, 17) for v in np.linalg.norm(points, axis=1)]
        pairs = [(0, 1), (1, 2), (0, 2)]
        distances = [sp.Float(np.linalg.norm(points[i] - points[j]), 17) for i, j in pairs]
        sign = int(np.sign(np.linalg.det(points)))
        built = np.array([[float(v) for v in p] for p in distance_points(radii, distances, sign)])
        assert np.allclose(np.linalg.norm(built, axis=1), np.linalg.norm(points, axis=1), atol=1e-12)
        for i, j in pairs:
            assert np.linalg.norm(built[i] - built[j]) == pytest.approx(
                np.linalg.norm(points[i] - points[j]), abs=1e-12
            )
        assert np.linalg.det(built) == pytest.approx(np.linalg.det(points), abs=1e-12)
        assert built[0, 1] == built[0, 2] == built[1, 2] == 0.0 and built[1, 1] > 0
        gram = float(distance_cosines(radii, distances)[3])
        assert gram == pytest.approx(np.linalg.det(points) ** 2 / np.prod(np.linalg.norm(points, axis=1)) ** 2)
        checked += 1
    assert checked == 20


def test_universal_prismatic_platform_reads_back_its_leg():
    """The platform of a passive U-P leg: at random joint values its rotation is Rot_x(a) Rot_y(b)
    (written out with NumPy), its origin lies on the leg's axis z_P at the distance s from the
    universal joint, and the inverse's reading of that pose returns a, b and s."""
    a, b, s = sp.symbols("a b s", real=True)
    platform = universal_prismatic_platform((a, b), s)
    assert platform.kind == "transform" and platform.coordinates == (a, b, s) and platform.angular == (a, b)
    rng = np.random.default_rng(7)
    for _ in range(10):
        values = {a: rng.uniform(-1.5, 1.5), b: rng.uniform(-3.1, 3.1), s: rng.uniform(0.1, 2.0)}
        ca, sa, cb, sb = np.cos(values[a]), np.sin(values[a]), np.cos(values[b]), np.sin(values[b])
        expected = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]]) @ np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
        rotation = np.array(platform.rotation.subs(values), dtype=float)
        position = np.array(platform.position.subs(values), dtype=float).ravel()
        assert np.allclose(rotation, expected, atol=1e-14)
        assert np.allclose(position, values[s] * rotation[:, 2], atol=1e-14)
        pose = dict(zip(POSE_ROTATION, rotation.ravel(), strict=True)) | dict(zip(POSE_POSITION, position, strict=True))
        read = {symbol: float(expression.subs(pose)) for symbol, expression in platform.read}
        assert read == pytest.approx(values, abs=1e-12)
