"""The declarative mechanism model that every module in ``mechanisms/`` fills in.

A mechanism is a set of serial legs (modified-DH chains from the fixed base frame {B} to the
moving platform frame {P}) that must all reach the same platform pose, plus optional closed-form
solutions supplied as SymPy expressions:

* ``InverseSolution``: a straight-line program (ordered assignments) from the platform pose to
  every actuated and passive variable, with ``branch`` symbols that take the values +1 and -1.
* ``ForwardElimination``: a univariate polynomial in one unknown whose coefficients depend on the
  actuated variables only, and the platform pose written in terms of a root (and branch signs).

The pose of {P} in {B} enters inverse programs through the symbols of ``POSE_SYMBOLS``
(rotation entries r11..r33 and position px, py, pz of ^B_P T).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import sympy as sp

from parakin.errors import BadInputError

from .frames import ModifiedDHLink, inverse_transform
from .graph import JointGraph
from .trigpoly import factor_list

POSE_ROTATION = sp.Matrix(3, 3, sp.symbols("r11 r12 r13 r21 r22 r23 r31 r32 r33", real=True))
POSE_POSITION = sp.Matrix(sp.symbols("px py pz", real=True))
POSE_SYMBOLS: list[sp.Symbol] = list(POSE_ROTATION) + list(POSE_POSITION)


@dataclass(frozen=True)
class PoseKind:
    """The poses ^B_P T a platform can take: which axes of {B} it translates along and turns
    about (0, 1, 2 = x, y, z). Its twist components are v<axis> then w<axis> of those axes, in
    {B} (the order of ``RateModel.twist``)."""

    description: str
    translation_axes: tuple[int, ...]
    rotation_axes: tuple[int, ...]

    @property
    def twist(self) -> tuple[str, ...]:
        return tuple(f"v{'xyz'[k]}" for k in self.translation_axes) + tuple(f"w{'xyz'[k]}" for k in self.rotation_axes)


#: every ``Mechanism.pose_kind`` (the runtime's ``parakin.pose.POSE_KINDS`` reads the same names)
POSE_KINDS = {
    "transform": PoseKind("a general rigid pose [R, p]", (0, 1, 2), (0, 1, 2)),
    "rotation": PoseKind("an orienting platform [R, 0]", (), (0, 1, 2)),
    "planar": PoseKind("planar motion [Rot_z(phi), (x, y, 0)]", (0, 1), (2,)),
    "translation": PoseKind("a translating platform [I, (x, y, z)]", (0, 1, 2), ()),
    "planar_translation": PoseKind("translation in the plane z = 0: [I, (x, y, 0)]", (0, 1), ()),
}


def pose_matrix() -> sp.Matrix:
    """^B_P T written with the pose symbols."""
    transform = sp.eye(4)
    transform[:3, :3] = POSE_ROTATION
    transform[:3, 3] = POSE_POSITION
    return transform


@dataclass
class SerialChain:
    """A leg: ^B_P T = base * prod(link transforms) * tool (modified DH, Craig)."""

    name: str
    base: sp.Matrix
    links: list[ModifiedDHLink]
    tool: sp.Matrix
    #: the leg's joint variables in the order of its Jacobian columns (eq 9 of Williams & Poling)
    joints: list[sp.Symbol]

    @cached_property
    def _frames(self) -> list[sp.Matrix]:
        current = self.base
        result = [current]
        for link in self.links:
            current = current * link.transform()
            result.append(current)
        return result

    def frames(self) -> list[sp.Matrix]:
        """^B_i T for i = 0..n (frame 0 is the leg's base frame), each simplified."""
        return list(self._frames)

    def end_transform(self) -> sp.Matrix:
        """^B_P T as reached by this leg."""
        return self._end

    @cached_property
    def _end(self) -> sp.Matrix:
        return self._frames[-1] * self.tool

    def geometric_jacobian(self) -> sp.Matrix:
        """6 x n Jacobian [v; w] of {P}: linear velocity of the origin of {P} and angular velocity,
        both expressed in {B}; columns ordered as ``joints``."""
        return self._jacobian(self.frames(), self.end_transform()[:3, 3])

    def determinant_jacobian(self) -> sp.Matrix:
        """The same Jacobian taken at the origin of the last DH frame and expressed in the leg's
        frame {0}. A change of reference point or of frame multiplies the Jacobian by a matrix
        of determinant 1, so its determinant equals that of ``geometric_jacobian``, in far
        smaller expressions (no base or tool offsets)."""
        frames = [sp.eye(4)]
        for link in self.links:
            frames.append(frames[-1] * link.transform())
        return self._jacobian(frames, frames[-1][:3, 3])

    def platform_frames(self) -> list[sp.Matrix]:
        """^P_i T for i = 0..n: each frame seen from the platform, written with the joints after
        it only (^P_i T = (prod of the later link transforms * tool)^-1)."""
        current = inverse_transform(self.tool)
        result = [current]
        for link in reversed(self.links):
            current = current * inverse_transform(link.transform())
            result.append(current)
        return result[::-1]

    def platform_jacobian(self, reference: sp.Matrix) -> sp.Matrix:
        """The Jacobian [v; w] in {P} coordinates, v of the point ``reference`` (in {P}); columns
        ordered as ``joints``. Its determinant equals that of ``geometric_jacobian`` (a change of
        frame and of reference point), written with each joint's later joints only."""
        return self._jacobian(self.platform_frames(), reference)

    @cached_property
    def factored_determinant(self) -> tuple[sp.Expr, list[tuple[sp.Expr, int]]]:
        """det of the leg Jacobian as (constant, [(factor, multiplicity), ...]) (``trigpoly``)."""
        return factor_list(self.determinant_jacobian().det(method="berkowitz"))

    def _jacobian(self, frames: list[sp.Matrix], platform_origin: sp.Matrix) -> sp.Matrix:
        columns: dict[sp.Symbol, sp.Matrix] = {}
        for index, link in enumerate(self.links, start=1):
            if link.joint is None:
                continue
            frame = frames[index]
            if link.kind() == "R":
                axis = frame[:3, 2] * sp.diff(link.theta, link.joint)
                linear = axis.cross(platform_origin - frame[:3, 3])
                columns[link.joint] = sp.Matrix.vstack(linear, axis)
            else:
                carrier = frames[index - 1][:3, 0] if link.prismatic_axis() == "x_prev" else frame[:3, 2]
                scale = sp.diff(link.a + link.d, link.joint)
                columns[link.joint] = sp.Matrix.vstack(carrier * scale, sp.zeros(3, 1))
        return sp.Matrix.hstack(*(columns[joint] for joint in self.joints))


def check_branch(branch: int, signs: int, what: str) -> None:
    """Refuse an inverse branch outside 0 .. 2 ** signs - 1 (``InverseSolution.at`` reads only the
    low bits: branch 8 of three signs would silently be branch 0, -1 branch 7).

    Parameters
    ----------
    branch : int
        The branch asked for.
    signs : int
        The inverse's number of sign choices (``len(InverseSolution.branches)``).
    what : str
        The caller, for the message.

    Raises
    ------
    BadInputError
        ``branch`` is not an integer in 0 .. 2 ** signs - 1; the message names the count.

    Example
    -------
    >>> check_branch(1, 0, "home_from_pose")
    Traceback (most recent call last):
    ...
    parakin.errors.BadInputError: home_from_pose: branch 1 is not one of this inverse's 1 branch (0 .. 0)
    """
    count = 2**signs
    if isinstance(branch, bool) or not isinstance(branch, int) or not 0 <= branch < count:
        raise BadInputError(
            f"{what}: branch {branch!r} is not one of this inverse's {count} branch{'es' if count > 1 else ''} "
            f"(0 .. {count - 1})"
        )


@dataclass(frozen=True)
class InverseReading:
    """How an inverse reads a pose onto a lower-mobility platform's reachable set (``readings``):
    its values are those of the reachable pose with the pose's controlled coordinates.

    ``axis`` is the unit axis k (3 x 1, in {B}, an expression of the parameters) of the height
    p . k and the tilt R^T k; ``controlled`` says the controlled and parasitic coordinates in
    words; ``unreachable`` is "invalid" (a pose off the set is invalid, through the validity
    conditions named in ``reachable``, which test the given pose against the set) or "read" (the
    reached pose is the answer, ``reachable`` empty)."""

    axis: sp.Matrix
    controlled: str
    unreachable: str
    reachable: tuple[str, ...] = ()


@dataclass
class InverseSolution:
    """Closed-form inverse pose: ordered assignments from the pose symbols to the joint variables.

    ``branches`` are symbols taking +1 or -1; combination k of all branches follows
    ``itertools.product((+1, -1), repeat=len(branches))`` (bit j set means branches[j] = -1,
    most significant bit first), so branch 0 is all signs +1.
    ``validity`` maps a name to an expression that must be positive for the branch to be valid;
    names ending in "reachable" mark workspace limits (UnreachablePoseError), the others serial
    singularities (SingularConfigurationError).
    """

    steps: list[tuple[sp.Symbol, sp.Expr]]
    branches: list[sp.Symbol]
    validity: dict[str, sp.Expr] = field(default_factory=dict)
    #: where the inverse reads a pose onto a lower-mobility platform's reachable set: how (the
    #: runtime's ``inverse_pose(onto_reachable=True)``); None where it takes the pose as given
    reading: InverseReading | None = None

    def at(
        self, rotation: sp.Matrix, position: sp.Matrix | None, branch: int, parameters: dict[sp.Symbol, float]
    ) -> dict[sp.Symbol, float]:
        """Every symbol of the inverse at the pose (^B_P R, position; None for an orienting
        platform) on branch ``branch`` (numbering above), evaluated step by step at 17 digits: a
        mechanism's home is its inverse pose itself, not a printed copy of it."""
        values: dict[sp.Symbol, sp.Expr] = dict(parameters)
        values.update({POSE_ROTATION[i, j]: rotation[i, j] for i in range(3) for j in range(3)})
        if position is not None:
            values.update(zip(POSE_POSITION, position, strict=True))
        count = len(self.branches)
        check_branch(branch, count, "inverse")
        values.update({b: -1 if (branch >> (count - 1 - k)) & 1 else 1 for k, b in enumerate(self.branches)})
        for target, expression in self.steps:
            values[target] = sp.N(expression.xreplace(values), 17)
        return {symbol: float(value) for symbol, value in values.items() if isinstance(symbol, sp.Symbol)}


@dataclass
class ForwardElimination:
    """Forward pose through a univariate polynomial sum_k coefficients[k] * unknown**k = 0.

    ``coefficients`` depend on actuated variables, parameters and the ``auxiliary`` assignments
    (themselves functions of the actuated variables). For each real root and each combination of
    ``branches`` (+1/-1), ``pose`` gives ^B_P T after the ``back_substitution`` assignments.
    """

    unknown: sp.Symbol
    coefficients: list[sp.Expr]
    branches: list[sp.Symbol]
    auxiliary: list[tuple[sp.Symbol, sp.Expr]]
    back_substitution: list[tuple[sp.Symbol, sp.Expr]]
    pose: sp.Matrix
    #: names and expressions that vanish where the elimination itself degenerates
    degeneracies: dict[str, sp.Expr] = field(default_factory=dict)


@dataclass
class ForwardHomotopy:
    """Forward pose by a parameter homotopy: a square polynomial system in ``unknowns`` whose
    coefficients are polynomials in the actuated variables and parameters.

    The generator picks a random complex instance of every actuated variable and parameter, finds
    all of its isolated solutions by monodromy (loops in the complex parameter space until no new
    solution appears) and stores them with the generated package; at run time each is followed
    along the straight segment from that instance to the caller's (real) values. The number of
    paths is the generic root count of the family, so every isolated solution of every instance
    is the end of some path (Morgan and Sommese's parameter homotopy theorem).

    ``homogeneous`` unknowns (a subset, or empty) appear in every equation so that the system is
    invariant under scaling them (with the other unknowns) jointly: the generator adds one random
    complex linear equation sum a_k z_k = 1 over them (a projective patch), and the runtime
    rotates the complex phase of an endpoint before reading it as a real solution. ``passive``
    gives the passive variables of a real solution, in the unknowns (invariant under that
    scaling).
    """

    unknowns: list[sp.Symbol]
    equations: list[sp.Expr]
    homogeneous: list[sp.Symbol]
    passive: list[sp.Expr]
    #: the seed of the random start instance and patch (a different seed, the same solutions)
    seed: int = 2026


@dataclass
class ClosureModel:
    """A loop closure written directly, for mechanisms whose legs are not modified-DH chains.

    ``residual`` (square in the passive variables) vanishes at a closed configuration;
    ``alignment`` entries are positive at a true closure and negative at a false one that the
    residual cannot tell apart (a mirror platform, a half-turn); ``pose`` is ^B_P T.
    """

    residual: sp.Matrix
    alignment: sp.Matrix
    pose: sp.Matrix


@dataclass
class RateModel:
    """Input-output velocity equations A twist = B actuated_rates (Gosselin and Angeles' form).

    ``twist`` names the twist components (e.g. wx, wy, wz for an orienting platform, in {B}).
    ``serial_factors`` multiply to det B (inverse, type I singularities); the mechanism's
    ``parallel_factors`` multiply to det A (direct, type II). Both products are verified.
    ``input_independent`` names serial factors whose zeros give assembly modes that do not depend
    on the inputs (the Agile Eye's folded poses); such modes are flagged, not counted.

    A lower-mobility platform (fewer actuators than twist components, e.g. a 3-PRS with its
    parasitic motion) adds ``constraints``: the constraint wrenches its legs transmit, one row
    per wrench over ``twist``, so that every motion it can make has constraints * twist = 0.
    A then has one row per actuator (the actuation wrenches) and the square matrix [A; constraints]
    is the mechanism's overall Jacobian (Joshi & Tsai 2002): its determinant is the product of the
    parallel factors, zero where the platform moves with the actuators locked.
    """

    twist: list[str]
    a: sp.Matrix
    b: sp.Matrix
    serial_factors: dict[str, sp.Expr]
    input_independent: list[str] = field(default_factory=list)
    constraints: sp.Matrix | None = None

    def overall(self) -> sp.Matrix:
        """[A; constraints]: square, one row per twist component."""
        return self.a if self.constraints is None else sp.Matrix.vstack(self.a, self.constraints)


@dataclass(frozen=True)
class Citation:
    """Where a mechanism comes from: printed in ``parakin list`` / ``inspect`` and the manifest."""

    authors: tuple[str, ...]
    title: str
    year: int | None = None
    venue: str | None = None
    doi: str | None = None

    def text(self) -> str:
        year = f" ({self.year})" if self.year else ""
        venue = f", {self.venue}" if self.venue else ""
        doi = f", doi:{self.doi}" if self.doi else ""
        return f"{', '.join(self.authors)}{year}: {self.title}{venue}{doi}"


#: parameter domains: any finite value, > 0, >= 0, != 0, or exactly +1 / -1
DOMAINS = ("real", "positive", "nonnegative", "nonzero", "sign")


@dataclass(frozen=True)
class ParameterInfo:
    """Unit and meaning of one parameter (``Mechanism.parameter_info``)."""

    unit: str
    description: str = ""
    #: the values the parameter may take, checked by ``parakin.load``: one of ``DOMAINS``
    domain: str = "real"

    def __post_init__(self) -> None:
        if self.domain not in DOMAINS:
            raise ValueError(f"parameter domain {self.domain!r} is not one of {DOMAINS}")


@dataclass
class Example:
    """A named configuration from the paper, reproduced by ``parakin demo`` and the contract tests.

    Either ``pose`` (^B_P T as a 4x4 nested list, or a 3x3 rotation for an orienting platform) is
    solved by ``inverse_pose`` and ``expected`` compares the branch ``branch`` (or the valid branch
    nearest the printed values), or ``actuated`` is solved by ``forward_pose_all`` and ``expected``
    may hold the printed ``mode_count`` and printed modes. Expected keys: ``actuated``, ``passive``
    (printed joint values, SI), ``mode_count``, ``poses`` (printed 4x4 poses of modes), each
    reproduced to ``tolerance`` (absolute, the printed precision)."""

    name: str
    description: str
    pose: list | None = None
    actuated: list[float] | None = None
    branch: int | None = None
    parameters: dict[str, float] = field(default_factory=dict)
    expected: dict[str, object] = field(default_factory=dict)
    tolerance: float = 1e-9


@dataclass
class Drawing:
    """What ``m.plot`` draws: named point sets (3 x n matrices in {B}, functions of the state and
    parameters) and polylines through them, each a list of (point set, column) pairs; ``parts``
    says which polyline is the base, a leg or the platform where its name does not
    (``generator.drawing``)."""

    points: dict[str, sp.Matrix]
    polylines: dict[str, list[tuple[str, int]]]
    parts: dict[str, str] = field(default_factory=dict)


@dataclass
class Mechanism:
    """A parallel mechanism: legs sharing the platform frame {P}, as in its paper."""

    name: str
    title: str
    citation: Citation
    #: parameter symbol -> default value (SI units), with the paper's values
    parameters: dict[sp.Symbol, float]
    actuated: list[sp.Symbol]
    passive: list[sp.Symbol]
    legs: list[SerialChain]
    inverse: InverseSolution | None = None
    forward: ForwardElimination | ForwardHomotopy | None = None
    #: a configuration used as the default Newton guess: variable -> value
    home: dict[sp.Symbol, float] = field(default_factory=dict)
    #: variable -> (lower, upper) physical range; outside it a branch or mode is flagged invalid
    limits: dict[sp.Symbol, tuple[float, float]] = field(default_factory=dict)
    #: names for factors of the leg determinants (factor expression -> name)
    serial_factor_names: dict[sp.Expr, str] = field(default_factory=dict)
    #: named factors whose product equals the closed-loop (type II) determinant
    parallel_factors: dict[str, sp.Expr] = field(default_factory=dict)
    #: angles (variables) that the runtime compares modulo 2 pi
    angular: list[sp.Symbol] = field(default_factory=list)
    #: variables without a unit (e.g. quaternion components); the others are lengths in metres
    dimensionless: list[sp.Symbol] = field(default_factory=list)
    #: the loop closure when it is not derived from ``legs``
    closure: ClosureModel | None = None
    #: input-output Jacobians when rates are not derived from ``legs``
    rates: RateModel | None = None
    #: the poses the platform takes, a key of ``POSE_KINDS`` ("transform": a general rigid pose,
    #: "rotation": an orienting platform, "planar_translation": x, y in the plane z = 0, ...)
    pose_kind: str = "transform"
    #: named expressions of the parameters only whose zeros make the design singular at every
    #: pose (architecture singularities); shown by ``parakin inspect``, evaluated by the runtime
    architecture: dict[str, sp.Expr] = field(default_factory=dict)
    #: further named singularity factors (e.g. of a serial chain's pointing map), already factored
    factors: dict[str, sp.Expr] = field(default_factory=dict)
    #: unit and description of each parameter (missing: unit "m" for lengths is NOT assumed)
    parameter_info: dict[sp.Symbol, ParameterInfo] = field(default_factory=dict)
    #: vector parameters: a name -> matrix of parameter symbols (e.g. a point list, one row a point)
    parameter_groups: dict[str, sp.Matrix] = field(default_factory=dict)
    #: the paper's named configurations
    examples: list[Example] = field(default_factory=list)
    #: the drawing kernel (base, platform, legs)
    drawing: Drawing | None = None
    #: actuator stiffness parameters, in actuated order (statics with compliant actuators)
    actuator_stiffness: list[sp.Symbol] = field(default_factory=list)
    #: the bodies and joints (``generator.graph``), where the mechanism was written as joints: the
    #: generator checks their mobility and motion by screw analysis against ``pose_kind``
    joint_graph: JointGraph | None = None
    #: names of architecture measures normalised to [0, 1]-like scale: below ``architecture_tolerance``
    #: the design is singular at every pose (``load`` warns)
    architecture_tolerance: float = 1e-9
