"""The total-degree runs' equilibration (generator/start_systems.py, ``equilibration`` and
``total_degree_run``): a system with a known count whose equations are scaled by 1e-6 and 1e6
loses solutions unscaled and keeps every one equilibrated.

Independent sources: s_0 (z0^3 + b0 z1 - r0) = 0, s_1 (z1^3 + b1 z0 - r1) = 0 has no solution at
infinity (the leading forms z0^3, z1^3 meet only at 0), so Bezout's 9; eliminating z1 = (r0 - z0^3)
/ b0 leaves the nonic (r0 - z0^3)^3 + b0^3 (b1 z0 - r1) = 0, whose roots numpy's companion matrix
gives. Constant factors s_k change no solution. The skew 3-RRS (tests/fixtures/rrs3_skew.py: 32
solutions by monodromy) is the slow end-to-end test (tests/test_numeric_leg.py)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("sympy")

import sympy as sp  # noqa: E402
from parakin.generator import start_systems as homotopy  # noqa: E402
from parakin.generator.polynomial_form import PolynomialForm  # noqa: E402

SCALES = (1e-6, 1e6)
B = np.array([0.8 - 0.5j, -0.6 + 0.9j])
R = np.array([1.3 + 0.4j, -0.7 + 1.1j])


def _scaled_cubics() -> tuple[homotopy.Family, np.ndarray, np.ndarray]:
    """The module's system as a family in (b, r), its instance and its 9 solutions (the nonic's)."""
    z, b, r = sp.symbols("z0:2"), sp.symbols("b0:2"), sp.symbols("r0:2")
    equations = [sp.Float(SCALES[k]) * (z[k] ** 3 + b[k] * z[1 - k] - r[k]) for k in range(2)]
    form = PolynomialForm(list(z), equations, [(s, s) for s in (*b, *r)], list(z))
    family = homotopy.Family(form, equations)
    cube = np.polynomial.Polynomial([R[0], 0, 0, -1]) ** 3
    nonic = cube + B[0] ** 3 * np.polynomial.Polynomial([-R[1], B[1]])
    z0 = nonic.roots()
    solutions = np.stack([z0, (R[0] - z0**3) / B[0]], axis=-1)
    return family, np.concatenate([B, R]), solutions


def _matched(found: np.ndarray, solutions: np.ndarray) -> int:
    """How many of ``solutions`` some point of ``found`` is within 1e-8 of."""
    return sum(bool(len(found) and np.abs(found - s).max(-1).min() < 1e-8) for s in solutions)


def test_equilibration_scales_each_equation_by_the_inverse_of_its_size() -> None:
    family, q, _ = _scaled_cubics()
    rows, columns = homotopy.equilibration(family, q)
    # equation k's coefficients are s_k times (1, b_k, -r_k), of sizes 0.9..1.4: r_k is 1 / s_k
    # up to a power of two, and no column is scaled
    assert np.all(np.abs(np.log2(rows * np.array(SCALES))) <= 1.0)
    assert np.all(rows == 2.0 ** np.round(np.log2(rows))) and np.all(columns == 1.0)
    _, fitted = homotopy.equilibration(family, q, columns=True)
    assert np.all(fitted == 2.0 ** np.round(np.log2(fitted))) and abs(np.log2(fitted).mean()) <= 0.5


def test_a_badly_scaled_system_keeps_its_known_count_only_equilibrated() -> None:
    family, q, solutions = _scaled_cubics()
    # the nonic's 9 roots are distinct and solve the scaled equations (to their scale's rounding)
    assert len(solutions) == 9 and homotopy._smallest_gap(solutions) > 1e-3
    assert np.all(np.abs(family.value(solutions, q[None, :])) <= 1e-12 * np.array(SCALES))
    seeds = range(5)
    equilibrated = [homotopy.total_degree_run(family, q, [3, 3], np.random.default_rng(s)) for s in seeds]
    unscaled = [
        homotopy.total_degree_run(family, q, [3, 3], np.random.default_rng(s), equilibrate=False) for s in seeds
    ]
    assert len(equilibrated) == 5 and all(len(f) == 9 and _matched(f, solutions) == 9 for f in equilibrated)
    # unscaled, the 1e-6 equation is still the start system's at the endgame's t = 1e-6: some
    # paths end outside their solution's Newton basin (at these seeds one run of five loses one)
    assert min(_matched(f, solutions) for f in unscaled) < 9


def test_a_stored_solution_at_the_rounding_level_is_verified_in_40_digits() -> None:
    """A Wilkinson polynomial prod_k (z - 0.7 k), k = 1..12, expanded, beside y = s (its roots
    0.7 k are ill-conditioned: rounding in the expanded form leaves Newton steps in doubles of
    1e-10 to 2e-9 at the roots rounded to doubles, as at the skew 3-RRS's). ``_solutions_at``
    accepts those (40-digit Newton returns each to itself) and rejects a root moved by 1e-9 of
    its size, which 40-digit Newton moves back."""
    z, y, r, s = sp.symbols("z y r s")
    equations = [sp.expand(sp.prod([z - k * sp.Rational(7, 10) for k in range(1, 13)])) - r, y - s]
    family = homotopy.Family(PolynomialForm([z, y], equations, [(r, r), (s, s)], [z, y]), equations)
    q = np.zeros(2, complex)
    roots = np.array([[0.7 * k, 0.0] for k in range(1, 13)], dtype=complex)
    size = homotopy.newton_size(family, roots, q)
    assert 1e-10 < size.max() < homotopy.REGULAR_RECHECK  # the doubles' own check cannot tell
    assert homotopy._solutions_at(family, q, roots)
    moved = roots.copy()
    moved[8, 0] *= 1 + 1e-9
    assert not homotopy._solutions_at(family, q, moved)
