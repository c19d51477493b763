"""Real-root isolation, written twice: generator/templates/real_roots.h (C, compiled here) and
parakin.solvers.polynomial.isolate_real_roots (NumPy). Checked against mpmath.polyroots at high precision,
on constructed multiple and near-multiple roots, and C against NumPy."""

import ctypes
import shutil
import subprocess
from pathlib import Path

import mpmath
import numpy as np
import pytest

from parakin.solvers.polynomial import (
    MAX_DEGREE,
    ROOT_CLUSTER,
    ROOT_NEAR,
    ROOT_SIMPLE,
    IsolatedRoots,
    isolate_real_roots,
)

HEADER = Path(__file__).resolve().parent.parent / "generator" / "templates" / "real_roots.h"
P = np.polynomial.polynomial
EPS = np.finfo(float).eps
WRAPPER = r"""
#include "real_roots.h"
void pk_batch(const double* c, int n, int degree, double leading_tolerance, double near_tolerance,
              double* roots, int* kind, int* count, int* at_infinity)
{
    int i;
    for (i = 0; i < n; ++i)
        count[i] = pk_real_roots(c + i * (degree + 1), degree, leading_tolerance, near_tolerance,
                                 roots + i * degree, kind + i * degree, at_infinity + i);
}
"""


@pytest.fixture(scope="module")
def c_batch(tmp_path_factory):
    """pk_real_roots over a batch, built with -Wall -Wextra -Werror (a warning fails the build);
    the result as IsolatedRoots. No contraction: a fused multiply-add would change last bits."""
    compiler = shutil.which("cc")
    if compiler is None:
        pytest.skip("no C compiler (cc)")
    folder = tmp_path_factory.mktemp("real_roots")
    (folder / "wrapper.c").write_text(WRAPPER)
    library = folder / "libreal_roots.so"
    flags = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-O2", "-shared", "-fPIC", "-ffp-contract=off"]
    built = subprocess.run(
        [compiler, *flags, f"-I{HEADER.parent}", str(folder / "wrapper.c"), "-o", str(library), "-lm"],
        capture_output=True,
        text=True,
    )
    assert built.returncode == 0, built.stderr
    function = ctypes.CDLL(str(library)).pk_batch
    pointer = np.ctypeslib.ndpointer
    function.argtypes = [pointer(np.float64), ctypes.c_int, ctypes.c_int, ctypes.c_double, ctypes.c_double]
    function.argtypes += [pointer(np.float64), pointer(np.int32), pointer(np.int32), pointer(np.int32)]

    def run(coefficients, leading_tolerance=1e-13, near_tolerance=1e-9):
        c = np.ascontiguousarray(np.atleast_2d(coefficients), dtype=np.float64)
        n, degree = c.shape[0], c.shape[1] - 1
        roots, kind = np.full((n, max(degree, 1)), np.nan), np.full((n, max(degree, 1)), -1, np.int32)
        count, at_infinity = np.zeros(n, np.int32), np.zeros(n, np.int32)
        function(c, n, degree, leading_tolerance, near_tolerance, roots, kind, count, at_infinity)
        padding = np.arange(max(degree, 1)) >= count[:, None]
        roots[padding], kind[padding] = np.nan, -1
        return IsolatedRoots(roots[:, :degree], kind[:, :degree].astype(np.int8), count, at_infinity, count == -1)

    return run


def both(c_batch, coefficients, **tolerances) -> IsolatedRoots:
    """The NumPy result for a batch (n, degree + 1), after checking that C decided the same."""
    ours, theirs = isolate_real_roots(coefficients, **tolerances), c_batch(coefficients, **tolerances)
    np.testing.assert_array_equal(theirs.vanishing, ours.vanishing)
    np.testing.assert_array_equal(np.where(theirs.vanishing, 0, theirs.count), ours.count)
    np.testing.assert_array_equal(theirs.kind, ours.kind)
    np.testing.assert_array_equal(theirs.at_infinity, ours.at_infinity)
    np.testing.assert_array_equal(np.isnan(theirs.roots), np.isnan(ours.roots))
    gap = np.nan_to_num(np.abs(theirs.roots - ours.roots) / (1 + np.abs(ours.roots)))
    assert gap.max(initial=0.0) <= 1e-12
    return ours


def no_real_roots(rng, degree):
    """A product of quadratics whose roots have |Im| in [0.1, 2]."""
    c = np.array([rng.uniform(0.5, 2.0)])
    for _ in range(degree // 2):
        re, im = rng.uniform(-2, 2), rng.uniform(0.1, 2)
        c = P.polymul(c, [re * re + im * im, -2 * re, 1.0])
    return c


def random_polynomial(rng, degree, case):
    """Random coefficients (0), known real roots times complex pairs (1), the same with pairs
    close to the real axis, |Im| in [1e-5, 1e-2] (2)."""
    if case == 0:
        return rng.standard_normal(degree + 1)
    n_real = int(rng.integers(0, degree + 1))
    n_real += (degree - n_real) % 2
    c = P.polyfromroots(rng.uniform(-3, 3, n_real)) * rng.uniform(0.5, 2)
    for _ in range((degree - n_real) // 2):
        re, im = rng.uniform(-3, 3), (rng.uniform(0.05, 2) if case == 1 else 10 ** rng.uniform(-5, -2))
        c = P.polymul(c, [re * re + im * im, -2 * re, 1.0])
    return c


@pytest.mark.parametrize("count", [150, pytest.param(2400, marks=pytest.mark.slow)])
def test_real_roots_match_mpmath_polyroots(c_batch, count):
    """mpmath.polyroots at 40 digits, where its real roots are separated by > 1e-6 (relative) and
    its complex ones have |Im| > 1e-6: exactly the oracle's real roots, as simple roots, to
    1e-10 (1 + |x|) or, for roots so ill-conditioned that one ulp in the coefficients moves them
    further, to eps S(x) / |p'(x)|. Random coefficients and pairs with |Im| >= 0.05: nothing else.
    Pairs with |Im| down to 1e-5: possibly clusters or near-real candidates too (about 1 in 5),
    each at z with an oracle root within twice the distance at which the second-order model
    p(z) + p''(z) (x - z)^2 / 2 reaches zero for |p(z)| = max(1e-9 S(z), 64 eps max|c| sum |z|^k)
    (the near test's two scales: backward error, and the coefficients' absolute rounding)."""
    rng = np.random.default_rng(20240601)
    cases = [(i % 3, random_polynomial(rng, int(rng.integers(2, 11)), i % 3)) for i in range(count)]
    checked = conditioned = flagged_total = 0
    for case, c in cases:
        with mpmath.workdps(40):
            exact = mpmath.polyroots([mpmath.mpf(v) for v in c[::-1]], maxsteps=200, extraprec=40)
            exact = np.array([complex(r) for r in exact])
        is_real = np.abs(exact.imag) <= 1e-20 * (1 + np.abs(exact))
        real, pairs = np.sort(exact.real[is_real]), exact[~is_real]
        if np.any(np.abs(pairs.imag) <= 1e-6 * (1 + np.abs(pairs))):
            continue
        if np.any(np.diff(real) <= 1e-6 * (1 + np.abs(real[1:]))):
            continue
        found = both(c_batch, c[None])
        roots, kind = found.roots[0, : found.count[0]], found.kind[0, : found.count[0]]
        assert found.at_infinity[0] == 0 and not found.vanishing[0]
        simple, flagged = roots[kind == ROOT_SIMPLE], roots[kind != ROOT_SIMPLE]
        assert case == 2 or flagged.size == 0, (c, roots, kind, exact)
        assert simple.size == real.size, (c, roots, kind, real)
        size = np.abs(c) @ np.abs(real)[None, :] ** np.arange(c.size)[:, None]
        conditioning = EPS * size / np.abs(P.polyval(real, P.polyder(c)))
        error, allowed = np.abs(simple - real), 1e-10 * (1 + np.abs(real))
        assert np.all(error <= np.maximum(allowed, conditioning)), (c, error, conditioning)
        conditioned += np.count_nonzero(error > allowed)
        for z in flagged:
            noise = 64 * EPS * np.abs(c).max() * P.polyval(abs(z), np.ones_like(c))  # coefficients' rounding
            scale = max(1e-9 * P.polyval(abs(z), np.abs(c)), noise)
            reach = np.sqrt(2 * scale / abs(P.polyval(z, P.polyder(c, 2))))
            assert np.min(np.abs(exact - z)) <= 2 * reach, (c, z, exact)
        flagged_total += flagged.size
        checked += 1
    assert checked >= 0.9 * count and conditioned <= 0.01 * checked, (checked, conditioned)
    # flagged roots: 21 on the 150 polynomials, 47 on 300, 109 on 600; at least 1 per 24 polynomials
    assert flagged_total >= count // 24, flagged_total  # 6 of 150; 100 of 2400, as before


@pytest.mark.parametrize(
    ("factor", "distance", "minimum_cluster_share"),
    [([1.0, 1.0], 1e-7, 0.95), ([1.0, 1.0, 1.0], 1e-4, 0.9), ([1.0, 1.0 + 1e-9], 1e-7, 0.95)],
    ids=["(x-a)^2", "(x-a)^3", "roots 1e-9 apart"],
)
def test_multiple_roots_are_never_lost(c_batch, factor, distance, minimum_cluster_share):
    """(x - a)^k q(x), q without real roots, built with rounding: at least one root within
    `distance` (1 + |a|) of a, on 300 random a and q; most are reported as one cluster (kind 1),
    the rest as close simple roots or a near-real candidate, never as nothing."""
    rng = np.random.default_rng(11)
    clusters = 0
    for _ in range(300):
        a = rng.uniform(-2, 2)
        c = P.polymul(P.polyfromroots(a * np.array(factor)), no_real_roots(rng, 2 * int(rng.integers(0, 4))))
        found = both(c_batch, c[None])
        roots, kind = found.roots[0, : found.count[0]], found.kind[0, : found.count[0]]
        close = np.abs(roots - a) <= distance * (1 + abs(a))
        assert close.any(), (a, c, roots, kind)
        clusters += list(kind[close]) == [ROOT_CLUSTER]
    assert clusters >= minimum_cluster_share * 300, clusters


def test_exact_double_root_is_one_cluster(c_batch):
    """(x - 0.5)^2 (x^2 + 1) has exact coefficients: one cluster, at the critical point next to
    0.5 (a root of p', refined to a few ulps)."""
    found = both(c_batch, P.polymul([0.25, -1.0, 1.0], [1.0, 0.0, 1.0])[None])
    assert found.count[0] == 1 and found.kind[0, 0] == ROOT_CLUSTER
    assert abs(found.roots[0, 0] - 0.5) <= 8 * EPS


@pytest.mark.parametrize("a", [-1.0, 0.25, 1.0, 1.5])
def test_near_real_pair_is_a_candidate(c_batch, a):
    """(x - a)^2 + 1e-14 (roots a +- 1e-7 i): one near-real candidate (kind 2) at a. Its backward
    error 1e-14 / S(a) lies between one ulp (cluster) and near_tolerance = 1e-9."""
    found = both(c_batch, np.array([[a * a + 1e-14, -2 * a, 1.0]]))
    assert found.count[0] == 1 and found.kind[0, 0] == ROOT_NEAR and found.roots[0, 0] == a


def test_near_tolerance_is_the_backward_error_of_the_pair(c_batch):
    """(x - 1)^2 + 1e-8: backward error 1e-8 / S(1) = 2.5e-9, a candidate only from 2.5e-9 up."""
    c = np.array([[1.0 + 1e-8, -2.0, 1.0]])
    assert both(c_batch, c).count[0] == 0
    found = both(c_batch, c, near_tolerance=1e-8)
    assert found.count[0] == 1 and found.kind[0, 0] == ROOT_NEAR


@pytest.mark.parametrize(("lead", "at_infinity"), [([0.0], 1), ([3e-17], 1), ([0.0, 0.0], 2), ([1e-17, 0.0], 2)])
def test_vanishing_leading_coefficients_are_roots_at_infinity(c_batch, lead, at_infinity):
    """(x - 1)(x - 2) padded with leading coefficients <= 1e-13 max|c|: the finite roots stay."""
    found = both(c_batch, np.array([[2.0, -3.0, 1.0, *lead]]))
    assert found.at_infinity[0] == at_infinity and found.count[0] == 2
    np.testing.assert_allclose(found.roots[0, :2], [1.0, 2.0], rtol=1e-14)


def test_small_kept_leading_coefficient_gives_a_huge_root(c_batch):
    """(x - 1)(x - 2)(1 + 1e-12 x): the leading coefficient is above the tolerance, so the root at
    -1e12 is finite and found (bisection in the exponent from the Cauchy bound)."""
    found = both(c_batch, P.polymul([2.0, -3.0, 1.0], [1.0, 1e-12])[None])
    assert found.at_infinity[0] == 0 and found.count[0] == 3
    np.testing.assert_allclose(found.roots[0], [-1e12, 1.0, 2.0], rtol=1e-12)


def test_vanishing_and_constant_polynomials(c_batch):
    """All zero, non-finite or below 1e-300: vanishing (C returns -1). A nonzero constant: no roots;
    stored as degree 2 it has two roots at infinity. 5 x^2: a cluster at 0."""
    c = np.array([[0.0, 0.0, 0.0], [0.0, np.nan, 1.0], [1e-310, 0.0, 0.0], [5.0, 0.0, 0.0], [0.0, 0.0, 5.0]])
    found = both(c_batch, c)
    np.testing.assert_array_equal(found.vanishing, [True, True, True, False, False])
    np.testing.assert_array_equal(c_batch(c).count, [-1, -1, -1, 0, 1])
    np.testing.assert_array_equal(found.at_infinity, [0, 0, 0, 2, 0])
    assert found.kind[4, 0] == ROOT_CLUSTER and found.roots[4, 0] == 0.0
    constant = isolate_real_roots([[5.0]])
    assert constant.roots.shape == (1, 0) and constant.count[0] == 0 and not constant.vanishing[0]


def test_batch_shapes_and_mixed_degrees():
    """Any leading batch shape, empty batches; entries of different effective degree in one batch
    give what each gives alone."""
    rng = np.random.default_rng(3)
    c = rng.standard_normal((2, 3, 7))
    c[0, 1, 4:] = 0.0
    c[1, 2, 6] = 1e-16
    batch = isolate_real_roots(c)
    assert batch.roots.shape == (2, 3, 6) and batch.count.shape == (2, 3)
    for index in np.ndindex(2, 3):
        alone = isolate_real_roots(c[index])
        np.testing.assert_array_equal(batch.roots[index], alone.roots)
        np.testing.assert_array_equal(batch.kind[index], alone.kind)
        assert batch.at_infinity[index] == alone.at_infinity
    assert batch.at_infinity[0, 1] == 3 and batch.at_infinity[1, 2] == 1
    empty = isolate_real_roots(np.zeros((0, 4, 5)))
    assert empty.roots.shape == (0, 4, 4) and empty.count.shape == (0, 4)
    with pytest.raises(ValueError, match="MAX_DEGREE"):
        isolate_real_roots(np.ones(MAX_DEGREE + 2))


def test_degree_above_maximum_is_refused_in_c(c_batch):
    assert c_batch(np.ones((1, MAX_DEGREE + 2))).count[0] == -2


def test_c_and_numpy_agree(c_batch):
    """Same counts, kinds and roots at infinity, roots to 1e-12, on 10,400 polynomials of degrees
    2, 4, 6, 8: random ones, ones with a double, near-double ((x - a)^2 + eta, eta from 0 to
    1e-8) or close pair of roots, and ones with leading coefficients dropped."""
    rng = np.random.default_rng(5)
    checked = 0
    for degree in (2, 4, 6, 8):
        c = rng.standard_normal((2600, degree + 1))
        for i in range(1000):
            a, eta = rng.uniform(-2, 2), [0.0, 1e-16, 1e-14, -1e-14, 1e-12, 1e-10, 1e-8][i % 7]
            c[i] = P.polymul(P.polyfromroots([a, a]) + [eta, 0, 0], rng.standard_normal(degree - 1))
        c[1000:1300, -1] = 0.0
        c[1300:1600, -2:] *= 1e-15
        found = both(c_batch, c)
        assert np.count_nonzero(found.kind == ROOT_NEAR) > 50 and np.count_nonzero(found.kind == ROOT_CLUSTER) > 50
        checked += len(c)
    found = both(c_batch, rng.standard_normal((100, 42)))  # odd degree 41: at least one root
    assert checked >= 10_000 and found.count.min() >= 1


def test_wilkinson_polynomial_all_twenty_roots(c_batch):
    """prod_{k=1..20} (x - k) (coefficients up to 20! ~ 2.4e18, so leading_tolerance=0 keeps the
    leading 1): 20 simple roots. Their condition numbers reach 1e13, so double precision gets them
    to ~3e-2 (np.roots: ~7e-2); every critical value is above one ulp of backward error (1.77 at
    least), so none is taken for a cluster."""
    c = P.polyfromroots(np.arange(1, 21))
    found = both(c_batch, c[None], leading_tolerance=0.0)
    assert found.count[0] == 20 and np.all(found.kind == ROOT_SIMPLE)
    np.testing.assert_allclose(found.roots[0], np.arange(1, 21), atol=0.05)
