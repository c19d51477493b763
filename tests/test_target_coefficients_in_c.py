"""The certificate's target system in one foreign call (every homotopy package's
``NAME_target_coefficients``; issue 33): the same numbers, bit for bit, as the two kernel calls of
``modes._target_coefficients`` at ``modes._family``'s values (inputs near home, far, non-finite),
and a system whose roots are the certified modes (its residual at the certificate's centres at
rounding: an independent check that the coefficients are the system at the inputs)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import parakin
from parakin.solvers import modes
from parakin.studies.sampling import sample_configurations


@pytest.mark.parametrize("name", ["planar_3rrr", "prs3"])
def test_target_coefficients_in_c_are_the_kernels_bit_for_bit(name: str) -> None:
    m: Any = parakin.load(name, backend="compiled")
    assert m.backend.target_coefficients is not None
    info = m.capabilities.forward
    near = sample_configurations(m, 120, spread=0.05, seed=4).actuated[:40]
    far = sample_configurations(m, 120, spread=2.0, seed=5).actuated[:40]
    count = near.shape[0] + far.shape[0]
    theta = np.vstack([near, far, np.full((2, near.shape[1]), np.nan), -near[:3]])
    assert count >= 40
    expected = modes._target_coefficients(m, info, *modes._family(m, info, theta))
    got = modes._certificate_system(m, info, theta)
    assert got.shape == expected.shape and got.dtype == expected.dtype
    bits, reference = got.view(np.int64), expected.view(np.int64)
    assert ((bits == reference) | (np.isnan(got.view(float)) & np.isnan(expected.view(float)))).all()
    assert np.isnan(got[count : count + 2]).any(-1).all() and np.isfinite(got[: near.shape[0]]).all()


def test_the_target_system_vanishes_at_the_certified_roots() -> None:
    m: Any = parakin.load("planar_3rrr", backend="compiled")
    info = m.capabilities.forward
    homotopy = info.homotopy
    theta = sample_configurations(m, 30, spread=0.05, seed=6).actuated[:1]
    c = modes._certificate_system(m, info, theta)[0]
    out = modes.compiled_modes(m, theta)
    ends = out["endpoints"][0, ..., 0] + 1j * out["endpoints"][0, ..., 1]
    checked = 0
    for z in ends[np.isfinite(ends).all(-1)]:
        terms = c * np.prod(z**homotopy.exponents, axis=-1)
        value = np.zeros(homotopy.equation.max() + 1, complex)
        np.add.at(value, homotopy.equation, terms)
        size = np.zeros(value.shape)
        np.add.at(size, homotopy.equation, abs(terms))
        assert (abs(value) <= 1e-9 * np.maximum(size, 1e-300)).all()
        checked += 1
    assert checked >= 4
