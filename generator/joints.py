"""Mechanisms described by their joints: a platform motion and legs, everything else derived.

A leg is a chain from the base to a platform joint whose closure is one distance: a point E on
the base side, placed by the leg's actuated joint, and the platform joint C = p + R c (c in {P})
are a fixed or actuated distance L apart, |C - E| = L. The kinds of leg (the joints of a chain,
base to platform; S a spherical joint, U a universal joint, the underlined one actuated):

* ``prismatic_leg``: S-P-S, U-P-S, R-P-R (planar): E = A fixed, L = the actuated length l; with
  a revolute axis n at A, R-P-S (the 3-RPS): the leg, and so C, stays in the plane through A
  normal to n, (C - A) . n = 0;
* ``crank_leg``: R-S-S, R-U-S, R-R-R (planar): an actuated crank of length r turns about the unit
  axis u through A, E = A + r (cos theta e0 + sin theta (u x e0)), e0 its zero direction (a unit
  vector normal to u); a link of fixed length L from E to C; with a revolute joint at E parallel
  to u, R-R-S (the 3-RRS): C stays in the crank's plane, (C - A) . u = 0;
* ``slider_leg``: P-S-S, P-U-S: a slider moves along the unit axis k through A, E = A + s k;
  a link of fixed length L; with a revolute axis n (normal to k), P-R-S: the revolute joint on
  the slider keeps the link, and so C, in the plane through A normal to n, (C - A) . n = 0.

A platform with fewer legs than twist components gets its missing constraints from such
revolute joints (lower mobility: the 3-PRS, whose platform also moves in parasitic components);
each adds a row (C - A) . n to the closure and a constraint wrench, the force along n through C,
(n, (C - p) x n), to the rate model (``RateModel.constraints``), and the parallel factor is the
determinant of all six wrenches.

A U at either end of a fixed-length link constrains nothing a distance does not (the link's spin
about its own line is not a coordinate of the model), so U and S legs share one model. The
platform's motion is declared (``Platform``: the pose kind and its coordinates, the Newton
unknowns), and the generator derives from the legs:

* the loop closure: (|C - E|^2 - L^2) / (2 L) per leg, in metres (|C - E| - L to first order; a
  polynomial, finite at a leg of zero length), with the unit-quaternion row of a rotating
  platform;
* the rate model A twist = B actuated_rates, from d/dt |d|^2 = d/dt L^2 with d = C - E:
  row i of A is (d, (E - p) x d) over the pose kind's twist (the Pluecker coordinates of the leg
  line, moment about the origin of {P}); B is diagonal with d . dE/dtheta + L dL/dtheta (l for a
  prismatic leg, u . ((E - A) x d) for a crank, d . k for a slider); one serial factor per leg;
  the parallel factor det A (written with moments about E_1, the same determinant in smaller
  expressions, for a planar or spherical-free platform);
* the inverse per leg in closed form: l = |C - A|; a crank's E cos + F sin + G = 0 by its
  tangent-half-angle quadratic with branch sign sigma_i; a slider's quadratic
  s = (C - A) . k - sigma_i sqrt(L^2 - |h|^2); with the validity of each (the discriminant made
  unitless); crank angles in (-pi, pi], the runtime's range (``crank_angle``); where the legs'
  three planes contain one axis (3-PRS, 3-RPS, 3-RRS), the pose read onto the reachable set
  (``readings``: the height and tilt controlled, the rest parasitic), so that the values are a
  configuration that closes; and one validity measure per plane constraint at the given pose,
  ``leg<i>_plane_reachable`` (``plane_measure``: the plane row relative to the leg's size), so
  that a pose off a lower-mobility platform's reachable set is invalid, naming the leg (unless
  the file declares ``unreachable="read"``);
* the drawing: base joints, elbows (crank tips, sliders), platform joints, each leg as a
  polyline, the base and platform polygons.
"""

from __future__ import annotations

import math
import random
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import sympy as sp

from .blocks import TWIST, block_laplace_det, check_branch, laplace_det, planar_coordinates
from .frames import homogeneous, quaternion_rotation, quaternion_rotation_unnormalised, quaternion_steps, rot_z
from .graph import Chain, Joint, JointGraph
from .model import (
    POSE_KINDS,
    POSE_POSITION,
    POSE_ROTATION,
    ClosureModel,
    Drawing,
    InverseReading,
    InverseSolution,
    RateModel,
)
from .readings import AxisReading, common_axis, vanishes

ZERO = sp.Matrix([0, 0, 0])


@dataclass(frozen=True)
class Platform:
    """How the platform moves: a pose kind (``model.POSE_KINDS``) and its coordinates, the
    passive variables. ``rotation`` and ``position`` are ^B_P T in the coordinates; ``read`` the
    inverse's assignments of the coordinates from a pose; ``pose`` the rotation and position that
    the inverse uses for the platform joints (the pose symbols themselves where every entry is a
    coordinate, the coordinates' pose where the kind reads only some: a planar pose).
    ``branches`` are sign symbols the reading takes (an Euler set's two triples), after the
    legs' in the inverse's branch numbering; ``validity`` names conditions of the reading."""

    kind: str
    coordinates: tuple[sp.Symbol, ...]
    rotation: sp.Matrix
    position: sp.Matrix
    read: tuple[tuple[sp.Symbol, sp.Expr], ...]
    pose: tuple[sp.Matrix, sp.Matrix]
    extra_residual: tuple[sp.Expr, ...] = ()
    angular: tuple[sp.Symbol, ...] = ()
    dimensionless: tuple[sp.Symbol, ...] = ()
    branches: tuple[sp.Symbol, ...] = ()
    validity: tuple[tuple[str, sp.Expr], ...] = ()

    @property
    def twist(self) -> list[str]:
        return list(POSE_KINDS[self.kind].twist)


def platform(kind: str) -> Platform:
    """The platform of a pose kind with its standard coordinates: 'transform' (x, y, z and a unit
    quaternion q0..q3, q0 >= 0 from the inverse), 'rotation' (q0..q3), 'planar' (x, y, phi),
    'translation' (x, y, z), 'planar_translation' (x, y)."""
    x, y, z, phi = sp.symbols("x y z phi", real=True)
    q = sp.symbols("q0:4", real=True)
    read: tuple[tuple[sp.Symbol, sp.Expr], ...]
    if kind == "transform":
        norm = (sum(c**2 for c in q) - 1) / 2
        read = ((x, POSE_POSITION[0]), (y, POSE_POSITION[1]), (z, POSE_POSITION[2]))
        read += tuple(quaternion_steps(POSE_ROTATION, q))
        return Platform(
            kind, (x, y, z, *q), quaternion_rotation(q), sp.Matrix([x, y, z]), read,
            (POSE_ROTATION, POSE_POSITION), (norm,), dimensionless=q,
        )  # fmt: skip
    if kind == "rotation":
        norm = (sum(c**2 for c in q) - 1) / 2
        read = tuple(quaternion_steps(POSE_ROTATION, q))
        return Platform(kind, q, quaternion_rotation(q), ZERO, read, (POSE_ROTATION, ZERO), (norm,), dimensionless=q)
    if kind == "planar":
        read = tuple(zip((x, y, phi), planar_coordinates(), strict=True))
        position = sp.Matrix([x, y, 0])
        return Platform(kind, (x, y, phi), rot_z(phi), position, read, (rot_z(phi), position), angular=(phi,))
    if kind == "translation":
        read = ((x, POSE_POSITION[0]), (y, POSE_POSITION[1]), (z, POSE_POSITION[2]))
        position = sp.Matrix([x, y, z])
        return Platform(kind, (x, y, z), sp.eye(3), position, read, (sp.eye(3), position))
    if kind == "planar_translation":
        position = sp.Matrix([x, y, 0])
        read = ((x, POSE_POSITION[0]), (y, POSE_POSITION[1]))
        return Platform(kind, (x, y), sp.eye(3), position, read, (sp.eye(3), position))
    raise ValueError(f"platform: unknown pose kind {kind!r}; one of {sorted(POSE_KINDS)}")


@dataclass(frozen=True)
class Leg:
    """One distance leg (module docstring). ``joint`` is the actuated variable; ``base`` the point A
    (the fixed base joint, the crank's centre, the slider's origin) in {B}; ``platform_joint`` c
    in {P}; ``link`` the fixed length L (None: the actuated length itself, a prismatic leg);
    ``axis`` the crank axis u or the slider axis k; ``zero`` the crank's zero direction e0."""

    kind: str  # "prismatic", "crank" or "slider"
    joint: sp.Symbol
    base: sp.Matrix
    platform_joint: sp.Matrix
    link: sp.Expr | None = None
    axis: sp.Matrix | None = None
    zero: sp.Matrix | None = None
    crank: sp.Expr | None = None
    #: which root the leg's branch sign +1 takes: +1 as documented per kind, -1 the other
    sign: int = 1
    #: the name of the leg's serial (type I) factor; None: the kind's (``SERIAL_NAMES``)
    serial_name: str | None = None
    #: a revolute joint's axis n that keeps the link, and so the platform joint, in the fixed
    #: plane through A normal to n (a P-R-S leg): one constraint wrench, the force along n
    #: through C; None: no such joint (S or U joints only)
    plane_normal: sp.Matrix | None = None
    #: the leg's joints in the joint graph (``generator.graph``), of which this is the distance form
    chain: Chain | None = field(default=None, compare=False, repr=False)
    #: a crank's elbow revolute axis h0 (at angle 0, turning with the crank) that is not parallel
    #: to the crank's axis (an R-R-S leg with skew axes): the link stays normal to h(theta), a
    #: constraint that turns with the crank; no closed-form inverse matches it, so the inverse
    #: solves the leg numerically (``numeric_leg_steps``) from ``start``; None: no such joint
    elbow_axis: sp.Matrix | None = None
    #: the numeric inverse's starting value of the joint (the middle of its limits, else 0)
    start: float = 0.0

    def turned_axis(self, value: sp.Expr | None = None) -> sp.Matrix:
        """h(theta) = Rot_u(theta) h0, the elbow axis at the joint value (default: the joint)."""
        assert self.elbow_axis is not None and self.axis is not None
        t, u, h = self.joint if value is None else value, self.axis, self.elbow_axis
        return sp.cos(t) * h + sp.sin(t) * u.cross(h) + (1 - sp.cos(t)) * u.dot(h) * u

    def elbow(self, value: sp.Expr | None = None) -> sp.Matrix:
        """E, the base-side end of the distance, at the joint value (default: the joint)."""
        t = self.joint if value is None else value
        if self.kind == "prismatic":
            return self.base
        assert self.axis is not None
        if self.kind == "slider":
            return self.base + t * self.axis
        assert self.zero is not None and self.crank is not None
        return self.base + self.crank * (sp.cos(t) * self.zero + sp.sin(t) * self.axis.cross(self.zero))

    def length(self) -> sp.Expr:
        """L: the link, or the actuated length."""
        return self.joint if self.link is None else self.link


def _vector(value: Sequence[sp.Expr] | sp.Matrix) -> sp.Matrix:
    v = sp.Matrix(value)
    if v.cols != 1 or not 1 <= v.rows <= 3:
        raise ValueError(f"a point or direction has 1 to 3 coordinates, got a {v.rows} x {v.cols} matrix")
    return sp.Matrix([v[k] if k < v.rows else 0 for k in range(3)])


def _unit(name: str, value: sp.Matrix) -> sp.Matrix:
    """A direction given in numbers must be a unit vector (one given by parameters is the user's
    to keep unit: the parameters' values are not known here)."""
    if not value.free_symbols and abs(float(value.dot(value)) - 1) > 1e-12:
        length = float(sp.sqrt(value.dot(value)))
        raise ValueError(f"{name} must be a unit vector, got {list(value)} of length {length:.6g}")
    return value


def _plane_normal(revolute_axis: Sequence[sp.Expr] | sp.Matrix | None) -> sp.Matrix | None:
    """The unit normal of the plane a constraining revolute joint keeps its leg in (None: none)."""
    return None if revolute_axis is None else _unit("a revolute joint's axis", _vector(revolute_axis))


def prismatic_leg(
    base: Sequence[sp.Expr] | sp.Matrix,
    platform_joint: Sequence[sp.Expr] | sp.Matrix,
    length: sp.Symbol,
    revolute_axis: Sequence[sp.Expr] | sp.Matrix | None = None,
    universal_axis: Sequence[sp.Expr] | sp.Matrix | None = None,
    platform_universal_axis: Sequence[sp.Expr] | sp.Matrix | None = None,
) -> Leg:
    """A leg whose actuated prismatic joint sets the distance from the base joint to the
    platform joint.

    Parameters
    ----------
    base : sequence of expressions or Matrix
        The base joint A, in {B}.
    platform_joint : sequence of expressions or Matrix
        The platform joint c, in {P}.
    length : Symbol
        The actuated length l = |C - A|.
    revolute_axis : sequence of expressions or Matrix, optional
        The unit axis n of a revolute joint at A (an R-P-S leg, as in the 3-RPS): it keeps the
        leg, and so the platform joint, in the plane through A normal to n, (C - A) . n = 0, a
        constraint on the platform (lower mobility). None (default): an S-P-S, U-P-S or planar
        R-P-R leg, no constraint.
    universal_axis : sequence of expressions or Matrix, optional
        The first (base) axis of a universal joint at A (a U-P-S leg; in the joint graph, the
        same distance and no constraint). None (default): a spherical joint there.
    platform_universal_axis : sequence of expressions or Matrix, optional
        The outer axis of a universal joint at the platform, fixed in {P} (a U-P-U leg: the
        same distance; in the joint graph its second axis is normal to it and to the leg, so
        that outer axes parallel at both ends leave the leg one constraint couple, the 3-UPU
        of Tsai 1996). None (default): a spherical joint there.

    Returns
    -------
    Leg
        The leg, for ``DistanceMechanism``.
    """
    a, normal = _vector(base), _plane_normal(revolute_axis)
    if normal is not None and universal_axis is not None:
        raise ValueError("a prismatic leg has a revolute or a universal joint at its base, not both")
    first = Joint("S", "base", a) if normal is None else Joint("R", "base", a, normal)
    if universal_axis is not None:
        first = Joint("U", "base", a, _unit("a universal joint's axis", _vector(universal_axis)))
    slide = Joint("P", "base", a, None, length, actuated=True)
    c = _vector(platform_joint)
    end = Joint("S", "platform", c)
    if platform_universal_axis is not None:
        end = Joint("U", "platform", c, _unit("a universal joint's axis", _vector(platform_universal_axis)))
    chain = Chain("leg", (first, slide, end))
    return distance_form(chain)


def crank_leg(
    base: Sequence[sp.Expr] | sp.Matrix,
    axis: Sequence[sp.Expr] | sp.Matrix,
    zero: Sequence[sp.Expr] | sp.Matrix,
    crank: sp.Expr,
    link: sp.Expr,
    platform_joint: Sequence[sp.Expr] | sp.Matrix,
    angle: sp.Symbol,
    sign: int = 1,
    serial_name: str | None = None,
    revolute_axis: Sequence[sp.Expr] | sp.Matrix | None = None,
    parallelogram: Sequence[sp.Expr] | sp.Matrix | None = None,
    spherical: bool = False,
) -> Leg:
    """A leg whose actuated crank carries a link of fixed length to the platform joint.

    R-S-S, R-U-S or planar R-R-R: an actuated crank of length ``crank`` turning by ``angle``
    about the unit ``axis`` through A from the unit direction ``zero`` (normal to the axis;
    counter-clockwise about the axis), then a link of length ``link`` to c (in {P}). Branch sign
    +1 turns the crank counter-clockwise from the line A -> C (``sign`` = -1: clockwise).

    Parameters
    ----------
    base, axis, zero : sequence of expressions or Matrix
        The crank's centre A (in {B}), its unit axis u and its unit zero direction e0 (normal to u).
    crank, link : expression
        The crank's length r and the link's length L.
    platform_joint : sequence of expressions or Matrix
        The platform joint c, in {P}.
    angle : Symbol
        The actuated crank angle theta.
    sign : int
        Which root branch sign +1 takes (above; -1 the other).
    serial_name : str, optional
        The name of the leg's serial factor (default ``leg{k}_links_aligned``).
    revolute_axis : sequence of expressions or Matrix, optional
        The axis of a revolute joint between crank and link (an R-R-S leg, as in the 3-RRS). It
        must be parallel to the crank's axis: the link then stays in the crank's plane, through A
        normal to u, (C - A) . u = 0, a constraint on the platform (lower mobility). None
        (default): a spherical or universal joint there, no constraint.
    parallelogram : sequence of expressions or Matrix, optional
        The hinge direction h of a parallelogram link (a delta's forearm: two bars of length
        ``link``, short sides along h at the crank and at the platform, in {B} and in {P} at
        the platform's zero orientation): revolute joints about h at both ends and the
        parallelogram between them, which keep the platform's side parallel to the crank's
        (no turn about two axes normal to h). The distance is the same; the joint graph, and
        so the screw analysis, has the parallelogram.
    spherical : bool
        An R-R-R leg of a spherical mechanism (the SPM), its crank's axis through the origin of
        {B}, the elbow and the platform joint on a sphere about it: revolute joints about the
        lines from the origin through the elbow and through the platform joint, meeting the
        crank's axis there. The distance is the same (the distal link's angle); the joint graph
        has the revolute joints.

    Returns
    -------
    Leg
        The leg, for ``DistanceMechanism``.
    """
    u, e0 = _unit("a crank's axis", _vector(axis)), _unit("a crank's zero direction", _vector(zero))
    if not (u.free_symbols or e0.free_symbols) and abs(float(u.dot(e0))) > 1e-12:
        raise ValueError(f"a crank's zero direction {list(e0)} must be normal to its axis {list(u)}")
    normal = _plane_normal(revolute_axis)
    if normal is not None and not (normal.free_symbols or u.free_symbols):
        if float(normal.cross(u).norm()) > 1e-12:
            raise ValueError(
                f"a crank's revolute axis {list(normal)} must be parallel to the crank's axis {list(u)} (the link "
                "then moves in the crank's plane; another revolute axis is not a fixed plane)"
            )
        normal = u  # the plane is the crank's: one normal, whichever of the two directions was given
    a, c = _vector(base), _vector(platform_joint)
    if spherical:
        if normal is not None or parallelogram is not None:
            raise ValueError("a spherical crank leg (axes meeting at the origin) has no revolute_axis or parallelogram")
        middle, end = _spherical(a + crank * e0, c)
    else:
        middle, end = _middle(normal, parallelogram), _platform_end(c, parallelogram)
    joints = (Joint("R", "base", a, u, angle, actuated=True), *middle, end)
    return distance_form(Chain("leg", joints, reach=(crank, e0), link=link, sign=sign, serial_name=serial_name))


def slider_leg(
    base: Sequence[sp.Expr] | sp.Matrix,
    axis: Sequence[sp.Expr] | sp.Matrix,
    link: sp.Expr,
    platform_joint: Sequence[sp.Expr] | sp.Matrix,
    stroke: sp.Symbol,
    sign: int = 1,
    serial_name: str | None = None,
    revolute_axis: Sequence[sp.Expr] | sp.Matrix | None = None,
    parallelogram: Sequence[sp.Expr] | sp.Matrix | None = None,
) -> Leg:
    """P-S-S or P-U-S: an actuated slider at A + stroke k along the unit ``axis`` k, then a link
    of length ``link`` to c (in {P}). Branch sign +1 puts the slider behind the platform joint
    along k (the link rising along k; ``sign`` = -1: ahead of it). With ``revolute_axis`` n (a
    unit vector normal to k), a P-R-S leg: a revolute joint on the slider keeps the link in the
    plane through A normal to n, a constraint on the platform (lower mobility). With
    ``parallelogram`` h, the link is a parallelogram hinged about h at both ends (``crank_leg``),
    a linear delta's."""
    k = _unit("a slider's axis", _vector(axis))
    normal = None
    if revolute_axis is not None:
        normal = _unit("a revolute joint's axis", _vector(revolute_axis))
        if not (normal.free_symbols or k.free_symbols) and abs(float(normal.dot(k))) > 1e-12:
            raise ValueError(
                f"a slider's revolute axis {list(normal)} must be normal to the slider's axis {list(k)} (the link's "
                "plane must hold the rail)"
            )
    a, c = _vector(base), _vector(platform_joint)
    middle = _middle(normal, parallelogram)
    joints = (Joint("P", "base", a, k, stroke, actuated=True), *middle, _platform_end(c, parallelogram))
    return distance_form(Chain("leg", joints, link=link, sign=sign, serial_name=serial_name))


def _middle(normal: sp.Matrix | None, parallelogram: Sequence[sp.Expr] | sp.Matrix | None) -> tuple[Joint, ...]:
    """The elbow's joints: S (default), R about ``normal``, or R and Pa about the parallelogram's
    hinge direction."""
    if parallelogram is not None:
        if normal is not None:
            raise ValueError("a leg has a revolute joint at its elbow or a parallelogram link, not both")
        hinge = _unit("a parallelogram's hinge axis", _vector(parallelogram))
        return (Joint("R", "elbow", None, hinge), Joint("Pa", "elbow", None, hinge))
    return (Joint("S", "elbow"),) if normal is None else (Joint("R", "elbow", None, normal),)


def _spherical(zero_elbow: sp.Matrix, platform_axis: sp.Matrix) -> tuple[tuple[Joint, ...], Joint]:
    """The elbow and platform joints of an R-R-R leg whose axes meet at the origin (a spherical
    mechanism's): revolute about the lines from the origin through the elbow (at zero, carried by
    the crank) and through the platform joint."""
    return (Joint("R", "elbow", None, zero_elbow),), Joint("R", "platform", platform_axis, platform_axis)


def _platform_end(point: sp.Matrix, parallelogram: Sequence[sp.Expr] | sp.Matrix | None) -> Joint:
    """The platform joint: S, or after a parallelogram R about its hinge direction (in {P})."""
    if parallelogram is None:
        return Joint("S", "platform", point)
    return Joint("R", "platform", point, _vector(parallelogram))


def passive_leg(
    base: Sequence[sp.Expr] | sp.Matrix,
    axis: Sequence[sp.Expr] | sp.Matrix,
    platform_point: Sequence[sp.Expr] | sp.Matrix,
    direction: Sequence[sp.Expr] | sp.Matrix,
) -> Chain:
    """A passive U-P leg fixed to the platform (the Tricept's central leg): a universal joint at
    A, the first axis a1 fixed in {B}, a passive prismatic joint along the leg's line, and the
    leg rigidly attached to the platform at c0 (in {P}), its line along the unit w (in {P}).

    It constrains the platform three times: C0 = p + R c0 stays on the line through A along
    R w, (C0 - A) . R b = (C0 - A) . R (w x b) = 0, and the universal joint's second axis, R b
    with b = a1 x w (the axes at the platform's zero orientation R = I), stays normal to the
    first, a1 . R b = 0. Its constraint wrenches: the forces through A along R b and R (w x b),
    and the couple a1 x R b.

    Parameters
    ----------
    base : sequence of expressions or Matrix
        The universal joint's centre A, in {B}.
    axis : sequence of expressions or Matrix
        The universal joint's first (base) axis a1, a unit vector in {B}, normal to w.
    platform_point : sequence of expressions or Matrix
        c0, where the leg is fixed to the platform, in {P}.
    direction : sequence of expressions or Matrix
        w, the leg's line in {P}, a unit vector.

    Returns
    -------
    Chain
        The leg in the joint graph, for ``DistanceMechanism`` (with the actuated legs).

    Raises
    ------
    ValueError
        If an axis is not a unit vector, or a1 is not normal to w.

    Example
    -------
    >>> leg = passive_leg([0, 0, 0], [1, 0, 0], [0, 0, 0], [0, 0, 1])
    >>> leg.kinds
    'U-P-F'
    """
    a1, w = _unit("a universal joint's axis", _vector(axis)), _unit("a passive leg's direction", _vector(direction))
    if not (a1.free_symbols or w.free_symbols) and abs(float(a1.dot(w))) > 1e-12:
        raise ValueError(f"a passive leg's universal axis {list(a1)} must be normal to its line {list(w)}")
    a = _vector(base)
    joints = (Joint("U", "base", a, a1), Joint("P", "base", a), Joint("F", "platform", _vector(platform_point), w))
    return Chain("leg", joints)


def central_joint() -> Chain:
    """A spherical joint at the origin of {B} holding the platform (a 3-SPS-1S): the platform of
    pose kind 'rotation' turns about it. It adds no row to the closure (the pose kind has no
    translation); the joint graph, and so the screw analysis, has it.

    Returns
    -------
    Chain
        The passive leg S-F, for ``DistanceMechanism``.

    Example
    -------
    >>> central_joint().kinds
    'S-F'
    """
    return Chain("leg", (Joint("S", "base", ZERO), Joint("F", "platform", ZERO)))


def distance_form(chain: Chain, pose_kind: str = "transform") -> Leg:
    """The distance form of a leg of the joint graph (module docstring): a prismatic leg (a line
    of variable length from A, its actuated prismatic joint), a crank (an actuated revolute joint
    at A carrying a crank of ``reach`` to the elbow) or a slider (an actuated prismatic joint
    along an axis), with a link of fixed length from the elbow to the platform joint, and the
    plane a revolute joint at A or at the elbow keeps it in.

    Parameters
    ----------
    chain : Chain
        The leg's joints, base to platform (``prismatic_leg``, ``crank_leg``, ``slider_leg`` or
        written joint by joint).
    pose_kind : str
        The platform's pose kind: in a planar one a plane normal to z is the pose kind's own,
        no constraint.

    Returns
    -------
    Leg
        Its distance form, ``chain`` kept.

    Raises
    ------
    ValueError
        Where the chain is none of these shapes, saying what it holds and what is supported.
    """
    joints = chain.joints
    actuated = [j for j in joints if j.actuated]
    shapes = (
        "supported: [S, U or R at A]-P(actuated, along A -> C)-[S or U at C]; R(actuated at A, with reach)-"
        "[S, U, R, or R-Pa at the elbow]-[S, U or R at C] with a link; P(actuated at A, with an axis)-[the same]"
    )
    if len(actuated) != 1 or actuated[0].variable is None:
        raise ValueError(f"leg {chain.name} ({chain.kinds}): one actuated joint with a variable; {shapes}")
    drive = actuated[0]
    elbow = chain.at("elbow")
    revolute = [j for j in (*chain.at("base"), *elbow) if j.kind == "R" and j is not drive]
    # a revolute joint keeps the leg in a plane where the link ends in a spherical or universal
    # joint; in an R-R-R leg the platform's revolute joint and the pose kind hold the rest
    spherical_end = joints[-1].kind in ("S", "U")
    normal = revolute[0].axis if revolute and spherical_end and not any(j.kind == "Pa" for j in elbow) else None
    if normal is not None and pose_kind in ("planar", "planar_translation") and list(normal) in ([0, 0, 1], [0, 0, -1]):
        normal = None  # the plane z = 0 is the pose kind's
    a, c = joints[0].point, joints[-1].point
    assert a is not None and c is not None
    if chain.link is None and drive.kind == "P" and drive.axis is None:
        return Leg("prismatic", drive.variable, a, c, plane_normal=normal, chain=chain)
    if chain.link is not None and drive is joints[0] and drive.kind == "R" and chain.reach is not None:
        crank, zero = chain.reach
        assert drive.axis is not None
        skew = normal is not None and not vanishes(normal.cross(drive.axis).norm() ** 2)
        start = 0.0 if drive.limits is None else (drive.limits[0] + drive.limits[1]) / 2
        return Leg(
            "crank", drive.variable, a, c, chain.link, drive.axis, zero, crank, chain.sign, chain.serial_name,
            None if skew else normal, chain, elbow_axis=normal if skew else None, start=start,
        )  # fmt: skip
    if chain.link is not None and drive is joints[0] and drive.kind == "P" and drive.axis is not None:
        if normal is not None and not vanishes(normal.dot(drive.axis)):
            raise ValueError(
                f"leg {chain.name} ({chain.kinds}): the revolute joint on the slider has axis {list(normal)}, not "
                f"normal to the slider's axis {list(drive.axis)}: the link's plane would move with the stroke, a leg "
                "no subproblem matches; turn the revolute axis normal to the rail (a P-R-S leg)"
            )
        return Leg(
            "slider", drive.variable, a, c, chain.link, drive.axis, None, None, chain.sign, chain.serial_name, normal, chain
        )  # fmt: skip
    raise ValueError(f"leg {chain.name} ({chain.kinds}) is not a distance leg; {shapes}")


#: Gauss-Newton steps of a leg's numeric inverse (``numeric_leg_steps``), unrolled into the program:
#: from a start within the basin the residual falls quadratically, below 1e-16 of the leg's size
NEWTON_STEPS = 12


def _leg_residuals(leg: Leg, joint: sp.Matrix, cosine: sp.Expr, sine: sp.Expr) -> tuple[list[sp.Expr], list[sp.Expr]]:
    """A turning leg's closure at the joint value theta (given by its cosine and sine):
    ((|d|^2 - L^2) / (2 L), d . h) with d = C - E (metres), and their derivatives in theta."""
    return _residuals_of(leg, *_leg_vectors(leg, joint, cosine, sine))


def _leg_vectors(leg: Leg, joint: sp.Matrix, cosine: sp.Expr, sine: sp.Expr) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """d = C - E, h(theta) and dE / dtheta of a turning leg, in {B}."""
    assert leg.axis is not None and leg.zero is not None and leg.crank is not None and leg.elbow_axis is not None
    u, zero, h0 = leg.axis, leg.zero, leg.elbow_axis
    d = joint - leg.base - leg.crank * (cosine * zero + sine * u.cross(zero))
    h = cosine * h0 + sine * u.cross(h0) + (1 - cosine) * u.dot(h0) * u
    return d, h, leg.crank * (-sine * zero + cosine * u.cross(zero))


def _residuals_of(leg: Leg, d: sp.Matrix, h: sp.Matrix, along: sp.Matrix) -> tuple[list[sp.Expr], list[sp.Expr]]:
    """The two residuals and their derivatives in theta from d, h and dE / dtheta (dh / dtheta = u x h)."""
    assert leg.link is not None and leg.axis is not None
    values = [(d.dot(d) - leg.link**2) / (2 * leg.link), d.dot(h)]
    return values, [-d.dot(along) / leg.link, -along.dot(h) + d.dot(leg.axis.cross(h))]


def numeric_leg_steps(leg: Leg, joint: sp.Matrix, number: int) -> tuple[list[tuple[sp.Symbol, sp.Expr]], sp.Expr]:
    """The inverse of a leg that no closed form matches, solved numerically: NEWTON_STEPS
    Gauss-Newton steps on the leg's own closure (its distance and its turning constraint, two
    equations in its joint value) from ``leg.start``, unrolled into the inverse's program.

    Parameters
    ----------
    leg : Leg
        A crank leg with a skew elbow axis (``Leg.elbow_axis``).
    joint : Matrix
        Its platform joint C at the pose, in {B} (3 x 1).
    number : int
        The leg's number (1-based), for the step symbols.

    Returns
    -------
    tuple
        The steps (one assigns the joint, in (-pi, pi]) and the validity measure
        1 - |residual|^2 / (PLANE_TOLERANCE s)^2 with s^2 = |A|^2 + |c|^2 + L^2 + r^2: negative
        where the closure at the computed joint value is not met, the pose off this leg's
        reachable set or Newton from the start not reaching it (``leg<i>_numeric_reachable``).
    """
    point = sp.Matrix(sp.symbols(f"leg{number}_joint_x leg{number}_joint_y leg{number}_joint_z", real=True))
    steps: list[tuple[sp.Symbol, sp.Expr]] = list(zip(point, joint, strict=True))
    value: sp.Expr = sp.Float(leg.start)
    for j in range(NEWTON_STEPS + 1):
        cosine, sine = sp.symbols(f"theta{number}_cos{j} theta{number}_sin{j}", real=True)
        steps += [(cosine, sp.cos(value)), (sine, sp.sin(value))]
        vectors = _leg_vectors(leg, point, cosine, sine)
        names = [sp.Matrix(sp.symbols(f"theta{number}_{v}{j}_0:3", real=True)) for v in ("d", "h", "along")]
        steps += [
            (n, e) for name, vector in zip(names, vectors, strict=True) for n, e in zip(name, vector, strict=True)
        ]
        (f, g), (df, dg) = _residuals_of(leg, *names)
        named = sp.symbols(f"theta{number}_f{j} theta{number}_g{j} theta{number}_df{j} theta{number}_dg{j}", real=True)
        steps += list(zip(named, (f, g, df, dg), strict=True))
        f, g, df, dg = named
        if j == NEWTON_STEPS:
            break
        following = sp.Symbol(f"theta{number}_newton{j + 1}", real=True)
        steps.append((following, value - (df * f + dg * g) / (df**2 + dg**2)))
        value = following
    steps.append((leg.joint, sp.atan2(sine, cosine)))
    assert leg.link is not None and leg.crank is not None
    size = leg.base.dot(leg.base) + leg.platform_joint.dot(leg.platform_joint) + leg.link**2 + leg.crank**2
    return steps, 1 - (f**2 + g**2) / (PLANE_TOLERANCE**2 * size)


def turning_force(leg: Leg, joint: sp.Matrix) -> sp.Matrix:
    """The constraint force through C of a turning leg: of the forces the leg holds with its crank
    locked, along d = C - E and along h(theta), the combination whose work leaves the crank's rate
    out: L (g' grad f - f' grad g) for f = (|d|^2 - L^2) / (2 L), g = d . h, so
    F = (d . h' - E' . h) d + (d . E') h (E', h' the derivatives in theta)."""
    _, (df, dg) = _leg_residuals(leg, joint, sp.cos(leg.joint), sp.sin(leg.joint))
    assert leg.link is not None
    d = joint - leg.elbow()
    return dg * d - df * leg.link * leg.turned_axis()  # L times dg grad f1 - df grad f2


#: a platform joint this far from its leg's plane, relative to the leg's size (``plane_measure``),
#: is off the reachable set: far below any distance a user means, far above the rounding of a
#: pose computed in double precision (1e-16 relative)
PLANE_TOLERANCE = 1e-6


def plane_measure(leg: Leg, offset: sp.Matrix) -> sp.Expr:
    """The inverse's validity measure of a leg's plane constraint.

    Parameters
    ----------
    leg : Leg
        A leg with a ``plane_normal`` n.
    offset : Matrix
        C - A, from the leg's base point to its platform joint at the pose, in {B}.

    Returns
    -------
    Expr
        1 - (((C - A) . n) / (PLANE_TOLERANCE s))^2, with s^2 = |A|^2 + |c|^2 + L^2 (+ r^2 for a
        crank) the leg's size: 1 where the platform joint lies in the plane, positive while it is
        within PLANE_TOLERANCE s of it, negative beyond. Unitless and the same at any scale (a
        tolerance in metres would accept a whole millimetre mechanism, or refuse the rounding of
        a large one).
    """
    assert leg.plane_normal is not None
    size = leg.base.dot(leg.base) + leg.platform_joint.dot(leg.platform_joint) + leg.length() ** 2
    size += 0 if leg.crank is None else leg.crank**2
    return 1 - offset.dot(leg.plane_normal) ** 2 / (PLANE_TOLERANCE**2 * size)


def passive_measures(leg: PassiveLeg, rotation: sp.Matrix, position: sp.Matrix) -> dict[str, sp.Expr]:
    """The inverse's validity measures of a passive leg at a pose (^B_P R, position).

    Parameters
    ----------
    leg : PassiveLeg
        The leg.
    rotation, position : Matrix
        The pose, in {B}.

    Returns
    -------
    dict
        ``<leg>_line_reachable``: 1 - ((C0 - A) . R b)^2 + ((C0 - A) . R (w x b))^2) / (PLANE_TOLERANCE
        s)^2, s^2 = |A|^2 + |c0|^2 + |C0 - A|^2, negative where C0 is off the leg's line;
        ``<leg>_u_joint_reachable``: 1 - (a1 . R b / PLANE_TOLERANCE)^2, negative where the
        platform turned about the leg (the universal joint cannot); ``<leg>_extension_reachable``:
        (C0 - A) . R w / s, negative where the leg would point away from the platform. Unitless.
    """
    d = leg.offset(rotation, position)
    across = leg.rows(rotation, position)
    size = leg.base.dot(leg.base) + leg.platform_point.dot(leg.platform_point) + d.dot(d)
    return {
        f"{leg.name}_line_reachable": 1 - (across[0] ** 2 + across[1] ** 2) / (PLANE_TOLERANCE**2 * size),
        f"{leg.name}_u_joint_reachable": 1 - across[2] ** 2 / PLANE_TOLERANCE**2,
        f"{leg.name}_extension_reachable": d.dot(rotation * leg.direction) / sp.sqrt(size),
    }


def crank_angle(
    cos_coefficient: sp.Expr, sin_coefficient: sp.Expr, constant: sp.Expr, sign: sp.Expr
) -> tuple[sp.Expr, sp.Expr]:
    """A crank's angle theta in (-pi, pi] with E cos(theta) + F sin(theta) + G = 0.

    Parameters
    ----------
    cos_coefficient, sin_coefficient, constant : Expr
        E, F and G.
    sign : Expr
        The root's sign (+1 or -1), as ``blocks.half_angle_solution`` takes it.

    Returns
    -------
    tuple of Expr
        theta and the discriminant E^2 + F^2 - G^2 (the branch's validity).

    Notes
    -----
    ``half_angle_solution`` writes theta = 2 atan2(Y, X), Y = -F + sign sqrt(disc), X = G - E, which
    lies in (-2 pi, 2 pi]: a home read from it (``home_at``) could be 5.95 rad where the runtime
    reports -0.33. The double-angle formulas give the same angle as atan2(2 X Y, X^2 - Y^2), in
    (-pi, pi] like every angle the runtime returns, with no further trigonometric function.
    """
    e, f, g = cos_coefficient, sin_coefficient, constant
    discriminant = e**2 + f**2 - g**2
    y, x = -f + sign * sp.sqrt(sp.Max(0, discriminant)), g - e
    return sp.atan2(2 * x * y, x**2 - y**2), discriminant


def wrapped_angle(angle: float) -> float:
    """``angle`` in (-pi, pi], the range of ``parakin.pose.wrap_angle``.

    Parameters
    ----------
    angle : float
        An angle in radians.

    Returns
    -------
    float
        The same angle modulo 2 pi, -pi given as pi.
    """
    value = math.remainder(angle, 2 * math.pi)
    return math.pi if value <= -math.pi else value


def _for_kind(chain: Chain, pose_kind: str) -> Chain:
    """A leg's joints in a planar mechanism: the shorthands' spherical joints are revolute joints
    about z there (what R-P-R and R-R-R legs have)."""
    if pose_kind not in ("planar", "planar_translation"):
        return chain
    z = sp.Matrix([0, 0, 1])
    joints = tuple(replace(j, kind="R", axis=z) if j.kind == "S" else j for j in chain.joints)
    return replace(chain, joints=joints)


@dataclass(frozen=True)
class PassiveLeg:
    """A passive U-P leg fixed to the platform (``passive_leg``): the universal joint's centre A
    and first axis a1 (in {B}), the fixed point c0 and the line w (in {P}), b = a1 x w the
    universal joint's second axis in {P}, and the leg's name."""

    name: str
    base: sp.Matrix
    axis: sp.Matrix
    platform_point: sp.Matrix
    direction: sp.Matrix

    @property
    def second(self) -> sp.Matrix:
        return self.axis.cross(self.direction)

    def offset(self, rotation: sp.Matrix, position: sp.Matrix) -> sp.Matrix:
        """C0 - A, in {B}."""
        return position + rotation * self.platform_point - self.base

    def rows(self, rotation: sp.Matrix, position: sp.Matrix) -> list[sp.Expr]:
        """(C0 - A) . R b, (C0 - A) . R (w x b) (metres) and a1 . R b: zero where the leg closes."""
        d, b = self.offset(rotation, position), self.second
        return [d.dot(rotation * b), d.dot(rotation * self.direction.cross(b)), self.axis.dot(rotation * b)]


def passive_form(chain: Chain) -> PassiveLeg:
    """The passive leg a chain of the joint graph is (``passive_leg``: U-P-F).

    Parameters
    ----------
    chain : Chain
        A leg without actuated joints.

    Returns
    -------
    PassiveLeg
        Its universal joint, fixed point and line.

    Raises
    ------
    ValueError
        If the chain is not a U-P-F leg (the one passive leg supported).
    """
    kinds = [j.kind for j in chain.joints]
    if kinds != ["U", "P", "F"] or chain.joints[2].axis is None or chain.joints[0].axis is None:
        raise ValueError(
            f"leg {chain.name} ({chain.kinds}) has no actuated joint: the one passive leg supported is U-P fixed "
            "to the platform (passive_leg: a Tricept's)"
        )
    base, fixed = chain.joints[0], chain.joints[2]
    assert base.point is not None and base.axis is not None and fixed.point is not None and fixed.axis is not None
    return PassiveLeg(chain.name, base.point, base.axis, fixed.point, fixed.axis)


SERIAL_NAMES = {"prismatic": "leg{k}_length", "crank": "leg{k}_links_aligned", "slider": "leg{k}_link_normal_to_rail"}


@dataclass
class DistanceMechanism:
    """A platform and its distance legs: the derivations of the module docstring. Pass the
    fields to ``model.Mechanism`` (``fields()``), with the file's parameters, examples and
    citation."""

    motion: Platform
    #: the legs: distance legs (``prismatic_leg``, ``crank_leg``, ``slider_leg``) or chains of the
    #: joint graph (``passive_leg``, or joint by joint); after construction their distance forms,
    #: the actuated ones, and ``passive`` the passive legs
    legs: list[Leg]
    #: the name of the parallel (type II) factor det A
    parallel_name: str = "leg_lines_dependent"
    #: what the inverse says of a pose off a lower-mobility platform's reachable set, where it reads
    #: the pose onto that set (``reading``): "invalid" (the given pose's plane constraints fail,
    #: ``leg<i>_plane_reachable`` naming each leg) or "read" (valid: the reachable pose of the
    #: controlled coordinates is the answer, as prs3 documents). Either way its values are the
    #: reachable pose's, a configuration that closes.
    unreachable: str = "invalid"
    #: the inverse's branch signs: sigma<k> of each crank or slider leg k, then the platform's
    branch_names: list[sp.Symbol] = field(init=False)
    #: the mechanism's bodies and joints, from which every derivation below starts
    graph: JointGraph = field(init=False)
    #: the passive legs (``passive_leg``), numbered after the actuated ones
    passive: list[PassiveLeg] = field(init=False)
    #: the reading of a pose onto the reachable set derived from the legs' planes
    #: (``readings.common_axis``); None where the platform reads the pose as given
    reading: AxisReading | None = field(init=False)

    def __post_init__(self) -> None:
        if not self.legs:
            raise ValueError("DistanceMechanism: no legs")
        chains = []
        for k, leg in enumerate(self.legs):
            chain = leg.chain if isinstance(leg, Leg) else leg
            if not isinstance(chain, Chain):
                raise ValueError(f"DistanceMechanism: leg {k + 1} is {type(leg).__name__}, not a leg or a chain")
            chains.append(_for_kind(replace(chain, name=f"leg{k + 1}"), self.motion.kind))
        self.graph = JointGraph(
            self.motion.kind, self.motion.coordinates, self.motion.rotation, self.motion.position, chains
        )
        # the one path: every derivation below reads the legs' distance forms from the graph
        self.legs = [distance_form(chain, self.motion.kind) for chain in self.graph.legs if chain.actuated]
        centres = [chain for chain in self.graph.legs if [j.kind for j in chain.joints] == ["S", "F"]]
        if centres and (self.motion.kind != "rotation" or any(c.joints[0].point != ZERO for c in centres)):
            raise ValueError(
                "DistanceMechanism: a central spherical joint (central_joint) holds a platform of pose kind 'rotation' "
                f"at the origin of {{B}}, got pose kind {self.motion.kind!r}"
            )
        rest = [chain for chain in self.graph.legs if not chain.actuated and chain not in centres]
        self.passive = [passive_form(chain) for chain in rest]
        planes = len(self.constrained) + len(self.turning)
        held = 3 * len(self.passive)
        if len(self.legs) + planes + held != len(self.motion.twist):
            passive = f" and {len(self.passive)} passive legs ({held} constraints)" if self.passive else ""
            raise ValueError(
                f"DistanceMechanism: {len(self.legs)} legs and {planes} constraining revolute joints{passive} for the "
                f"{len(self.motion.twist)} twist components of pose kind {self.motion.kind!r} "
                f"({', '.join(self.motion.twist)}): one leg per degree of freedom, one constraint per missing one"
            )
        if self.passive_in_coordinates:
            self._check_passive_coordinates()
        self.reading = self._derive_reading()
        if self.unreachable not in ("invalid", "read"):
            raise ValueError(f"DistanceMechanism: unreachable={self.unreachable!r}, not 'invalid' or 'read'")
        if self.unreachable == "read" and self.reading is None:
            raise ValueError(
                "DistanceMechanism: unreachable='read' needs a reading of the pose onto the reachable set, and none "
                "is derived for these legs (three plane constraints whose planes contain one axis, on a 'transform' "
                "platform with its standard coordinates)"
            )
        signed = [k for k, leg in enumerate(self.legs) if leg.kind != "prismatic" and leg.elbow_axis is None]
        self.branch_names = [sp.Symbol(f"sigma{k + 1}", real=True) for k in signed] + list(self.motion.branches)

    @property
    def actuated(self) -> list[sp.Symbol]:
        return [leg.joint for leg in self.legs]

    @property
    def passive_in_coordinates(self) -> bool:
        """Whether the platform's coordinates are the passive legs' own joints (a Tricept's two
        universal joint angles and its length: fewer coordinates than the pose kind's twist has,
        less the extra rows), so that the passive legs close by construction and add no row."""
        free = len(self.motion.coordinates) - len(self.motion.extra_residual)
        return bool(self.passive) and free < len(self.motion.twist)

    def _passive_rows(self) -> list[sp.Expr]:
        return [row for leg in self.passive for row in leg.rows(self.motion.rotation, self.motion.position)]

    def _check_passive_coordinates(self) -> None:
        """The passive legs' rows vanish at random coordinates (1e-12), else ValueError."""
        rng = random.Random(20261128)
        rows = self._passive_rows()
        free = sorted(set().union(*(sp.sympify(r).free_symbols for r in rows)), key=str)
        for _ in range(3):
            values = {v: sp.Float(rng.uniform(-1, 1), 30) for v in free}
            worst = max(abs(float(sp.sympify(r).xreplace(values).evalf(30))) for r in rows)
            if worst > 1e-12:
                raise ValueError(
                    f"DistanceMechanism: the platform's {len(self.motion.coordinates)} coordinates are fewer than pose "
                    f"kind {self.motion.kind!r} has, but its passive legs do not close in them (a row is {worst:.3g} "
                    "at random values): write the rotation and position as the passive legs' joints make them"
                )

    @property
    def constrained(self) -> list[int]:
        """The legs whose revolute joint keeps the platform joint in a plane (lower mobility)."""
        return [k for k, leg in enumerate(self.legs) if leg.plane_normal is not None]

    @property
    def turning(self) -> list[int]:
        """The crank legs whose skew elbow axis keeps the link normal to it (``Leg.elbow_axis``):
        a constraint that turns with the crank, and a numeric inverse."""
        return [k for k, leg in enumerate(self.legs) if leg.elbow_axis is not None]

    def platform_joints(self, rotation: sp.Matrix | None = None, position: sp.Matrix | None = None) -> list[sp.Matrix]:
        """C_i = p + R c_i in {B} (default: the platform's coordinates)."""
        rotation = self.motion.rotation if rotation is None else rotation
        position = self.motion.position if position is None else position
        return [position + rotation * leg.platform_joint for leg in self.legs]

    def links(self) -> list[sp.Matrix]:
        """d_i = C_i - E_i, in {B}."""
        return [c - leg.elbow() for c, leg in zip(self.platform_joints(), self.legs, strict=True)]

    def closure(self, squared: bool = True) -> ClosureModel:
        """Per leg (|d|^2 - L^2) / (2 L), in metres and polynomial; or with ``squared`` False
        |d| - L (a mechanism whose polynomial family was proven in that form keeps it)."""
        rows = [
            (d.dot(d) - leg.length() ** 2) / (2 * leg.length()) if squared else sp.sqrt(d.dot(d)) - leg.length()
            for d, leg in zip(self.links(), self.legs, strict=True)
        ]
        joints = self.platform_joints()
        planes = [(joints[k] - self.legs[k].base).dot(self.legs[k].plane_normal) for k in self.constrained]
        planes += [(joints[k] - self.legs[k].elbow()).dot(self.legs[k].turned_axis()) for k in self.turning]
        held = [] if self.passive_in_coordinates else self._passive_rows()
        residual = sp.Matrix([*planes, *held, *rows, *self.motion.extra_residual])
        pose = homogeneous(self.motion.rotation, self.motion.position)
        # a passive leg's line closes with the platform on either side of its universal joint: only
        # the side its prismatic joint reaches, (C0 - A) . R w > 0, is a closure (a mode there)
        alignment = [
            passive_measures(leg, self.motion.rotation, self.motion.position)[f"{leg.name}_extension_reachable"]
            for leg in self.passive
        ]
        return ClosureModel(residual, sp.Matrix(alignment or [sp.Integer(1)]), pose)

    def _rows(self, points: list[sp.Matrix], origin: sp.Matrix) -> sp.Matrix:
        """Rows (d_i, (point_i - origin) x d_i) over the platform's twist components."""
        columns = [TWIST.index(name) for name in self.motion.twist]
        rows = []
        for point, d in zip(points, self.links(), strict=True):
            full = list(d) + list((point - origin).cross(d))
            rows.append([full[c] for c in columns])
        return sp.Matrix(rows)

    def rates(self) -> RateModel:
        elbows = [leg.elbow() for leg in self.legs]
        diagonal = []
        for leg, d, e in zip(self.legs, self.links(), elbows, strict=True):
            if leg.kind == "prismatic":
                diagonal.append(leg.joint)
            elif leg.kind == "crank":
                assert leg.axis is not None
                diagonal.append(leg.axis.dot((e - leg.base).cross(d)))
            else:
                assert leg.axis is not None
                diagonal.append(d.dot(leg.axis))
        serial = {
            (leg.serial_name or SERIAL_NAMES[leg.kind]).format(k=k + 1): diagonal[k] for k, leg in enumerate(self.legs)
        }
        a = self._rows(elbows, self.motion.position)
        return RateModel(self.motion.twist, a, sp.diag(*diagonal), serial, constraints=self._constraint_rows())

    def _constraint_rows(self, origin: sp.Matrix | None = None) -> sp.Matrix | None:
        """One row per plane: the force along its normal n through the platform joint C,
        (n, (C - origin) x n) over the platform's twist components (origin: p)."""
        if not self.constrained and not self.passive and not self.turning:
            return None
        origin = self.motion.position if origin is None else origin
        columns = [TWIST.index(name) for name in self.motion.twist]
        joints = self.platform_joints()
        rows = []
        for k in self.constrained:
            n = self.legs[k].plane_normal
            assert n is not None
            full = list(n) + list((joints[k] - origin).cross(n))
            rows.append([full[c] for c in columns])
        for k in self.turning:  # the force through C whose work leaves the crank's rate out
            force = turning_force(self.legs[k], joints[k])
            full = list(force) + list((joints[k] - origin).cross(force))
            rows.append([full[c] for c in columns])
        rotation = self.motion.rotation
        for leg in self.passive:  # forces through A along R b, R (w x b); the couple a1 x R b
            b = rotation * leg.second
            for force in (b, rotation * leg.direction.cross(leg.second)):
                full = list(force) + list((leg.base - origin).cross(force))
                rows.append([full[c] for c in columns])
            full = [0, 0, 0, *leg.axis.cross(b)]
            rows.append([full[c] for c in columns])
        return sp.Matrix(rows)

    def parallel_factors(self) -> dict[str, sp.Expr]:
        """det A ([A; constraints] for a lower-mobility platform). A platform that does not turn about all three axes writes its moments about E_1
        (a column operation: the same determinant in smaller expressions)."""
        elbows = [leg.elbow() for leg in self.legs]
        q = self.motion.dimensionless
        quaternion = len(q) == 4 and self.motion.rotation == quaternion_rotation(q)
        if self.motion.kind == "transform" and quaternion and not self.passive and not self.turning:
            # rows (d_i ; (E_i - p) x d_i) times n = q . q, less [p]x times the first three
            # columns: (R_u c_i + n (p - E_i) ; E_i x (R_u c_i + n p)), polynomial in q, and
            # det A = det P / n^6 by Laplace's expansion in 3 x 3 blocks (600 entry occurrences
            # instead of 1956)
            norm, turned = sum(c**2 for c in q), quaternion_rotation_unnormalised(q)
            rows = []
            for leg, e in zip(self.legs, elbows, strict=True):
                joint = turned * leg.platform_joint + norm * self.motion.position
                rows.append([*(joint - norm * e), *e.cross(joint)])
            for k in self.constrained:  # (n, (C - p) x n) the same way: (norm n, (R_u c + norm p) x n)
                n = self.legs[k].plane_normal
                assert n is not None
                joint = turned * self.legs[k].platform_joint + norm * self.motion.position
                rows.append([*(norm * n), *joint.cross(n)])
            return {self.parallel_name: block_laplace_det(sp.Matrix(rows)) / norm**6}
        spatial = len(POSE_KINDS[self.motion.kind].rotation_axes) == 3
        origin = self.motion.position if spatial else elbows[0]
        rows = self._rows(elbows, origin)
        constraints = self._constraint_rows(origin)
        rows = rows if constraints is None else sp.Matrix.vstack(rows, constraints)
        return {self.parallel_name: block_laplace_det(rows) if rows.cols == 6 else laplace_det(rows)}

    def _derive_reading(self) -> AxisReading | None:
        """The reading of a pose onto the reachable set (``readings``), where the platform is a
        'transform' one with its standard reading and the legs' three planes contain one axis;
        the platform's ``read`` and ``pose`` become the reading's."""
        standard = platform("transform")
        if self.motion.kind != "transform" or self.motion.read != standard.read or self.passive or self.turning:
            return None
        if len(self.constrained) != 3:
            return None
        legs = [self.legs[k] for k in self.constrained]
        normals = [leg.plane_normal for leg in legs]
        assert all(n is not None for n in normals)
        found = common_axis(normals, [leg.base for leg in legs], [leg.platform_joint for leg in legs])  # type: ignore[arg-type]
        if found is not None:
            steps, pose = found.steps(self.motion.coordinates)
            self.motion = replace(self.motion, read=tuple(steps), pose=pose)
            self.graph.controlled = found.describe()
        return found

    @property
    def checks_planes(self) -> bool:
        """Whether the inverse checks each plane constraint at the given pose (``plane_measure``):
        where it reads the pose's coordinates as given (the pose kind's own reading), a pose off
        the reachable set puts platform joints out of their planes; where it reads the pose onto
        the reachable set (``reading``), unless the file declares ``unreachable='read'``. A
        platform that writes its own reading answers for what it reads."""
        if self.reading is not None:
            return self.unreachable == "invalid"
        standard = platform(self.motion.kind)
        return self.motion.read == standard.read and all(
            mine == theirs for mine, theirs in zip(self.motion.pose, standard.pose, strict=True)
        )

    def inverse(self) -> InverseSolution:
        """Each leg in closed form and the platform's coordinates read from the pose (the
        coordinates first where the legs' platform joints are written in them: a planar pose)."""
        steps: list[tuple[sp.Symbol, sp.Expr]] = []
        validity: dict[str, sp.Expr] = {}
        rotation, position = self.motion.pose
        joints = self.platform_joints(rotation, position)
        signs = iter(self.branch_names)
        planes = self.checks_planes
        on_set: list[str] = []  # the conditions that test the given pose against the reachable set
        for k, (leg, c) in enumerate(zip(self.legs, joints, strict=True)):
            v = c - leg.base
            if leg.kind == "prismatic":
                steps.append((leg.joint, sp.sqrt(v.dot(v))))
                validity[f"leg{k + 1}_length"] = leg.joint
            elif leg.elbow_axis is not None:  # no subproblem matches: Newton on the leg's own closure
                solved, measure = numeric_leg_steps(leg, c, k + 1)
                steps += solved
                validity[f"leg{k + 1}_numeric_reachable"] = measure
            elif leg.kind == "crank":
                assert leg.axis is not None and leg.zero is not None and leg.crank is not None and leg.link is not None
                e, f, g = sp.symbols(f"E{k + 1} F{k + 1} G{k + 1}", real=True)
                r, side = leg.crank, leg.axis.cross(leg.zero)
                steps += [(e, -2 * r * v.dot(leg.zero)), (f, -2 * r * v.dot(side)), (g, v.dot(v) + r**2 - leg.link**2)]
                # sign +1 turns the crank counter-clockwise (about its axis) from the line A -> C
                angle, discriminant = crank_angle(e, f, g, leg.sign * next(signs))
                steps.append((leg.joint, angle))
                validity[f"leg{k + 1}_reachable"] = discriminant / (e**2 + f**2 + g**2)
            else:
                assert leg.axis is not None and leg.link is not None
                along, disc = sp.symbols(f"along{k + 1} disc{k + 1}", real=True)
                steps += [(along, v.dot(leg.axis)), (disc, leg.link**2 - v.dot(v) + along**2)]
                # sign +1 puts the slider below the platform joint along the axis
                steps.append((leg.joint, along - leg.sign * next(signs) * sp.sqrt(sp.Max(0, disc))))
                validity[f"leg{k + 1}_reachable"] = disc / leg.link**2
            if planes and leg.plane_normal is not None:  # the given pose's joint, off its plane or not
                given = POSE_POSITION + POSE_ROTATION * leg.platform_joint if self.reading is not None else c
                validity[f"leg{k + 1}_plane_reachable"] = plane_measure(leg, given - leg.base)
                on_set.append(f"leg{k + 1}_plane_reachable")
        for held in self.passive:
            validity.update(passive_measures(held, rotation, position))
        validity.update(self.motion.validity)
        read = list(self.motion.read)
        uses_coordinates = sp.Matrix.hstack(*self.motion.pose).has(*self.motion.coordinates)
        steps = read + steps if uses_coordinates else steps + read
        reading = None
        if self.reading is not None:  # the values are the reached pose's; on_set tests the given one
            reading = InverseReading(self.reading.axis, self.reading.describe(), self.unreachable, tuple(on_set))
        return InverseSolution(steps, self.branch_names, validity, reading)

    def drawing(self) -> Drawing:
        """Base joints, elbows (where a leg has one), platform joints; each leg as a polyline, the
        base and platform polygons (no platform polygon where the legs meet in one point)."""
        count = len(self.legs)
        points = {"base": sp.Matrix.hstack(*(leg.base for leg in self.legs))}
        with_elbow = all(leg.kind != "prismatic" for leg in self.legs)
        if with_elbow:
            points["elbow"] = sp.Matrix.hstack(*(leg.elbow() for leg in self.legs))
        points["platform"] = sp.Matrix.hstack(*self.platform_joints())
        chain = ["base", "elbow", "platform"] if with_elbow else ["base", "platform"]
        polylines = {f"leg{i + 1}": [(point, i) for point in chain] for i in range(count)}
        polylines["base"] = [("base", i % count) for i in range(count + 1)]
        if any(leg.platform_joint != self.legs[0].platform_joint for leg in self.legs):  # not a point
            polylines["platform"] = [("platform", i % count) for i in range(count + 1)]
        if self.passive:  # each passive leg from its universal joint to where it holds the platform
            rotation, position = self.motion.rotation, self.motion.position
            points["passive_base"] = sp.Matrix.hstack(*(leg.base for leg in self.passive))
            points["passive_joint"] = sp.Matrix.hstack(
                *(position + rotation * leg.platform_point for leg in self.passive)
            )
            for k, leg in enumerate(self.passive):
                polylines[leg.name] = [("passive_base", k), ("passive_joint", k)]
        parts = {name: name if name in ("base", "platform") else "leg" for name in polylines}
        return Drawing(points=points, polylines=polylines, parts=parts)

    def home_at(
        self, rotation: sp.Matrix, position: sp.Matrix | None, branch: int, parameters: dict[sp.Symbol, float]
    ) -> dict[sp.Symbol, float]:
        """A home configuration: the actuated and passive values of the pose (^B_P R, position)
        on inverse branch ``branch`` at the parameters (every step of the inverse evaluated),
        angles in (-pi, pi] as the runtime's inverse returns them; a branch outside 0 ..
        2 ** len(branch_names) - 1 is refused (BadInputError naming the count)."""
        check_branch(branch, len(self.branch_names), "home_at")
        values = self.inverse().at(rotation, position, branch, parameters)
        angular = {leg.joint for leg in self.legs if leg.kind == "crank"} | set(self.motion.angular)
        return {
            v: wrapped_angle(values[v]) if v in angular else values[v]
            for v in (*self.actuated, *self.motion.coordinates)
        }

    def fields(self) -> dict[str, object]:
        """The ``model.Mechanism`` fields the legs determine."""
        return {
            "actuated": self.actuated,
            "passive": list(self.motion.coordinates),
            "legs": [],
            "inverse": self.inverse(),
            "closure": self.closure(),
            "rates": self.rates(),
            "parallel_factors": self.parallel_factors(),
            "pose_kind": self.motion.kind,
            "angular": [leg.joint for leg in self.legs if leg.kind == "crank"] + list(self.motion.angular),
            "dimensionless": list(self.motion.dimensionless),
            "drawing": self.drawing(),
            "joint_graph": self.graph,
        }
