"""A third start instance next to the mechanism's home: most inputs a user solves lie near it.

The parameter homotopy's paths run from a start instance q_start to the input's family values
q_target along q(s) = (1 - s) q_target + s q_start (``start_systems``). Any complex q_start off the
discriminant gives a valid homotopy; the farther it lies from the input, the longer the paths and
the more steps they take. The stored start instance is random with unit-size values, often far
from a mechanism's geometry (its lengths in metres, its angles' circle parameters). This module
places one more instance, ``near``, at the family's values at the mechanism's home plus a complex
offset of relative size ``OFFSETS[0]`` in a random direction (seeded), and follows every stored start
solution to it. The family's values include the parameters, so the test is on the geometry too: an
input whose family values each lie within ``RADIUS`` of home's, relative to ``scale`` (the value's
own size at home plus a tenth of the mean size: a coordinate that is zero at home gets the least
room, about 5 % of the mechanism's size), starts there; any other input (a far pose, a geometry
loaded far from the default) starts from the stored instance as before. Measured by ``make bench``
on inputs near home (the C tracker, steps per path): prs3 26.9 -> 5.0, planar_3rrr 34.5 -> 8.5,
Stewart at Dietmaier's input 48.2 -> 13.6, rus6 104.7 -> 22.4; the same modes on the 10^4-input
census. The values are those of the all-modes solver (lengths over its power-of-two unit:
``parakin.mechanism.Mechanism._unit_free``): the exported C, called with other numbers, starts
from the stored instance.

The choice is efficiency only: every path's end is certified afterwards as before, and an input
whose certificate is not complete is tracked again from the second stored instance.

The near solutions keep the stored start's order (path p of the stored start ends at near
solution p), so the sign symmetry's pairs of paths are the same for both instances; each is
refined in 40-digit arithmetic and rounded, so the stored doubles do not depend on the machine.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import sympy as sp

from parakin.log import logger
from parakin.solvers.path_tracking import circle_parameter

from .polynomial_form import MOEBIUS_A, MOEBIUS_B, PolynomialForm

#: the offsets of the near instance from the home's family values, relative to ``scale``, tried
#: in turn until every stored start solution reaches it apart (a home with roots near infinity,
#: rus6's, may need a larger one)
OFFSETS = (0.15, 0.3, 0.6)
#: inputs whose family values lie within this distance of home (max over values of |q - home| /
#: scale) start at the near instance: measured on planar_3rrr inputs a radian from home, still 3x
#: fewer steps than from the stored instance with every endpoint the same
RADIUS = 1.0
#: the scale of a family value: its own size at home plus this fraction of the mean size (values
#: that are zero at home, a base point at the origin)
SCALE_FLOOR = 0.1
#: significant digits of the near instance's values (short, exactly reproducible numbers)
DIGITS = 6


def home_point(form: PolynomialForm, free: list[sp.Symbol], values: Mapping[sp.Symbol, float]) -> np.ndarray | None:
    """The family's parameters at the mechanism's values (actuated at home and parameters): the
    free values, then the circle parameter u of each angle; None where a value is missing or not
    finite (a home that does not fix every actuated value)."""
    known: dict[sp.Symbol, sp.Expr] = {k: sp.Float(v) for k, v in values.items()}
    for symbol, expression in form.family:
        if symbol not in known:
            known[symbol] = expression.xreplace(known)
    try:
        free_values = np.array([complex(sp.N(known[symbol])) for symbol in free], dtype=complex)
        angles = np.array([float(sp.N(angle.xreplace(known))) for _, angle, _ in form.circles])
    except (KeyError, TypeError, ValueError):
        return None
    # u as the runtime computes it from an input's angles
    circles = circle_parameter(angles, complex(MOEBIUS_A), complex(MOEBIUS_B))
    array = np.concatenate([free_values, circles]).astype(complex)
    return array if np.isfinite(array).all() else None


def scale_of(center: np.ndarray) -> np.ndarray:
    """Each family value's scale for the offset and the radius (``SCALE_FLOOR``)."""
    sizes = np.abs(center)
    return sizes + SCALE_FLOOR * max(float(sizes.mean()), 1e-300)


def _rounded(value: complex) -> list[float]:
    return [float(f"{value.real:.{DIGITS}g}"), float(f"{value.imag:.{DIGITS}g}")]


def near_record(name: str, family, form: PolynomialForm, record: dict, values: Mapping[sp.Symbol, float], seed: int):
    """The manifest's ``near`` entry (instance, solutions in the stored start's order, center,
    scale, radius), or None where the home gives no family point or the stored start's paths do
    not all reach distinct regular solutions there (then no input starts near home)."""
    from .start_systems import _newton_40, _segment, _smallest_gap, _track

    center = home_point(form, list(family.free), values)
    if center is None or len(center) != family.m:
        logger.info("%s: no start near home (the home does not fix every family value)", name)
        return None
    scale = scale_of(center)
    rng = np.random.default_rng(seed + 3)
    direction = (rng.normal(size=center.size) + 1j * rng.normal(size=center.size)) / np.sqrt(2)
    start_q = np.array([complex(*v) for v in record["instance"]])
    start = np.array([[complex(*c) for c in row] for row in record["solutions"]])
    for offset in OFFSETS:
        instance = np.array([complex(*_rounded(v)) for v in center + offset * scale * direction])
        moved, reached = _track(_segment(family, start_q, instance), start)
        refined = _newton_40(family, instance, moved, lambdified=True) if reached.all() else []
        regular = sum(row is not None for row in refined)
        if regular == len(start) and _smallest_gap(np.array(refined)) > 1e-6:
            break
        logger.info(
            "%s: no start at offset %g from home: of its %d paths from the stored start %d reached, %d regular there",
            name, offset, len(start), int(reached.sum()), regular,
        )  # fmt: skip
    else:
        logger.warning("%s: no start near home (its paths from the stored start did not all reach it apart)", name)
        return None
    solutions = np.array(refined)
    return {
        "instance": {"real": instance.real.tolist(), "imag": instance.imag.tolist()},
        "solutions": {"real": solutions.real.tolist(), "imag": solutions.imag.tolist()},
        "center": {"real": [_rounded(v)[0] for v in center], "imag": [_rounded(v)[1] for v in center]},
        "scale": [float(f"{v:.{DIGITS}g}") for v in scale],
        "radius": RADIUS,
    }
