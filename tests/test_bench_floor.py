"""bench/floor.py: the interleaved timing rotates the contenders' order, and the peer fkSGP is
called as its README says (Dietmaier's geometry has 40 real postures, Dietmaier 1998)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

# bench/ is a folder of scripts run from the repository root (python -m bench), not a package on
# the tests' path: its module is loaded from its file
_SPEC = importlib.util.spec_from_file_location(
    "bench_floor", Path(__file__).resolve().parent.parent / "bench" / "floor.py"
)
assert _SPEC is not None and _SPEC.loader is not None
floor = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(floor)


def test_interleaved_rotates_the_order() -> None:
    calls: list[str] = []
    times = floor.interleaved({name: (lambda name=name: calls.append(name)) for name in "abc"}, rounds=3)
    assert [len(value) for value in times.values()] == [3, 3, 3]
    assert calls[:3] == ["a", "b", "c"]  # the warm-up
    assert calls[3:] == ["a", "b", "c", "b", "c", "a", "c", "a", "b"]
    assert all((value >= 0).all() for value in times.values())


def test_fksgp_finds_dietmaier_s_forty_postures() -> None:
    solver = floor.load_fksgp()
    if solver is None:
        pytest.skip(f"fkSGP is not in {floor.PEERS}")
    np.random.seed(1)
    postures, errors = solver(floor.DIETMAIER_BASE, floor.DIETMAIER_PLATFORM, floor.DIETMAIER_LEGS**2, 1)
    assert len(postures) == 40
    # each posture (R | t), platform point i in the base frame: X_i = R x_i + t, |X_i - A_i| = L_i
    for pose in postures:
        placed = floor.DIETMAIER_PLATFORM @ pose[:, :3].T + pose[:, 3]
        lengths = np.linalg.norm(placed - floor.DIETMAIER_BASE, axis=1)
        np.testing.assert_allclose(lengths, floor.DIETMAIER_LEGS, rtol=1e-6)


def test_numpy_certificate_swap_is_local_and_keeps_the_modes() -> None:
    """bench's numpy_certificate swaps the certificate forward_pose_all uses (the package's C on
    the compiled backend) for NumPy's inside its block only; the 3-RRR's modes and their
    certificate are the same with either."""
    import parakin
    from parakin.solvers import certify, modes

    m = parakin.load("planar_3rrr", backend="compiled")
    theta = m.home_actuated
    reference = m.forward_pose_all(theta, strict=False)
    calls = floor.certify_calls(m, theta)
    assert calls and modes.certify_roots_compiled is certify.certify_roots_compiled
    with floor.numpy_certificate():
        assert modes.certify_roots_compiled is not certify.certify_roots_compiled
        swapped = m.forward_pose_all(theta, strict=False)
    assert modes.certify_roots_compiled is certify.certify_roots_compiled
    assert swapped.count == reference.count >= 2
    assert swapped.certificate()["complete"] == reference.certificate()["complete"]
    np.testing.assert_allclose(swapped.poses, reference.poses)
