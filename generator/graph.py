"""The joint graph: a mechanism as bodies and joints, the one description the generator derives from.

A parallel mechanism is a fixed base {B}, a moving platform {P} and legs, each a serial chain of
joints from the base to the platform (``Chain``). Every joint (``Joint``) has a kind (``KINDS``):

* ``R`` revolute, ``P`` prismatic, ``C`` cylindrical (R and P about one axis), each about or
  along its ``axis``;
* ``U`` universal (two revolute axes meeting at its point, the first ``axis`` on the body before
  it, the second normal to it and to the link after it), ``S`` spherical (three);
* ``planar`` (two translations normal to its ``axis`` and the turn about it);
* ``Pa`` a parallelogram: two bars of equal length hinged at both ends about axes along ``axis``
  (the short sides), whose far side translates on a circle without turning: one translation,
  normal to the bars in the parallelogram's plane;
* ``F`` a rigid attachment (no motion): a passive leg fixed to the platform.

A joint lies at one of three *sites* of its leg: the base point A (``site`` "base": ``point`` in
{B}), the elbow E, where the leg's first joint carries its first body (``site`` "elbow": placed
by the chain), or the platform point C = p + R c (``site`` "platform": ``point`` c in {P}). Axes
are unit vectors, in {B} at the base and the elbow (the elbow's turned with the first body: a
crank's), in {P} at the platform. Points and axes are SymPy expressions of the parameters.

A leg's first joint moves the elbow: a revolute joint turns the first body, of ``reach``
(length r, unit zero direction e0 normal to the axis u), E = A + r (cos q e0 + sin q (u x e0));
a prismatic joint slides it, E = A + q k; a leg whose first joints are all at the base has no
elbow. From the elbow (or from A) to C runs a link of fixed length ``link``, or, where ``link``
is None, a prismatic joint along the line A -> C (a leg of variable length: S-P-S, U-P-S,
R-P-S, the passive U-P of a Tricept).

Each joint has a ``variable`` where it is one coordinate of the model (the actuated ones), an
``actuated`` mark and ``limits``; a leg is actuated when one of its joints is, passive
otherwise; where a leg meets the platform is a loop constraint (``Loop``). Bodies (``Body``) may
carry inertial symbols (``Inertial``: mass, centre, inertia) for dynamics and calibration.

Derived here, numerically at generic configurations (``screw_analysis``): each joint's unit
twists at its site (``joint_twists``), each leg's constraint wrenches (the wrenches reciprocal to
all its joints' twists) and, with its actuators locked, its actuation wrenches; the platform's
twists (reciprocal to every leg's constraint wrenches), its mobility, and its motion
(translational, spherical, planar, spatial, or lower mobility with parasitic motion), checked
against the declared pose kind and actuators (``check_motion``). The closure, rates, factors,
inverse and drawing of a mechanism of distance legs are derived from the graph's legs by
``generator.joints`` (``distance_form``).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
import sympy as sp

from .errors import GenerationError

#: every joint kind and its degrees of freedom
KINDS = {"R": 1, "P": 1, "C": 2, "U": 2, "S": 3, "planar": 3, "Pa": 1, "F": 0}
#: the kinds that need an axis
AXIAL = ("R", "P", "C", "U", "planar", "Pa")
SITES = ("base", "elbow", "platform", "chain")
#: twist components, (v of the platform origin p, w), in {B}
TWIST = ("vx", "vy", "vz", "wx", "wy", "wz")


@dataclass(frozen=True)
class Inertial:
    """A body's inertial parameters, as symbols (for dynamics and calibration): the mass (kg), the
    centre of mass in the body's frame (m) and the inertia about it (kg m^2, symmetric)."""

    mass: sp.Symbol
    centre: sp.Matrix
    inertia: sp.Matrix

    @classmethod
    def symbols(cls, body: str) -> Inertial:
        """The inertial symbols of the body named ``body``: m_<body>, c<axis>_<body>, I<ij>_<body>.

        Parameters
        ----------
        body : str
            The body's name.

        Returns
        -------
        Inertial
            Mass, centre (3 x 1) and the symmetric inertia (3 x 3, six symbols).

        Example
        -------
        >>> Inertial.symbols("platform").mass
        m_platform
        """
        mass = sp.Symbol(f"m_{body}", positive=True)
        centre = sp.Matrix(sp.symbols(f"cx_{body} cy_{body} cz_{body}", real=True))
        entries = {(i, j): sp.Symbol(f"I{'xyz'[i]}{'xyz'[j]}_{body}", real=True) for i in range(3) for j in range(i, 3)}
        inertia = sp.Matrix(3, 3, lambda i, j: entries[(min(i, j), max(i, j))])
        return cls(mass, centre, inertia)


@dataclass(frozen=True)
class Body:
    """A rigid body: the base, the platform or a link of a leg. A link's frame is that of the
    joint carrying it (origin at the joint's point, z along its axis where it has one), the
    platform's {P}, the base's {B}."""

    name: str
    inertial: Inertial | None = None


@dataclass(frozen=True)
class Joint:
    """One joint (module docstring): its kind, site, point and axis, its variable, whether it is
    actuated, and its limits (radians or metres)."""

    kind: str
    site: str
    point: sp.Matrix | None = None
    axis: sp.Matrix | None = None
    variable: sp.Symbol | None = None
    actuated: bool = False
    limits: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"a joint's kind is one of {list(KINDS)}, got {self.kind!r}")
        if self.site not in SITES:
            raise ValueError(f"a joint's site is one of {list(SITES)}, got {self.site!r}")
        if self.site != "elbow" and self.point is None:
            raise ValueError(f"a {self.kind} joint at the {self.site} needs its point")
        if self.actuated and KINDS[self.kind] != 1:
            raise ValueError(f"an actuated joint has one degree of freedom (R, P or Pa), got {self.kind}")

    @property
    def dof(self) -> int:
        return KINDS[self.kind]


@dataclass(frozen=True)
class Chain:
    """A leg: its joints from the base to the platform and the bodies between them
    (``len(joints) - 1`` links), what its first body reaches (``reach``: the crank's length and
    zero direction; None: no elbow or a slider's) and the fixed distance from elbow to platform
    joint (``link``; None: a line of variable length from A). ``sign`` and ``serial_name`` are the
    inverse's branch convention and the serial factor's name (``generator.joints``)."""

    name: str
    joints: tuple[Joint, ...]
    bodies: tuple[Body, ...] = ()
    reach: tuple[sp.Expr, sp.Matrix] | None = None
    link: sp.Expr | None = None
    sign: int = 1
    serial_name: str | None = None

    def __post_init__(self) -> None:
        if self.serial:
            return
        if not self.joints or self.joints[0].site != "base" or self.joints[-1].site != "platform":
            sites = [j.site for j in self.joints]
            raise ValueError(f"leg {self.name}: joints run from the base to the platform, got sites {sites}")
        if self.bodies and len(self.bodies) != len(self.joints) - 1:
            raise ValueError(f"leg {self.name}: {len(self.joints)} joints hold {len(self.joints) - 1} bodies")

    @property
    def serial(self) -> bool:
        """Whether the leg is a serial chain of R and P joints placed by their products of
        exponentials (site "chain": each joint's point and axis in {B} with every joint at 0)."""
        return bool(self.joints) and all(j.site == "chain" for j in self.joints)

    @property
    def kinds(self) -> str:
        """The joints' kinds, base to platform, the actuated one underlined by a trailing '_'."""
        return "-".join(j.kind + ("_" if j.actuated else "") for j in self.joints)

    @property
    def actuated(self) -> bool:
        return any(j.actuated for j in self.joints)

    def at(self, site: str) -> list[Joint]:
        return [j for j in self.joints if j.site == site]


@dataclass(frozen=True)
class Loop:
    """Where a leg meets the platform: its platform joint (a loop constraint of the graph)."""

    leg: str
    joint: Joint


@dataclass
class JointGraph:
    """A mechanism's bodies and joints: the platform's pose kind and coordinates (``rotation`` and
    ``position`` of ^B_P T in them) and its legs."""

    pose_kind: str
    coordinates: tuple[sp.Symbol, ...]
    rotation: sp.Matrix
    position: sp.Matrix
    legs: list[Chain]
    base: Body = field(default_factory=lambda: Body("base"))
    platform: Body = field(default_factory=lambda: Body("platform"))
    #: a lower-mobility platform's controlled and parasitic coordinates, in words, where the inverse
    #: reads a pose onto its reachable set (``generator.readings``); None otherwise
    controlled: str | None = None

    @property
    def bodies(self) -> list[Body]:
        return [self.base, self.platform, *(body for leg in self.legs for body in leg.bodies)]

    def named(self) -> JointGraph:
        """The graph with every leg's links named <leg>_link<k> where the leg gave none."""
        legs = []
        for leg in self.legs:
            bodies = leg.bodies or tuple(Body(f"{leg.name}_link{k + 1}") for k in range(len(leg.joints) - 1))
            legs.append(replace(leg, bodies=bodies))
        return replace(self, legs=legs)

    @property
    def loops(self) -> list[Loop]:
        return [Loop(leg.name, leg.joints[-1]) for leg in self.legs]

    @property
    def actuated(self) -> list[sp.Symbol]:
        return [j.variable for leg in self.legs for j in leg.joints if j.actuated and j.variable is not None]

    def describe(self) -> str:
        """The legs' joints, e.g. '3 x R-P_-S (actuated)'."""
        counts: dict[tuple[str, bool], int] = {}
        for leg in self.legs:
            key = (leg.kinds, leg.actuated)
            counts[key] = counts.get(key, 0) + 1
        return ", ".join(f"{n} x {k} ({'actuated' if a else 'passive'})" for (k, a), n in counts.items())


def _unit(vector: np.ndarray) -> np.ndarray:
    norm = float(np.linalg.norm(vector))
    if norm == 0:
        raise ValueError("a joint axis of zero length at this configuration")
    return vector / norm


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues' rotation about a unit axis."""
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)


@dataclass
class Placement:
    """One leg at one configuration, numerically in {B}: A, E (None: no elbow), C, the platform's
    rotation R and origin p, and the turn of the first body (to carry the elbow's axes)."""

    base: np.ndarray
    elbow: np.ndarray | None
    joint: np.ndarray
    rotation: np.ndarray
    origin: np.ndarray
    carried: np.ndarray


def place(leg: Chain, rotation: np.ndarray, origin: np.ndarray, values: Callable[[sp.Expr], np.ndarray]) -> Placement:
    """A leg's sites at a configuration: ``rotation`` and ``origin`` of the platform, ``values``
    evaluating a point or axis expression (parameters and joint variables) numerically."""
    first = leg.joints[0]
    if leg.serial:  # placed joint by joint (``serial_twists``)
        return Placement(np.zeros(3), None, origin, rotation, origin, np.eye(3))
    base = values(first.point).reshape(3)
    joint = origin + rotation @ values(leg.joints[-1].point).reshape(3)
    carried = np.eye(3)
    elbow: np.ndarray | None = None
    if leg.link is not None:
        assert first.variable is not None and first.axis is not None
        q = float(values(first.variable))
        axis = _unit(values(first.axis).reshape(3))
        if first.kind == "R":
            assert leg.reach is not None
            length, zero = leg.reach
            carried = _rotation(axis, q)
            elbow = base + float(values(length)) * (carried @ values(zero).reshape(3))
        else:
            elbow = base + q * axis
    return Placement(base, elbow, joint, rotation, origin, carried)


def serial_twists(
    leg: Chain, origin: np.ndarray, values: Callable[[sp.Expr], np.ndarray]
) -> list[tuple[Joint, np.ndarray]]:
    """The twists of a serial chain's joints (``Chain.serial``) at its joints' values, by the
    product of exponentials: joint k's axis and point are those at zero carried by the motions
    of the joints before it (v of the platform origin ``origin``, w; in {B})."""
    turn, shift = np.eye(3), np.zeros(3)
    result = []
    for joint in leg.joints:
        assert joint.axis is not None and joint.point is not None and joint.variable is not None
        axis = turn @ _unit(values(joint.axis).reshape(3))
        point = turn @ values(joint.point).reshape(3) + shift
        q = float(values(joint.variable))
        if joint.kind == "R":
            result.append((joint, np.concatenate([np.cross(point - origin, axis), axis])))
            step = _rotation(axis, q)
            turn, shift = step @ turn, step @ (shift - point) + point
        elif joint.kind == "P":
            result.append((joint, np.concatenate([axis, np.zeros(3)])))
            shift = shift + q * axis
        else:
            raise ValueError(f"leg {leg.name}: a serial chain holds R and P joints, got {joint.kind}")
    return result


def joint_twists(leg: Chain, at: Placement, values: Callable[[sp.Expr], np.ndarray]) -> list[tuple[Joint, np.ndarray]]:
    """Each joint's unit twists (v of the platform origin p, w; in {B}) at a placement: one per
    degree of freedom, (joint, 6-vector) pairs, base to platform."""
    if leg.serial:
        return serial_twists(leg, at.origin, values)
    start = at.elbow if at.elbow is not None else at.base
    span = at.joint - start
    if float(np.linalg.norm(span)) == 0 and any(
        j.kind in ("U", "Pa") or (j.kind == "P" and j.axis is None) for j in leg.joints
    ):
        raise ValueError(f"leg {leg.name}: the link has zero length at this configuration")
    line = span / (float(np.linalg.norm(span)) or 1.0)
    result: list[tuple[Joint, np.ndarray]] = []

    def rotation(joint: Joint, point: np.ndarray, axis: np.ndarray) -> None:
        result.append((joint, np.concatenate([np.cross(point - at.origin, axis), axis])))

    def translation(joint: Joint, direction: np.ndarray) -> None:
        result.append((joint, np.concatenate([direction, np.zeros(3)])))

    for joint in leg.joints:
        point = {"base": at.base, "elbow": start, "platform": at.joint}[joint.site]
        if joint.axis is None:
            axis = None
        elif joint.site == "platform":
            axis = _unit(at.rotation @ values(joint.axis).reshape(3))
        elif joint.site == "elbow":
            axis = _unit(at.carried @ values(joint.axis).reshape(3))
        else:
            axis = _unit(values(joint.axis).reshape(3))
        if joint.kind == "S":
            for e in np.eye(3):
                rotation(joint, point, e)
        elif joint.kind == "R":
            assert axis is not None
            rotation(joint, point, axis)
        elif joint.kind == "P":
            translation(joint, line if axis is None else axis)  # no axis: along the leg's line
        elif joint.kind == "C":
            assert axis is not None
            rotation(joint, point, axis)
            translation(joint, axis)
        elif joint.kind == "U":
            assert axis is not None
            rotation(joint, point, axis)
            rotation(joint, point, _unit(np.cross(axis, line)))
        elif joint.kind == "planar":
            assert axis is not None
            rotation(joint, point, axis)
            other = np.eye(3)[int(np.argmin(np.abs(axis)))]
            first = _unit(np.cross(axis, other))
            translation(joint, first)
            translation(joint, np.cross(axis, first))
        elif joint.kind == "Pa":
            assert axis is not None
            normal = _unit(np.cross(axis, line))  # the hinges' normal: the parallelogram's plane holds axis and line
            translation(joint, _unit(np.cross(normal, line)))
    return result


def reciprocal(twists: np.ndarray, tolerance: float = 1e-9) -> np.ndarray:
    """A basis (rows) of the wrenches (f, m about p) reciprocal to every column of ``twists``
    (f . v + m . w = 0): the null space of twists^T, by SVD with a relative rank tolerance."""
    if twists.size == 0:
        return np.eye(6)
    _, s, vt = np.linalg.svd(twists.T)
    rank = int(np.sum(s > tolerance * max(1.0, float(s[0]))))
    return vt[rank:]


def rank(matrix: np.ndarray, tolerance: float = 1e-9) -> int:
    if matrix.size == 0:
        return 0
    s = np.linalg.svd(matrix, compute_uv=False)
    return int(np.sum(s > tolerance * max(1.0, float(s[0]))))


@dataclass
class Screws:
    """The screw analysis of one configuration: each leg's constraint wrenches (rows), with its
    actuators locked its constraint and actuation wrenches, and the platform's twists (columns)."""

    constraints: dict[str, np.ndarray]
    locked: dict[str, np.ndarray]
    twists: np.ndarray
    #: the platform's twists with its actuators locked (columns; none: rigid)
    locked_twists: np.ndarray


def screw_analysis(graph: JointGraph, placements: dict[str, Placement], values: Callable) -> Screws:
    """Constraint and actuation wrenches of every leg and the platform's twist space at one
    configuration (``place`` each leg first).

    Parameters
    ----------
    graph : JointGraph
        The mechanism.
    placements : dict
        Leg name -> its ``Placement`` at the configuration.
    values : callable
        Evaluates a point or axis expression at the configuration's parameters and joints.

    Returns
    -------
    Screws
        The wrenches (rows of (f, m about p), in {B}) and the platform's twists (columns).
    """
    constraints, locked = {}, {}
    for leg in graph.legs:
        pairs = joint_twists(leg, placements[leg.name], values)
        every = np.array([t for _, t in pairs]).T
        free = np.array([t for j, t in pairs if not j.actuated]).T.reshape(6, -1)
        constraints[leg.name] = reciprocal(every)
        locked[leg.name] = reciprocal(free)
    stacked = np.vstack([w for w in constraints.values()] or [np.zeros((0, 6))])
    _, s, vt = np.linalg.svd(stacked) if stacked.size else (None, np.zeros(0), np.eye(6))
    tolerance = 1e-9 * max(1.0, float(s[0]) if s.size else 1.0)
    twists = vt[int(np.sum(s > tolerance)) :].T
    all_locked = np.vstack(list(locked.values()))
    _, s_locked, vt_locked = np.linalg.svd(all_locked)
    kept = int(np.sum(s_locked > 1e-9 * max(1.0, float(s_locked[0]))))
    return Screws(constraints, locked, twists, vt_locked[kept:].T)


#: the twist components each pose kind allows (v of p, w; in {B})
ALLOWED = {
    "transform": (0, 1, 2, 3, 4, 5),
    "rotation": (3, 4, 5),
    "planar": (0, 1, 5),
    "translation": (0, 1, 2),
    "planar_translation": (0, 1),
}
MOTIONS = {
    "transform": "spatial (3 translations, 3 rotations)",
    "rotation": "spherical (3 rotations about the origin of {B})",
    "planar": "planar (2 translations in the plane z = 0, the rotation about z)",
    "translation": "translational (3 translations)",
    "planar_translation": "planar translational (2 translations in the plane z = 0)",
}


@dataclass
class Motion:
    """What the screw analysis found over the sampled configurations (``motion``)."""

    #: the platform's degrees of freedom with its actuators free (its mobility), at every sample
    mobility: int
    #: the pose kind whose twist components hold every sampled twist space (smallest), or None
    kind: str | None
    #: translations and rotations of the twist space at the first configuration (nTmR)
    translations: int
    rotations: int
    #: the twist spaces differ between configurations beyond the kind (parasitic motion)
    parasitic: bool
    #: the degrees of freedom left with the actuators locked, at each configuration
    locked: list[int]
    samples: int

    def text(self) -> str:
        """e.g. '3 degrees of freedom, 1T2R with parasitic motion'."""
        if self.kind is not None and self.kind != "transform":
            return f"{self.mobility} degrees of freedom, {MOTIONS[self.kind]}"
        shape = f"{self.translations}T{self.rotations}R"
        if self.mobility == 6:
            return f"6 degrees of freedom, {MOTIONS['transform']}"
        return f"{self.mobility} degrees of freedom, {shape}" + (" with parasitic motion" if self.parasitic else "")


def motion(samples: list[Screws], point_platform: bool = False) -> Motion:
    """The platform's mobility and motion over sampled configurations (the first a typical one:
    the home), from their ``Screws``. A platform that is one point (every leg meets it at the
    same point) has no orientation: its idle rotations about that point are left out.

    Parameters
    ----------
    samples : list of Screws
        ``screw_analysis`` at each configuration.
    point_platform : bool
        Whether the platform is a point.

    Returns
    -------
    Motion
        Mobility, the smallest pose kind holding every twist, nTmR at the first configuration,
        parasitic motion, and the mobility with the actuators locked.

    Raises
    ------
    ValueError
        If no configuration was sampled.
    """
    if not samples:
        raise ValueError("motion: no configuration sampled")
    kept = 3 if point_platform else 6  # a point's twist: its velocity only
    mobilities = [rank(s.twists[:kept]) for s in samples]
    locked = [rank(s.locked_twists[:kept]) for s in samples]
    kind = None
    for name in ("planar_translation", "translation", "rotation", "planar", "transform"):
        outside = [k for k in range(kept) if k not in ALLOWED[name]]
        if all(float(np.abs(s.twists[outside]).max(initial=0)) < 1e-8 for s in samples):
            kind = name
            break
    first = samples[0].twists[:kept]
    rotations = rank(first[3:]) if kept == 6 else 0
    union = rank(np.hstack([s.twists[:kept] for s in samples]))
    mobility = max(mobilities)
    parasitic = union > mobility and kind == "transform"
    return Motion(mobility, kind, mobility - rotations, rotations, parasitic, locked, len(samples))


def check_motion(name: str, graph: JointGraph, found: Motion, actuators: int) -> None:
    """Compare the screw analysis with the mechanism's declaration: its actuators (one per degree
    of freedom) and its pose kind (the platform moves in the kind's twist components, and in no
    smaller kind's).

    Parameters
    ----------
    name : str
        The mechanism's name, for the message.
    graph : JointGraph
        Its joints (described in the message).
    found : Motion
        What ``motion`` found.
    actuators : int
        The number of actuated joints.

    Raises
    ------
    GenerationError
        Naming what differs: the mobility, or the motion against the declared pose kind.
    """
    legs = graph.describe()
    if found.mobility != actuators:
        raise GenerationError(
            f"{name}: its legs ({legs}) leave the platform {found.text()} by screw analysis at "
            f"{found.samples} configurations, but it has {actuators} actuated joints (one per degree of freedom); "
            "add or remove legs or actuators, or joints that constrain the platform (a revolute joint, a "
            "parallelogram, a passive leg)"
        )
    if found.kind is None or (found.kind != graph.pose_kind and ALLOWED[graph.pose_kind] != ALLOWED["transform"]):
        raise GenerationError(
            f"{name}: declared pose kind {graph.pose_kind!r} ({MOTIONS[graph.pose_kind]}), but its legs ({legs}) "
            f"leave the platform {found.text()} by screw analysis at {found.samples} configurations"
        )
    if graph.pose_kind == "transform" and found.kind != "transform":
        raise GenerationError(
            f"{name}: declared pose kind 'transform', but its legs ({legs}) leave the platform {found.text()} "
            f"by screw analysis at {found.samples} configurations: declare pose kind {found.kind!r}"
        )
    if all(m != 0 for m in found.locked):
        raise GenerationError(
            f"{name}: with its actuators locked the platform still moves ({found.locked[0]} degrees of freedom) "
            f"at every sampled configuration; its legs: {legs}"
        )


def vectors(values: Sequence[sp.Expr] | sp.Matrix) -> sp.Matrix:
    """A point or direction as a 3 x 1 matrix (1 to 3 coordinates, the rest 0)."""
    v = sp.Matrix(values)
    if v.cols != 1 or not 1 <= v.rows <= 3:
        raise ValueError(f"a point or direction has 1 to 3 coordinates, got a {v.rows} x {v.cols} matrix")
    return sp.Matrix([v[k] if k < v.rows else 0 for k in range(3)])


def analyse(
    graph: JointGraph,
    residual: sp.Matrix,
    actuated: Sequence[sp.Symbol],
    passive: Sequence[sp.Symbol],
    parameters: dict[sp.Symbol, float],
    home: dict[sp.Symbol, float],
    angular: Sequence[sp.Symbol] = (),
    count: int = 6,
    seed: int = 20261128,
) -> Motion:
    """The screw analysis of a mechanism at its home and at ``count`` - 1 generic configurations
    near it (the actuated values moved at random, by up to 0.05 rad or 1 % of each length, the
    passive ones found by Newton's method on the closure).

    Parameters
    ----------
    graph : JointGraph
        The mechanism's joints.
    residual : Matrix
        Its loop closure, square in ``passive``.
    actuated, passive : sequence of Symbol
        The actuated variables and the platform's coordinates.
    parameters : dict
        Parameter values (SI).
    home : dict
        A closed configuration: every actuated and passive variable.
    angular : sequence of Symbol
        The angles among the actuated variables.
    count : int
        How many configurations (the home first).
    seed : int
        The random generator's seed.

    Returns
    -------
    Motion
        What ``motion`` finds over the configurations that closed.

    Raises
    ------
    GenerationError
        If the home is missing a variable or does not close.
    """
    missing = [str(v) for v in (*actuated, *passive) if v not in home]
    if missing:
        raise GenerationError(f"screw analysis: the home has no value for {missing}")
    residual = residual.xreplace({k: sp.Float(v) for k, v in parameters.items()})
    unknowns = list(passive)
    state = [*actuated, *unknowns]
    closure_fn = sp.lambdify(state, residual, modules="numpy", cse=True)
    jacobian_fn = sp.lambdify(state, residual.jacobian(unknowns), modules="numpy", cse=True)
    lengths = [abs(home[v]) for v in actuated if v not in angular]
    size = max(lengths) if lengths else 1.0  # metres: the Newton threshold and the inputs' steps
    rng = np.random.default_rng(seed)
    samples = []
    ends = [leg.joints[-1].point for leg in graph.legs if not leg.serial]
    point_platform = len(ends) == len(graph.legs) and all(end == ends[0] for end in ends)
    for k in range(count):
        inputs = np.array([home[v] for v in actuated], dtype=float)
        if k:
            steps = [0.05 if v in angular else 0.01 * (abs(home[v]) or size) for v in actuated]
            inputs = inputs + np.array(steps) * rng.uniform(-1, 1, len(steps))
        guess = np.array([home[v] for v in unknowns], dtype=float)
        for _ in range(50):
            value = np.asarray(closure_fn(*inputs, *guess), dtype=float).reshape(-1)
            if float(np.abs(value).max()) < 1e-12 * size:
                break
            jacobian = np.asarray(jacobian_fn(*inputs, *guess), dtype=float)
            guess = guess - np.linalg.lstsq(jacobian, value, rcond=None)[0]
        else:
            if not k:
                raise GenerationError(f"screw analysis: the home does not close (residual {value})")
            continue
        config = dict(zip(state, [*inputs, *guess], strict=True))
        samples.append(_screws_at(graph, parameters, config))
    return motion(samples, point_platform)


def _screws_at(graph: JointGraph, parameters: dict[sp.Symbol, float], config: dict[sp.Symbol, float]) -> Screws:
    values_of = {**{k: sp.Float(v) for k, v in parameters.items()}, **{k: sp.Float(v) for k, v in config.items()}}

    def values(expression: sp.Expr) -> np.ndarray:
        return np.array(sp.sympify(expression).xreplace(values_of).evalf(), dtype=float)

    rotation = values(graph.rotation).reshape(3, 3)
    origin = values(graph.position).reshape(3)
    placements = {leg.name: place(leg, rotation, origin, values) for leg in graph.legs}
    return screw_analysis(graph, placements, values)


def _text(value: sp.Matrix | sp.Expr | None) -> list[str] | str | None:
    if value is None:
        return None
    if isinstance(value, sp.MatrixBase):
        return [str(entry) for entry in value]
    return str(value)


def to_json(graph: JointGraph, found: Motion | None = None) -> dict[str, object]:
    """The graph as plain data (for a manifest): bodies with their inertial symbols, legs with
    their joints (kind, site, point and axis as expression strings, variable, actuated mark,
    limits), the loops, and what the screw analysis found (its text followed by the controlled
    coordinates where the inverse reads a pose onto a lower-mobility platform's reachable set).

    Parameters
    ----------
    graph : JointGraph
        The mechanism's joints.
    found : Motion, optional
        Its screw analysis (``analyse``).

    Returns
    -------
    dict
        JSON-ready: strings, numbers, lists, dictionaries and None.

    Example
    -------
    >>> import sympy as sp
    >>> from parakin.generator import joints
    >>> legs = [joints.prismatic_leg([k, 0, 0], [0, 0, 0], sp.Symbol(f"l{k}")) for k in range(3)]
    >>> model = joints.DistanceMechanism(joints.platform("translation"), legs)
    >>> to_json(model.graph)["legs"][0]["joints"][1]["kind"]
    'P'
    """
    named = graph.named()

    def inertial(body: Body) -> dict[str, object] | None:
        if body.inertial is None:
            return None
        return {
            "mass": str(body.inertial.mass),
            "centre": _text(body.inertial.centre),
            "inertia": _text(body.inertial.inertia),
        }

    legs = []
    for leg in named.legs:
        joints = [
            {
                "kind": j.kind,
                "site": j.site,
                "point": _text(j.point),
                "axis": _text(j.axis),
                "variable": None if j.variable is None else str(j.variable),
                "actuated": j.actuated,
                "limits": None if j.limits is None else [float(j.limits[0]), float(j.limits[1])],
            }
            for j in leg.joints
        ]
        reach = None if leg.reach is None else {"length": str(leg.reach[0]), "direction": _text(leg.reach[1])}
        legs.append(
            {
                "name": leg.name,
                "actuated": leg.actuated,
                "joints": joints,
                "bodies": [b.name for b in leg.bodies],
                "reach": reach,
                "link": _text(leg.link),
            }
        )
    motion = None
    if found is not None:
        motion = {
            "mobility": found.mobility,
            "kind": found.kind,
            "translations": found.translations,
            "rotations": found.rotations,
            "parasitic": found.parasitic,
            "samples": found.samples,
            "text": found.text() + ("" if graph.controlled is None else f"; {graph.controlled}"),
        }
    return {
        "pose_kind": graph.pose_kind,
        "bodies": [{"name": b.name, "inertial": inertial(b)} for b in named.bodies],
        "legs": legs,
        "loops": [{"leg": loop.leg, "joint": len(named.legs[k].joints) - 1} for k, loop in enumerate(named.loops)],
        "motion": motion,
    }
