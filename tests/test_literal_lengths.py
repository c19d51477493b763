"""A model that writes a length as a number instead of a parameter (issue 32's skew 3-RRS fixture:
``R_B = 0.2`` in its joints' points) is not the same geometry when its length parameters are
rescaled. The all-modes solver of a homotopy works in the geometry's own size (issue 31: every
length divided by a power of two near the size); before, it rescaled such a model too and solved
another mechanism: the skew 3-RRS listed 2 "modes" per input whose closure residual was 0.09-0.17
m and missed the home. Now the rescaling is taken only where the closure scales with the lengths
(``modes.scales_with_lengths``), and a mode whose closure in the caller's units is not below the
closure tolerance is never a mode (``modes._closed_modes``, the last check of both backends).

The mechanism with a literal length here is the shipped planar 3-RRR whose kernels read one base
coordinate as a number (the NumPy kernels with that parameter frozen at its default): the same
geometry as the package's at its defaults, so the exact oracle (``tests/oracle_modes.py``,
rational elimination, no parakin solver) gives its modes.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import Any

import numpy as np
import oracle_modes as om
import pytest

import parakin
from parakin.solvers import modes as solver

#: the planar 3-RRR's parameter read as a number (its largest length: the rescaling moves it most)
FROZEN = "base_y3"
#: inputs: the home's cranks moved by these (rad); every one has 2 real modes (the oracle's count)
MOVES = [(0.1, -0.05, 0.15), (-0.15, 0.1, 0.05), (0.05, 0.2, -0.1)]
ANGULAR = (False, False, True)


class LiteralLength:
    """A NumPy backend whose kernels read parameter ``index`` as the number ``value``, whatever
    the caller passes: a package generated from a model with that length written as a number."""

    name = "numpy"

    def __init__(self, backend: Any, index: int, value: float) -> None:
        def frozen(kernel: Callable) -> Callable:
            def call(*inputs: np.ndarray) -> dict:
                params = np.array(inputs[-1], dtype=float)
                params[..., index] = value
                return kernel(*inputs[:-1], params)

            return call

        self.kernels = {
            name: frozen(kernel) if list(inspect.signature(kernel).parameters)[-1] == "params" else kernel
            for name, kernel in backend.kernels.items()
        }

    def call(self, kernel: str, *inputs: np.ndarray) -> dict:
        return self.kernels[kernel](*inputs)


def literal_3rrr() -> tuple[parakin.Mechanism, dict[str, float]]:
    m = parakin.load("planar_3rrr", backend="numpy")
    names = [p.name for p in m.manifest.parameters]
    index = names.index(FROZEN)
    m.backend = LiteralLength(m.backend, index, float(m.params[index]))
    return m, dict(zip(names, m.params.tolist(), strict=True))


def test_rows_that_scale_by_a_power_of_the_unit():
    """Hand-written closure rows at a configuration and at it with every length halved: a squared
    distance (degree 2), a position difference (1) and a rotation error (0) scale; the same rows
    with the circle's centre written as a number (0.2 m, not halved) do not."""
    p, c, length, angle = np.array([0.31, -0.12]), np.array([0.2, 0.05]), 0.27, 0.4

    def rows(p: np.ndarray, c: np.ndarray, length: float) -> np.ndarray:
        return np.array([np.sum((p - c) ** 2) - length**2, p[0] - c[0] - length, np.sin(angle) - 0.3])

    assert solver._rows_scale(rows(p, c, length), rows(p / 2, c / 2, length / 2), 2.0)
    assert not solver._rows_scale(rows(p, c, length), rows(p / 2, c, length / 2), 2.0)
    # a row that vanishes at one scale only does not scale either
    assert not solver._rows_scale(np.array([0.0, 1e-3]), np.array([2e-3, 5e-4]), 2.0)


def test_every_shipped_closure_scales_with_its_lengths():
    """The rescaling of issue 31 stays on for every shipped mechanism (their closures have no
    literal length); the planar 3-RRR with a literal length is detected."""
    checked = 0
    for name in parakin.available():
        m = parakin.load(name, backend="numpy")
        assert solver.scales_with_lengths(m), name
        checked += 1
    assert checked >= 14
    m, parameters = literal_3rrr()
    assert not solver.scales_with_lengths(m)
    assert solver.length_scale(m) == 1.0 and max(abs(v) for v in parameters.values()) == 0.5


def test_a_literal_length_gets_the_modes_of_its_own_geometry():
    """Before: both modes listed at each of these 3 inputs were the rescaled model's (the oracle's
    closure |leg|^2 - b^2 0.037-0.237 m^2, 0.37-0.46 from the oracle's poses), certified complete.
    Now: the
    oracle's 2 modes (1e-12), each closing the oracle's closure to 1e-13 m^2."""
    m, parameters = literal_3rrr()
    checked = 0
    for move in MOVES:
        theta = m.home_actuated + np.array(move)
        oracle = om.planar_3rrr(parameters, theta)
        assert oracle.usable and oracle.count == 2
        modes = m.forward_pose_all(theta, strict=False)
        listed = modes.passive[modes.valid]
        assert om.match(listed, oracle.array(), ANGULAR, 0.5) < 1e-12
        for pose in listed:
            assert max(abs(float(r)) for r in om.closure("planar_3rrr", parameters, theta, pose)) < 1e-13
        checked += 1
    assert checked == len(MOVES)


def test_a_mode_that_does_not_close_the_callers_geometry_is_never_a_mode(monkeypatch):
    """The last check alone: with the scaling test fooled (the literal length taken to scale), the
    solver solves the rescaled model; its modes, which do not close the caller's loop (0.037-0.237
    m^2 by the oracle's closure), are "not closed", none is listed, and the input is not complete."""
    m, parameters = literal_3rrr()
    monkeypatch.setattr(solver, "scales_with_lengths", lambda m: True)
    theta = m.home_actuated + np.array(MOVES[0])
    modes = m.forward_pose_all(theta, strict=False)
    rejected = modes.outcome == modes.outcomes.index("not_closed")
    assert int(modes.count) == 0 and not modes.valid.any() and rejected.sum() == 2
    assert not bool(modes.complete()) and int(modes.undecided_roots) == 2
    for pose in modes.passive[rejected]:
        assert max(abs(float(r)) for r in om.closure("planar_3rrr", parameters, theta, pose)) > 0.01
    assert (modes.residual[rejected] > solver.closure_tolerance(m)).all()


@pytest.mark.parametrize("backend", ["numpy", "compiled"])
def test_the_gate_keeps_the_modes_of_a_mechanism_that_scales(backend):
    """The shipped planar 3-RRR (its closure scales): the last check takes nothing away; its modes
    are the oracle's at the same inputs (1e-12)."""
    m = parakin.load("planar_3rrr", backend=backend)
    parameters = dict(zip([p.name for p in m.manifest.parameters], m.params.tolist(), strict=True))
    theta = m.home_actuated + np.array(MOVES[1])
    modes = m.forward_pose_all(theta, strict=False)
    assert not (modes.outcome == modes.outcomes.index("not_closed")).any()
    assert om.match(modes.passive[modes.valid], om.planar_3rrr(parameters, theta).array(), ANGULAR, 0.5) < 1e-12
