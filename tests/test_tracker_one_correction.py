"""The tracker's corrector stops after one Newton correction where the path's running Newton
constant allows (issue 33, item 2: ``ONE_STEP_BASIN``, ``ONE_STEP_ERROR`` of
parakin.solvers.path_tracking; the C tracker is the same algorithm, tests/test_c_runtime.py):
no path jumps on homotopies whose two paths pass close to each other, against the closed form,
and stopping after one correction saves evaluations without moving an endpoint."""

from __future__ import annotations

import numpy as np
import pytest

from parakin.solvers import path_tracking as tracking


def _square_root_homotopy(a: complex) -> tracking.System:
    """z^2 - ((1 - s) a + s): from z = +-1 at s = 1 to z = +-sqrt(a) at s = 0."""
    table = np.zeros((1, 2, 2), complex)
    table[0, 0] = [1.0, -a]
    table[0, 1] = [0.0, a - 1.0]
    return tracking.sparse_system(table, np.array([[2], [0]]), np.array([0, 0]), 2)


START = np.array([[1.0 + 0j], [-1.0 + 0j]])


@pytest.mark.parametrize("delta", [1e-2, 1e-4, 1e-6])
def test_paths_passing_a_branch_point_do_not_jump(delta: float) -> None:
    """a = -1 + i delta: c(s) = (1 - s) a + s = 2 s - 1 + i delta (1 - s) stays in the upper half
    plane and passes i delta / 2 at s = 1/2, so the two paths +-sqrt(c(s)) (principal root,
    continuous there) come within sqrt(2 delta) of each other (1.4e-3 for delta = 1e-6); each
    must end at its own continuation, +-sqrt(a), not at its neighbour's."""
    a = -1.0 + 1j * delta
    ends = tracking.track_hermite(_square_root_homotopy(a), START, 1e-7)
    assert (ends.status == tracking.PATH_REACHED).all()
    np.testing.assert_allclose(ends.z[:, 0], np.array([1.0, -1.0]) * np.sqrt(a), rtol=1e-10)


def test_one_correction_saves_evaluations_and_moves_no_endpoint(monkeypatch: pytest.MonkeyPatch) -> None:
    """The same paths with one-correction steps switched off (ONE_STEP_BASIN = 0: every step
    corrects until the tolerance): the same endpoints (closed form), and the default takes fewer
    evaluations in total over homotopies with roots spread around the circle."""
    roots = 4.0 * np.exp(1j * np.linspace(0.2, 2 * np.pi - 0.2, 8))  # never -4: c(s) would pass 0
    default, off = 0, 0
    for a in roots:
        system = _square_root_homotopy(complex(a))
        ends = tracking.track_hermite(system, START, 1e-7)
        with monkeypatch.context() as patch:
            patch.setattr(tracking, "ONE_STEP_BASIN", 0.0)
            strict = tracking.track_hermite(system, START, 1e-7)
        for result in (ends, strict):
            assert (result.status == tracking.PATH_REACHED).all()
            assert np.allclose(result.z[:, 0] ** 2, a, rtol=1e-12)
            assert (np.real(result.z[:, 0] / START[:, 0]) > 0).all()  # each start's own root
        default += int(ends.evaluations.sum())
        off += int(strict.evaluations.sum())
    assert default < 0.9 * off
