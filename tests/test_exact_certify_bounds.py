"""The exact certifier reports its radius as a double that bounds the exact dyadic one from above,
whatever the mantissa's size (a 384-bit mantissa from the fixed-point Gauss-Jordan overflowed
``math.ldexp`` at rus6's home: forward_pose_all raised OverflowError)."""

import math
from fractions import Fraction

from parakin.solvers.exact_certify import _upper_float


def test_the_reported_radius_bounds_the_exact_one_from_above():
    cases = [(3, -1), ((1 << 384) + 1, -300), ((1 << 384) - 1, -700), (12345678901234567891, -80), (0, 5)]
    for mantissa, exponent in cases:
        bound = _upper_float((mantissa, exponent))
        exact = Fraction(mantissa) * Fraction(2) ** exponent
        assert Fraction(bound) >= exact
        assert bound <= float(exact) * (1 + 2**-50) + 5e-324  # and tight: a few ulps
    assert len(cases) == 5


def test_a_radius_beyond_the_double_range_is_infinite():
    assert _upper_float((1 << 400, 2000)) == math.inf
