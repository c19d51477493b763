"""The bookkeeping of forward_pose_all after the C (issue 33: its Python share), against rules
written out here from their docstrings: repeats of a pose marked in slot order
(``modes._same_pose``: a slot marked a repeat is no longer an earlier mode), clusters of
overlapping certified boxes (``certify.cluster_labels``: connected components, labelled by their
first member) and the clusters a certificate carries (``Certificate.labels``), and the one batch
rule of ``validation.broadcast_batch``. Each reference is the plain loop; the code under test is
vectorised."""

import numpy as np
import pytest

import parakin
from parakin.errors import BadInputError
from parakin.solvers import modes as modes_module
from parakin.solvers.certify import UNIT, certify_roots, cluster_labels
from parakin.validation import broadcast_batch

MODE, DUPLICATE, OTHER = 0, 7, 3


def _turn(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _pose(angle: float, position) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3], pose[:3, 3] = _turn(angle), position
    return pose


def _same_pose_reference(outcome: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """The rule, input by input and slot by slot: a mode whose rotation is within SAME_POSE of an
    earlier mode's (entry by entry) and its position within SAME_POSE times the input's largest
    mode position (NaN if one is undefined) is a duplicate; once marked, it is no longer an earlier mode."""
    outcome = outcome.copy()
    tolerance = modes_module.SAME_POSE
    for i in range(outcome.shape[0]):
        valid = outcome[i] == MODE
        position = np.max(np.abs(poses[i, valid, :3, 3]), initial=0.0)
        for s in range(outcome.shape[1]):
            if outcome[i, s] != MODE:
                continue
            for t in range(s):
                if outcome[i, t] != MODE:
                    continue
                rotation = np.abs(poses[i, s, :3, :3] - poses[i, t, :3, :3]).max()
                moved = np.abs(poses[i, s, :3, 3] - poses[i, t, :3, 3]).max()
                if rotation <= tolerance and moved <= tolerance * position:
                    outcome[i, s] = DUPLICATE
                    break
    return outcome


@pytest.fixture(params=["one by one", "slot by slot"])
def walk(request, monkeypatch):
    """Both walks of ``_same_pose``: its pairs one by one (few), or slot by slot in NumPy (many)."""
    if request.param == "slot by slot":
        monkeypatch.setattr(modes_module, "SAME_POSE_PAIRS", 0)
    return request.param


def test_a_chain_of_near_poses_marks_only_repeats_of_a_mode_still_standing(walk):
    # B is within 0.8e-9 of A, C within 0.8e-9 of B but 1.6e-9 from A: B repeats A; C would repeat
    # B, but B is no longer a mode, so C stays one
    step = 0.8 * modes_module.SAME_POSE
    poses = np.stack([_pose(0.3 + k * step, [0.5, 0.2, 1.0]) for k in range(3)])[None]
    outcome = np.full((1, 3), MODE, dtype=np.int32)
    modes_module._same_pose(outcome, poses, MODE, DUPLICATE)
    assert outcome.tolist() == [[MODE, DUPLICATE, MODE]]


def test_repeats_of_poses_agree_with_the_slot_by_slot_rule_on_many_inputs(walk):
    rng = np.random.default_rng(11)
    inputs, slots = 3 * modes_module.SAME_POSE_ROWS + 5, 12  # several chunks of rows
    poses = np.stack([[_pose(rng.uniform(-3, 3), rng.uniform(-1, 1, 3)) for _ in range(slots)] for _ in range(inputs)])
    outcome = rng.choice([MODE, MODE, MODE, OTHER], size=(inputs, slots)).astype(np.int32)
    planted = 0
    for i in range(inputs):  # repeats: exact copies, copies within the tolerance, and just outside it
        for _ in range(rng.integers(0, 4)):
            s, t = sorted(rng.choice(slots, 2, replace=False))
            shift = rng.choice([0.0, 0.5, 0.9, 3.0]) * modes_module.SAME_POSE
            poses[i, t] = poses[i, s]
            poses[i, t, 0, 0] += shift
            planted += 1
    poses[1, 2], outcome[1, 2] = np.nan, MODE  # an undefined pose: no position scale, no repeat
    expected = _same_pose_reference(outcome, poses)
    got = outcome.copy()
    modes_module._same_pose(got, poses, MODE, DUPLICATE)
    assert planted >= 60
    assert (expected == DUPLICATE).sum() >= 20  # the rule had repeats to find
    np.testing.assert_array_equal(got, expected)


def _components(x: np.ndarray, r: np.ndarray, unique: np.ndarray) -> list[int]:
    """Connected components of the overlap graph of the boxes (centres x (P, n), radii r (P, n)),
    by depth-first search, each labelled by its smallest member; -1 where not unique."""
    count = unique.size
    margin_gap, margin_sum = 1 - 8 * UNIT, 1 + 8 * UNIT

    def touch(p: int, q: int) -> bool:
        return bool(unique[p] and unique[q] and (abs(x[p] - x[q]) * margin_gap <= (r[p] + r[q]) * margin_sum).all())

    labels = [-1] * count
    for p in range(count):
        if not unique[p] or labels[p] >= 0:
            continue
        stack, labels[p] = [p], p
        while stack:
            a = stack.pop()
            for b in range(count):
                if labels[b] < 0 and touch(a, b):
                    labels[b] = p
                    stack.append(b)
    return labels


def test_cluster_labels_are_the_connected_components_of_overlapping_boxes():
    rng = np.random.default_rng(5)
    checked = touching = 0
    for trial in range(60):
        count = int(rng.integers(2, 12))
        x = rng.uniform(-1, 1, (count, 2)) + 1j * rng.uniform(-1, 1, (count, 2))
        if trial % 3:  # chains: each box next to the previous, overlapping or not
            x[1:] = x[:1] + np.cumsum(rng.uniform(0.05, 0.15, (count - 1, 2)), axis=0)
        r = rng.uniform(0.01, 0.1, (count, 2))
        unique = rng.random(count) < 0.85
        labels, distinct = cluster_labels(x, np.where(unique[:, None], r, 0.0), unique)
        expected = _components(x, np.where(unique[:, None], r, 0.0), unique)
        assert labels.tolist() == expected
        alone = [label == p for p, label in enumerate(expected) if unique[p]]
        assert bool(distinct) == all(alone)
        checked += 1
        touching += not all(alone)
    assert checked == 60 and touching >= 15  # both branches: boxes apart, and clusters to close


def test_a_certificate_carries_its_clusters():
    # (z - 2)(z + 3) = z^2 + z - 6: candidates twice at 2 (one cluster), once at -3
    exponents, equation, coefficients = np.array([[2], [1], [0]]), np.array([0, 0, 0]), np.array([1, 1, -6.0])
    found = certify_roots(coefficients, exponents, equation, np.array([[2.0], [-3.0], [2.0 + 1e-12]]))
    assert found.unique.all()
    assert found.labels is not None and found.labels.tolist() == [0, 1, 0]
    assert int(found.certified_distinct) == 2 and not bool(found.distinct)


@pytest.mark.parametrize(
    ("shapes", "batch"),
    [([(3, 2), (4,)], (3,)), ([(2, 5, 2), (5, 4)], (2, 5)), ([(1, 2), (4, 3)], (4,)), ([(2,), (3,)], ())],
)
def test_broadcast_batch_is_numpy_broadcasting_of_the_batch_axes(shapes, batch):
    inputs = [np.arange(np.prod(shape), dtype=float).reshape(shape) for shape in shapes]
    shape, flat = broadcast_batch(tuple(inputs))
    assert shape == batch == np.broadcast_shapes(*(s[:-1] for s in shapes))
    count = int(np.prod(batch))
    for x, f in zip(inputs, flat, strict=True):
        expected = np.broadcast_to(x, batch + x.shape[-1:]).reshape(count, -1) if x.ndim > 1 else x[None]
        np.testing.assert_array_equal(f, expected)
        assert f.flags.c_contiguous


def test_broadcast_batch_names_shapes_that_do_not_broadcast():
    with pytest.raises(BadInputError, match=r"\(3,\), \(4,\)"):
        broadcast_batch((np.zeros((3, 2)), np.zeros((4, 2))))


@pytest.mark.parametrize("name", ["prs3", "rps3"])
def test_a_modes_quaternion_is_the_same_on_every_backend_and_is_the_homes(name):
    """q and -q are one rotation: the modes' passive values carry the inverse's sign (first
    component beyond rounding positive), so both backends give the same values (prs3's half-turn
    modes differed by sign between them) and forward_pose from the home's inputs returns the home's
    passive values (a user's 3-RPS returned -q). The quaternion is checked against the mode's own
    rotation matrix by the textbook formula."""
    from parakin.solvers.modes import QUATERNION_ZERO

    compiled, numpy = (parakin.load(name, backend=b) for b in ("compiled", "numpy"))
    rng = np.random.default_rng(5)
    inputs = compiled.home_actuated * (1 + 0.02 * rng.uniform(-1, 1, (12, compiled.home_actuated.size)))
    inputs = np.vstack([compiled.home_actuated, inputs])
    a, b = (m.forward_pose_all(inputs) for m in (compiled, numpy))
    assert np.array_equal(a.valid, b.valid) and a.valid.sum() >= 60
    k = [v.name for v in compiled.manifest.passive].index("q0")
    q = a.passive[a.valid][:, k : k + 4]
    np.testing.assert_allclose(q, b.passive[a.valid][:, k : k + 4], rtol=0, atol=1e-9)
    first = np.take_along_axis(q, np.argmax(np.abs(q) > QUATERNION_ZERO, -1)[:, None], -1)[:, 0]
    assert (first > 0).all()
    w, x, y, z = q.T  # R(q), Shuster's convention for a unit q = (w, x, y, z)
    rotation = np.stack(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    ).transpose(2, 0, 1)
    np.testing.assert_allclose(rotation, a.poses[a.valid][:, :3, :3], rtol=0, atol=1e-9)
    for m in (compiled, numpy):
        np.testing.assert_allclose(m.forward_pose(m.home_actuated).passive, m.home_passive, rtol=0, atol=1e-9)
