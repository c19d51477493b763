"""Modes decided by the certificate, not by thresholds (issue 31, items 1-3): a certified real
root is listed whatever its endpoint's imaginary part or the geometry's units, a certified
non-real root never is, a root the certificate cannot decide is named and the input is not
complete. Independent checks: the closed-form elimination of planar_3rpr (another method:
the univariate polynomial's real roots isolated by Sturm-like bracketing), exact arithmetic,
and the same geometry in metres."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import parakin
from parakin.solvers import modes as modes_module
from parakin.solvers.certify import certify_roots
from parakin.solvers.path_tracking import phase_normalised


def _geometry(name: str, seed: int, spread: float = 0.15) -> dict[str, float]:
    m = parakin.load(name, backend="numpy")
    rng = np.random.default_rng(seed)
    return {p.name: p.default * (1 + spread * rng.standard_normal()) for p in m.manifest.parameters}


def _scaled(name: str, geometry: dict[str, float], scale: float, backend: str = "numpy") -> parakin.Mechanism:
    m = parakin.load(name, backend="numpy")
    units = {p.name: p.unit for p in m.manifest.parameters}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return parakin.load(
            name, backend=backend, **{k: v * scale if units[k] == "m" else v for k, v in geometry.items()}
        )


def _fold(m: parakin.Mechanism, start: np.ndarray, direction: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """An input on each side of a change of the mode count along start + t direction, t in
    [-1.5, 1.5], bisected to 1e-13."""
    grid = start + np.linspace(-1.5, 1.5, 41)[:, None] * direction
    counts = m.forward_pose_all(grid, strict=False).count
    change = np.nonzero(np.diff(counts))[0]
    if not change.size:
        return None
    a, b = grid[change[0]].copy(), grid[change[0] + 1].copy()
    first = counts[change[0]]
    while np.abs(b - a).max() > 1e-13:
        middle = (a + b) / 2
        if m.forward_pose_all(middle, strict=False).count == first:
            a = middle
        else:
            b = middle
    return a, b


def test_a_root_at_the_origin_is_real() -> None:
    """A translating platform at home: every unknown 0 (item 2); 0/0 was "complex"."""
    z = np.zeros((1, 3), dtype=complex)
    _, imaginary = phase_normalised(z, [])
    assert imaginary[0] == 0.0


def test_a_certified_root_at_the_origin_is_real_at_any_scale() -> None:
    """x^2 - s x = 0 (roots 0 and s) for s from 1e-6 to 1e6, candidates from a tracker's
    rounding: both certified, both real, at every scale (the box is measured in the system's
    own size, not in absolute units)."""
    exponents, equation = np.array([[2], [1]]), np.array([0, 0])
    checked = 0
    for s in 10.0 ** np.arange(-6, 7):
        roots = np.array([[1e-17 * s + 1e-18j * s], [s * (1 + 1e-15) - 1e-16j * s]])
        cert = certify_roots(np.array([1.0, -s]), exponents, equation, roots)
        assert cert.unique.all() and (cert.real == 1).all() and cert.certified_distinct == 2, s
        checked += 1
    assert checked == 13


@pytest.mark.parametrize("backend", ["numpy", "compiled"])
def test_planar_3rrr_modes_do_not_depend_on_the_units(backend: str) -> None:
    """Item 1: random geometries in metres, millimetres and kilometres, inputs 1e-9 and 1e-6
    rad past a fold of the forward map (where two real modes are born): the same number of modes
    at every scale, certified complete, poses equal scaled; at 44aede2 the millimetre geometry
    lost the two modes near the fold and still said "complete"."""
    checked = 0
    for seed in (0, 5):
        geometry = _geometry("planar_3rrr", seed)
        metres = _scaled("planar_3rrr", geometry, 1.0, backend)
        home = metres.inverse_pose(np.zeros(3), strict=False).actuated[0]
        fold = _fold(metres, home, np.array([1.0, 0.0, 0.0]))
        assert fold is not None
        a, b = fold
        more = (
            b if metres.forward_pose_all(b, strict=False).count > metres.forward_pose_all(a, strict=False).count else a
        )
        step = (more - (a + b) / 2) / np.abs(more - (a + b) / 2).max()
        for offset in (1e-9, 1e-6):
            theta = (a + b) / 2 + offset * step
            reference = metres.forward_pose_all(theta, strict=False)
            assert bool(reference.certificate()["complete"])
            for scale in (1e-3, 1e3):
                other = _scaled("planar_3rrr", geometry, scale, backend).forward_pose_all(theta, strict=False)
                assert bool(other.certificate()["complete"]), (seed, offset, scale)
                assert int(other.count) == int(reference.count), (seed, offset, scale)
                mine = reference.poses[reference.valid][:, :3, 3] * scale
                theirs = other.poses[other.valid][:, :3, 3]
                distance = np.abs(mine[:, None, :] - theirs[None, :, :]).max(-1)
                assert (distance.min(1) <= 1e-7 * scale).all(), (seed, offset, scale)
                checked += 1
    assert checked == 8


def test_a_near_real_pair_is_never_a_mode_next_to_a_fold() -> None:
    """Item 3: planar_3rpr by the automatic method just past a fold on the side with fewer modes
    (the pair there is complex, 1e-9 and 1e-6 m past; closer, the uncertified elimination cannot tell a
    near-real pair from a double root in double precision): as many modes as the closed-form
    elimination (an independent method) finds where its real-root isolation saw no near-real
    pair, certified complete; each mode closes."""
    m = parakin.load("planar_3rpr", backend="numpy")
    checked = 0
    for seed in range(3):
        state = m.inverse_pose(np.array([0.02 * seed, -0.01, 0.1]), strict=False)
        theta = state.actuated[np.flatnonzero(state.valid)[0]]
        fold = _fold(m, theta, theta * np.array([0.6, 0.2, -0.2]))
        if fold is None:
            continue
        a, b = fold
        fewer = a if m.forward_pose_all(a, strict=False).count < m.forward_pose_all(b, strict=False).count else b
        step = (fewer - (a + b) / 2) / np.abs(fewer - (a + b) / 2).max()
        for offset in (1e-9, 1e-6):
            x = (a + b) / 2 + offset * step
            automatic = m.forward_pose_all(x, strict=False, method="automatic")
            closed = m.forward_pose_all(x, strict=False, method="elimination")
            if not bool(automatic.certificate()["complete"]) or int(closed.near_roots):
                continue  # not claimed, or the elimination itself saw a near-real pair
            assert int(automatic.count) == int(closed.count), (seed, offset)
            assert (automatic.residual[automatic.valid] < 1e-10).all()
            checked += 1
    assert checked >= 3


def test_an_uncertified_real_looking_endpoint_is_not_a_mode() -> None:
    """A real mode whose endpoint is spoiled (moved 1e-3 off its root: no box holds it) is
    reported 'uncertified', not listed, and the input is not complete."""
    m = parakin.load("planar_3rpr", backend="numpy")
    info = m.capabilities.forward_methods["automatic"]
    theta = m.inverse_pose(np.array([0.02, -0.01, 0.1]), strict=False).actuated[:1]
    out = modes_module.numpy_modes(m, theta, info)
    codes = {name: code for code, name in enumerate(m.manifest.abi.mode_outcomes)}
    mode_slot = int(np.flatnonzero(out["outcome"][0] == codes["mode"])[0])
    spoiled = out["endpoints"].copy()
    spoiled[0, mode_slot] += 1e-3
    cert = modes_module.certify(m, info, theta, spoiled)
    fixed = modes_module.reconcile(m, info, theta, dict(out, endpoints=spoiled), cert)
    assert fixed["outcome"][0, mode_slot] == codes["uncertified"]
    assert fixed["count"][0] == (out["outcome"][0] == codes["mode"]).sum() - 1
    assert cert.certified[0] < info.homotopy.root_count.count  # type: ignore[union-attr]
