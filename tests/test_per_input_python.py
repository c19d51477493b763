"""The Python around the C of one ``forward_pose_all`` call (issue 33), cut to fewer array
operations: each shortened step is checked against the longer formula it replaces, bit for bit,
including the signs of zeros, NaN and infinities."""

from __future__ import annotations

import numpy as np
import pytest

import parakin
from parakin.solvers import modes as modes_module
from parakin.studies.sampling import sample_configurations


def _complex_formula(m, info, free, angles):
    """The target coefficients as complex values: (cos, sin, 1) per angle after the free values,
    every value + 0j, through the monomials kernel (the formula the in-place version replaces)."""
    circle = np.stack([np.cos(angles), np.sin(angles), np.ones_like(angles)], axis=-1)
    values = np.concatenate([free + 0j, circle.reshape(angles.shape[:-1] + (-1,)) + 0j], axis=-1)
    return modes_module._monomials(m, info)(values)


def _bits(x: np.ndarray) -> np.ndarray:
    """The bit patterns of a float or complex array (so that -0.0 differs from 0.0, and NaNs compare)."""
    return np.ascontiguousarray(x).view(np.uint64)


@pytest.mark.parametrize("name", ["planar_3rrr", "prs3"])
def test_target_coefficients_written_in_place_are_the_complex_formulas_bits(name):
    m = parakin.load(name, backend="numpy")
    info = m.capabilities.forward
    theta = sample_configurations(m, 12, spread=0.5, seed=3).actuated
    free, angles = modes_module._family(m, info, theta)
    free, angles = free.copy(), angles.copy()
    # the awkward values: signed zeros (x + 0j turns -0.0 into 0.0), NaN and infinities
    free[0, 0], free[1, 1], free[2, -1] = -0.0, np.nan, np.inf
    if angles.shape[1]:  # prs3's family has no circle
        angles[0, 0], angles[1, 0], angles[2, -1], angles[3, 0] = -0.0, np.nan, np.inf, -np.pi
    assert theta.shape[0] >= 6
    checked = 0
    with np.errstate(all="ignore"):
        expected = _complex_formula(m, info, free, angles)
        for rows in (slice(None), slice(0, 1), slice(4, 5)):  # a batch, the awkward row, a plain one
            got = modes_module._target_coefficients(m, info, free[rows], angles[rows])
            assert got.dtype == expected.dtype and got.shape == expected[rows].shape
            assert np.array_equal(_bits(got), _bits(expected[rows]))
            checked += got.size
    assert checked == (theta.shape[0] + 2) * expected.shape[1]
    assert np.isnan(expected[1]).any() and np.isfinite(expected[4]).all()  # the cases are there


def test_paired_certificate_side_by_side_equals_the_slot_by_slot_assembly(monkeypatch):
    # prs3's 32 paths pair up under q -> -q (16 tracked, 16 images): the certificate of the first
    # paths and their images put side by side in path order must be the arrays the general
    # assembly writes slot by slot (forced here by refusing the pairs' order)
    m = parakin.load("prs3", backend="numpy")
    info = m.capabilities.forward
    homotopy = info.homotopy
    theta = sample_configurations(m, 2, spread=0.05, seed=7).actuated
    out = modes_module.numpy_modes(m, theta, info)
    coefficients = modes_module._target_coefficients(m, info, *modes_module._family(m, info, theta))
    roots = out["endpoints"][..., 0] + 1j * out["endpoints"][..., 1]
    pairs = modes_module.path_pairs(homotopy.exponents, homotopy.equation, homotopy.start)
    paired = modes_module._paired_ends(pairs, roots)
    assert pairs is not None and paired.all() and theta.shape[0] == 2
    assert modes_module._pair_order(pairs, roots.shape[1]) is not None
    fast = modes_module._certify_endpoints(homotopy, coefficients, roots, pairs, paired)
    monkeypatch.setattr(
        modes_module, "_fixed", lambda kind, owner, compute: None if kind == "pair_order" else compute()
    )
    general = modes_module._certify_endpoints(homotopy, coefficients, roots, pairs, paired)
    for field in ("unique", "radius", "real", "distinct", "certified_distinct", "center", "radii", "labels"):
        a, b = getattr(fast, field), getattr(general, field)
        assert a.dtype == b.dtype and a.shape == b.shape and a.strides == b.strides, field
        assert np.array_equal(a, b, equal_nan=a.dtype.kind in "fc"), field
    assert (fast.certified_distinct == 32).all() and fast.unique.all()  # the case is the usual one


def test_pairs_that_miss_a_path_have_no_side_by_side_order():
    pairs = modes_module.PathPairs(np.array([1.0, -1.0]), np.array([1, 0, 2]), np.array([0]), np.array([1]))
    assert modes_module._pair_order(pairs, 3) is None
    assert modes_module._pair_order(pairs, 2).tolist() == [0, 1]
    swapped = modes_module.PathPairs(pairs.flip, np.array([1, 0]), np.array([1]), np.array([0]))
    assert modes_module._pair_order(swapped, 2).tolist() == [1, 0]


@pytest.mark.parametrize("name", ["prs3", "planar_3rrr"])
def test_one_input_gets_the_modes_it_gets_in_a_batch(name):
    # one input takes the single-input shortcuts (its actuated row shared by the re-checked
    # roots, reused buffers, deferred conditioning); the same input in a batch takes none
    m = parakin.load(name, backend="compiled")
    theta = sample_configurations(m, 6, spread=0.05, seed=9).actuated
    batch = m.forward_pose_all(theta, strict=False)
    fields = (
        "poses", "passive", "residual", "root", "real", "valid", "count", "outcome", "root_kind", "conditioning",
        "real_roots", "near_roots", "at_infinity", "status", "certified_roots", "path_certified", "retracked",
        "undecided_roots",
    )  # fmt: skip
    checked = 0
    for i in range(theta.shape[0]):
        one = m.forward_pose_all(theta[i], strict=False)
        for field in fields:
            a, b = np.asarray(getattr(one, field)), np.asarray(getattr(batch, field)[i])
            assert a.dtype == b.dtype and np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), (i, field)
        checked += int(one.count)
    assert checked >= theta.shape[0]
    assert batch.complete().all()


def test_one_inputs_decision_slot_by_slot_is_the_array_decision():
    # reconcile's decision of one input in plain Python (``_decided_one``) against the array
    # version (``_decided``) on random certificates: certified or not, real, non-real or
    # undecided, every outcome code in every slot; overlapping boxes are left to the arrays
    m = parakin.load("prs3", backend="numpy")
    codes = len(m.manifest.abi.mode_outcomes)
    rng = np.random.default_rng(5)
    decided = overlapping = 0
    for _ in range(300):
        paths = int(rng.integers(1, 40))
        unique = rng.random((1, paths)) < 0.8
        real = rng.choice(np.array([-1, 0, 1], dtype=np.int8), size=(1, paths), p=[0.4, 0.1, 0.5])
        labels = np.where(unique, np.arange(paths), -1)
        if rng.random() < 0.2 and unique.sum() >= 2:  # two boxes overlap: the later joins the earlier's cluster
            a, b = np.sort(rng.choice(np.flatnonzero(unique[0]), 2, replace=False))
            labels[0, b] = a
        cert = modes_module.PathCertificate(
            unique.sum(-1), unique, real, np.zeros((1, paths, 2), complex), np.zeros((1, paths, 2)), labels
        )
        outcome = rng.integers(0, codes, size=(1, paths)).astype(np.int32)
        kind = rng.integers(-1, 4, size=(1, paths)).astype(np.int32)
        one_outcome, one_kind = outcome.copy(), kind.copy()
        one = modes_module._decided_one(m, cert, one_outcome, one_kind)
        if one is None:
            assert (labels != np.where(unique, np.arange(paths), -1)).any()
            overlapping += 1
            continue
        expected = modes_module._decided(m, cert, outcome, kind)
        assert np.array_equal(one_outcome, outcome) and np.array_equal(one_kind, kind)
        for got, want in zip(one, expected, strict=True):
            assert got.dtype == want.dtype and np.array_equal(got, want)
        decided += 1
    assert decided >= 200 and overlapping >= 20


@pytest.mark.parametrize("name", ["prs3", "planar_3rrr"])
def test_length_factors_scale_as_the_division_by_the_unit_does(name):
    # the unit-free geometry's inputs x * (1 / unit) and its passive values back p * unit (1.0
    # for what is no length) must be the bits of np.where(length, x / unit, x), signed zeros,
    # subnormals and infinities included
    m = parakin.load(name, backend="numpy")
    scaled, unit = m._unit_free
    assert unit != 1.0 and np.log2(unit) == np.round(np.log2(unit))  # a power of two
    down, up = m._length_factors
    length_actuated, length_passive = m._length_variables
    rng = np.random.default_rng(2)
    specials = np.array([0.0, -0.0, 5e-324, -2.5e-310, 1e308, -np.inf, np.nan, 1.0])
    for variables, factor, mask, forward in (
        (len(m.actuated_names), down, length_actuated, True),
        (len(m.passive_names), up, length_passive, False),
    ):
        x = rng.normal(size=(50, variables)) * 10.0 ** rng.integers(-300, 300, (50, 1))
        x = np.concatenate([x, np.repeat(specials[:, None], variables, axis=1)])
        with np.errstate(all="ignore"):  # 1e308 / 0.25 overflows on both sides alike
            expected = np.where(mask, x / unit, x) if forward else np.where(mask, x * unit, x)
            assert np.array_equal(_bits(x * factor), _bits(expected))
    assert not down.flags.writeable and not up.flags.writeable


def test_real_centres_are_the_phase_normalised_centres_real_parts():
    # reconcile's real point of a certified centre: path_tracking.phase_normalised's, without
    # its measure of the imaginary part, bit for bit (NaN rows, zero blocks, infinities too)
    from parakin.solvers.path_tracking import phase_normalised

    rng = np.random.default_rng(4)
    z = rng.normal(size=(40, 7)) + 1j * rng.normal(size=(40, 7))
    z[3], z[4, 3:], z[5, 3], z[6, 4] = np.nan, 0.0, np.inf, -0.0 - 1e-300j
    for homogeneous in ((3, 4, 5, 6), (0,), ()):
        with np.errstate(all="ignore"):
            expected = phase_normalised(z, list(homogeneous))[0].real
            got = modes_module._real_centres(z, homogeneous)
        assert got.shape == (40, 7) and np.array_equal(_bits(got), _bits(expected)), homogeneous
        assert (homogeneous == ()) == np.array_equal(_bits(got), _bits(z.real))  # the scaling acts


@pytest.mark.parametrize("inputs", [1, 3])
def test_a_partners_repeat_is_a_repeat_of_an_earlier_mode(inputs):
    # reconcile asks the partner slot first (q and -q: prs3's 16 repeats) and every earlier mode
    # only for the rest: the partner's answer must be one the full search gives, and the two
    # together the full search's, on random poses near (1e-12), at (1e-9) and beyond the
    # threshold, NaN poses and non-modes included
    rng = np.random.default_rng(inputs)
    slots = 32
    partner = np.arange(slots) ^ 1  # 0 <-> 1, 2 <-> 3, ...
    agreed = partners = 0
    for _ in range(60):
        poses = np.tile(np.eye(4), (inputs, slots, 1, 1))
        poses[..., :3, :] = rng.normal(size=(inputs, slots, 3, 4))
        valid = rng.random((inputs, slots)) < 0.7
        rows = rng.integers(0, inputs, 12)
        columns = rng.integers(0, slots, 12)
        pose = poses[rows, partner[columns]].copy()  # the partner's pose, moved a little or more
        pose[..., :3, :] += rng.choice([0.0, 1e-12, 1e-9, 1e-3], size=(12, 1, 1)) * rng.normal(size=(12, 3, 4))
        pose[rng.random(12) < 0.1, 0, 3] = np.nan
        poses[0, rng.integers(0, slots), 1, 1] = np.nan
        full = modes_module._repeats_earlier_mode(valid, poses, rows, columns, pose)
        first = modes_module._repeats_partner(valid, poses, rows, columns, pose, partner)
        assert not (first & ~full).any()  # a partner's repeat is a repeat
        both = first.copy()
        rest = ~first
        if rest.any():
            both[rest] = modes_module._repeats_earlier_mode(valid, poses, rows[rest], columns[rest], pose[rest])
        assert np.array_equal(both, full)
        agreed += int(full.sum())
        partners += int(first.sum())
    assert partners >= 100 and agreed >= partners
