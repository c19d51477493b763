"""parakin.solvers.certify: Krawczyk certificates of roots, checked against systems whose roots are known
exactly (products of linear factors with integer or Gaussian-integer roots: exact coefficients)."""

import itertools

import numpy as np
import pytest

from parakin.errors import BadInputError
from parakin.solvers.certify import _monomials, _System, certify_roots

pytestmark = pytest.mark.filterwarnings("error")  # certify_roots never warns, NaN rows included


# ---------------------------------------------------------------- polynomials as {exponents: coefficient}
def var(i, n):
    return {tuple(int(k == i) for k in range(n)): 1}


def const(value, n):
    return {(0,) * n: value}


def add(*polys):
    out = {}
    for p in polys:
        for e, v in p.items():
            out[e] = out.get(e, 0) + v
    return {e: v for e, v in out.items() if v != 0}


def mul(*polys):
    out = polys[0]
    for q in polys[1:]:
        acc = {}
        for (e, v), (f, w) in itertools.product(out.items(), q.items()):
            key = tuple(a + b for a, b in zip(e, f, strict=True))
            acc[key] = acc.get(key, 0) + v * w
        out = {e: v for e, v in acc.items() if v != 0}
    return out


def lin(i, root, n):  # z_i - root
    return add(var(i, n), const(-root, n))


def sparse(polys):
    """(coefficients, exponents, equation) of a list of polynomials."""
    rows = [(k, e, v) for k, p in enumerate(polys) for e, v in sorted(p.items())]
    return (
        np.array([v for _, _, v in rows], dtype=complex),
        np.array([e for _, e, _ in rows], dtype=int),
        np.array([k for k, _, _ in rows], dtype=int),
    )


def inside(cert, exact):
    """Per certified root: how many exact roots its box holds (max-norm distance <= radius)."""
    distance = abs(cert.center[:, None, :] - np.asarray(exact)[None, :, :]).max(-1)
    return (distance <= cert.radius[:, None]).sum(-1)


# ---------------------------------------------------------------- known roots
def test_square_root_of_two():
    z = var(0, 1)
    c, e, q = sparse([add(mul(z, z), const(-2, 1))])
    s = np.sqrt(2.0)
    cert = certify_roots(c, e, q, np.array([[s + 1e-12], [-s]]))
    assert cert.unique.all() and (cert.real == 1).all()
    assert cert.distinct and cert.certified_distinct == 2
    assert (abs(abs(cert.center[:, 0]) - np.sqrt(2)) <= cert.radius).all()
    assert (cert.radius < 1e-12).all()
    cert = certify_roots(*sparse([add(mul(z, z), const(2, 1))]), np.array([[1j * s], [-1j * s]]))
    assert cert.unique.all() and (cert.real == -1).all() and cert.certified_distinct == 2


def test_circle_and_line():
    n = 2
    circle = add(mul(var(0, n), var(0, n)), mul(var(1, n), var(1, n)), const(-25, n))
    c, e, q = sparse([circle, add(var(0, n), mul(const(-1, n), var(1, n)), const(-1, n))])  # x - y = 1
    exact = np.array([[4, 3], [-3, -4]], dtype=complex)
    cert = certify_roots(c, e, q, exact * (1 + 1e-11))
    assert cert.unique.all() and (cert.real == 1).all() and cert.certified_distinct == 2
    assert (inside(cert, exact) == 1).all()
    # x = 2 meets x^2 + y^2 = 1 at (2, +-i sqrt 3): non-real
    unit = add(mul(var(0, n), var(0, n)), mul(var(1, n), var(1, n)), const(-1, n))
    c, e, q = sparse([unit, lin(0, 2, n)])
    cert = certify_roots(c, e, q, np.array([[2, 1j * np.sqrt(3)], [2, -1j * np.sqrt(3)]]))
    assert cert.unique.all() and (cert.real == -1).all() and cert.certified_distinct == 2


def product_system():
    """(x - 1)(x^2 + 4), (y - 2)(y + x), (z - x)(z - 1 - y): 12 simple roots, 4 real."""
    n = 3
    x, y, z = (var(i, n) for i in range(n))
    polys = [
        mul(lin(0, 1, n), add(mul(x, x), const(4, n))),
        mul(lin(1, 2, n), add(y, x)),
        mul(add(z, mul(const(-1, n), x)), add(z, const(-1, n), mul(const(-1, n), y))),
    ]
    roots = [(a, b, g) for a in (1, 2j, -2j) for b in (2, -a) for g in (a, 1 + b)]
    return sparse(polys), np.array(roots, dtype=complex)


def test_product_system_all_roots():
    (c, e, q), exact = product_system()
    assert len({tuple(r) for r in exact}) == 12
    rng = np.random.default_rng(1)
    candidates = exact + 1e-10 * (rng.standard_normal(exact.shape) + 1j * rng.standard_normal(exact.shape))
    cert = certify_roots(c, e, q, candidates)
    assert cert.unique.all() and cert.distinct and cert.certified_distinct == 12
    real = (exact.imag == 0).all(-1)
    assert real.sum() == 4
    np.testing.assert_array_equal(cert.real, np.where(real, 1, -1))
    assert (inside(cert, exact) == 1).all()
    # without the promise of real coefficients nothing is certified real; non-real stays decided
    cert = certify_roots(c, e, q, candidates, real_coefficients=False)
    np.testing.assert_array_equal(cert.real, np.where(real, 0, -1))
    # complex coefficients are never taken as real, whatever the flag says
    cert = certify_roots(c * np.exp(0.3j), e, q, candidates)
    assert cert.unique.all() and (cert.real <= 0).all()


def test_point_away_from_a_root_is_not_certified():
    (c, e, q), exact = product_system()
    cert = certify_roots(c, e, q, exact + 1e-2)
    assert not cert.unique.any() and np.isnan(cert.radius).all() and (cert.real == 0).all()
    assert cert.certified_distinct == 0 and cert.distinct


def test_double_roots_are_not_certified():
    square = sparse([mul(var(0, 1), var(0, 1))])  # z^2 = 0
    cert = certify_roots(*square, np.array([[0.0], [1e-8], [1e-300]]))
    assert not cert.unique.any()
    n = 2  # (x - 1)^2 = 0, y = x: two coincident roots at (1, 1)
    c, e, q = sparse([mul(lin(0, 1, n), lin(0, 1, n)), add(var(1, n), mul(const(-1, n), var(0, n)))])
    cert = certify_roots(c, e, q, np.array([[1, 1], [1 + 1e-9, 1], [1 - 1e-7, 1 + 1e-7]], dtype=complex))
    assert not cert.unique.any() and cert.certified_distinct == 0


def test_roots_1e9_apart_overlap():
    # z^2 - eps^2, roots +-5e-10 (1e-9 apart). Near z = 1 such a pair is beyond double precision
    # (rounding moves the roots by sqrt(u) ~ 1e-8); near the origin both are well conditioned.
    eps = 5e-10
    c, e, q = sparse([add(mul(var(0, 1), var(0, 1)), const(-(eps**2), 1))])
    twin = np.array([[eps * (1 + 1e-12)], [eps * (1 - 1e-12)]])
    cert = certify_roots(c, e, q, twin)
    assert cert.unique.all() and (cert.real == 1).all()
    assert not cert.distinct and cert.certified_distinct == 1
    assert (cert.radius < 1e-12 * eps).all()
    cert = certify_roots(c, e, q, np.concatenate([twin, [[-eps]]]))
    assert cert.unique.all() and not cert.distinct and cert.certified_distinct == 2


def projective_system(rng):
    """(x - w)(x + 2w), (y - 3w)(y^2 + x^2) and a random complex patch a.(x, y, w) = 1."""
    n = 3
    x, y, w = (var(i, n) for i in range(n))
    minus = const(-1, n)
    patch_coefficients = rng.standard_normal(3) + 1j * rng.standard_normal(3)
    patch = add(*(mul(const(a, n), var(i, n)) for i, a in enumerate(patch_coefficients)), minus)
    polys = [
        mul(add(x, mul(minus, w)), add(x, mul(const(2, n), w))),
        mul(add(y, mul(const(-3, n), w)), add(mul(y, y), mul(x, x))),
        patch,
    ]
    points = np.array([[1, 3, 1], [1, 1j, 1], [1, -1j, 1], [-2, 3, 1], [-2, 2j, 1], [-2, -2j, 1]], dtype=complex)
    roots = points / (points @ patch_coefficients)[:, None]
    return sparse(polys), roots, np.array([1, -1, -1, 1, -1, -1])


def test_homogeneous_real_in_the_chart():
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(5):
        (c, e, q), roots, expected = projective_system(rng)
        assert (abs(roots.imag) > 1e-3).any(-1).all()  # every patch solution has complex coordinates
        cert = certify_roots(c, e, q, roots, homogeneous=[0, 1, 2], patch_equation=2)
        assert cert.unique.all() and cert.distinct and cert.certified_distinct == 6
        np.testing.assert_array_equal(cert.real, expected)
        checked += 6
        # taken as a plain system (complex patch coefficients), no root is certified real
        cert = certify_roots(c, e, q, roots)
        assert cert.unique.all() and (cert.real <= 0).all()
    assert checked == 30


def test_homogeneous_with_other_unknowns():
    # [x : w] homogeneous, t an ordinary unknown: (x - w)(x + 2w) = 0, t^2 = 4 or t^2 = -4
    n = 3
    x, w, t = (var(i, n) for i in range(n))
    a = np.array([0.3 - 1.1j, 0.7 + 0.4j])
    patch = add(mul(const(a[0], n), x), mul(const(a[1], n), w), const(-1, n))
    for square, expected in ((-4, 1), (4, -1)):
        c, e, q = sparse(
            [mul(add(x, mul(const(-1, n), w)), add(x, mul(const(2, n), w))), add(mul(t, t), const(square, n)), patch]
        )
        tt = np.sqrt(complex(-square))
        points = np.array([[1, 1], [-2, 1]], dtype=complex)
        scaled = points / (points @ a)[:, None]
        roots = np.array([[*p, s * tt] for p in scaled for s in (1, -1)])
        cert = certify_roots(c, e, q, roots, homogeneous=[0, 1], patch_equation=2)
        assert cert.unique.all() and cert.certified_distinct == 4
        assert (cert.real == expected).all()


def test_batches_and_nan_rows():
    c0, e, q = sparse([add(mul(var(0, 1), var(0, 1)), const(-1, 1))])
    k = np.arange(1.0, 7.0).reshape(2, 3)
    c = np.stack([-k, np.ones_like(k)], -1)  # z^2 - k (terms sorted: constant first), (2, 3, T)
    assert (e[:, 0] == [0, 2]).all()
    roots = np.stack([np.sqrt(k), -np.sqrt(k), np.full_like(k, np.nan)], -1)[..., None]  # (2, 3, P = 3, 1)
    cert = certify_roots(c, e, q, roots)
    assert cert.unique.shape == cert.radius.shape == cert.real.shape == (2, 3, 3)
    assert cert.distinct.shape == cert.certified_distinct.shape == (2, 3) and cert.center.shape == (2, 3, 3, 1)
    assert cert.unique[..., :2].all() and not cert.unique[..., 2].any() and np.isnan(cert.radius[..., 2]).all()
    assert (cert.real[..., :2] == 1).all() and (cert.real[..., 2] == 0).all() and np.isnan(cert.center[..., 2, :]).all()
    assert (cert.certified_distinct == 2).all() and cert.distinct.all()
    # one system, a batch of candidate sets
    cert = certify_roots(c0, e, q, np.array([[[1.0], [-1.0]], [[1.0], [1.0]], [[np.nan], [2.0]]]))
    np.testing.assert_array_equal(cert.unique, [[True, True], [True, True], [False, False]])
    np.testing.assert_array_equal(cert.certified_distinct, [2, 1, 0])
    np.testing.assert_array_equal(cert.distinct, [True, False, True])


def test_bad_inputs():
    c, e, q = sparse([add(mul(var(0, 2), var(0, 2)), var(1, 2)), lin(1, 2, 2)])
    with pytest.raises(BadInputError):
        certify_roots(c, e, q, np.zeros((1, 3)))
    with pytest.raises(BadInputError):
        certify_roots(c[:-1], e, q, np.zeros((1, 2)))
    with pytest.raises(BadInputError):  # the first equation is not homogeneous in (x, y)
        certify_roots(c, e, q, np.zeros((1, 2)), homogeneous=[0, 1], patch_equation=1)
    with pytest.raises(BadInputError):
        certify_roots(c, e, q, np.zeros((1, 2)), homogeneous=[0, 2], patch_equation=1)
    with pytest.raises(BadInputError):  # the patch must be linear
        certify_roots(c, e, q, np.zeros((1, 2)), homogeneous=[0], patch_equation=0)
    with pytest.raises(BadInputError):
        certify_roots(c, e, q, np.zeros((2, 1, 2)), homogeneous=[0], patch_equation=None)
    with pytest.raises(BadInputError):
        certify_roots(np.ones((3, len(c))), e, q, np.zeros((2, 1, 2)))


def test_exact_root_at_the_origin():
    z = var(0, 1)
    cert = certify_roots(*sparse([add(mul(z, z), mul(const(-3, 1), z))]), np.array([[0.0], [3.0], [1e-300]]))
    assert cert.unique.all() and (cert.real == 1).all() and cert.certified_distinct == 2
    assert cert.radius[0] < 1e-100 and cert.center[0, 0] == 0


# ---------------------------------------------------------------- soundness on random systems
def test_second_derivative_bound():
    """||J(z) - J(x)|| <= r max_k H_k(|x| + r) on sampled points of the box (J from the dict form)."""
    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(40):
        n = int(rng.integers(1, 4))
        polys = [
            add(
                *(
                    mul(const(complex(*rng.standard_normal(2)), n), *(var(i, n) for i in rng.integers(0, n, int(d))))
                    for d in rng.integers(0, 5, 4)
                )
            )
            for _ in range(n)
        ]
        polys = [p or const(1, n) for p in polys]
        c, e, q = sparse(polys)
        system = _System(c, e, q)
        x = rng.standard_normal(n) + 1j * rng.standard_normal(n)
        r = 10.0 ** rng.uniform(-3, 0)

        def jacobian(z, polys=polys, n=n):
            return np.array(
                [
                    [
                        sum(
                            v * a[i] * np.prod(z ** (np.array(a) - np.eye(n, dtype=int)[i]).clip(0))
                            for a, v in p.items()
                            if a[i]
                        )
                        for i in range(n)
                    ]
                    for p in polys
                ]
            )

        bound = r * system.H(_monomials((abs(x) + r)[None, :], system.second)).max()
        for _ in range(20):
            z = x + r * rng.uniform(0, 1, n) * np.exp(2j * np.pi * rng.uniform(0, 1, n))
            assert abs(jacobian(z) - jacobian(x)).sum(-1).max() <= bound * (1 + 1e-12)
            checked += 1
    assert checked >= 800


def integer_roots(rng, degree, gaussian):
    """Roots with small integer (or Gaussian integer) parts, sometimes repeated."""
    parts = rng.integers(-4, 5, (degree, 2))
    return parts[:, 0] + (1j * parts[:, 1] if gaussian else 0)


def test_certified_boxes_hold_exactly_one_root_univariate():
    rng = np.random.default_rng(11)
    checked = repeated = decided = 0
    for trial in range(150):
        degree = int(rng.integers(2, 8))
        exact = integer_roots(rng, degree, gaussian=trial % 2 == 1)
        poly = mul(*(lin(0, complex(r), 1) for r in exact))
        c, e, q = sparse([poly])
        candidates = np.roots(np.array([poly.get((d,), 0) for d in range(degree, -1, -1)], dtype=complex))
        noise = 10.0 ** rng.uniform(-15, -2, degree)
        candidates = candidates * (1 + noise * np.exp(2j * np.pi * rng.uniform(size=degree)))
        cert = certify_roots(c, e, q, candidates[:, None])
        held = inside(cert, exact[:, None])[cert.unique]
        assert (held == 1).all(), (exact, candidates)  # a double root counts twice: never certified
        multiplicity = (exact[:, None] == exact[None, :]).sum(1)
        simple = set(exact[multiplicity == 1].tolist())
        assert cert.certified_distinct <= len(simple)
        if trial % 2 == 0:  # real coefficients: realness decisions agree with the exact roots
            nearest = exact[abs(cert.center[:, 0, None] - exact[None, :]).argmin(-1)]
            assert (cert.real[cert.real != 0] == np.where(nearest.imag == 0, 1, -1)[cert.real != 0]).all()
            decided += int((cert.real != 0).sum())
            assert (cert.real[cert.unique] != 0).all()  # a certified root of a real polynomial is decided
        checked += int(cert.unique.sum())
        repeated += int((multiplicity > 1).any())
    assert checked >= 200 and repeated >= 20 and decided >= 100


def test_certified_boxes_hold_exactly_one_root_triangular():
    rng = np.random.default_rng(12)
    checked = 0
    n = 2
    for _ in range(100):
        xs = integer_roots(rng, int(rng.integers(1, 4)), gaussian=False)
        slopes, offsets = rng.integers(-3, 4, (2, 2))
        f1 = mul(*(lin(0, int(r), n) for r in xs))
        f2 = mul(
            *(
                add(var(1, n), mul(const(-int(m), n), var(0, n)), const(-int(b), n))
                for m, b in zip(slopes, offsets, strict=True)
            )
        )
        c, e, q = sparse([f1, f2])
        exact = np.array([(x, m * x + b) for x in xs for m, b in zip(slopes, offsets, strict=True)], dtype=complex)
        noise = 10.0 ** rng.uniform(-14, -3, exact.shape)
        cert = certify_roots(c, e, q, exact + noise)
        held = inside(cert, exact)[cert.unique]
        assert (held == 1).all()  # exact roots listed twice (repeated x or equal lines) are double
        checked += int(cert.unique.sum())
    assert checked >= 150


def test_roots_of_very_different_sizes_are_certified_in_their_own_scale():
    """(x - 2^20)(x - 3) = 0, (y - 2^-10 x)(y + 1) = 0: roots with coordinates from 1 to 2^20.
    Each candidate is tested in coordinates scaled by powers of two to its size, so the large
    ones certify with boxes as wide, per coordinate, as that size allows; every box holds its
    root and no other, and the four roots are distinct."""
    n, big = 2, 2.0**20
    polys = [mul(lin(0, big, n), lin(0, 3, n)), mul(add(var(1, n), {(1, 0): -(2.0**-10)}), lin(1, -1, n))]
    exact = np.array([[big, 2.0**10], [big, -1], [3, 3 * 2.0**-10], [3, -1]], dtype=complex)
    c, e, q = sparse(polys)
    cert = certify_roots(c, e, q, exact * (1 + 1e-9))
    assert cert.unique.all() and cert.distinct and cert.certified_distinct == 4
    assert (cert.real == 1).all()
    # per-coordinate half-widths: the box around (2^20, 2^10) is wider in x than in y
    assert cert.radii[0, 0] > cert.radii[0, 1] > 0
    held = (abs(cert.center[:, None, :] - exact[None]) <= cert.radii[:, None, :]).all(-1)
    assert (held == np.eye(4, dtype=bool)).all()


def test_dense_and_term_by_term_evaluations_agree(monkeypatch):
    """A polynomial map is a matrix product with per-input tables (dense) or a sum of the terms'
    products: both give F, J, S, SJ and the second-derivative sums to rounding, and the same
    certificates, on batches of random systems (the choice is a speed trade only)."""
    import parakin.solvers.certify as certify

    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(30):
        n = int(rng.integers(1, 5))
        exponents = rng.integers(0, 3, (int(rng.integers(n, 4 * n)), n))
        equation = np.r_[np.arange(n), rng.integers(0, n, exponents.shape[0] - n)]
        c = rng.standard_normal((3, exponents.shape[0])) + 1j * rng.standard_normal((3, exponents.shape[0]))
        x = rng.standard_normal((3, 5, n)) + 1j * rng.standard_normal((3, 5, n))
        results = []
        for dense in (0.0, np.inf):  # every map dense; every map term by term
            monkeypatch.setattr(certify, "DENSE", dense)
            system = _System(c, exponents, equation)
            assert {system.F.dense, system.J.dense, system.H.dense} == {dense == 0.0}
            rho = abs(x) + 0.1
            values = system.evaluate(x) + (system.H(_monomials(rho, system.second)),)
            results.append((values, certify_roots(c, exponents, equation, x)))
        for a, b in zip(results[0][0], results[1][0], strict=True):
            assert np.allclose(a, b, rtol=1e-12, atol=1e-12 * abs(a).max())
        for field in ("unique", "real", "certified_distinct"):
            assert np.array_equal(getattr(results[0][1], field), getattr(results[1][1], field))
        checked += x.shape[0] * x.shape[1]
    assert checked >= 400
    (c, e, q), exact = product_system()
    for dense in (0.0, np.inf):  # and both certify every root of a system with known roots
        monkeypatch.setattr(certify, "DENSE", dense)
        cert = certify_roots(c, e, q, exact + 1e-10)
        assert cert.unique.all() and cert.certified_distinct == 12 and (inside(cert, exact) == 1).all()
