"""The value curve's trace test (generator/start_systems.py, ``value_trace_test``), the proof of a new
family's root count: it closes on a complete solution set whose size is known independently and
stays open when one solution is withheld.

Independent sources: the 3-RPR's 6 assembly modes (Gosselin, Sefrioui and Richard 1994; a
sextic), and a system with a known Bezout count whose solutions are written in closed form
(z_k^2 = r_k: 2^n solutions). The Hexaglide (40 poses, 80 solutions with the quaternion's sign)
is the slow test."""

from __future__ import annotations

import itertools
import json
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("sympy")

import sympy as sp  # noqa: E402
from parakin.generator import start_systems as homotopy  # noqa: E402
from parakin.generator.polynomial_form import PolynomialForm, derive  # noqa: E402


def _planar_3rpr() -> tuple[homotopy.Family, np.ndarray, np.ndarray]:
    from parakin.mechanisms import planar_3rpr

    import parakin

    mechanism = planar_3rpr.build()
    assert mechanism.closure is not None
    form = derive(
        list(mechanism.closure.residual), mechanism.passive, mechanism.actuated, list(mechanism.parameters),
        mechanism.angular,
    )  # fmt: skip
    family = homotopy.Family(form, list(form.equations))
    automatic = parakin.load("planar_3rpr", backend="numpy").capabilities.forward_methods["automatic"].homotopy
    assert automatic is not None
    return family, automatic.start_instance, automatic.start


def _squares(n: int) -> tuple[homotopy.Family, np.ndarray, np.ndarray]:
    """z_k^2 + b_k z_{k+1} - r_k = 0 (cyclic, b = 0 at the instance used): Bezout number 2^n,
    reached (2^n regular solutions z_k = +-sqrt(r_k) where b = 0)."""
    z = sp.symbols(f"z0:{n}")
    b = sp.symbols(f"b0:{n}")
    r = sp.symbols(f"r0:{n}")
    equations = [z[k] ** 2 + b[k] * z[(k + 1) % n] - r[k] for k in range(n)]
    form = PolynomialForm(list(z), equations, [(s, s) for s in (*b, *r)], list(z))
    family = homotopy.Family(form, equations)
    roots = np.sqrt(np.array([1.3 + 0.4j, -0.7 + 1.1j, 2.1 - 0.3j, 0.5 - 0.9j][:n]))
    q = np.concatenate([np.zeros(n), roots**2])
    solutions = np.array([roots * np.array(signs) for signs in itertools.product((1, -1), repeat=n)])
    assert [str(p) for p in family.parameters] == [*map(str, b), *map(str, r)]
    return family, q.astype(complex), solutions.astype(complex)


def test_a_known_count_is_proven_and_one_withheld_is_not() -> None:
    family, q, solutions = _squares(3)
    assert np.abs(family.value(solutions, q[None, :])).max() < 1e-14 and len(solutions) == 2**3
    began = time.process_time()
    complete = homotopy.value_trace_test("squares", family, q, solutions, np.random.default_rng(1))
    incomplete = homotopy.value_trace_test("squares", family, q, solutions[1:], np.random.default_rng(1))
    assert complete["complete"] and complete["deviation"] < homotopy.VALUE_TRACE_TOLERANCE
    assert complete["witnesses"] > 0
    assert not incomplete["complete"] and incomplete["deviation"] > 1e-6
    assert time.process_time() - began < 10


@pytest.mark.slow
def test_the_3rpr_count_is_proven_and_one_withheld_is_not() -> None:
    family, q, solutions = _planar_3rpr()
    assert len(solutions) == 6  # the 3-RPR's six assembly modes
    complete = homotopy.value_trace_test("planar_3rpr", family, q, solutions, np.random.default_rng(4))
    assert complete["complete"] and complete["deviation"] < homotopy.VALUE_TRACE_TOLERANCE
    partial = np.delete(solutions, 5, axis=0)
    verdict = homotopy.value_trace_test("planar_3rpr", family, q, partial, np.random.default_rng(4))
    assert not verdict["complete"] and verdict["deviation"] > 1e-6


@pytest.mark.slow
def test_value_monodromy_finds_every_solution_from_one() -> None:
    """From one solution, loops in the equations' values reach all 6 of the 3-RPR (z-space is
    irreducible: no second component is out of reach)."""
    for family, q, solutions in (_planar_3rpr(),):
        found = homotopy.value_monodromy("test", family, q, solutions[:1], [], np.random.default_rng(3), 10)
        assert len(found) == len(solutions)
        assert all(np.abs(found - z).max(-1).min() < 1e-8 for z in solutions)


def test_the_40_digit_refinement_keeps_the_stored_start_system() -> None:
    """The monomial-table Newton (coefficients evaluated once) reproduces the stored, sorted
    start system of planar_3rpr bit for bit from slightly perturbed points."""
    family, q, solutions = _planar_3rpr()
    rng = np.random.default_rng(2)
    moved = solutions + 1e-9 * (rng.normal(size=solutions.shape) + 1j * rng.normal(size=solutions.shape))
    refined = np.array(homotopy._refine_exact(family, q, moved[::-1]))
    assert np.array_equal(refined, solutions)


@pytest.mark.slow
def test_the_hexaglide_generates_with_its_count_proven_within_a_minute(tmp_path: Path) -> None:
    """A user's Hexaglide (6-PUS, 40 poses: 80 solutions with the quaternion's sign) generates with
    no stored start systems, its count proven by the value curve's trace test, within 60 s of CPU
    (it took 232 s by two total-degree runs of 8192 paths)."""
    import os

    import parakin
    from parakin.interfaces.cli import main

    source = Path(__file__).parent / "fixtures" / "hexaglide.py"
    cache = tmp_path / "cache"
    cache.mkdir(mode=0o700)
    os.environ["PARAKIN_CACHE"] = str(cache)
    try:
        began = time.process_time()
        assert main(["generate", str(source), "--out", str(tmp_path / "pkg")]) == 0
        seconds = time.process_time() - began
        # the record cached by the first build is reused as it is (no total-degree runs added)
        began = time.process_time()
        assert main(["generate", str(source), "--out", str(tmp_path / "again")]) == 0
        again = time.process_time() - began
    finally:
        del os.environ["PARAKIN_CACHE"]
    first, second = ((tmp_path / folder / "manifest.json").read_text() for folder in ("pkg", "again"))
    assert first == second and again < seconds / 2
    proof = parakin.load(tmp_path / "pkg", backend="numpy").capabilities.forward_methods["automatic"]
    assert proof.homotopy is not None and proof.homotopy.root_count is not None
    count = proof.homotopy.root_count
    # 80 for the family; 72 where the derivation passes the parameter values: the fixture's rails
    # are shared (y1 = y2, y3 = y6, y4 = y5), and 8 of the 80 are at infinity there
    # (tests/test_family_coincidences.py)
    subfamily = json.loads(first)["capabilities"]["forward"]["methods"]["automatic"].get("subfamily", {})
    expected = 72 if subfamily.get("identical") else 80
    assert count.count == expected and count.proven and count.method.startswith(homotopy.VALUE_TRACE_METHOD)
    assert count.deviation < homotopy.VALUE_TRACE_TOLERANCE
    assert seconds < 60, f"{seconds:.0f} s of CPU"
