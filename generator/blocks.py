"""Reusable modelling blocks, so that a mechanism file reads like its paper's section.

* ``point_parameters``: a point list as parameters (a ``count x dims`` matrix of real symbols
  ``name_x1, name_y1, ...``) to register in ``Mechanism.parameter_groups[name]``, with
  ``point_defaults`` / ``point_info`` for its default values and units, ``as_points`` for the
  points as 3-vectors (planar lists get z = 0).
* ``planar_pose``: ^B_P T of a planar platform, Rot_z(phi) and (x, y, 0); ``planar_coordinates``
  reads (x, y, phi) back from the pose symbols of an inverse program.
* ``PrismaticLegs``: legs of variable length between a base point A_i (in {B}) and a platform
  point b_i (in {P}), the SPS / UPS / RPR leg: leg vectors d_i = p + R b_i - A_i, the closed-form
  inverse l_i = |d_i|, the residual |d_i| - l_i, and the Pluecker rows (d_i ; (A_i - p) x d_i) of
  A in A twist = diag(l) l_dot (twist = (v of the origin of {P}, w), both in {B}).
* ``half_angle_solution``: the two roots of E cos(theta) + F sin(theta) + G = 0 through the
  tan-half-angle quadratic, one per sign, as a single atan2 (finite everywhere).
* ``half_angle_forms`` and ``remove_spurious_factors``: build a univariate elimination polynomial
  in t = tan(phi / 2) with exact polynomial arithmetic and strip what the elimination introduced
  (numeric or symbolic content, powers of (1 + t^2) or other known factors, powers of t).
* What a mechanism file would otherwise write by hand (issue 32, item 4):
  - layouts: ``circle_points``, ``paired_circle_points`` and ``pair_sides`` (default joint
    positions on circles, numerically; their angles in degrees, keyword-only ``angles_deg``,
    ``centres_deg``, ``offset_deg``), ``radial_directions`` (exact unit vectors at equal
    angles), ``crank_bases`` (shafts that put crank tips on given points);
  - declarations: ``point_group``, ``leg_parameters`` and ``scalar_parameter`` with
    ``parameter_fields`` (the parameters, their defaults and meaning, declared once);
  - poses and homes: ``pose_values``, ``planar_pose_values``, ``euler_pose_values`` and
    ``frame_pose_values`` (an example pose as a 4x4 list; ``euler_pose`` as a 17-digit matrix),
    ``home_from_pose`` (a home read by the model's inverse at a pose);
  - ``euler_platform``: Euler-angle platform coordinates and their reading from a pose, for any
    of the twelve sequences; ``universal_prismatic_platform``: the coordinates of a passive U-P
    leg carrying the platform (a Tricept's) and their reading;
  - bodies from distances: ``distance_points`` (three points of a body from their distances to
    its origin and to one another) and ``distance_cosines`` (their cosines, Gram determinant).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol, TypedDict

import sympy as sp

from .frames import homogeneous, rot_x, rot_y, rot_z
from .model import POSE_POSITION, POSE_ROTATION, InverseSolution, ParameterInfo, RateModel, check_branch

if TYPE_CHECKING:
    from .joints import Platform

AXES = "xyz"
#: twist components of a rigid body, in the order of a Pluecker row (v of the origin of {P}, w)
TWIST = ("vx", "vy", "vz", "wx", "wy", "wz")


# ------------------------------------------------------------------ point-list parameters
def point_parameters(name: str, count: int, dims: int = 3) -> sp.Matrix:
    """A ``count x dims`` matrix of real symbols, row k the point k + 1: ``name_x1, name_y1,
    (name_z1), name_x2, ...``. Register it as ``Mechanism.parameter_groups[name]``; a user then
    passes the whole list, ``parakin.load(mechanism, name=[[x1, y1], ...])``."""
    if not 1 <= dims <= 3:
        raise ValueError(f"point_parameters: dims must be 1, 2 or 3, got {dims}")
    return sp.Matrix(count, dims, lambda k, j: sp.Symbol(f"{name}_{AXES[j]}{k + 1}", real=True))


def point_defaults(points: sp.Matrix, values: Sequence[Sequence[float]]) -> dict[sp.Symbol, float]:
    """Default values of a point list, one row of ``values`` per point."""
    if len(values) != points.rows or any(len(row) != points.cols for row in values):
        raise ValueError(f"point_defaults: expected {points.rows} rows of {points.cols} values")
    return {points[k, j]: float(values[k][j]) for k in range(points.rows) for j in range(points.cols)}


def point_info(points: sp.Matrix, description: str, unit: str = "m") -> dict[sp.Symbol, ParameterInfo]:
    """``ParameterInfo`` of every coordinate: '<axis> of <description>' with ``{k}`` in
    ``description`` replaced by the point's number (e.g. 'base joint A{k}, in {B}' gives
    'x of base joint A2, in {B}'; other braces are left alone)."""
    return {
        points[k, j]: ParameterInfo(unit, f"{AXES[j]} of {description.replace('{k}', str(k + 1))}")
        for k in range(points.rows)
        for j in range(points.cols)
    }


def as_points(points: sp.Matrix) -> list[sp.Matrix]:
    """The rows of a point list as 3x1 column vectors (missing coordinates are 0)."""
    return [sp.Matrix([points[k, j] if j < points.cols else 0 for j in range(3)]) for k in range(points.rows)]


# ------------------------------------------------------------------ default layouts
# The layout builders take their angles in DEGREES, as a paper prints a layout (joints at 0, 120,
# 240 deg), and every such argument says so in its name (``angles_deg``, ``centres_deg``,
# ``offset_deg``) and is keyword-only: radians passed by position (the unit of the rest of the
# API) would otherwise give joints a few degrees apart and a near-singular home without a word.
def pair_sides(*, centres_deg: Sequence[float]) -> list[tuple[float, int]]:
    """The pair centre (radians) and side of every point of a paired layout: two points per
    centre, side -1 first, then +1.

    Parameters
    ----------
    centres_deg : sequence of float, length n
        The pair centres, DEGREES from the x axis (keyword-only).

    Returns
    -------
    list of (float, int), length 2 n
        (math.radians(centre), side) for the points in order: the centre in radians.

    Example
    -------
    >>> pair_sides(centres_deg=[0.0, 90.0])
    [(0.0, -1), (0.0, 1), (1.5707963267948966, -1), (1.5707963267948966, 1)]
    """
    return [(math.radians(centre), side) for centre in centres_deg for side in (-1, 1)]


def _on_circle(radius: float, angle: float, dims: int) -> list[float]:
    if dims not in (2, 3):
        raise ValueError(f"a point on a circle has 2 or 3 coordinates, got dims={dims}")
    return [radius * math.cos(angle), radius * math.sin(angle), 0.0][:dims]


def circle_points(radius: float, *, angles_deg: Sequence[float], dims: int = 3) -> list[list[float]]:
    """Points on a circle about the origin in the plane z = 0: r (cos t, sin t, 0) per angle.

    Parameters
    ----------
    radius : float
        The circle's radius r, metres.
    angles_deg : sequence of float
        The points' angles t from the x axis, counter-clockwise, DEGREES (keyword-only).
    dims : int
        3 for (x, y, 0), 2 for (x, y) (a planar mechanism's point group).

    Returns
    -------
    list of list of float, shape (len(angles_deg), dims)
        One row per point, in the order of ``angles_deg``.

    Raises
    ------
    ValueError
        ``dims`` is not 2 or 3.

    Example
    -------
    >>> [[round(v, 12) for v in p] for p in circle_points(2.0, angles_deg=[0.0, 90.0], dims=2)]
    [[2.0, 0.0], [0.0, 2.0]]
    """
    return [_on_circle(radius, math.radians(angle), dims) for angle in angles_deg]


def paired_circle_points(
    radius: float, *, centres_deg: Sequence[float], offset_deg: float, dims: int = 3
) -> list[list[float]]:
    """Points in pairs on a circle about the origin (z = 0): two per centre c, at c - offset and
    c + offset, the usual hexapod layout (three pairs at 0, 120, 240 deg).

    Parameters
    ----------
    radius : float
        The circle's radius, metres.
    centres_deg : sequence of float, length n
        The pair centres, DEGREES from the x axis, counter-clockwise (keyword-only).
    offset_deg : float
        Half the angle between the two points of a pair, DEGREES (keyword-only).
    dims : int
        3 for (x, y, 0), 2 for (x, y).

    Returns
    -------
    list of list of float, shape (2 n, dims)
        Point 2 k at centres_deg[k] - offset_deg, point 2 k + 1 at centres_deg[k] + offset_deg
        (``pair_sides``).

    Raises
    ------
    ValueError
        ``dims`` is not 2 or 3.

    Example
    -------
    >>> [[round(v, 12) for v in p] for p in paired_circle_points(1.0, centres_deg=[90.0], offset_deg=90.0)]
    [[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]]
    """
    sides = pair_sides(centres_deg=centres_deg)
    return [_on_circle(radius, centre + side * math.radians(offset_deg), dims) for centre, side in sides]


def radial_directions(count: int, start: sp.Expr | int = 0) -> list[sp.Matrix]:
    """Exact unit vectors (cos eta_k, sin eta_k, 0), eta_k = start + 2 pi k / count, k = 0 ..
    count - 1: the directions of legs spaced evenly about the z axis (for three legs from 0 the
    entries are 1, 0, -1/2, +-sqrt(3)/2), so that the derived closure carries no rounded constant.

    Parameters
    ----------
    count : int
        The number of directions, at least 1.
    start : sympy expression
        eta_0, radians (exact, e.g. ``sp.pi / 2``).

    Returns
    -------
    list of sympy.Matrix, each 3 x 1
        e_k in {B}; z x e_k = (-sin eta_k, cos eta_k, 0) is the tangent.

    Raises
    ------
    ValueError
        ``count`` < 1.

    Example
    -------
    >>> radial_directions(3)[1].T
    Matrix([[-1/2, sqrt(3)/2, 0]])
    """
    if count < 1:
        raise ValueError(f"radial_directions: count must be at least 1, got {count}")
    angles = [start + 2 * sp.pi * k / count for k in range(count)]
    return [sp.Matrix([sp.cos(eta), sp.sin(eta), 0]) for eta in angles]


def crank_bases(
    tips: Sequence[Sequence[float]],
    axes: Sequence[Sequence[float]],
    zeros: Sequence[Sequence[float]],
    crank: float,
    angle: float,
) -> list[list[float]]:
    """The crank shafts A_i that put each crank tip at a given point at a given crank angle:
    A_i = X_i - a (cos t e1_i + sin t e2_i), e2_i = u_i x e1_i (the tip of a crank of length a
    turned by t about u_i from e1_i, as ``joints.crank_leg`` turns it), e.g. to place cranks under
    another mechanism's base points.

    Parameters
    ----------
    tips : sequence of 3 floats per leg
        The tip positions X_i, in {B}, metres.
    axes, zeros : sequence of 3 floats per leg
        The crank axes u_i and the directions e1_i at angle 0 (unit, normal to u_i), in {B}.
    crank : float
        The crank length a, metres.
    angle : float
        The crank angle t, radians.

    Returns
    -------
    list of list of float, shape (n, 3)
        The shaft points A_i.

    Example
    -------
    >>> crank_bases([[1.0, 0.0, 0.0]], [[0.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]], 0.5, 0.0)
    [[0.5, 0.0, 0.0]]
    """
    c, s = math.cos(angle), math.sin(angle)
    shafts = []
    for tip, u, e1 in zip(tips, axes, zeros, strict=True):
        e2 = [u[1] * e1[2] - u[2] * e1[1], u[2] * e1[0] - u[0] * e1[2], u[0] * e1[1] - u[1] * e1[0]]
        shafts.append([tip[k] - crank * (c * e1[k] + s * e2[k]) for k in range(3)])
    return shafts


# ------------------------------------------------------------------ parameter declarations
@dataclass(frozen=True)
class ParameterGroup:
    """Parameters declared once: their symbols, default values and meaning. ``name`` is the
    group's name in ``Mechanism.parameter_groups`` (a point list a user passes whole), None for
    parameters passed one by one (``leg_parameters``)."""

    name: str | None
    symbols: sp.Matrix
    defaults: dict[sp.Symbol, float]
    info: dict[sp.Symbol, ParameterInfo]

    @property
    def points(self) -> list[sp.Matrix]:
        """The rows as 3x1 column vectors (``as_points``)."""
        return as_points(self.symbols)


def _check_numbered(what: str, description: str, count: int, item: str) -> None:
    """Refuse a description of several items without ``{k}``: each item's meaning (shown by
    ``parakin info``, the parameter table) would be the same text."""
    if count > 1 and "{k}" not in description:
        raise ValueError(
            f"{what}: the description {description!r} has no {{k}}, so all {count} would read the same; "
            f"write {{k}} where the {item}'s number goes (e.g. 'base joint A{{k}}, in {{B}}')"
        )


def point_group(name: str, values: Sequence[Sequence[float]], description: str, unit: str = "m") -> ParameterGroup:
    """A point list as parameters, with its default values and meaning in one declaration.

    Parameters
    ----------
    name : str
        The group's name: symbols ``name_x1, name_y1, ...`` (``point_parameters``).
    values : sequence of sequence of float, shape (n, dims)
        The default points, one row per point (dims 1 to 3), in the group's frame and ``unit``.
    description : str
        What point k is, with ``{k}`` for its number (``point_info``), e.g. 'base joint A{k},
        in {B}'.
    unit : str
        The coordinates' unit ('m'; '' for a unit vector).

    Returns
    -------
    ParameterGroup
        ``symbols`` the n x dims matrix, ``points`` its rows as 3-vectors.

    Raises
    ------
    ValueError
        The rows are not all of one length from 1 to 3, or there are two or more points and
        ``description`` has no ``{k}`` (every point would be described the same).

    Example
    -------
    >>> group = point_group("base", [(0.0, 0.0), (1.0, 0.0)], "base joint A{k}, in {B}")
    >>> group.defaults[group.symbols[1, 0]], group.info[group.symbols[1, 0]].description
    (1.0, 'x of base joint A2, in {B}')
    """
    if not values or len({len(row) for row in values}) != 1:
        raise ValueError(f"point_group {name!r}: give one or more rows of equal length")
    _check_numbered(f"point_group {name!r}", description, len(values), "point")
    symbols = point_parameters(name, len(values), len(values[0]))
    return ParameterGroup(name, symbols, point_defaults(symbols, values), point_info(symbols, description, unit))


def scalar_parameter(
    symbol: sp.Symbol, value: float, description: str, unit: str = "m", domain: str = "real"
) -> ParameterGroup:
    """One parameter with its default and meaning, declared together (for ``parameter_fields``).

    Parameters
    ----------
    symbol : sympy.Symbol
        The parameter.
    value : float
        Its default, in ``unit``.
    description : str
        What it is, in the user's terms.
    unit : str
        Its unit ('m'; '' for a number without one, 'N/m', ...).
    domain : str
        The values it may take (``model.DOMAINS``: 'real', 'positive', 'nonzero', 'sign').

    Returns
    -------
    ParameterGroup
        Without a group name.

    Example
    -------
    >>> r = sp.Symbol("r", positive=True)
    >>> scalar_parameter(r, 0.05, "platform radius", domain="positive").info[r]
    ParameterInfo(unit='m', description='platform radius', domain='positive')
    """
    return ParameterGroup(
        None, sp.Matrix([symbol]), {symbol: value}, {symbol: ParameterInfo(unit, description, domain)}
    )


def leg_parameters(
    symbols: Sequence[sp.Symbol],
    value: float | Sequence[float],
    description: str,
    unit: str = "m",
    domain: str = "positive",
) -> ParameterGroup:
    """One parameter per leg with the same default, e.g. the crank lengths a1..a6.

    Parameters
    ----------
    symbols : sequence of sympy.Symbol
        The parameters, leg 1 first.
    value : float or sequence of float
        The default of every one, or one default per leg, in ``unit``.
    description : str
        What the parameter of leg k is, with ``{k}`` for the leg's number.
    unit : str
        Its unit ('m').
    domain : str
        The values it may take (``model.DOMAINS``; 'positive' for a length).

    Returns
    -------
    ParameterGroup
        Without a group name: a user passes each parameter by its own name.

    Raises
    ------
    ValueError
        A sequence of defaults of another length than ``symbols``, or two or more parameters and
        ``description`` has no ``{k}`` (every leg's parameter would be described the same).

    Example
    -------
    >>> a = sp.symbols("a1:3", positive=True)
    >>> leg_parameters(a, 0.15, "crank {k} length").info[a[1]].description
    'crank 2 length'
    """
    _check_numbered(f"leg_parameters {[str(s) for s in symbols]}", description, len(symbols), "leg")
    info = {s: ParameterInfo(unit, description.replace("{k}", str(k + 1)), domain) for k, s in enumerate(symbols)}
    if isinstance(value, Sequence):
        if len(value) != len(symbols):
            raise ValueError(f"leg_parameters: {len(symbols)} parameters but {len(value)} defaults")
        return ParameterGroup(None, sp.Matrix(list(symbols)), dict(zip(symbols, value, strict=True)), info)
    return ParameterGroup(None, sp.Matrix(list(symbols)), dict.fromkeys(symbols, value), info)


class ParameterFields(TypedDict):
    """``Mechanism`` fields of declared parameters (``parameter_fields``)."""

    parameters: dict[sp.Symbol, float]
    parameter_info: dict[sp.Symbol, ParameterInfo]
    parameter_groups: dict[str, sp.Matrix]


def parameter_fields(*groups: ParameterGroup) -> ParameterFields:
    """The ``Mechanism`` fields ``parameters``, ``parameter_info`` and ``parameter_groups`` of
    declared parameters, in the order given (the order of the generated parameter vector).

    Parameters
    ----------
    *groups : ParameterGroup
        From ``point_group`` and ``leg_parameters``.

    Returns
    -------
    ParameterFields
        A dict for ``Mechanism(**parameter_fields(...), ...)``; ``["parameters"]`` the defaults.

    Raises
    ------
    ValueError
        A parameter is declared twice.

    Example
    -------
    >>> a = sp.symbols("a1:3", positive=True)
    >>> fields = parameter_fields(point_group("base", [(0.0, 0.0)], "A{k}"), leg_parameters(a, 0.2, "a{k}"))
    >>> [str(s) for s in fields["parameters"]], list(fields["parameter_groups"])
    (['base_x1', 'base_y1', 'a1', 'a2'], ['base'])
    """
    parameters: dict[sp.Symbol, float] = {}
    info: dict[sp.Symbol, ParameterInfo] = {}
    for group in groups:
        if set(group.defaults) & set(parameters):
            raise ValueError(f"parameter_fields: {sorted(map(str, set(group.defaults) & set(parameters)))} twice")
        parameters |= group.defaults
        info |= group.info
    named = {group.name: group.symbols for group in groups if group.name is not None}
    return {"parameters": parameters, "parameter_info": info, "parameter_groups": named}


# ------------------------------------------------------------------ example poses and homes
def pose_values(
    rotation: sp.Matrix | Sequence[Sequence[float]], position: Sequence[float] | sp.Matrix
) -> list[list[float]]:
    """^B_P T as the 4x4 nested list of floats an ``Example`` or a home takes.

    Parameters
    ----------
    rotation : 3 x 3 sympy.Matrix or nested sequence
        ^B_P R (numbers; a sympy matrix is converted entry by entry, ``float(entry)``).
    position : 3 numbers
        The origin of {P} in {B}, metres.

    Returns
    -------
    list of list of float, shape (4, 4)
        [[R, p], [0, 0, 0, 1]].

    Example
    -------
    >>> pose_values([[1, 0, 0], [0, 1, 0], [0, 0, 1]], [0.0, 0.0, 0.5])[2]
    [0.0, 0.0, 1.0, 0.5]
    """
    rows = sp.Matrix(rotation).tolist()
    return [[*map(float, row), float(t)] for row, t in zip(rows, list(position), strict=True)] + [[0.0, 0.0, 0.0, 1.0]]


def planar_pose_values(x: float, y: float, phi: float) -> list[list[float]]:
    """``planar_pose`` numerically: [[Rot_z(phi), (x, y, 0)], [0, 0, 0, 1]] as floats.

    Parameters
    ----------
    x, y : float
        The origin of {P} in {B}, metres.
    phi : float
        The platform's angle about z, radians (evaluated to 17 digits).

    Returns
    -------
    list of list of float, shape (4, 4)

    Example
    -------
    >>> planar_pose_values(0.1, 0.2, 0.0)[0]
    [1.0, 0.0, 0.0, 0.1]
    """
    return pose_values(rot_z(sp.Float(phi, 17)), [x, y, 0.0])


def frame_pose_values(
    x_toward: Sequence[float], y_toward: Sequence[float], origin: Sequence[float] = (0.0, 0.0, 0.0)
) -> list[list[float]]:
    """^B_P T of the frame at ``origin`` with x_P along ``x_toward`` and y_P toward ``y_toward``
    (Gram-Schmidt: the part of ``y_toward`` across x_P), z_P = x_P x y_P; e.g. a platform frame from
    printed points, x_P through one, the x_P y_P plane through another.

    Parameters
    ----------
    x_toward, y_toward : 3 floats each
        Directions in {B} (not parallel), relative to ``origin``.
    origin : 3 floats
        The origin of {P} in {B}, metres.

    Returns
    -------
    list of list of float, shape (4, 4)

    Example
    -------
    >>> frame_pose_values([2.0, 0.0, 0.0], [1.0, 3.0, 0.0])[1]
    [0.0, 1.0, 0.0, 0.0]
    """
    x_axis = sp.Matrix(x_toward).normalized()
    y_axis = (sp.Matrix(y_toward) - x_axis.dot(sp.Matrix(y_toward)) * x_axis).normalized()
    return pose_values(sp.Matrix.hstack(x_axis, y_axis, x_axis.cross(y_axis)), list(origin))


class _HasHome(Protocol):
    def inverse(self) -> InverseSolution: ...

    def home_at(
        self, rotation: sp.Matrix, position: sp.Matrix, branch: int, parameters: dict[sp.Symbol, float]
    ) -> dict[sp.Symbol, float]: ...


def home_from_pose(
    model: _HasHome, pose: sp.Matrix | Sequence[Sequence[float]], branch: int, parameters: dict[sp.Symbol, float]
) -> dict[sp.Symbol, float]:
    """A home configuration read by the model's inverse at a pose: every actuated and passive
    value of ``pose`` on inverse branch ``branch`` (``DistanceMechanism.home_at``,
    ``ChainMechanism.home_at``).

    Parameters
    ----------
    model : joints.DistanceMechanism or chains.ChainMechanism
        The mechanism's model.
    pose : 4 x 4 nested sequence, or 3 x 3 for an orienting platform
        ^B_P T (or ^B_P R), e.g. from ``pose_values``.
    branch : int
        The inverse branch.
    parameters : dict
        Parameter values (the defaults).

    Returns
    -------
    dict
        The actuated and passive values (angles in (-pi, pi] for a distance model), for
        ``Mechanism(home=...)``.

    Raises
    ------
    BadInputError
        ``branch`` is not one of the inverse's branches 0 .. count - 1 (count = 2 ** the number of
        its sign choices; the message names it).

    Example
    -------
    See ``mechanisms/rus6.py``: ``home=home_from_pose(MODEL, HOME_POSE, 0, defaults)``.
    """
    check_branch(branch, len(model.inverse().branches), "home_from_pose")
    matrix = sp.Matrix(pose)
    if matrix.shape == (3, 3):
        return model.home_at(matrix, None, branch, parameters)  # type: ignore[arg-type]
    return model.home_at(matrix[:3, :3], matrix[:3, 3], branch, parameters)


# ------------------------------------------------------------------ bodies from distances
def distance_cosines(
    radii: Sequence[sp.Expr], distances: Sequence[sp.Expr]
) -> tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr]:
    """The cosines of the angles at a centre Q between three points of a body, from their distances
    to Q and to one another (the law of cosines), and their Gram determinant.

    Parameters
    ----------
    radii : 3 sympy expressions
        r_i = |Q B_i|, metres (nonzero).
    distances : 3 sympy expressions
        r_12 = |B_1 B_2|, r_23 = |B_2 B_3|, r_13 = |B_1 B_3|, metres (in that order).

    Returns
    -------
    tuple of 4 sympy expressions
        q12, q13, q23 (q_ij = (r_i^2 + r_j^2 - r_ij^2) / (2 r_i r_j), the cosine of the angle B_i Q
        B_j) and D = 1 - q12^2 - q13^2 - q23^2 + 2 q12 q13 q23, the determinant of the matrix of
        cosines (zero when Q, B_1, B_2 and B_3 are coplanar, negative when no such points exist).

    Example
    -------
    >>> r = sp.Integer(1)
    >>> distance_cosines((r, r, r), (sp.sqrt(2), sp.sqrt(2), sp.sqrt(2)))
    (0, 0, 0, 1)
    """
    (r1, r2, r3), (r12, r23, r13) = radii, distances
    q12 = (r1**2 + r2**2 - r12**2) / (2 * r1 * r2)
    q13 = (r1**2 + r3**2 - r13**2) / (2 * r1 * r3)
    q23 = (r2**2 + r3**2 - r23**2) / (2 * r2 * r3)
    return q12, q13, q23, 1 - q12**2 - q13**2 - q23**2 + 2 * q12 * q13 * q23


def distance_points(radii: Sequence[sp.Expr], distances: Sequence[sp.Expr], handedness: sp.Expr) -> list[sp.Matrix]:
    """Three points of a body located by their distances to its origin Q and to one another, in
    the body's frame with x along Q B_1 and y in the plane Q B_1 B_2 (B_2 on its +y side); B_3 on
    the side of the x y plane that ``handedness`` says (the sign of det[B_1 B_2 B_3]).

    Parameters
    ----------
    radii, distances : 3 sympy expressions each
        As ``distance_cosines``: |Q B_i| and |B_1 B_2|, |B_2 B_3|, |B_1 B_3|, metres.
    handedness : sympy expression
        +1 or -1 (or a parameter taking those values).

    Returns
    -------
    list of 3 sympy.Matrix, each 3 x 1
        B_1 = r_1 (1, 0, 0), B_2 = r_2 (q12, s, 0) and B_3 = r_3 (q13, (q23 - q12 q13) / s,
        handedness sqrt(max(0, D)) / s), s = sqrt(1 - q12^2) (``distance_cosines``); D < 0 (no
        such points) is clamped to 0.

    Example
    -------
    >>> r, d = sp.Integer(1), sp.sqrt(2)
    >>> [list(p) for p in distance_points((r, r, r), (d, d, d), -1)]
    [[1, 0, 0], [0, 1, 0], [0, 0, -1]]
    """
    q12, q13, q23, gram = distance_cosines(radii, distances)
    s = sp.sqrt(1 - q12**2)
    r1, r2, r3 = radii
    return [
        r1 * sp.Matrix([1, 0, 0]),
        r2 * sp.Matrix([q12, s, 0]),
        r3 * sp.Matrix([q13, (q23 - q12 * q13) / s, handedness * sp.sqrt(sp.Max(0, gram)) / s]),
    ]


# ------------------------------------------------------------------ planar poses
def planar_pose(x: sp.Expr, y: sp.Expr, phi: sp.Expr) -> sp.Matrix:
    """^B_P T of a platform moving in the plane z = 0: Rot_z(phi), origin of {P} at (x, y, 0)."""
    return homogeneous(rot_z(phi), [x, y, 0])


def planar_coordinates() -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """(x, y, phi) read from the pose symbols of an inverse program: px, py and
    atan2(r21, r11). The other entries of ^B_P T are not read (the pose is planar)."""
    return POSE_POSITION[0], POSE_POSITION[1], sp.atan2(POSE_ROTATION[1, 0], POSE_ROTATION[0, 0])


# ------------------------------------------------------------------ Euler-angle platforms
_AXIS_INDEX = {"x": 0, "y": 1, "z": 2}
_ROTATIONS = {"x": rot_x, "y": rot_y, "z": rot_z}


def euler_platform(
    sequence: str,
    angles: Sequence[sp.Symbol],
    position: Sequence[sp.Symbol] | None = None,
    branch: str = "sigma",
) -> Platform:
    """A platform whose orientation coordinates are Euler angles, with the inverse's reading of
    them from a pose: R = R_i(alpha) R_j(beta) R_k(gamma) for the axes of ``sequence`` (intrinsic,
    e.g. 'zyx': Rot_z(alpha) Rot_y(beta) Rot_x(gamma)).

    A Tait-Bryan sequence (three different axes) reads beta in [-pi/2, pi/2], with e = +1 for a
    cyclic sequence (xyz, yzx, zxy), -1 otherwise:
    alpha = atan2(-e r_jk, r_kk), beta = atan2(e r_ik, sqrt(r_kk^2 + r_jk^2)),
    gamma = atan2(-e r_ij, r_ii); singular (gimbal lock) at beta = +-pi/2, a singularity of the
    angles only. A proper sequence (i j i, k the third axis) has two triples per rotation, chosen
    by the inverse branch sign ``branch`` = sign(sin beta): sin_beta = sqrt(r_ij^2 + r_ik^2),
    beta = atan2(sigma sin_beta, r_ii), alpha = atan2(sigma r_ji, -e sigma r_ki), gamma =
    atan2(sigma r_ij, e sigma r_ik), with the validity ``euler_angles_regular`` (sin_beta^2,
    zero where the set is singular).

    Parameters
    ----------
    sequence : str
        Three axis letters, e.g. 'zyx' or 'xyx'.
    angles : three sympy.Symbol
        (alpha, beta, gamma), radians.
    position : three sympy.Symbol, optional
        The coordinates (x, y, z) of the origin of {P} in {B}, metres, read from the pose (pose
        kind 'transform'); None for a platform that only turns about the origin (kind 'rotation').
    branch : str
        The name of the branch sign of a proper sequence.

    Returns
    -------
    joints.Platform
        Coordinates (x, y, z, alpha, beta, gamma) or (alpha, beta, gamma), the angles angular.

    Raises
    ------
    ValueError
        ``sequence`` is not three of x, y, z with no two consecutive alike.

    Example
    -------
    >>> alpha, beta, gamma = sp.symbols("alpha beta gamma", real=True)
    >>> euler_platform("xyx", (alpha, beta, gamma)).read[1]
    (beta, atan2(sigma*sin_beta, r11))
    """
    from .joints import Platform  # joints imports this module

    if (
        len(sequence) != 3
        or set(sequence) - set(_AXIS_INDEX)
        or sequence[0] == sequence[1]
        or sequence[1] == sequence[2]
    ):
        raise ValueError(f"euler_platform: {sequence!r} is not an Euler sequence (e.g. 'zyx', 'xyx')")
    alpha, beta, gamma = angles
    rotation = _ROTATIONS[sequence[0]](alpha) * _ROTATIONS[sequence[1]](beta) * _ROTATIONS[sequence[2]](gamma)
    i, j = _AXIS_INDEX[sequence[0]], _AXIS_INDEX[sequence[1]]
    k = 3 - i - j
    e = 1 if (j - i) % 3 == 1 else -1  # +1 for a cyclic sequence i -> j -> k
    r = POSE_ROTATION
    branches: tuple[sp.Symbol, ...] = ()
    validity: tuple[tuple[str, sp.Expr], ...] = ()
    if sequence[2] != sequence[0]:
        read: tuple[tuple[sp.Symbol, sp.Expr], ...] = (
            (alpha, sp.atan2(-e * r[j, k], r[k, k])),
            (beta, sp.atan2(e * r[i, k], sp.sqrt(r[k, k] ** 2 + r[j, k] ** 2))),
            (gamma, sp.atan2(-e * r[i, j], r[i, i])),
        )
    else:
        sign, sine = sp.Symbol(branch, real=True), sp.Symbol(f"sin_{beta}", real=True)
        read = (
            (sine, sp.sqrt(r[i, j] ** 2 + r[i, k] ** 2)),
            (beta, sp.atan2(sign * sine, r[i, i])),
            (alpha, sp.atan2(sign * r[j, i], -e * sign * r[k, i])),
            (gamma, sp.atan2(sign * r[i, j], e * sign * r[i, k])),
        )
        branches, validity = (sign,), (("euler_angles_regular", sine**2),)
    if position is None:
        zero = sp.zeros(3, 1)
        return Platform(
            "rotation", tuple(angles), rotation, zero, read, (r, zero), angular=tuple(angles),
            branches=branches, validity=validity,
        )  # fmt: skip
    located = tuple(zip(position, POSE_POSITION, strict=True))
    return Platform(
        "transform", (*position, *angles), rotation, sp.Matrix(list(position)), located + read, (r, POSE_POSITION),
        angular=tuple(angles), branches=branches, validity=validity,
    )  # fmt: skip


def universal_prismatic_platform(angles: Sequence[sp.Symbol], length: sp.Symbol) -> Platform:
    """A platform carried by a passive U-P leg fixed to it (a Tricept's central leg), with the
    inverse's reading of the leg's coordinates from a pose: the universal joint at the origin of
    {B} turns about x_B by a, then about the turned y axis by b; the prismatic joint slides the
    origin of {P} along the leg, z_P, to the length s. R = Rot_x(a) Rot_y(b), p = s R z_P; read
    back as a = atan2(r32, r22), b = atan2(r13, r11), s = p . R z_P (a in (-pi/2, pi/2) where the
    leg is not folded onto the base plane; the reading of a pose off the set keeps the leg's
    coordinates nearest it).

    Parameters
    ----------
    angles : two sympy.Symbol
        (a, b), the universal joint's angles, radians.
    length : sympy.Symbol
        s, the leg's length from the origin of {B} to the origin of {P}, metres.

    Returns
    -------
    joints.Platform
        Of pose kind 'transform', coordinates (a, b, s), a and b angular.

    Example
    -------
    >>> a, b, s = sp.symbols("a b s", real=True)
    >>> universal_prismatic_platform((a, b), s).position.T
    Matrix([[s*sin(b), -s*sin(a)*cos(b), s*cos(a)*cos(b)]])
    """
    from .joints import Platform  # joints imports this module

    a, b = angles
    turn = rot_x(a) * rot_y(b)
    read = (
        (a, sp.atan2(POSE_ROTATION[2, 1], POSE_ROTATION[1, 1])),
        (b, sp.atan2(POSE_ROTATION[0, 2], POSE_ROTATION[0, 0])),
        (length, POSE_POSITION.dot(POSE_ROTATION[:, 2])),
    )
    return Platform(
        "transform", (a, b, length), turn, length * turn[:, 2], read, (POSE_ROTATION, POSE_POSITION), angular=(a, b)
    )


def euler_pose(sequence: str, angles: Sequence[float], position: Sequence[float]) -> sp.Matrix:
    """^B_P T of Euler angles and a position, numerically to 17 digits: R = R_i(alpha) R_j(beta)
    R_k(gamma) for the axes of ``sequence`` (as ``euler_platform``).

    Parameters
    ----------
    sequence : str
        Three axis letters, e.g. 'zyx'.
    angles : three floats
        (alpha, beta, gamma), radians.
    position : three floats
        The origin of {P} in {B}, metres.

    Returns
    -------
    sympy.Matrix, 4 x 4
        Entries sympy Floats of 17 digits (``euler_pose_values``: as floats; ``home_from_pose``
        takes either).

    Example
    -------
    >>> euler_pose("zyx", (0.0, 0.0, 0.0), (1.0, 2.0, 3.0))[:3, 3].T
    Matrix([[1.0, 2.0, 3.0]])
    """
    rotations = [_ROTATIONS[axis](sp.Float(value, 17)) for axis, value in zip(sequence, angles, strict=True)]
    transform = homogeneous(rotations[0] * rotations[1] * rotations[2], [sp.Float(v, 17) for v in position])
    return transform.evalf(17)


def euler_pose_values(sequence: str, angles: Sequence[float], position: Sequence[float]) -> list[list[float]]:
    """``euler_pose`` as the 4x4 list of floats an ``Example`` takes.

    Example
    -------
    >>> [round(v, 12) for v in euler_pose_values("zyx", (math.pi / 2, 0.0, 0.0), (1.0, 2.0, 3.0))[0]]
    [0.0, -1.0, 0.0, 1.0]
    """
    transform = euler_pose(sequence, angles, position)
    return pose_values(transform[:3, :3], transform[:3, 3])


# ------------------------------------------------------------------ prismatic legs
@dataclass(frozen=True)
class PrismaticLegs:
    """Legs of variable length l_i from a base point A_i (in {B}) to a platform point b_i (in
    {P}), for the platform pose (R, p) = ^B_P T: the SPS, UPS and (planar) RPR leg."""

    base: tuple[sp.Matrix, ...]
    platform: tuple[sp.Matrix, ...]
    rotation: sp.Matrix
    position: sp.Matrix

    def vectors(self) -> list[sp.Matrix]:
        """d_i = p + R b_i - A_i, from the base point to the platform point, in {B}."""
        return [self.position + self.rotation * b - a for a, b in zip(self.base, self.platform, strict=True)]

    def platform_points(self) -> list[sp.Matrix]:
        """B_i = p + R b_i in {B}."""
        return [self.position + self.rotation * b for b in self.platform]

    def lengths(self) -> list[sp.Expr]:
        """The closed-form inverse: l_i = |d_i|."""
        return [sp.sqrt(d.dot(d)) for d in self.vectors()]

    def inverse_steps(self, lengths: Sequence[sp.Symbol]) -> list[tuple[sp.Symbol, sp.Expr]]:
        """Inverse-program assignments l_i = |d_i|."""
        return list(zip(lengths, self.lengths(), strict=True))

    def residual(self, lengths: Sequence[sp.Expr], squared: bool = False) -> sp.Matrix:
        """One row per leg, zero at a closed configuration, in metres: |d_i| - l_i, or with
        ``squared`` (d_i . d_i - l_i^2) / (2 l_i), equal to |d_i| - l_i to first order. The
        squared form is a polynomial: its Jacobian d_i^T (dd_i / dq) / l_i stays finite where a
        leg has zero length (where that of |d_i| is 0 / 0), e.g. at a trial configuration."""
        if squared:
            return sp.Matrix([(d.dot(d) - n**2) / (2 * n) for d, n in zip(self.vectors(), lengths, strict=True)])
        return sp.Matrix([length - target for length, target in zip(self.lengths(), lengths, strict=True)])

    def pluecker_rows(self, twist: Sequence[str] = TWIST) -> sp.Matrix:
        """Rows (d_i ; (A_i - p) x d_i), the unnormalised Pluecker coordinates of leg line i with
        the moment about the origin of {P}: l_i l_dot_i = d_i . v + ((A_i - p) x d_i) . w, because
        R b_i = d_i + A_i - p. ``twist`` picks and orders the columns (e.g. vx, vy, wz for a
        planar platform)."""
        columns = [TWIST.index(name) for name in twist]
        rows = []
        for a, d in zip(self.base, self.vectors(), strict=True):
            full = list(d) + list((a - self.position).cross(d))
            rows.append([full[c] for c in columns])
        return sp.Matrix(rows)

    def rate_model(self, lengths: Sequence[sp.Symbol], twist: Sequence[str] = TWIST) -> RateModel:
        """A twist = B l_dot with A the Pluecker rows and B = diag(l_i); det B = prod l_i, one
        serial factor ``leg<i>_length`` per leg (a leg of zero length has no direction)."""
        serial = {f"leg{k + 1}_length": length for k, length in enumerate(lengths)}
        return RateModel(twist=list(twist), a=self.pluecker_rows(twist), b=sp.diag(*lengths), serial_factors=serial)


def prismatic_legs(
    base: sp.Matrix | Iterable[sp.Matrix],
    platform: sp.Matrix | Iterable[sp.Matrix],
    rotation: sp.Matrix,
    position: sp.Matrix,
) -> PrismaticLegs:
    """Prismatic legs from point lists: each a ``n x dims`` matrix (one row a point, e.g. from
    ``point_parameters``) or an iterable of 3x1 vectors; base points in {B}, platform points in {P}."""

    def points(value: sp.Matrix | Iterable[sp.Matrix]) -> tuple[sp.Matrix, ...]:
        if isinstance(value, sp.MatrixBase):
            return tuple(as_points(sp.Matrix(value)))
        return tuple(sp.Matrix(v) for v in value)

    legs = PrismaticLegs(points(base), points(platform), sp.Matrix(rotation), sp.Matrix(position))
    if len(legs.base) != len(legs.platform):
        raise ValueError(f"prismatic_legs: {len(legs.base)} base points but {len(legs.platform)} platform points")
    return legs


# ------------------------------------------------------------------ small determinants
def laplace_det(matrix: sp.Matrix) -> sp.Expr:
    """det of a small square matrix by cofactor expansion along the first row, as written (no
    expansion or simplification): for the 2x2 and 3x3 rate matrices of planar and translational
    mechanisms far smaller than ``Matrix.det`` (Berkowitz), which multiplies entries out."""
    if matrix.rows != matrix.cols:
        raise ValueError(f"laplace_det: {matrix.rows}x{matrix.cols} is not square")
    if matrix.rows == 1:
        return matrix[0, 0]
    total = sp.Integer(0)
    for j in range(matrix.cols):
        minor = matrix.extract(list(range(1, matrix.rows)), [c for c in range(matrix.cols) if c != j])
        total += (-1) ** j * matrix[0, j] * laplace_det(minor)
    return total


# ------------------------------------------------------------------ one angle from one equation
def block_laplace_det(matrix: sp.Matrix) -> sp.Expr:
    """det of a 6 x 6 matrix by Laplace's expansion along its first three columns: the sum over
    3-row subsets S of (-1)^(sum of S + 0 + 1 + 2) det(M[S, :3]) det(M[not S, 3:]) (0-based), 20
    products of 3 x 3 ``laplace_det``s. As written, a third of the size of the cofactor expansion
    along a row (600 entry occurrences instead of 1956)."""
    total = sp.Integer(0)
    for chosen in itertools.combinations(range(6), 3):
        rest = [k for k in range(6) if k not in chosen]
        sign = (-1) ** (sum(chosen) + 3)
        total += (
            sign * laplace_det(matrix.extract(list(chosen), [0, 1, 2])) * laplace_det(matrix.extract(rest, [3, 4, 5]))
        )
    return total


def half_angle_solution(
    cos_coefficient: sp.Expr, sin_coefficient: sp.Expr, constant: sp.Expr, sign: sp.Expr
) -> tuple[sp.Expr, sp.Expr]:
    """theta with E cos(theta) + F sin(theta) + G = 0, and the discriminant E^2 + F^2 - G^2.

    With tau = tan(theta / 2): (G - E) tau^2 + 2 F tau + (G + E) = 0, tau = (-F + sign sqrt(disc))
    / (G - E); written theta = 2 atan2(-F + sign sqrt(disc), G - E), which stays finite where
    G = E (theta = pi) and equals atan2(F, E) - sign acos(-G / sqrt(E^2 + F^2)) (mod 2 pi). The
    discriminant is clamped at 0 so that an unreachable branch stays finite: report ``disc`` as
    the branch's validity."""
    e, f, g = cos_coefficient, sin_coefficient, constant
    discriminant = e**2 + f**2 - g**2
    angle = 2 * sp.atan2(-f + sign * sp.sqrt(sp.Max(0, discriminant)), g - e)
    return angle, discriminant


# ------------------------------------------------------------------ univariate elimination
def half_angle_forms(unknown: sp.Symbol, domain: sp.polys.domains.Domain) -> tuple[sp.Poly, sp.Poly, sp.Poly]:
    """(1 + t^2) (cos phi, sin phi, 1) = (1 - t^2, 2 t, 1 + t^2) as ``Poly`` in t = tan(phi / 2)
    over ``domain`` (e.g. ``sp.QQ[symbols]``). A form a0 + a1 cos + a2 sin becomes a quadratic in
    t by a0 W + a1 C + a2 S; products of k such forms are (1 + t^2)^k times the trigonometric
    expression. Poly arithmetic over an explicit domain is orders of magnitude faster than
    ``expand`` followed by ``Poly``."""

    def poly(expr: sp.Expr) -> sp.Poly:
        return sp.Poly(expr, unknown, domain=domain)

    return poly(1 - unknown**2), poly(2 * unknown), poly(1 + unknown**2)


@dataclass(frozen=True)
class CleanPolynomial:
    """A univariate polynomial with its spurious factors removed.

    ``coefficients`` are ascending in ``unknown``; the input was ``content * unknown**zero_roots *
    prod(factor**multiplicity for factor, multiplicity in removed) * sum(c_k unknown^k)``.
    ``content`` is a number or an expression in the other symbols: where it vanishes the input
    vanished identically (report it as a degeneracy when it can vanish)."""

    unknown: sp.Symbol
    coefficients: list[sp.Expr]
    content: sp.Expr
    removed: list[tuple[sp.Expr, int]]
    zero_roots: int

    @property
    def degree(self) -> int:
        return len(self.coefficients) - 1

    def as_expr(self) -> sp.Expr:
        return sp.Add(*(c * self.unknown**k for k, c in enumerate(self.coefficients)))


def remove_spurious_factors(
    polynomial: sp.Poly | sp.Expr,
    unknown: sp.Symbol,
    spurious: Iterable[sp.Expr] = (),
    zero_is_root: bool = True,
    content: bool = True,
) -> CleanPolynomial:
    """Strip from a univariate elimination polynomial what the elimination introduced.

    ``polynomial``: a ``Poly`` in ``unknown`` (its coefficients may hold other symbols) or an
    expression (expanded and converted; build large ones as ``Poly``, see ``half_angle_forms``).
    In order:
    * ``content``: the gcd of the coefficients (a number, or a polynomial in the other symbols);
    * every factor of ``spurious`` (e.g. 1 + t^2, whose roots t = +-i are no half-angle tangent of
      a real angle), divided out as often as it divides, each irreducible factor on its own: the
      gcd with the polynomial, so a product of candidate factors may be given as one;
    * unless ``zero_is_root``, the power of ``unknown`` that divides the polynomial (a root t = 0
      that is known to be no solution).
    Raises ValueError on a polynomial that is identically zero.
    """
    poly = polynomial if isinstance(polynomial, sp.Poly) else sp.Poly(sp.expand(polynomial), unknown)
    if poly.gens != (unknown,):
        poly = sp.Poly(poly.as_expr(), unknown)
    if poly.is_zero:
        raise ValueError("remove_spurious_factors: the polynomial is identically zero")
    factor_content: sp.Expr = sp.Integer(1)
    if content:
        common, poly = poly.primitive()
        factor_content = poly.domain.to_sympy(common) if not isinstance(common, sp.Basic) else common
    removed: list[tuple[sp.Expr, int]] = []
    for factor in spurious:
        poly, found = _divide_out(poly, sp.Poly(factor, unknown, domain=poly.domain))
        removed += found
    zero_roots = 0
    if not zero_is_root:
        zero_roots = min(monomial[0] for monomial in poly.monoms())
        if zero_roots:
            poly = poly.exquo(sp.Poly(unknown**zero_roots, unknown, domain=poly.domain))
    coefficients = [poly.coeff_monomial(unknown**k) for k in range(poly.degree() + 1)]
    return CleanPolynomial(unknown, coefficients, factor_content, removed, zero_roots)


def _divide_out(poly: sp.Poly, factor: sp.Poly) -> tuple[sp.Poly, list[tuple[sp.Expr, int]]]:
    """``poly`` with every power of ``factor`` divided out, irreducible factor by irreducible
    factor: the part of ``factor`` that ``poly`` shares (their gcd) is a product of those, and
    exact division by each (small, often monic) factor is far cheaper than a multivariate gcd."""
    if factor.degree() < 1:
        return poly, []
    found = []
    _, irreducible = sp.factor_list(factor.as_expr(), factor.gens[0])
    for part, _ in irreducible:
        divisor = sp.Poly(part, factor.gens[0], domain=poly.domain)
        if divisor.degree() < 1:
            continue
        count = 0
        while poly.degree() >= divisor.degree():
            quotient, remainder = poly.div(divisor)
            if not remainder.is_zero:
                break
            poly, count = quotient, count + 1
        if count:
            found.append((divisor.as_expr(), count))
    return poly, found


__all__ = [
    "CleanPolynomial",
    "ParameterFields",
    "ParameterGroup",
    "PrismaticLegs",
    "TWIST",
    "as_points",
    "circle_points",
    "crank_bases",
    "euler_platform",
    "euler_pose",
    "euler_pose_values",
    "frame_pose_values",
    "home_from_pose",
    "leg_parameters",
    "pair_sides",
    "paired_circle_points",
    "parameter_fields",
    "planar_pose_values",
    "point_group",
    "pose_values",
    "radial_directions",
    "half_angle_forms",
    "half_angle_solution",
    "laplace_det",
    "planar_coordinates",
    "planar_pose",
    "point_defaults",
    "point_info",
    "point_parameters",
    "prismatic_legs",
    "remove_spurious_factors",
    "scalar_parameter",
]
