"""Sign symmetries of a homotopy family (``parakin.solvers.path_tracking.sign_symmetry``): where every
equation is even or odd under z -> S z (q -> -q of a quaternion), the paths pair up and one of
each pair is tracked. Checked against the full tracking (each partner path followed on its own
ends at the image of its representative's end) and against the generated C driver's table."""

from __future__ import annotations

import re

import numpy as np
import pytest

import parakin
from parakin.solvers.modes import _path_table
from parakin.solvers.path_tracking import (
    path_pairs,
    sign_symmetry,
    sparse_system,
    symmetric_partners,
    track,
    track_symmetric,
)
from parakin.studies.sampling import sample_configurations


def test_the_parity_test_finds_the_quaternion_sign_and_nothing_where_there_is_none():
    # x^2 + y^2 - 1 and x y - c: even under (x, y) -> (-x, -y); x + y: odd under it too
    exponents = np.array([[2, 0], [0, 2], [0, 0], [1, 1], [0, 0]])
    assert list(sign_symmetry(exponents, np.array([0, 0, 0, 1, 1]))) == [-1.0, -1.0]
    # x^2 + y - 1: even under x -> -x alone
    assert list(sign_symmetry(np.array([[2, 0], [0, 1], [0, 0]]), np.array([0, 0, 0]))) == [-1.0, 1.0]
    assert sign_symmetry(np.array([[1, 0], [0, 1], [0, 0]]), np.array([0, 0, 0])) is None  # x + y - 1
    prs3 = parakin.metadata("prs3").capabilities.forward.homotopy
    flip = sign_symmetry(prs3.exponents, prs3.equation)
    flipped = [name for name, f in zip(prs3.unknowns, flip, strict=True) if f < 0]
    assert flipped == ["z_q0", "z_q1", "z_q2", "z_q3"]
    planar = parakin.metadata("planar_3rrr").capabilities.forward.homotopy
    assert sign_symmetry(planar.exponents, planar.equation) is None


@pytest.mark.parametrize("name", ["prs3"])
def test_a_partner_path_tracked_on_its_own_ends_at_the_image_of_its_representative(name):
    m = parakin.load(name, backend="numpy")
    info = m.capabilities.forward
    homotopy = info.homotopy
    theta = sample_configurations(m, 3, seed=21).actuated
    table = _path_table(m, info, theta, 0)
    flip = sign_symmetry(homotopy.exponents, homotopy.equation)
    partner = symmetric_partners(homotopy.start, flip)
    assert partner is not None and (partner[partner] == np.arange(partner.size)).all()
    paths = homotopy.start.shape[0]
    full = track(sparse_system(table, homotopy.exponents, homotopy.equation, paths), np.tile(homotopy.start, (3, 1)))
    pairs = path_pairs(homotopy.exponents, homotopy.equation, homotopy.start)
    assert pairs is not None and (pairs.partner == partner).all() and (pairs.first < pairs.second).all()
    half = track_symmetric(
        lambda per: sparse_system(table, homotopy.exponents, homotopy.equation, per), homotopy.start, 3, 1e-7, pairs
    )
    assert (full.status == 0).all() and (half.status == 0).all()
    scale = 1 + np.abs(full.z).max(-1)
    assert (np.abs(full.z - half.z).max(-1) / scale).max() < 1e-9, "each partner path ends at the image"
    assert full.z.shape[0] == 3 * paths


@pytest.mark.parametrize("name", ["prs3", "rus6"])
def test_the_generated_driver_pairs_the_paths_as_the_runtime_does(name):
    homotopy = parakin.metadata(name).capabilities.forward.homotopy
    flip = sign_symmetry(homotopy.exponents, homotopy.equation)
    partner = symmetric_partners(homotopy.start, flip)
    sources = parakin.load(name, backend="numpy").package.c_sources()
    driver = next(p for p in sources if p.name == "driver.c").read_text()
    table = re.search(r"static const int partner\[DEGREE\] = \{ ([^}]*) \};", driver)
    assert table is not None
    assert [int(v) for v in table.group(1).split(",")] == list(partner)


def test_certifying_one_path_of_each_pair_gives_the_full_certificate():
    """prs3 on 40 sampled inputs: the certificate by symmetry (boxes of the first path of each
    pair, their images for the other) has the same certified paths and the same count of distinct
    certified roots as certifying every endpoint, and every image box holds its path's end."""
    from parakin.solvers.certify import certify_roots
    from parakin.solvers.modes import (
        _certified_group,
        _certify_endpoints,
        _family,
        _paired_ends,
        _target_coefficients,
        compiled_modes,
    )

    m = parakin.load("prs3", backend="compiled")
    info = m.capabilities.forward
    homotopy = info.homotopy
    theta = sample_configurations(m, 40, seed=31).actuated
    endpoints = compiled_modes(m, theta)["endpoints"]
    roots = endpoints[..., 0] + 1j * endpoints[..., 1]
    coefficients = _target_coefficients(m, info, *_family(m, info, theta))
    full = certify_roots(
        coefficients, homotopy.exponents, homotopy.equation, roots,
        homogeneous=_certified_group(homotopy), patch_equation=homotopy.patch_equation,
    )  # fmt: skip
    pairs = path_pairs(homotopy.exponents, homotopy.equation, homotopy.start)
    paired = _paired_ends(pairs, roots)
    assert paired.all(), "every input's ends pair up as tracked"
    mirrored = _certify_endpoints(homotopy, coefficients, roots, pairs, paired)
    assert theta.shape[0] >= 30
    assert (mirrored.unique == full.unique).all()
    assert (mirrored.certified_distinct == full.certified_distinct).all() and (full.certified_distinct == 32).all()
    inside = np.abs(roots - mirrored.center) <= mirrored.radii
    assert inside[mirrored.unique].all()


def test_exact_certificates_of_image_paths_are_the_images_of_their_boxes(monkeypatch):
    """rus6 (80 roots in +-q pairs, many beyond double precision's Krawczyk test): on 3 sampled
    inputs the exact certification of one path of each pair, mirrored, certifies the same paths
    and the same number of distinct roots as certifying every path exactly."""
    import parakin.solvers.modes as modes

    m = parakin.load("rus6", backend="compiled")
    info = m.capabilities.forward
    theta = sample_configurations(m, 3, seed=5).actuated
    endpoints = modes.compiled_modes(m, theta)["endpoints"]
    mirrored = modes.certify(m, info, theta, endpoints, exact=True)
    monkeypatch.setattr(modes, "path_pairs", lambda exponents, equation, start: None)
    every = modes.certify(m, info, theta, endpoints, exact=True)
    assert theta.shape[0] == 3
    assert (mirrored.certified == every.certified).all() and (mirrored.unique == every.unique).all()
    assert (mirrored.real == every.real).all()
    assert (every.certified > 56).all(), "exact arithmetic certified roots that double precision could not"
