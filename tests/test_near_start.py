"""The start near home (generator/near_start.py, the manifest's ``near``): inputs near a
mechanism's home begin their paths at a third start instance next to it. Checked against
independent sources: its solutions are roots of the family there (the generated monomials
kernel, not the generator's 40-digit Newton that refined them), all distinct and as many as the
proven root count; its centre is the family kernel's values at the home in the solver's
numbers; the roots reached from it are the roots reached from the stored first start (a separate
set of paths, in projective space); the C driver takes it where NumPy does (its path counts);
and an input of another geometry does not take it."""

from __future__ import annotations

import numpy as np
import pytest

import parakin
from parakin.packages.compiled import CompiledBackend
from parakin.solvers import modes as modes_module
from parakin.solvers.path_tracking import circle_parameter, path_pairs
from parakin.studies.sampling import sample_configurations


def _unit_free(m: parakin.Mechanism, theta: np.ndarray) -> tuple[parakin.Mechanism, np.ndarray]:
    """The mechanism and inputs in the all-modes solver's numbers (lengths over its unit)."""
    scaled = m._unit_free
    if scaled is None:
        return m, theta
    lengths = np.array([v.unit == "m" for v in m.manifest.actuated])
    return scaled[0], np.where(lengths, theta / scaled[1], theta)


def _near_families() -> list[str]:
    names = []
    for name in parakin.available():
        forward = parakin.load(name, backend="numpy").capabilities.forward
        if forward is not None and forward.homotopy is not None and forward.homotopy.near is not None:
            names.append(name)
    return names


@pytest.mark.parametrize("name", _near_families())
def test_near_solutions_are_the_roots_there(name: str) -> None:
    """Each stored near solution zeroes the family at the near instance (the monomials kernel
    and the term table, evaluated here), they are distinct, one per path of the proven count,
    and pair under the sign symmetry as the first start's do (the C driver's ``partner``)."""
    m = parakin.load(name, backend="numpy")
    info = m.capabilities.forward
    assert info is not None and info.homotopy is not None and info.homotopy.near is not None
    homotopy, near = info.homotopy, info.homotopy.near
    a, b = homotopy.circle_constants
    free = len(homotopy.free)
    u = near.instance[free:]
    # (C, S, D) of each angle from u, as the generated homotopy moves them along the circle
    one_minus, a_minus = 1 - u, a - b * u
    circle = np.stack([one_minus**2 - a_minus**2, 2 * a_minus * one_minus, one_minus**2 + a_minus**2], -1)
    values = np.concatenate([near.instance[:free], circle.ravel()])[None, :]
    coefficients = modes_module._monomials(m, info)(values)[0]
    z = near.solutions
    monomials = np.prod(z[:, None, :] ** homotopy.exponents[None], axis=-1)
    residual = np.zeros(z.shape, dtype=complex)
    np.add.at(residual.T, homotopy.equation, (coefficients * monomials).T)
    scale = np.abs(coefficients * monomials).max(-1, keepdims=True)
    assert (np.abs(residual) <= 1e-12 * scale).all(), np.abs(residual).max()
    assert homotopy.root_count is not None and len(z) == homotopy.root_count.count
    gaps = np.where(np.eye(len(z), dtype=bool), np.inf, np.abs(z[:, None] - z[None]).max(-1))
    assert gaps.min() > 1e-6
    first, second = (path_pairs(homotopy.exponents, homotopy.equation, s) for s in (homotopy.start, z))
    assert (first is None) == (second is None)
    if first is not None and second is not None:
        assert np.array_equal(first.partner, second.partner)


@pytest.mark.parametrize("name", ["prs3", "planar_3rrr"])
def test_centre_is_the_home_in_the_solver_numbers(name: str) -> None:
    """The near start's centre equals the family kernel's values (free values, then the circle
    parameter of each angle) at the home actuated values, in the solver's unit-free numbers."""
    m = parakin.load(name, backend="numpy")
    info = m.capabilities.forward
    assert info is not None and info.homotopy is not None and info.homotopy.near is not None
    scaled, theta = _unit_free(m, m.home_actuated[None])
    free, angles = modes_module._family(scaled, info, theta)
    point = np.concatenate([free[0], circle_parameter(angles[0], *info.homotopy.circle_constants)])
    assert np.allclose(point, info.homotopy.near.center, rtol=1e-5, atol=1e-12)
    assert modes_module.first_instances(scaled, info, theta).tolist() == [2]


@pytest.mark.parametrize("name", ["prs3", "planar_3rrr"])
def test_the_same_roots_as_from_the_first_start(name: str) -> None:
    """Near home the roots reached from the near start (the all-modes pipeline) are those
    reached from the stored first start along other paths (every path again, in projective
    space): each endpoint of either run is one of the other's."""
    m = parakin.load(name, backend="numpy")
    info = m.capabilities.forward
    assert info is not None and info.homotopy is not None
    inputs = sample_configurations(m, 18, spread=0.1, seed=3).actuated[:6]
    scaled, theta = _unit_free(m, inputs)
    assert (modes_module.first_instances(scaled, info, theta) == 2).all()
    near = modes_module.numpy_modes(scaled, theta, info)["endpoints"]
    first = modes_module.numpy_modes(scaled, theta, info, retrack=modes_module.Retrack(0))["endpoints"]
    checked = 0
    for here, there in ((near, first), (first, near)):
        z, w = here[..., 0] + 1j * here[..., 1], there[..., 0] + 1j * there[..., 1]
        for i in range(len(theta)):
            ends, others = z[i][np.isfinite(z[i]).all(-1)], w[i][np.isfinite(w[i]).all(-1)]
            assert len(ends) == info.homotopy.start.shape[0]
            distance = np.abs(ends[:, None] - others[None]).max(-1).min(-1)
            assert (distance <= 1e-8 * (1 + np.abs(ends).max(-1))).all(), distance
            checked += len(ends)
    assert checked >= 2 * 6 * 6


def test_the_c_driver_takes_it_where_numpy_does() -> None:
    """prs3 near home: the C tracker's steps per path are those of the near start (about 5,
    against about 26 from the first start at the same inputs), and an input of the same
    mechanism loaded with a platform three times as wide (its family values far from home) takes
    the first."""
    m = parakin.load("prs3", backend="compiled")
    backend = m.backend
    assert isinstance(backend, CompiledBackend)
    inputs = sample_configurations(m, 30, spread=0.05, seed=5).actuated[:10]
    with backend.counting() as counts:
        m.forward_pose_all(inputs, strict=False)
    assert counts.paths == 10 * 16 and counts.steps / counts.paths < 10
    other = parakin.load("prs3", backend="compiled", r_p=3 * m.parameters["r_p"])
    info = other.capabilities.forward
    assert info is not None
    scaled, theta = _unit_free(other, other.home_actuated[None])
    assert modes_module.first_instances(scaled, info, theta).tolist() == [0]
    other_backend = other.backend
    assert isinstance(other_backend, CompiledBackend)
    with other_backend.counting() as counts:
        other.forward_pose_all(other.home_actuated, strict=False)
    assert counts.paths == 16 and counts.steps / counts.paths > 15
