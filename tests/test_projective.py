"""Tracking in projective space (``parakin.solvers.projective``): the homogenised family is the
family (checked by evaluation), a root near infinity that affine tracking gives up on is reached
and equals the root NumPy's companion-matrix solver finds, symmetric pairs stay pairs, and a
6-RUS input whose first (affine) run misses roots near infinity is certified complete after the
projective re-track."""

from __future__ import annotations

import numpy as np
import pytest

import parakin
from parakin.solvers.path_tracking import PATH_REACHED, path_pairs, sparse_system, track, track_symmetric
from parakin.solvers.projective import projective_family, projective_table, to_affine, to_projective


def _linear_in_s(target: np.ndarray, start: np.ndarray) -> np.ndarray:
    """Coefficients (1, 2, T) of c(s) = (1 - s) target + s start."""
    return np.stack([target, start - target])[None]


def test_the_homogenised_family_is_the_family_scaled_on_the_patch():
    rng = np.random.default_rng(3)
    exponents = np.array([[2, 1], [1, 0], [0, 0], [0, 3], [1, 1], [0, 0]])
    equation = np.array([0, 0, 0, 1, 1, 1])
    coefficients = rng.normal(size=6) + 1j * rng.normal(size=6)
    table = coefficients[None, None, :]
    family = projective_family(exponents, equation, None)
    assert family.exponents.shape == (6 + 4, 3) and (family.exponents[:6].sum(-1) == [3, 3, 3, 3, 3, 3]).all()
    z = rng.normal(size=(5, 2)) + 1j * rng.normal(size=(5, 2))
    point = to_projective(family, z)
    assert np.allclose(point @ family.patch, 1.0)
    affine, _, _ = sparse_system(table, exponents, equation, 5)(np.arange(5), z, np.zeros(5))
    value, jacobian, _ = sparse_system(projective_table(family, table), family.exponents, family.equation, 5)(
        np.arange(5), point, np.zeros(5)
    )
    w = point[:, 2:]
    # both equations have degree 3: F_k(z / w) w^3 = F_k(Z), and the patch holds
    assert np.abs(value[:, :2] - affine * w**3).max() < 1e-12 * (1 + np.abs(value).max())
    assert np.abs(value[:, 2]).max() < 1e-14
    # the Jacobian against central differences along each unknown
    step = 1e-6
    for i in range(3):
        shift = np.zeros(3)
        shift[i] = step
        system = sparse_system(projective_table(family, table), family.exponents, family.equation, 5)
        upper, _, _ = system(np.arange(5), point + shift, np.zeros(5))
        lower, _, _ = system(np.arange(5), point - shift, np.zeros(5))
        assert np.abs((upper - lower) / (2 * step) - jacobian[:, :, i]).max() < 1e-7


def test_a_root_near_infinity_is_reached_projectively_and_lost_affinely():
    """e x^2 + x - 1 with e = 1e-9 at the target: roots near 1 and near -1e9. Affine tracking
    never delivers the large one (here both paths jump to the root near 1); projective tracking
    reaches both, and they are the roots of the companion matrix, to 1e-9 relative."""
    exponents, equation = np.array([[2], [1], [0]]), np.zeros(3, dtype=int)
    target = np.array([1e-9, 1.0, -1.0], dtype=complex)
    start = np.array([0.7 + 0.4j, -0.3 + 0.9j, 0.5 - 0.6j])
    table = _linear_in_s(target, start)
    start_roots = np.roots(start)[:, None]
    affine = track(sparse_system(table, exponents, equation, 2), start_roots)
    family = projective_family(exponents, equation, None)
    projective = to_affine(
        track(sparse_system(projective_table(family, table), family.exponents, family.equation, 2),
              to_projective(family, start_roots))
    )  # fmt: skip
    exact = np.sort_complex(np.roots(target))
    large = exact[np.abs(exact).argmax()]
    delivered = (affine.status == PATH_REACHED) & (np.abs(affine.z[:, 0] - large) < 1e-3 * abs(large))
    assert not delivered.any(), affine
    assert (projective.status == PATH_REACHED).all(), projective.status
    ends = np.sort_complex(projective.z[:, 0])
    assert np.abs(ends - exact).max() / np.abs(exact).max() < 1e-9 and np.abs(ends).max() > 1e8


def test_symmetric_pairs_stay_pairs_on_the_patch():
    """x^2 + y^2 - a, x y - b (even under (x, y) -> (-x, -y)): the patch ignores the flipped
    unknowns, so tracking one of each pair equals tracking all four paths."""
    exponents = np.array([[2, 0], [0, 2], [0, 0], [1, 1], [0, 0]])
    equation = np.array([0, 0, 0, 1, 1])
    start = np.array([1.0, 1.0, -2.0, 1.0, -1.0 + 0.5j])
    target = np.array([1.0, 1.0, -5.0, 1.0, -2.0 + 0j])
    table = _linear_in_s(target, start)
    # start roots: x^2 + y^2 = 2, x y = 1 - 0.5j
    roots = []
    for x2 in np.roots([1.0, -2.0, (1 - 0.5j) ** 2]):
        x = np.sqrt(x2)
        for sign in (1, -1):
            roots.append([sign * x, sign * (1 - 0.5j) / x])
    start_roots = np.array(roots)
    pairs = path_pairs(exponents, equation, start_roots)
    assert pairs is not None
    family = projective_family(exponents, equation, pairs)
    assert family.patch[0] == family.patch[1] == 0 and family.patch[2] != 0
    assert family.pairs is not None and list(family.pairs.flip) == [-1.0, -1.0, 1.0]
    extended = projective_table(family, table)

    def system_for(per: int):
        return sparse_system(extended, family.exponents, family.equation, per)

    half = to_affine(track_symmetric(system_for, to_projective(family, start_roots), 1, 1e-7, family.pairs))
    full = to_affine(track(system_for(4), to_projective(family, start_roots)))
    assert (half.status == PATH_REACHED).all() and (full.status == PATH_REACHED).all()
    assert np.abs(half.z - full.z).max() < 1e-9
    x, y = full.z[:, 0], full.z[:, 1]
    assert np.abs(x**2 + y**2 - 5).max() < 1e-10 and np.abs(x * y - 2).max() < 1e-10


@pytest.mark.slow
def test_a_6rus_input_missing_roots_near_infinity_is_completed_by_the_projective_retrack():
    """A rus6 input whose first (affine, generated C) run certifies fewer than 80 roots and is
    re-tracked (input 13 of tests/test_certified_completion.py's formerly incomplete census
    inputs: with the one-correction tracker no sample of 600 near home needs a re-track): the
    re-track in projective space certifies all 80, and the roots it adds are large (near
    infinity)."""
    from parakin.solvers.modes import certify, compiled_modes

    m = parakin.load("rus6", backend="compiled")
    info = m.capabilities.forward
    theta = np.array([[-0.012545665489522118, -0.037207343640052376, 0.018596055218490403,
                       -0.05543893581877939, -0.009847219432879686, 0.025557614774868002]])  # fmt: skip
    first = compiled_modes(m, theta)
    certified, unique = certify(m, info, theta, first["endpoints"], exact=True)[:2]
    assert certified[0] < 80
    modes = m.forward_pose_all(theta[0])
    certificate = modes.certificate()
    assert int(certificate["certified_roots"]) == 80 and bool(certificate["complete"])
    assert bool(certificate["retracked"])
    ends = first["endpoints"][0, ..., 0] + 1j * first["endpoints"][0, ..., 1]
    # the first run's shortfall: paths that did not end (diverged or failed), ended far out, or
    # ended on a root another path holds (two paths on one far root): what affine tracking
    # handles badly
    lost = ends[~unique[0]]
    assert (np.isnan(lost).all(-1) | (np.abs(lost).max(-1) > 1e2)).all(), np.abs(lost).max(-1)


def test_suspect_paths_are_the_uncertified_the_unfinished_and_the_twins():
    from parakin.solvers.modes import suspect_paths

    z = np.array([[1.0, 2.0], [1.0 + 1e-6, 2.0], [5.0, -1.0], [np.nan, np.nan], [-3.0, 4.0], [7.0, 7.0]])
    endpoints = np.stack([z, np.zeros_like(z)], -1)[None]  # (1 input, 6 paths, 2 unknowns, re/im)
    unique = np.array([[True, True, True, False, True, False]])
    suspect = suspect_paths(endpoints, unique)
    # 0 and 1 ended on one root, 3 did not end, 5 is not certified; 2 and 4 are alone
    assert suspect.tolist() == [[True, True, False, True, False, True]]


def test_a_partial_retrack_keeps_the_other_ends_and_tracks_the_chosen_paths_like_a_full_one():
    """Re-tracking some paths (closed under symmetric partners) gives those paths the ends of a
    full projective re-track from the same start, and leaves every other end as it was."""
    from parakin.solvers.modes import Retrack, _homotopy_candidates
    from parakin.studies.sampling import sample_configurations

    m = parakin.load("prs3", backend="numpy")
    info = m.capabilities.forward
    theta = sample_configurations(m, 6, seed=31).actuated[:3]
    paths = info.homotopy.start.shape[0]
    full = _homotopy_candidates(m, theta, info, Retrack(0))["endpoints"]
    marked = np.zeros((3, paths), bool)
    marked[0, 3] = marked[2, [0, 9]] = True
    placeholder = np.full(full.shape[:-1], 7.0 + 0j)  # the 'earlier' ends of the paths kept
    part = _homotopy_candidates(m, theta, info, Retrack(0, marked, placeholder))["endpoints"]
    pairs = path_pairs(info.homotopy.exponents, info.homotopy.equation, info.homotopy.start)
    redo = marked | marked[:, pairs.partner]
    assert redo.sum() == 6 and np.isfinite(full).all()
    kept = part[~redo]
    assert (kept[..., 0] == 7.0).all() and (kept[..., 1] == 0.0).all()
    assert np.abs(part[redo] - full[redo]).max() < 1e-9 * (1 + np.abs(full[redo]).max())
