"""Completion of a homotopy's certificate on benign inputs (issue 31, item 4): roots near infinity
certified in exact arithmetic with a high-precision inverse, complex conjugates of certified
non-real roots, and certified roots merged across re-track runs.

The rus6 inputs below are the four of ``tests/completion_census.py``'s 300 (seed 31) that were
not certified complete (76-78 of 80 roots: paths toward complex roots of size ~4e7, near a
singular root at infinity, failed or could not be certified in double precision); each is
checked here against independent sources: every real mode by the inverse kinematics (its
actuated values come back), the roots of size > 1e6 by the exact certifier called directly
(a box holding exactly one root, disjoint from its conjugate's), and in the slow test every one of
the 80 roots by the exact certifier, boxes pairwise disjoint.
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np
import pytest

import parakin
from parakin.solvers import exact_certify
from parakin.solvers import modes as modes_module
from parakin.solvers.certify import certify_roots
from parakin.solvers.exact_certify import certify_root_exactly

#: actuated values (rad) of the formerly incomplete inputs (the census's inputs 13, 156, 178, 195)
FORMERLY_INCOMPLETE = {
    13: [-0.012545665489522118, -0.037207343640052376, 0.018596055218490403,
         -0.05543893581877939, -0.009847219432879686, 0.025557614774868002],
    156: [0.0003080812463646586, -0.03992358732483717, -0.047731843640936945,
          -0.012121690235337282, -0.03555442034982781, -0.03292330542389041],
    178: [0.02479568359070527, 0.03604662502295875, -0.016290023630249797,
          -0.02289273418805038, -0.02812502972012071, -0.029478593460372744],
    195: [-0.0037052048182475155, -0.021465210707048422, -0.030332874038972866,
          0.01382166842413561, -0.0005002951815634501, -0.04885435114538993],
}  # fmt: skip


@pytest.fixture(scope="module")
def rus6():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return parakin.load("rus6", backend="compiled")


def _system(m, theta):
    """The family's system at the input as the certificate sees it (the unit-free geometry)."""
    scaled, unit = m._unit_free or (m, 1.0)
    info = scaled.capabilities.forward
    free, angles = modes_module._family(scaled, info, theta[None])
    coefficients = modes_module._target_coefficients(scaled, info, free, angles)[0]
    return info.homotopy, coefficients


def _check_modes_by_inverse(m, theta, modes):
    """Each mode's pose, through the inverse kinematics, gives back the input on one branch."""
    poses = modes.poses[modes.valid]
    assert poses.shape[0] >= 2
    for pose in poses:
        ik = m.inverse_pose(pose, strict=False)
        gap = np.abs(ik.actuated[ik.valid] - theta).max(-1)
        assert gap.min() < 1e-9


def _exact_box(homotopy, coefficients, root):
    box = certify_root_exactly(coefficients, homotopy.exponents, homotopy.equation, root, True)
    assert box.unique
    return box


def _run(m, theta):
    """forward_pose_all's arrays (as its result object) and the slots' roots (unit-free coordinates)."""
    info = m.capabilities.forward
    out = m._every_mode(info, theta[None], True)
    modes = modes_module.assemble(m, theta[None], out, info)
    return modes, out["endpoints"][0, ..., 0] + 1j * out["endpoints"][0, ..., 1]


def _pairwise_disjoint(boxes) -> bool:
    centres = np.array([box.center for box in boxes])
    radii = np.array([box.radius for box in boxes])
    gap = np.abs(centres[:, None, :] - centres[None, :, :]).max(-1)
    apart = gap > radii[:, None] + radii[None, :]
    return bool(apart[~np.eye(len(boxes), dtype=bool)].all())


def test_a_formerly_incomplete_rus6_input_is_certified_complete(rus6):
    theta = np.array(FORMERLY_INCOMPLETE[13])
    start = time.process_time()
    modes, z = _run(rus6, theta)
    elapsed = time.process_time() - start
    certificate = modes.certificate()
    assert bool(certificate["complete"][0]) and int(certificate["certified_roots"][0]) == 80
    assert int(certificate["uncertified_paths"][0]) == 0
    _check_modes_by_inverse(rus6, theta, modes)
    # the roots near infinity (the ones the first run missed), each certified again by the exact
    # certifier from its slot's root: one root in its box, non-real, the boxes disjoint, and each
    # one's conjugate among them
    homotopy, coefficients = _system(rus6, theta)
    far = np.nonzero(np.abs(z).max(-1) > 1e6)[0]
    assert far.size >= 4
    boxes = [_exact_box(homotopy, coefficients, z[p]) for p in far]
    assert all(box.real == -1 for box in boxes)
    assert _pairwise_disjoint(boxes)
    for box in boxes:
        assert min(np.abs(np.conj(box.center) - other.center).max() - other.radius for other in boxes) <= box.radius
    assert elapsed < 30  # was 15-28 s and incomplete; about 1 s now


def test_exact_certifier_inverts_a_jacobian_that_double_precision_rounds_to_singular():
    # z1 + z2 - 2 = 0, z1 + (1 + e) z2 - (2 + e) = 0 with e = 2^-60: the root (1, 1) is simple, but
    # its Jacobian [[1, 1], [1, 1 + e]] rounds to a singular matrix in double precision
    e = 2.0**-60
    exponents = np.array([[1, 0], [0, 1], [0, 0], [1, 0], [0, 1], [0, 1], [0, 0], [0, 0]])
    equation = np.array([0, 0, 0, 1, 1, 1, 1, 1])
    coefficients = np.array([1, 1, -2, 1, 1, e, -2, -e], dtype=complex)
    box = certify_root_exactly(coefficients, exponents, equation, np.array([1.0 + 1e-9, 1.0 - 1e-9]), True)
    assert box.unique and box.real == 1
    assert np.abs(box.center - 1).max() <= box.radius + 1e-15
    # the double-precision test cannot: its Jacobian is singular as rounded
    assert not certify_roots(coefficients, exponents, equation, np.array([[1.0, 1.0]])).unique.any()


@pytest.mark.slow
@pytest.mark.parametrize("index", sorted(FORMERLY_INCOMPLETE))
def test_every_root_of_the_formerly_incomplete_rus6_inputs_is_certified_exactly(rus6, index):
    theta = np.array(FORMERLY_INCOMPLETE[index])
    modes, z = _run(rus6, theta)
    assert bool(modes.certificate()["complete"][0])
    _check_modes_by_inverse(rus6, theta, modes)
    homotopy, coefficients = _system(rus6, theta)
    boxes = [_exact_box(homotopy, coefficients, root) for root in z]
    assert _pairwise_disjoint(boxes)  # 80 distinct roots, each alone in its box
    assert sum(box.real == 1 for box in boxes) == int(modes.real_roots[0])


def _first_run(m, theta):
    """The compiled first run of one input in the certificate's own numbers, and its certificate."""
    scaled, _ = m._unit_free or (m, 1.0)
    info = scaled.capabilities.forward
    out = modes_module.compiled_modes(scaled, theta[None])
    return scaled, info, out, modes_module.certify(scaled, info, theta[None], out["endpoints"], True)


def _forget(out, found, slots):
    """The slots as if their paths had failed: no endpoint, no box."""
    out["endpoints"][0, slots] = np.nan
    found.unique[0, slots] = False
    found.centre[0, slots] = np.nan
    found.radii[0, slots] = np.nan
    modes_module._recount(found, np.array([0]))


def test_conjugates_and_other_runs_fill_the_slots_no_box_holds_and_count_each_root_once(rus6):
    theta = np.array(FORMERLY_INCOMPLETE[178])
    m, info, out, found = _first_run(rus6, theta)
    nonreal = np.nonzero(found.unique[0] & (found.real[0] == -1))[0]
    z = found.centre[0]
    # the certified non-real roots whose conjugate is also a certified root of the run, each
    # alone in its cluster (two paths may end at one root: their boxes form one cluster, and
    # forgetting one of them takes no root away): forget one of each of a few such pairs
    alone = np.bincount(found.labels[0][found.unique[0]], minlength=z.shape[0]) == 1
    partner = {}
    for p in nonreal[alone[found.labels[0][nonreal]]]:
        distance = np.abs(z - np.conj(z[p])).max(-1)
        q = int(np.argmin(np.where(found.unique[0], distance, np.inf)))
        close = np.abs(z[q] - np.conj(z[p])).max() <= found.radii[0, p].max() + found.radii[0, q].max()
        if close and alone[found.labels[0][q]]:
            partner[int(p)] = q
    assert len(partner) >= 20
    forgotten = sorted({max(p, q) for p, q in list(partner.items())[:12]})
    assert len(forgotten) >= 4
    before = int(found.certified[0])
    kept = {key: value.copy() for key, value in out.items()}
    _forget(out, found, forgotten)
    assert int(found.certified[0]) == before - len(forgotten)
    held = found.unique[0].copy()
    modes_module.add_conjugates(m, info, theta[None], out, found, np.array([0]))
    restored = int(found.certified[0])
    filled = np.nonzero(found.unique[0] & ~held)[0]
    # each forgotten root is back, as its conjugate's image (and any other missing conjugate)
    assert restored >= before and filled.size == restored - before + len(forgotten)
    homotopy, coefficients = _system(rus6, theta)
    for slot in filled:
        box = _exact_box(homotopy, coefficients, found.centre[0, slot])  # independently certified
        assert box.real == -1
    # another run holding the same roots adds none (no root counted twice); one holding the
    # forgotten ones restores them
    again = {key: value.copy() for key, value in kept.items()}
    second = modes_module.certify(m, info, theta[None], again["endpoints"], True)
    modes_module.merge_roots(out, found, np.array([0]), again, second)
    assert int(found.certified[0]) == restored
    _forget(out, found, filled)
    assert int(found.certified[0]) == restored - filled.size
    modes_module.merge_roots(out, found, np.array([0]), again, second)
    assert int(found.certified[0]) == restored - filled.size + len(forgotten)


def test_an_exact_radius_with_a_mantissa_beyond_the_double_range_is_reported_rounded_up():
    # the fixed-point inverse makes Y's mantissas hundreds of bits long, so the exact radius can
    # have a mantissa far beyond 2^1024 (float(int) overflows) while its value is small
    value = (3 * 2**1200 + 1, -1200)  # 3 + 2^-1200
    reported = exact_certify._upper_float(value)
    assert 3.0 < reported <= 3.0 * (1 + 2**-50)
    assert exact_certify._upper_float((2**1100, 0)) == math.inf
    assert exact_certify._upper_float((1, -1074)) >= 2.0**-1074
