"""Typed view of a generated package's ``manifest.json`` (schema 2).

The runtime reads mechanisms only through these objects: which kernels exist and their shapes,
which capabilities a mechanism has, its variables with units and limits, its examples. A feature
that a mechanism lacks is a ``None`` capability here, never a test of its name.

A manifest is untrusted text until read: every name in it (mechanism, parameters, variables,
kernels, C symbols, ...) must be a Python identifier, because names become file names, module
names and C symbols; every file entry (``c.sources``, ``c.headers``, ``c.header``) must be a plain
file name inside the package folder. Every other field is checked too, for its type, shape and
range and against the fields it must agree with (``Manifest.from_dict``). Anything else is a
BrokenPackageError (a BadInputError) naming the field's path and the bad value.
"""

from __future__ import annotations

import difflib
import json
import math
import re
import reprlib
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from parakin.errors import NEWTON_STATUS_NAMES, BadInputError, BrokenPackageError
from parakin.packages import expression
from parakin.pose import POSE_KINDS
from parakin.validation import MAX_MAGNITUDE, in_domain

SUPPORTED_SCHEMA = 2


@dataclass(frozen=True)
class Citation:
    authors: tuple[str, ...]
    title: str
    year: int | None
    venue: str | None
    doi: str | None

    def __str__(self) -> str:
        year = f" ({self.year})" if self.year else ""
        venue = f". {self.venue}" if self.venue else ""
        doi = f". doi:{self.doi}" if self.doi else ""
        return f"{', '.join(self.authors)}{year}. {self.title}{venue}{doi}"


@dataclass(frozen=True)
class Parameter:
    """A scalar parameter; ``domain``: real, positive, nonnegative, nonzero or sign (+1 / -1)."""

    name: str
    default: float
    unit: str
    description: str
    domain: str = "real"


@dataclass(frozen=True)
class ParameterGroup:
    """A vector parameter (e.g. a list of points): ``symbols`` fill ``shape`` row by row."""

    name: str
    shape: tuple[int, ...]
    symbols: tuple[str, ...]


@dataclass(frozen=True)
class Variable:
    """A variable: revolute (rad), prismatic (m) or dimensionless (a quaternion component), with
    its home value and limits."""

    name: str
    kind: str
    unit: str
    home: float | None
    limits: tuple[float, float]

    @property
    def revolute(self) -> bool:
        return self.kind == "revolute"


@dataclass(frozen=True)
class KernelIO:
    name: str
    shape: tuple[int, ...]


@dataclass(frozen=True)
class Kernel:
    """One generated function: named inputs (vectors of ``size``) and outputs (shapes)."""

    name: str
    doc: str
    operations: int
    inputs: tuple[KernelIO, ...]
    outputs: tuple[KernelIO, ...]
    c_symbol: str


@dataclass(frozen=True)
class Reading:
    """How a lower-mobility platform's inverse reads a pose onto its reachable set: its values
    are those of the reachable pose with the pose's controlled coordinates, the height p . k and
    the tilt R^T k about the unit ``axis`` k (three expressions of the parameters, in {B});
    ``controlled`` says the controlled and parasitic coordinates in words. ``unreachable``:
    "invalid" (a pose off the set is invalid through the validity conditions ``reachable``, which
    test the given pose) or "read" (the reached pose is the answer; ``reachable`` empty)."""

    axis: tuple[str, str, str]
    controlled: str
    unreachable: str
    reachable: tuple[str, ...]


@dataclass(frozen=True)
class Inverse:
    """Closed-form inverse: branch k has the signs ``combinations[k]`` of ``branches``.

    Branch symbols fall into independent ``groups`` (one per leg, typically); ``*_groups`` give
    the group of each actuated, passive and validity output (-1: no branch symbol changes it), and
    ``patterns[p]`` the signs of the ``inverse_pose_patterns`` kernel's column p."""

    branches: tuple[str, ...]
    combinations: tuple[tuple[int, ...], ...]
    validity: tuple[str, ...]
    groups: tuple[tuple[int, ...], ...] = ()
    actuated_groups: tuple[int, ...] = ()
    passive_groups: tuple[int, ...] = ()
    validity_groups: tuple[int, ...] = ()
    patterns: tuple[tuple[int, ...], ...] = ()
    #: the reading onto a lower-mobility platform's reachable set (optional field
    #: ``reading``); None where the inverse takes the pose as given
    reading: Reading | None = None


@dataclass(frozen=True)
class Homotopy:
    """A generated parameter homotopy: its unknowns, which of them are homogeneous (one random
    complex patch fixes their scale), and the start solutions (paths, unknowns), complex."""

    unknowns: tuple[str, ...]
    homogeneous: tuple[int, ...]
    start: np.ndarray = field(compare=False)
    #: the solutions of the second start instance (retried where a path of the first fails)
    alternative: np.ndarray = field(compare=False)
    #: the monomials: term t is prod_i z_i^exponents[t, i] in equation ``equation[t]``
    exponents: np.ndarray = field(compare=False, default_factory=lambda: np.zeros((0, 0), dtype=np.int64))
    equation: np.ndarray = field(compare=False, default_factory=lambda: np.zeros(0, dtype=np.int64))
    #: the equation that is the random patch of the homogeneous unknowns (None: no patch)
    patch_equation: int | None = None
    #: the generic root count and how it was proven at generation time
    root_count: RootCount | None = None
    #: coefficients are polynomials of degree < powers in s
    powers: int = 1
    #: the family's free parameters and angles (kernel ``{method}_family``), and the constants
    #: a, b of the circle parametrisation u of each angle
    free: tuple[str, ...] = ()
    circles: tuple[str, ...] = ()
    circle_constants: tuple[complex, complex] = (0j, 0j)
    #: the start instances (free parameters, then one u per angle), complex
    start_instance: np.ndarray = field(compare=False, default_factory=lambda: np.zeros(0, dtype=complex))
    alternative_instance: np.ndarray = field(compare=False, default_factory=lambda: np.zeros(0, dtype=complex))
    #: where the root count was proven on a subfamily (the mechanism's parameters sharing a value,
    #: ``parakin.solvers.subfamily_membership``): groups of indices into the start instance's values that are
    #: equal there, their relative tolerance and the relations in words; () for the whole family
    subfamily_identical: tuple[tuple[int, ...], ...] = ()
    subfamily_tolerance: float = 0.0
    subfamily_relations: str = ""
    #: the start near the mechanism's home (``NearStart``), None where the package has none
    near: NearStart | None = field(compare=False, default=None)


@dataclass(frozen=True)
class NearStart:
    """A third start instance next to the mechanism's home (generator/near_start.py): inputs
    whose family values lie within ``radius`` of ``center`` (max over values of |q - center| /
    ``scale``) start here, on shorter paths; ``solutions`` (paths, unknowns) in the first start's
    order (its sign symmetry's pairs are the same)."""

    instance: np.ndarray = field(compare=False)
    solutions: np.ndarray = field(compare=False)
    center: np.ndarray = field(compare=False)
    scale: np.ndarray = field(compare=False)
    radius: float = 0.0


@dataclass(frozen=True)
class RootCount:
    """The family's generic number of isolated solutions (the paths), proven at generation time:
    ``method`` names the proof. The trace test: ``deviation`` its measure (0 for a complete set)
    against ``tolerance``, ``witnesses`` the auxiliary points it used. The total-degree bound:
    ``bezout_paths`` paths per run and the regular solutions each independent run found
    (``regular_endpoints``, all equal to ``count`` when proven)."""

    count: int
    method: str
    deviation: float
    tolerance: float
    witnesses: int
    #: False: neither proof closed at generation; the count is monodromy's (every found
    #: solution is a solution, but more may exist)
    proven: bool = True
    bezout_paths: int = 0
    regular_endpoints: tuple[int, ...] = ()


@dataclass(frozen=True)
class Forward:
    """Every assembly mode by one method: a univariate polynomial in ``unknown`` of ``degree``
    (method "elimination", written with the mechanism), or a parameter homotopy with ``degree``
    paths (method "homotopy": the mechanism's own polynomial system; "automatic": the polynomial
    form the generator derives from the loop closure)."""

    unknown: str
    degree: int
    branches: tuple[str, ...]
    combinations: tuple[tuple[int, ...], ...]
    degeneracies: tuple[str, ...]
    method: str = "elimination"
    homotopy: Homotopy | None = None


@dataclass(frozen=True)
class Leg:
    name: str
    joints: tuple[str, ...]


@dataclass(frozen=True)
class RateModel:
    """A twist = B actuated_rates, twist components named ``twist``; a lower-mobility platform
    also has ``constraints`` constraint wrenches (rows C with C twist = 0 for every motion it
    can make), A one row per actuator."""

    twist: tuple[str, ...]
    input_independent: tuple[str, ...]
    constraints: int = 0


@dataclass(frozen=True)
class Architecture:
    measures: tuple[str, ...]
    tolerance: float


#: what a drawing's polyline can be (generator/drawing.py)
DRAWING_PARTS = ("base", "leg", "platform")


@dataclass(frozen=True)
class Drawing:
    """Point sets (name -> number of points) and polylines of (point set, index) pairs; each
    polyline's part ("base", "leg" or "platform") and the point sets fixed to the base (their
    kernel expressions hold no actuated or passive variable), both from the generator."""

    points: dict[str, int]
    polylines: dict[str, tuple[tuple[str, int], ...]]
    parts: dict[str, str]
    fixed: tuple[str, ...]


@dataclass(frozen=True)
class Statics:
    stiffness: tuple[str, ...]


@dataclass(frozen=True)
class Example:
    name: str
    description: str
    pose: Any
    actuated: tuple[float, ...] | None
    branch: int | None
    parameters: dict[str, float]
    expected: dict[str, Any]
    tolerance: float


@dataclass(frozen=True)
class Capabilities:
    inverse: Inverse | None
    forward: Forward | None
    legs: tuple[Leg, ...] | None
    rates: RateModel | None
    architecture: Architecture | None
    drawing: Drawing | None
    statics: Statics | None
    #: every method of forward_pose_all by name ("elimination", "homotopy", "automatic"); the
    #: default, ``forward``, is the fastest one with a complete answer
    forward_methods: dict[str, Forward] = field(default_factory=dict)


@dataclass(frozen=True)
class Newton:
    """The C Newton driver's layout (shared with ``parakin.packages.compiled``)."""

    symbol: str
    unknowns: int
    actuated: int


@dataclass(frozen=True)
class Abi:
    """The C ABI as the generator wrote it: status code names (their index is the code) and
    the fields (name, type) of the job structures that ``parakin.packages.compiled`` binds."""

    newton_status: tuple[str, ...]
    mode_outcomes: tuple[str, ...]
    input_status: tuple[str, ...]
    root_kinds: tuple[str, ...]
    newton_job: tuple[tuple[str, str], ...]
    modes_job: tuple[tuple[str, str], ...]
    modes_symbol: str | None

    def code(self, table: str, name: str) -> int:
        """The integer code of ``name`` in one of the status tables."""
        return getattr(self, table).index(name)


#: joint kinds of the graph and their degrees of freedom (generator.graph.KINDS)
JOINT_KINDS = {"R": 1, "P": 1, "C": 2, "U": 2, "S": 3, "planar": 3, "Pa": 1, "F": 0}
#: the kinds that need an axis (a prismatic joint without one slides along its leg's line)
AXIAL_KINDS = ("R", "C", "U", "planar", "Pa")
#: where a joint lies on its leg: the base point A, the elbow E, the platform point C, or placed
#: by a serial chain's product of exponentials ("chain")
JOINT_SITES = ("base", "elbow", "platform", "chain")


@dataclass(frozen=True)
class GraphJoint:
    """One joint of the joint graph (``generator.graph.Joint``): its kind (``JOINT_KINDS``) and
    site (``JOINT_SITES``); ``point`` and ``axis`` as three expression texts of the parameters
    (``parakin.packages.expression``; in {B} at the base and the elbow, the elbow's before the
    first body turns, in {P} at the platform; None where the kind or site has none); the
    ``variable`` it carries (an actuated variable where ``actuated``), and its limits (rad or m)."""

    kind: str
    site: str
    point: tuple[str, str, str] | None
    axis: tuple[str, str, str] | None
    variable: str | None
    actuated: bool
    limits: tuple[float, float] | None

    @property
    def dof(self) -> int:
        return JOINT_KINDS[self.kind]


@dataclass(frozen=True)
class GraphLeg:
    """A leg: its joints from the base to the platform and the bodies between them (one fewer);
    ``reach`` the first body's length and zero direction (expressions) where it is a crank;
    ``link`` the fixed elbow-to-platform distance (None: a line of variable length from A)."""

    name: str
    actuated: bool
    joints: tuple[GraphJoint, ...]
    bodies: tuple[str, ...]
    reach: tuple[str, tuple[str, str, str]] | None
    link: str | None

    @property
    def serial(self) -> bool:
        """Whether the leg is a serial chain placed by products of exponentials (site "chain")."""
        return all(j.site == "chain" for j in self.joints)


@dataclass(frozen=True)
class GraphInertial:
    """A body's inertial symbols (names): mass, centre (3) and inertia (3 x 3, row by row)."""

    mass: str
    centre: tuple[str, ...]
    inertia: tuple[str, ...]


@dataclass(frozen=True)
class GraphBody:
    name: str
    inertial: GraphInertial | None


@dataclass(frozen=True)
class GraphLoop:
    """A loop constraint: leg ``leg`` meets the platform at its joint number ``joint``."""

    leg: str
    joint: int


@dataclass(frozen=True)
class GraphMotion:
    """What the generator's screw analysis found: the platform's mobility, the smallest pose
    kind holding its twists (None: none), nTmR, parasitic motion, the configurations sampled."""

    mobility: int
    kind: str | None
    translations: int
    rotations: int
    parasitic: bool
    samples: int
    text: str


@dataclass(frozen=True)
class JointGraph:
    """The mechanism as bodies and joints (``generator.graph``; the manifest's ``joints``): the
    platform's pose kind, bodies, legs, loops and the screw analysis's ``motion``."""

    pose_kind: str
    bodies: tuple[GraphBody, ...]
    legs: tuple[GraphLeg, ...]
    loops: tuple[GraphLoop, ...]
    motion: GraphMotion | None


@dataclass(frozen=True)
class Manifest:
    schema: int
    name: str
    title: str
    citation: Citation
    conventions: str
    generator_version: str
    source: str
    pose_kind: str
    parameters: tuple[Parameter, ...]
    parameter_groups: tuple[ParameterGroup, ...]
    actuated: tuple[Variable, ...]
    passive: tuple[Variable, ...]
    singularity_factors: tuple[str, ...]
    determinants: tuple[str, ...]
    capabilities: Capabilities
    examples: tuple[Example, ...]
    #: a ``Tolerances``: a missing name is a BrokenPackageError, not a KeyError
    tolerances: dict[str, float]
    kernels: dict[str, Kernel]
    c_sources: tuple[str, ...]
    c_header: str
    c_headers: tuple[str, ...]
    newton: Newton
    abi: Abi
    #: the bodies and joints (None: a package generated before the manifest carried them)
    joints: JointGraph | None = None

    @property
    def actuated_names(self) -> list[str]:
        return [v.name for v in self.actuated]

    @property
    def passive_names(self) -> list[str]:
        return [v.name for v in self.passive]

    @property
    def parameter_defaults(self) -> dict[str, float]:
        return {p.name: p.default for p in self.parameters}

    @property
    def twist_size(self) -> int:
        """Components of a platform twist (and wrench): 6 = (v, w) for leg models."""
        rates = self.capabilities.rates
        return len(rates.twist) if rates is not None else 6

    def has_kernel(self, name: str) -> bool:
        return name in self.kernels

    @property
    def parameter_names(self) -> list[str]:
        """What ``parakin.load`` takes as parameters: scalar names, then vector group names."""
        return [*(p.name for p in self.parameters), *(g.name for g in self.parameter_groups)]

    @property
    def files(self) -> tuple[str, ...]:
        """Every file the manifest names (C sources and headers), relative to its folder."""
        return tuple(dict.fromkeys([*self.c_sources, *self.c_headers, self.c_header]))

    @classmethod
    def read(cls, path: Path) -> Manifest:
        """Read and check ``path`` (a manifest.json): every field (``from_dict``), and every file
        entry a plain file name that resolves inside the package folder. BrokenPackageError
        (a BadInputError) naming the file, the field and the bad value otherwise.

        Parameters
        ----------
        path : pathlib.Path or str
            The ``manifest.json`` of a generated package folder (``m.package.path``).

        Returns
        -------
        Manifest
            The typed manifest: variables with units and limits, parameters, kernels,
            capabilities, examples, tolerances.

        Raises
        ------
        BrokenPackageError
            The file cannot be read or is no JSON, a field is missing or malformed (named with its
            path in the manifest and the bad value), or a C file it lists resolves outside the
            package folder.

        Examples
        --------
        >>> import parakin
        >>> from parakin.packages.manifest import Manifest
        >>> folder = parakin.load("five_bar", backend="numpy").package.path
        >>> manifest = Manifest.read(folder / "manifest.json")
        >>> manifest.name, manifest.actuated_names, manifest.passive_names, manifest.pose_kind
        ('five_bar', ['theta1', 'theta2'], ['x', 'y'], 'planar_translation')
        >>> Manifest.read(folder / "missing.json")
        Traceback (most recent call last):
        ...
        parakin.errors.BrokenPackageError: cannot read the manifest .../missing.json: [Errno 2] No such file ...
        """
        path = Path(path)
        try:
            data = json.loads(path.read_text())
        # RecursionError: brackets nested past the parser's depth
        except (OSError, ValueError, RecursionError) as error:
            raise BrokenPackageError(f"cannot read the manifest {path}: {error}") from error
        try:
            manifest = cls.from_dict(data)
        except BadInputError as error:
            raise BrokenPackageError(f"manifest {path}: {error}") from error
        folder = path.parent.resolve()
        for name in manifest.files:
            if not (folder / name).resolve().is_relative_to(folder):  # a symbolic link out of the folder
                raise BrokenPackageError(f"manifest {path}: file {name!r} resolves outside the package folder {folder}")
        return manifest

    @classmethod
    def from_dict(cls, data: object) -> Manifest:
        """The typed manifest of a parsed manifest.json. Total: every field is checked for its
        type, shape and range, and against the fields it must agree with (sizes of variables,
        branches, unknowns, the kernels each capability calls), so that a manifest read here
        cannot make a solver fail later with a raw error; anything else is a BrokenPackageError
        naming the field's path and the bad value.

        Parameters
        ----------
        data : object
            The parsed JSON (``json.loads``): a dict with the manifest's fields, of schema
            ``SUPPORTED_SCHEMA``; any other value is refused with the reason.

        Returns
        -------
        Manifest
            The typed manifest (no file is checked: ``read`` checks the listed files).

        Raises
        ------
        BrokenPackageError
            Not a JSON object, an unsupported schema (regenerate the package), or a field
            missing, of the wrong type, shape or range, or disagreeing with another (named by its
            path, e.g. ``actuated[0].limits``, with the bad value).

        Examples
        --------
        >>> import json, parakin
        >>> from parakin.packages.manifest import Manifest
        >>> folder = parakin.load("five_bar", backend="numpy").package.path
        >>> data = json.loads((folder / "manifest.json").read_text())
        >>> Manifest.from_dict(data).actuated[0]
        Variable(name='theta1', kind='revolute', unit='rad', home=1.86..., limits=(-inf, inf))
        >>> data["actuated"][0]["limits"] = [2.0, 1.0]
        >>> Manifest.from_dict(data)
        Traceback (most recent call last):
        ...
        parakin.errors.BrokenPackageError: field actuated.limits: [2.0, 1.0] is not a range (low > high) (at actuated[0].limits)
        """
        if not isinstance(data, dict):
            raise BrokenPackageError(f"a manifest is a JSON object, got {type(data).__name__}")
        schema = data.get("schema")
        if schema != SUPPORTED_SCHEMA or isinstance(schema, bool):
            raise BrokenPackageError(
                f"manifest schema {_shown(schema)} is not supported by this parakin (schema {SUPPORTED_SCHEMA}); "
                "regenerate"
            )
        try:
            manifest = cls._from_dict(data)
            _check_agreement(manifest)
        except BadInputError as error:
            if isinstance(error, BrokenPackageError):
                raise
            raise BrokenPackageError(str(error)) from error
        # a safety net: every check above names its field; an error that escapes them is still
        # a broken package, not a crash
        except (TypeError, ValueError, AttributeError, IndexError, KeyError, OverflowError) as error:
            raise BrokenPackageError(
                f"malformed manifest ({type(error).__name__}: {error}); regenerate the package"
            ) from error
        return manifest

    @classmethod
    def _from_dict(cls, data: dict[str, Any]) -> Manifest:
        caps = _object(_member(data, "capabilities", ""), "capabilities")
        c = _object(_member(data, "c", ""), "c")
        actuated = _variables(_member(data, "actuated", ""), "actuated", at_least=1)
        passive = _variables(_member(data, "passive", ""), "passive")
        parameters = _list(_member(data, "parameters", ""), "parameters")
        generator = _object(_member(data, "generator", ""), "generator")
        forward, forward_methods = _forward_methods(_member(caps, "forward", "capabilities"))
        abi = _object(_member(c, "abi", "c"), "c.abi")
        newton = _object(_member(c, "newton", "c"), "c.newton")
        modes = _member(c, "modes", "c") if "modes" in c else None
        if modes is not None:
            modes = _object(modes, "c.modes")
        parsed_parameters = _unique(
            tuple(_parameter(p, f"parameters[{k}]") for k, p in enumerate(parameters)), "parameters"
        )
        return cls(
            schema=SUPPORTED_SCHEMA,
            name=_name(_member(data, "name", ""), "name"),
            title=_text(_member(data, "title", ""), "title"),
            citation=_citation(_member(data, "citation", "")),
            conventions=_text(_member(data, "conventions", ""), "conventions"),
            generator_version=_text(_member(generator, "version", "generator"), "generator.version"),
            source=_text(_member(generator, "source", "generator"), "generator.source"),
            pose_kind=_pose_kind(_member(data, "pose_kind", "")),
            parameters=parsed_parameters,
            parameter_groups=_unique(
                tuple(
                    _parameter_group(g, f"parameter_groups[{k}]")
                    for k, g in enumerate(_list(_member(data, "parameter_groups", ""), "parameter_groups"))
                ),
                "parameter_groups",
            ),
            actuated=actuated,
            passive=passive,
            singularity_factors=_names(_member(data, "singularity_factors", ""), "singularity_factors"),
            determinants=_names(_member(data, "determinants", ""), "determinants"),
            capabilities=Capabilities(
                inverse=_inverse(
                    _member(caps, "inverse", "capabilities"),
                    len(actuated),
                    len(passive),
                    [p.name for p in parsed_parameters],
                ),
                forward=forward,
                forward_methods=forward_methods,
                legs=_legs(_member(caps, "legs", "capabilities")),
                rates=_rates(_member(caps, "rates", "capabilities")),
                architecture=_architecture(_member(caps, "architecture", "capabilities")),
                drawing=_drawing(_member(caps, "drawing", "capabilities")),
                statics=_statics(_member(caps, "statics", "capabilities")),
            ),
            examples=tuple(
                _example(e, f"examples[{k}]", len(actuated), len(passive))
                for k, e in enumerate(_list(_member(data, "examples", ""), "examples"))
            ),
            tolerances=_tolerances(_member(data, "tolerances", "")),
            kernels=_kernels(_member(data, "kernels", "")),
            c_sources=tuple(
                _file_name(f, f"c.sources[{k}]") for k, f in enumerate(_list(_member(c, "sources", "c"), "c.sources"))
            ),
            c_header=_file_name(_member(c, "header", "c"), "c.header"),
            c_headers=tuple(
                _file_name(f, f"c.headers[{k}]") for k, f in enumerate(_list(_member(c, "headers", "c"), "c.headers"))
            ),
            newton=Newton(
                _name(_member(newton, "symbol", "c.newton"), "c.newton.symbol"),
                _integer(_member(newton, "unknowns", "c.newton"), "c.newton.unknowns"),
                _integer(_member(newton, "actuated", "c.newton"), "c.newton.actuated"),
            ),
            abi=Abi(
                _newton_status(_member(abi, "newton_status", "c.abi")),
                _codes(abi, "mode_outcomes"),
                _codes(abi, "input_status"),
                _codes(abi, "root_kinds"),
                _job(_member(abi, "newton_job", "c.abi"), "c.abi.newton_job"),
                _job(_member(abi, "modes_job", "c.abi"), "c.abi.modes_job"),
                _optional_name(modes.get("symbol") if modes is not None else None, "c.modes.symbol"),
            ),
            joints=_joint_graph(data.get("joints"), [p.name for p in parsed_parameters]),
        )


class Tolerances(dict[str, float]):
    """The manifest's tolerances by name: every value a finite number >= 0; asking for one the
    manifest lacks is a BrokenPackageError naming it (not a KeyError deep inside a solver)."""

    def __missing__(self, key: str) -> float:
        raise BrokenPackageError(
            f"field tolerances: the manifest has no tolerance {key!r}, which this parakin reads; regenerate the package"
        )


#: the names of status codes this parakin looks up in the manifest's ABI tables (``Abi``): a
#: table may name more (a newer generator), never fewer
ABI_NAMES_READ = {
    "mode_outcomes": (
        "mode",
        "no_root",
        "back_substitution_undefined",
        "not_closed",
        "false_closure",
        "not_converged",
        "outside_limits",
        "duplicate",
        "input_independent",
        "complex",
        "at_infinity",
        "path_failed",
        "uncertified",
    ),
    "root_kinds": ("simple", "cluster", "near_real", "complex", "at_infinity", "failed"),
    "input_status": ("ok", "nonfinite", "degenerate"),
}
#: the largest count a manifest may give (sizes, degrees, points, paths): far above any
#: mechanism's, far below what would exhaust memory when arrays are allocated from it
MAX_COUNT = 1_000_000
#: the most iterations a tolerance may ask for (``polish_iterations``)
MAX_ITERATIONS = 10_000
#: variable kinds and parameter domains (``parakin.validation.in_domain``)
VARIABLE_KINDS = ("revolute", "prismatic", "dimensionless")
PARAMETER_DOMAINS = ("real", "positive", "nonnegative", "nonzero", "sign")
#: what a message shows of a bad value: short, however large the value
_REPR = reprlib.Repr()  # keyword arguments only from Python 3.12
_REPR.maxlevel, _REPR.maxlist, _REPR.maxdict, _REPR.maxstring, _REPR.maxother, _REPR.maxlong = 3, 4, 4, 60, 60, 40


def unknown_name(kind: str, key: object, valid: Iterable[str], owner: str) -> BadInputError:
    """The error for a name that is not one of ``valid`` (a parameter, a limit): it names the
    key, suggests the closest valid names (a case-insensitive match first, then the closest
    spellings) and lists them all."""
    valid = list(valid)
    text = str(key)
    same_case = [v for v in valid if v.lower() == text.lower()]
    close = same_case or difflib.get_close_matches(text, valid, n=3, cutoff=0.6)
    hint = f"did you mean {' or '.join(map(repr, close))}? " if close else ""
    return BadInputError(f"unknown {kind} {key!r} for {owner!r}; {hint}valid: {valid}")


# ---------------------------------------------------------------- checked readers of JSON values
def _shown(value: object) -> str:
    return _REPR.repr(value)


def _bad(path: str, value: object, what: str) -> BrokenPackageError:
    """The error for the field at ``path`` (with list indices: ``a.b[2].c``): the message names
    the field as the schema does (``a.b.c``), the value, what it should be, and where it is."""
    field_name = re.sub(r"\[\d+\]", "", path)
    where = f" (at {path})" if field_name != path else ""
    return BrokenPackageError(f"field {field_name}: {_shown(value)} {what}{where}")


def _member(data: dict[str, Any], key: str, path: str) -> Any:
    if key not in data:
        raise BrokenPackageError(f"field {f'{path}.{key}' if path else key!r} is missing; regenerate the package")
    return data[key]


def _object(value: object, path: str) -> dict[str, Any]:
    if not isinstance(value, dict):
        raise _bad(path, value, "is not an object (a JSON {...})")
    return value


def _optional_object(value: object, path: str) -> dict[str, Any] | None:
    """A capability: None where the mechanism lacks it, else a complete object (an empty one is
    not 'absent': the generator writes null)."""
    return None if value is None else _object(value, path)


def _list(value: object, path: str, length: int | None = None, at_least: int = 0) -> list[Any]:
    if not isinstance(value, list):
        raise _bad(path, value, "is not a list")
    if length is not None and len(value) != length:
        raise _bad(path, value, f"has {len(value)} entries, not {length}")
    if len(value) < at_least:
        raise _bad(path, value, f"has {len(value)} entries, fewer than {at_least}")
    if len(value) > MAX_COUNT:
        raise _bad(path, value, f"has {len(value)} entries, more than {MAX_COUNT}")
    return value


def _text(value: object, path: str) -> str:
    if not isinstance(value, str):
        raise _bad(path, value, "is not a string")
    return value


def _optional_text(value: object, path: str) -> str | None:
    return None if value is None else _text(value, path)


def _integer(value: object, path: str, low: int = 0, high: int = MAX_COUNT) -> int:
    if type(value) is not int:  # not a bool, not a float
        raise _bad(path, value, "is not an integer")
    if not low <= value <= high:
        raise _bad(path, value, f"is outside [{low}, {high}]")
    return value


def _number(value: object, path: str, low: float = -math.inf, high: float = math.inf) -> float:
    """A finite real number in [low, high] (JSON ints included, booleans not)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise _bad(path, value, "is not a number")
    try:
        number = float(value)
    except OverflowError:
        raise _bad(path, value, "is not a finite number") from None
    if not math.isfinite(number):
        raise _bad(path, value, "is not a finite number")
    if not low <= number <= high:
        raise _bad(path, value, f"is outside [{low:g}, {high:g}]")
    return number


def _flag(value: object, path: str) -> bool:
    if not isinstance(value, bool):
        raise _bad(path, value, "is not true or false")
    return value


def _sign(value: object, path: str) -> int:
    if isinstance(value, bool) or not isinstance(value, int | float) or value not in (1, -1):
        raise _bad(path, value, "is not a branch sign (+1 or -1)")
    return int(value)


def _signs(value: object, path: str, length: int) -> tuple[tuple[int, ...], ...]:
    """Sign combinations: at least one, each of ``length`` signs."""
    rows = _list(value, path, at_least=1)
    return tuple(
        tuple(_sign(s, f"{path}[{k}][{j}]") for j, s in enumerate(_list(row, f"{path}[{k}]", length)))
        for k, row in enumerate(rows)
    )


def _indices(value: object, path: str, low: int, high: int) -> tuple[int, ...]:
    return tuple(_integer(v, f"{path}[{k}]", low, high) for k, v in enumerate(_list(value, path)))


def _numbers(value: object, path: str, length: int | None = None) -> tuple[float, ...]:
    return tuple(_number(v, f"{path}[{k}]") for k, v in enumerate(_list(value, path, length)))


def _matrix(value: object, path: str, rows: int | None = None, columns: int | None = None) -> np.ndarray:
    """A matrix of finite numbers, a list of rows of equal length (``rows`` x ``columns`` when given)."""
    entries = _list(value, path, rows)
    values = [_numbers(row, f"{path}[{k}]", columns) for k, row in enumerate(entries)]
    width = {len(row) for row in values}
    if len(width) > 1:
        raise _bad(path, value, "has rows of different lengths")
    return np.array(values, dtype=float).reshape(len(values), width.pop() if width else (columns or 0))


def _complex_matrix(value: object, path: str, rows: int, columns: int) -> np.ndarray:
    """``{"real": matrix, "imag": matrix}`` of ``rows`` x ``columns``."""
    data = _object(value, path)
    real = _matrix(_member(data, "real", path), f"{path}.real", rows, columns)
    imag = _matrix(_member(data, "imag", path), f"{path}.imag", rows, columns)
    return real + 1j * imag


def _complex_vector(value: object, path: str, length: int) -> np.ndarray:
    data = _object(value, path)
    real = np.array(_numbers(_member(data, "real", path), f"{path}.real", length))
    imag = np.array(_numbers(_member(data, "imag", path), f"{path}.imag", length))
    return (real + 1j * imag).astype(complex)


def _name(value: object, field: str) -> str:
    """A name from the manifest: a Python identifier (names become module names, file names
    and C symbols, so nothing else may pass)."""
    if not (isinstance(value, str) and value.isidentifier() and value.isascii()):
        raise _bad(field, value, "is not a name (an ASCII Python identifier)")
    return value


def _names(values: object, field: str) -> tuple[str, ...]:
    if not isinstance(values, list):
        raise _bad(field, values, "is not a list of names")
    return tuple(_name(v, f"{field}[{k}]") for k, v in enumerate(_list(values, field)))


def _optional_name(value: object, field: str) -> str | None:
    return None if value is None else _name(value, field)


def _unique(items: tuple[Any, ...], field: str) -> tuple[Any, ...]:
    """Entries with a ``name`` attribute, no name twice."""
    seen: set[str] = set()
    for k, item in enumerate(items):
        if item.name in seen:
            raise _bad(f"{field}[{k}].name", item.name, "names a second entry")
        seen.add(item.name)
    return items


def _file_name(value: object, field: str) -> str:
    """A file entry: a plain file name in the package folder (no folder part, no '..', not
    absolute), so that building and exporting touch nothing outside the folders they are given."""
    if not (
        isinstance(value, str)
        and value not in ("", ".", "..")
        and "/" not in value
        and "\\" not in value
        and "\0" not in value
        and Path(value).name == value
    ):
        raise _bad(field, value, "is not a plain file name inside the package folder")
    return value


def _pose_kind(value: object) -> str:
    if not isinstance(value, str) or value not in POSE_KINDS:
        raise _bad("pose_kind", value, f"is not a pose kind of this parakin ({sorted(POSE_KINDS)})")
    return value


def _citation(value: object) -> Citation:
    data = _object(value, "citation")
    year = _member(data, "year", "citation")
    return Citation(
        tuple(
            _text(a, f"citation.authors[{k}]")
            for k, a in enumerate(_list(_member(data, "authors", "citation"), "citation.authors"))
        ),
        _text(_member(data, "title", "citation"), "citation.title"),
        None if year is None else _integer(year, "citation.year", 0, 9999),
        _optional_text(_member(data, "venue", "citation"), "citation.venue"),
        _optional_text(_member(data, "doi", "citation"), "citation.doi"),
    )


def _parameter(value: object, path: str) -> Parameter:
    data = _object(value, path)
    name = _name(_member(data, "name", path), f"{path}.name")
    domain = _text(data.get("domain", "real"), f"{path}.domain")
    if domain not in PARAMETER_DOMAINS:
        raise _bad(f"{path}.domain", domain, f"is not a parameter domain ({', '.join(PARAMETER_DOMAINS)})")
    # the load refuses larger values (beyond them the kinematics overflows)
    default = _number(_member(data, "default", path), f"{path}.default", -MAX_MAGNITUDE, MAX_MAGNITUDE)
    try:
        in_domain(default, name, domain)
    except BadInputError as error:
        raise _bad(f"{path}.default", default, f"is outside its domain: {error}") from None
    return Parameter(
        name,
        default,
        _text(_member(data, "unit", path), f"{path}.unit"),
        _text(_member(data, "description", path), f"{path}.description"),
        domain,
    )


def _parameter_group(value: object, path: str) -> ParameterGroup:
    data = _object(value, path)
    shape = tuple(
        _integer(n, f"{path}.shape[{k}]", 1)
        for k, n in enumerate(_list(_member(data, "shape", path), f"{path}.shape", at_least=1))
    )
    symbols = _names(_member(data, "symbols", path), f"{path}.symbols")
    if len(symbols) != math.prod(shape):
        raise _bad(
            f"{path}.symbols", list(symbols), f"has {len(symbols)} names, not {math.prod(shape)} (shape {shape})"
        )
    return ParameterGroup(_name(_member(data, "name", path), f"{path}.name"), shape, symbols)


def _variables(value: object, field: str, at_least: int = 0) -> tuple[Variable, ...]:
    entries = _list(value, field, at_least=at_least)
    return _unique(tuple(_variable(v, f"{field}[{k}]") for k, v in enumerate(entries)), field)


def _variable(value: object, path: str) -> Variable:
    data = _object(value, path)
    kind = _text(_member(data, "kind", path), f"{path}.kind")
    if kind not in VARIABLE_KINDS:
        raise _bad(f"{path}.kind", kind, f"is not a variable kind ({', '.join(VARIABLE_KINDS)})")
    low, high = _list(_member(data, "limits", path), f"{path}.limits", 2)
    bounds = (
        -math.inf if low is None else _number(low, f"{path}.limits[0]"),
        math.inf if high is None else _number(high, f"{path}.limits[1]"),
    )
    if bounds[0] > bounds[1]:
        raise _bad(f"{path}.limits", [low, high], "is not a range (low > high)")
    home = _member(data, "home", path)
    return Variable(
        _name(_member(data, "name", path), f"{path}.name"),
        kind,
        _text(_member(data, "unit", path), f"{path}.unit"),
        None if home is None else _number(home, f"{path}.home", -MAX_MAGNITUDE, MAX_MAGNITUDE),
        bounds,
    )


def _inverse(value: object, n_actuated: int, n_passive: int, parameters: list[str]) -> Inverse | None:
    path = "capabilities.inverse"
    data = _optional_object(value, path)
    if data is None:
        return None
    branches = _names(_member(data, "branches", path), f"{path}.branches")
    validity = _names(_member(data, "validity", path), f"{path}.validity")
    groups = tuple(
        _indices(g, f"{path}.groups[{k}]", 0, len(branches) - 1)
        for k, g in enumerate(_list(_member(data, "groups", path), f"{path}.groups"))
    )

    def group_of(key: str, length: int) -> tuple[int, ...]:
        # -1: an output that no branch symbol changes
        return tuple(
            _integer(v, f"{path}.{key}[{k}]", -1, len(groups) - 1)
            for k, v in enumerate(_list(_member(data, key, path), f"{path}.{key}", length))
        )

    return Inverse(
        branches,
        _signs(_member(data, "combinations", path), f"{path}.combinations", len(branches)),
        validity,
        groups,
        group_of("actuated_groups", n_actuated),
        group_of("passive_groups", n_passive),
        group_of("validity_groups", len(validity)),
        _signs(_member(data, "patterns", path), f"{path}.patterns", len(branches)),
        _reading(data.get("reading"), validity, parameters),
    )


def _reading(value: object, validity: tuple[str, ...], parameters: list[str]) -> Reading | None:
    """``capabilities.inverse.reading`` (optional): the axis, the coordinates in words, "invalid"
    or "read", and validity names of the inverse's own."""
    path = "capabilities.inverse.reading"
    data = _optional_object(value, path)
    if data is None:
        return None
    unreachable = _member(data, "unreachable", path)
    if unreachable not in ("invalid", "read"):
        raise _bad(f"{path}.unreachable", unreachable, "is not 'invalid' or 'read'")
    reachable = _names(_member(data, "reachable", path), f"{path}.reachable")
    stray = [name for name in reachable if name not in validity]
    if stray:
        raise _bad(f"{path}.reachable", list(reachable), f"names {stray}, not validity conditions of the inverse")
    if unreachable == "read" and reachable:
        raise _bad(f"{path}.reachable", list(reachable), "is not empty, and the inverse reads every pose ('read')")
    return Reading(
        _vector_text(_member(data, "axis", path), f"{path}.axis", parameters),
        _text(_member(data, "controlled", path), f"{path}.controlled"),
        str(unreachable),
        reachable,
    )


def _legs(value: object) -> tuple[Leg, ...] | None:
    if value is None:
        return None
    path = "capabilities.legs"
    legs = []
    for k, entry in enumerate(_list(value, path, at_least=1)):
        data = _object(entry, f"{path}[{k}]")
        legs.append(
            Leg(
                _name(_member(data, "name", f"{path}[{k}]"), f"{path}[{k}].name"),
                _names(_member(data, "joints", f"{path}[{k}]"), f"{path}[{k}].joints"),
            )
        )
    return _unique(tuple(legs), path)


def _rates(value: object) -> RateModel | None:
    path = "capabilities.rates"
    data = _optional_object(value, path)
    if data is None:
        return None
    return RateModel(
        _names(_member(data, "twist", path), f"{path}.twist"),
        _names(_member(data, "input_independent", path), f"{path}.input_independent"),
        _integer(data.get("constraints", 0), f"{path}.constraints", 0, 6),
    )


def _architecture(value: object) -> Architecture | None:
    path = "capabilities.architecture"
    data = _optional_object(value, path)
    if data is None:
        return None
    return Architecture(
        _names(_member(data, "measures", path), f"{path}.measures"),
        _number(_member(data, "tolerance", path), f"{path}.tolerance", 0.0),
    )


def _statics(value: object) -> Statics | None:
    path = "capabilities.statics"
    data = _optional_object(value, path)
    if data is None:
        return None
    return Statics(_names(_member(data, "stiffness", path), f"{path}.stiffness"))


def _drawing(value: object) -> Drawing | None:
    path = "capabilities.drawing"
    data = _optional_object(value, path)
    if data is None:
        return None
    points = {
        _name(k, f"{path}.points"): _integer(v, f"{path}.points.{k}", 1)
        for k, v in _object(_member(data, "points", path), f"{path}.points").items()
    }
    polylines: dict[str, tuple[tuple[str, int], ...]] = {}
    for name, vertices in _object(_member(data, "polylines", path), f"{path}.polylines").items():
        where = f"{path}.polylines.{_name(name, f'{path}.polylines')}"
        line = []
        for k, vertex in enumerate(_list(vertices, where)):
            point_set, index = _list(vertex, f"{where}[{k}]", 2)
            if point_set not in points:
                raise _bad(f"{where}[{k}][0]", point_set, f"is not a point set of the drawing ({', '.join(points)})")
            line.append((point_set, _integer(index, f"{where}[{k}][1]", 0, points[point_set] - 1)))
        polylines[name] = tuple(line)
    parts = {
        _name(k, f"{path}.parts"): _text(v, f"{path}.parts.{k}")
        for k, v in _object(_member(data, "parts", path), f"{path}.parts").items()
    }
    if set(parts) != set(polylines) or not set(parts.values()) <= set(DRAWING_PARTS):
        raise BrokenPackageError(
            f"capabilities.drawing.parts {parts}: one of {', '.join(DRAWING_PARTS)} for each polyline "
            f"({', '.join(polylines)})"
        )
    fixed = _names(_member(data, "fixed", path), f"{path}.fixed")
    if not set(fixed) <= set(points):
        raise BrokenPackageError(f"capabilities.drawing.fixed {list(fixed)} names point sets the drawing lacks")
    return Drawing(points, polylines, parts, fixed)


def _example(value: object, path: str, n_actuated: int, n_passive: int) -> Example:
    data = _object(value, path)
    pose, actuated = _member(data, "pose", path), _member(data, "actuated", path)
    if (pose is None) == (actuated is None):
        raise _bad(path, {"pose": pose, "actuated": actuated}, "gives not exactly one of a pose and actuated values")
    branch = _member(data, "branch", path)
    expected = _object(_member(data, "expected", path), f"{path}.expected")
    checked: dict[str, Any] = dict(expected)
    if "actuated" in expected:
        checked["actuated"] = _numbers(expected["actuated"], f"{path}.expected.actuated", n_actuated)
    if "passive" in expected:
        checked["passive"] = _numbers(expected["passive"], f"{path}.expected.passive", n_passive)
    if "mode_count" in expected:
        checked["mode_count"] = _integer(expected["mode_count"], f"{path}.expected.mode_count")
    if "poses" in expected:
        checked["poses"] = [
            _matrix(p, f"{path}.expected.poses[{k}]", 4, 4).tolist()
            for k, p in enumerate(_list(expected["poses"], f"{path}.expected.poses"))
        ]
    if pose is not None:
        size = len(_list(pose, f"{path}.pose"))
        pose = _matrix(pose, f"{path}.pose", size, size).tolist() if size in (3, 4) else None
        if pose is None:
            raise _bad(f"{path}.pose", data["pose"], "is not a 4 x 4 pose or a 3 x 3 rotation")
    return Example(
        _name(_member(data, "name", path), f"{path}.name"),
        _text(_member(data, "description", path), f"{path}.description"),
        pose,
        None if actuated is None else _numbers(actuated, f"{path}.actuated", n_actuated),
        None if branch is None else _integer(branch, f"{path}.branch"),
        {
            _name(k, f"{path}.parameters"): _number(v, f"{path}.parameters.{k}", -MAX_MAGNITUDE, MAX_MAGNITUDE)
            for k, v in _object(_member(data, "parameters", path), f"{path}.parameters").items()
        },
        checked,
        _number(_member(data, "tolerance", path), f"{path}.tolerance", 0.0),
    )


def _tolerances(value: object) -> Tolerances:
    tolerances = Tolerances()
    for name, tolerance in _object(value, "tolerances").items():
        if name.endswith("_iterations"):  # a count, not a size
            tolerances[_name(name, "tolerances")] = _integer(tolerance, f"tolerances.{name}", 1, MAX_ITERATIONS)
        else:
            tolerances[_name(name, "tolerances")] = _number(tolerance, f"tolerances.{name}", 0.0)
    return tolerances


def _kernels(value: object) -> dict[str, Kernel]:
    kernels: dict[str, Kernel] = {}
    for k, entry in enumerate(_list(value, "kernels")):
        path = f"kernels[{k}]"
        data = _object(entry, path)
        name = _name(_member(data, "name", path), f"{path}.name")
        if name in kernels:
            raise _bad(f"{path}.name", name, "names a second kernel")
        inputs = []
        for j, item in enumerate(_list(_member(data, "inputs", path), f"{path}.inputs")):
            where = f"{path}.inputs[{j}]"
            item = _object(item, where)
            inputs.append(
                KernelIO(
                    _name(_member(item, "name", where), f"{where}.name"),
                    (_integer(_member(item, "size", where), f"{where}.size"),),
                )
            )
        outputs = []
        for j, item in enumerate(_list(_member(data, "outputs", path), f"{path}.outputs")):
            where = f"{path}.outputs[{j}]"
            item = _object(item, where)
            shape = tuple(
                _integer(n, f"{where}.shape[{i}]")
                for i, n in enumerate(_list(_member(item, "shape", where), f"{where}.shape"))
            )
            if len(shape) > 4 or math.prod(shape) > MAX_COUNT:
                raise _bad(
                    f"{where}.shape", list(shape), f"is not an output shape (at most 4 axes, {MAX_COUNT} values)"
                )
            outputs.append(KernelIO(_name(_member(item, "name", where), f"{where}.name"), shape))
        kernels[name] = Kernel(
            name,
            _text(_member(data, "doc", path), f"{path}.doc"),
            _integer(_member(data, "operations", path), f"{path}.operations", 0, 10**12),
            tuple(inputs),
            tuple(outputs),
            _name(_member(data, "c_symbol", path), f"{path}.c_symbol"),
        )
    return kernels


def _codes(abi: dict[str, Any], table: str) -> tuple[str, ...]:
    """A table of status code names (the index is the code): unique names, among them every name
    this parakin looks up (``ABI_NAMES_READ``)."""
    path = f"c.abi.{table}"
    names = _names(_member(abi, table, "c.abi"), path)
    if len(set(names)) != len(names):
        raise _bad(path, list(names), "names a code twice")
    missing = [n for n in ABI_NAMES_READ[table] if n not in names]
    if missing:
        raise _bad(path, list(names), f"lacks {missing}, which this parakin reads; regenerate the package")
    return names


def _job(value: object, path: str) -> tuple[tuple[str, str], ...]:
    fields = []
    for k, entry in enumerate(_list(value, path, at_least=1)):
        name, kind = _list(entry, f"{path}[{k}]", 2)
        fields.append((_name(name, f"{path}[{k}][0]"), _text(kind, f"{path}[{k}][1]")))
    return tuple(fields)


def _newton_status(names: object) -> tuple[str, ...]:
    if not isinstance(names, list) or tuple(names) != NEWTON_STATUS_NAMES:
        raise BrokenPackageError(
            f"the package's Newton status codes {_shown(names)} differ from this parakin's; regenerate it"
        )
    return NEWTON_STATUS_NAMES


def _forward_methods(value: object) -> tuple[Forward | None, dict[str, Forward]]:
    """The default method and every method, by name."""
    path = "capabilities.forward"
    data = _optional_object(value, path)
    if data is None:
        return None, {}
    entries = _object(_member(data, "methods", path), f"{path}.methods")
    if not entries:
        raise _bad(f"{path}.methods", entries, "names no method")
    methods = {
        _name(name, f"{path}.methods"): _forward(name, entry, f"{path}.methods.{name}")
        for name, entry in entries.items()
    }
    default = _member(data, "default", path)
    if not isinstance(default, str) or default not in methods:
        raise _bad(f"{path}.default", default, f"is not one of the methods ({', '.join(methods)})")
    return methods[default], methods


def _forward(method: str, value: object, path: str) -> Forward:
    data = _object(value, path)
    branches = _names(_member(data, "branches", path), f"{path}.branches")
    degree = _integer(_member(data, "degree", path), f"{path}.degree", 1)
    homotopy = _homotopy(data, path, degree) if "start" in data else None
    unknown = data.get("unknown", "")
    if homotopy is None or unknown != "":
        unknown = _name(unknown, f"{path}.unknown")
    return Forward(
        unknown,
        degree,
        branches,
        _signs(_member(data, "combinations", path), f"{path}.combinations", len(branches)),
        _names(_member(data, "degeneracies", path), f"{path}.degeneracies"),
        method,
        homotopy,
    )


def _homotopy(data: dict[str, Any], path: str, paths: int) -> Homotopy:
    """A homotopy method's data: ``paths`` start solutions of its unknowns, the sparse system's
    terms over them, the family's parameters and the root count's proof."""
    unknowns = _names(_member(data, "unknowns", path), f"{path}.unknowns")
    n = len(unknowns)
    if n == 0:
        raise _bad(f"{path}.unknowns", [], "names no unknown")
    exponents, equations = [], []
    for k, term in enumerate(_list(_member(data, "terms", path), f"{path}.terms", at_least=1)):
        equation, powers = _list(term, f"{path}.terms[{k}]", 2)
        equations.append(_integer(equation, f"{path}.terms[{k}][0]", 0, n - 1))
        exponents.append(_indices(powers, f"{path}.terms[{k}][1]", 0, 1000))
        if len(exponents[-1]) != n:
            raise _bad(
                f"{path}.terms[{k}][1]", powers, f"has {len(exponents[-1])} exponents, not one per unknown ({n})"
            )
    patch = data.get("patch_equation")
    # the family's parameters and angles as the generator prints them (expressions such as
    # 'alpha2/2', not names): shown by inspect, never used as names
    free, circles = (
        tuple(_text(v, f"{path}.{key}[{k}]") for k, v in enumerate(_list(_member(data, key, path), f"{path}.{key}")))
        for key in ("free", "circles")
    )
    constants = _list(_member(data, "circle_constants", path), f"{path}.circle_constants", 2)
    a, b = (complex(*_numbers(c, f"{path}.circle_constants[{k}]", 2)) for k, c in enumerate(constants))
    instance = len(free) + len(circles)
    return Homotopy(
        unknowns,
        _indices(_member(data, "homogeneous", path), f"{path}.homogeneous", 0, n - 1),
        _complex_matrix(_member(data, "start", path), f"{path}.start", paths, n),
        _complex_matrix(_member(data, "alternative", path), f"{path}.alternative", paths, n),
        np.array(exponents, dtype=np.int64).reshape(len(exponents), n),
        np.array(equations, dtype=np.int64),
        None if patch is None else _integer(patch, f"{path}.patch_equation", 0, n - 1),
        _root_count(_member(data, "root_count", path), f"{path}.root_count", paths),
        _integer(_member(data, "powers", path), f"{path}.powers", 1, 1000),
        free,
        circles,
        (a, b),
        _complex_vector(_member(data, "start_instance", path), f"{path}.start_instance", instance),
        _complex_vector(_member(data, "alternative_instance", path), f"{path}.alternative_instance", instance),
        *_subfamily(data.get("subfamily"), f"{path}.subfamily", instance),
        _near(data.get("near"), f"{path}.near", paths, n, instance),
    )


def _near(value: object, path: str, paths: int, n: int, instance: int) -> NearStart | None:
    """The optional ``near`` start of a homotopy (``NearStart``)."""
    if value is None:
        return None
    data = _object(value, path)
    scale = np.array(_numbers(_member(data, "scale", path), f"{path}.scale", instance))
    if not (scale > 0).all():
        raise _bad(f"{path}.scale", data["scale"], "has a value that is not positive")
    return NearStart(
        _complex_vector(_member(data, "instance", path), f"{path}.instance", instance),
        _complex_matrix(_member(data, "solutions", path), f"{path}.solutions", paths, n),
        _complex_vector(_member(data, "center", path), f"{path}.center", instance),
        scale,
        _number(_member(data, "radius", path), f"{path}.radius", 0.0),
    )


def _subfamily(value: object, path: str, instance: int) -> tuple[tuple[tuple[int, ...], ...], float, str]:
    """The optional ``subfamily`` of a homotopy: its groups of identical values (indices into the
    start instance, ``instance`` values), their tolerance and the relations in words."""
    if value is None:
        return (), 0.0, ""
    data = _object(value, path)
    groups = tuple(
        _indices(group, f"{path}.identical[{k}]", 0, instance - 1)
        for k, group in enumerate(_list(_member(data, "identical", path), f"{path}.identical"))
    )
    if any(len(group) < 2 for group in groups):
        raise _bad(f"{path}.identical", data["identical"], "has a group of fewer than two values")
    tolerance = _number(_member(data, "tolerance", path), f"{path}.tolerance", 0.0)
    return groups, tolerance, _text(data.get("relations", ""), f"{path}.relations")


def _root_count(value: object, path: str, paths: int) -> RootCount:
    data = _object(value, path)
    return RootCount(
        _integer(_member(data, "count", path), f"{path}.count", 0, paths),
        _text(_member(data, "method", path), f"{path}.method"),
        _number(_member(data, "trace_deviation", path), f"{path}.trace_deviation", 0.0),
        _number(_member(data, "tolerance", path), f"{path}.tolerance", 0.0),
        _integer(_member(data, "witnesses", path), f"{path}.witnesses", 0, 10**9),
        _flag(data.get("proven", True), f"{path}.proven"),
        _integer(data.get("bezout_paths", 0), f"{path}.bezout_paths", 0, 10**12),
        _indices(data.get("regular_endpoints", []), f"{path}.regular_endpoints", 0, 10**12),
    )


# ---------------------------------------------------------------- the joint graph
def _expression(value: object, path: str, parameters: list[str]) -> str:
    """An expression of the parameters (``parakin.packages.expression``), as text."""
    if not isinstance(value, str):
        raise _bad(path, value, "is not an expression (text)")
    try:
        used = expression.names(value)
    except BrokenPackageError as error:
        raise _bad(path, value, f"is not an allowed expression ({error})") from None
    unknown = sorted(used - set(parameters))
    if unknown:
        raise _bad(path, value, f"names {unknown}, not parameters")
    return value


def _vector_text(value: object, path: str, parameters: list[str]) -> tuple[str, str, str]:
    """Three expressions of the parameters (a point or an axis)."""
    entries = _list(value, path, 3)
    x, y, z = (_expression(e, f"{path}[{k}]", parameters) for k, e in enumerate(entries))
    return x, y, z


def _optional_vector(value: object, path: str, parameters: list[str]) -> tuple[str, str, str] | None:
    return None if value is None else _vector_text(value, path, parameters)


def _graph_joint(value: object, path: str, parameters: list[str]) -> GraphJoint:
    data = _object(value, path)
    kind = _member(data, "kind", path)
    if not isinstance(kind, str) or kind not in JOINT_KINDS:
        raise _bad(f"{path}.kind", kind, f"is not a joint kind ({', '.join(JOINT_KINDS)})")
    site = _member(data, "site", path)
    if not isinstance(site, str) or site not in JOINT_SITES:
        raise _bad(f"{path}.site", site, f"is not a joint site ({', '.join(JOINT_SITES)})")
    point = _optional_vector(_member(data, "point", path), f"{path}.point", parameters)
    axis = _optional_vector(_member(data, "axis", path), f"{path}.axis", parameters)
    if point is None and site != "elbow":
        raise _bad(f"{path}.point", None, f"is missing: a joint at the {site} has a point")
    if axis is None and kind in AXIAL_KINDS:
        raise _bad(f"{path}.axis", None, f"is missing: a {kind} joint has an axis")
    variable = _optional_name(_member(data, "variable", path), f"{path}.variable")
    actuated = _flag(_member(data, "actuated", path), f"{path}.actuated")
    if actuated and (JOINT_KINDS[kind] != 1 or variable is None):
        raise _bad(f"{path}.actuated", actuated, f"marks a {kind} joint with variable {variable}: an actuated joint "
                   "has one degree of freedom and a variable")  # fmt: skip
    limits = _member(data, "limits", path)
    if limits is not None:
        low, high = _numbers(limits, f"{path}.limits", 2)
        if not low <= high:
            raise _bad(f"{path}.limits", limits, "is not an interval (low <= high)")
        limits = (low, high)
    return GraphJoint(kind, site, point, axis, variable, actuated, limits)


def _graph_leg(value: object, path: str, parameters: list[str]) -> GraphLeg:
    data = _object(value, path)
    joints = tuple(
        _graph_joint(j, f"{path}.joints[{k}]", parameters)
        for k, j in enumerate(_list(_member(data, "joints", path), f"{path}.joints", at_least=1))
    )
    bodies = _names(_member(data, "bodies", path), f"{path}.bodies")
    if len(bodies) != len(joints) - 1:
        raise _bad(f"{path}.bodies", list(bodies), f"has {len(bodies)} names: {len(joints)} joints hold "
                   f"{len(joints) - 1} bodies")  # fmt: skip
    serial = all(j.site == "chain" for j in joints)
    if not serial and (joints[0].site != "base" or joints[-1].site != "platform"):
        raise _bad(f"{path}.joints", [j.site for j in joints], "do not run from the base to the platform (sites)")
    reach = _member(data, "reach", path)
    if reach is not None:
        reach_data = _object(reach, f"{path}.reach")
        reach = (
            _expression(_member(reach_data, "length", f"{path}.reach"), f"{path}.reach.length", parameters),
            _vector_text(_member(reach_data, "direction", f"{path}.reach"), f"{path}.reach.direction", parameters),
        )
    link = _member(data, "link", path)
    if link is not None:
        link = _expression(link, f"{path}.link", parameters)
    actuated = _flag(_member(data, "actuated", path), f"{path}.actuated")
    if actuated != any(j.actuated for j in joints):
        raise _bad(f"{path}.actuated", actuated, "disagrees with its joints' actuated marks")
    return GraphLeg(_name(_member(data, "name", path), f"{path}.name"), actuated, joints, bodies, reach, link)


def _graph_body(value: object, path: str) -> GraphBody:
    data = _object(value, path)
    inertial = _member(data, "inertial", path)
    if inertial is not None:
        where = f"{path}.inertial"
        entries = _object(inertial, where)
        inertial = GraphInertial(
            _name(_member(entries, "mass", where), f"{where}.mass"),
            _names(_list(_member(entries, "centre", where), f"{where}.centre", 3), f"{where}.centre"),
            _names(_list(_member(entries, "inertia", where), f"{where}.inertia", 9), f"{where}.inertia"),
        )
    return GraphBody(_name(_member(data, "name", path), f"{path}.name"), inertial)


def _graph_motion(value: object) -> GraphMotion | None:
    path = "joints.motion"
    data = _optional_object(value, path)
    if data is None:
        return None
    kind = _member(data, "kind", path)
    if kind is not None:
        kind = _pose_kind(kind)
    return GraphMotion(
        _integer(_member(data, "mobility", path), f"{path}.mobility", 0, 6),
        kind,
        _integer(_member(data, "translations", path), f"{path}.translations", 0, 6),
        _integer(_member(data, "rotations", path), f"{path}.rotations", 0, 6),
        _flag(_member(data, "parasitic", path), f"{path}.parasitic"),
        _integer(_member(data, "samples", path), f"{path}.samples", 0, MAX_COUNT),
        _text(_member(data, "text", path), f"{path}.text"),
    )


def _joint_graph(value: object, parameters: list[str]) -> JointGraph | None:
    """The manifest's ``joints`` (optional: None where an older package lacks it): every joint's
    kind, site, point and axis (expressions of ``parameters`` only), legs and bodies by name,
    loops naming a leg and one of its joints."""
    data = _optional_object(value, "joints")
    if data is None:
        return None
    legs = _unique(
        tuple(
            _graph_leg(leg, f"joints.legs[{k}]", parameters)
            for k, leg in enumerate(_list(_member(data, "legs", "joints"), "joints.legs", at_least=1))
        ),
        "joints.legs",
    )
    bodies = _unique(
        tuple(
            _graph_body(body, f"joints.bodies[{k}]")
            for k, body in enumerate(_list(_member(data, "bodies", "joints"), "joints.bodies"))
        ),
        "joints.bodies",
    )
    known = {body.name for body in bodies}
    for k, leg in enumerate(legs):
        missing = [name for name in leg.bodies if name not in known]
        if missing:
            raise _bad(f"joints.legs[{k}].bodies", list(leg.bodies), f"names {missing}, not bodies of joints.bodies")
    by_name = {leg.name: leg for leg in legs}
    loops = []
    for k, loop in enumerate(_list(_member(data, "loops", "joints"), "joints.loops")):
        path = f"joints.loops[{k}]"
        entry = _object(loop, path)
        leg_name = _member(entry, "leg", path)
        if not isinstance(leg_name, str) or leg_name not in by_name:
            raise _bad(f"{path}.leg", leg_name, f"is not a leg of joints.legs ({', '.join(by_name)})")
        joint = _integer(_member(entry, "joint", path), f"{path}.joint", 0, len(by_name[leg_name].joints) - 1)
        loops.append(GraphLoop(leg_name, joint))
    return JointGraph(
        _pose_kind(_member(data, "pose_kind", "joints")), bodies, legs, tuple(loops),
        _graph_motion(_member(data, "motion", "joints")),
    )  # fmt: skip


# ---------------------------------------------------------------- what fields must agree on
def _required_kernels(manifest: Manifest) -> dict[str, str]:
    """Kernel -> the capability that calls it."""
    caps = manifest.capabilities
    needed = dict.fromkeys(
        ("platform_pose", "loop_closure", "loop_closure_actuated", "singularity_factors"), "the model"
    )
    if caps.inverse is not None:
        needed["inverse_pose"] = "capabilities.inverse"
    for name, method in caps.forward_methods.items():
        if method.homotopy is None:  # back substitution, then the passive values by the inverse's patterns
            kernels = ("forward_polynomial", "forward_back_substitution", "inverse_pose_patterns")
            needed.update(dict.fromkeys(kernels, f"forward method {name!r}"))
        else:
            needed.update({f"{name}_{part}": f"forward method {name!r}" for part in ("family", "monomials", "passive")})
    for capability, kernel in (
        ("rates", "rate_jacobians"),
        ("legs", "leg_jacobians"),
        ("drawing", "drawing"),
        ("architecture", "architecture"),
    ):
        if getattr(caps, capability) is not None:
            needed[kernel] = f"capabilities.{capability}"
    return needed


def _check_agreement(manifest: Manifest) -> None:
    """Fields that must agree with each other: the kernels each capability calls exist, with the
    sizes of the variables, parameters, branches and names the manifest lists."""
    kernels = manifest.kernels
    for kernel, caller in _required_kernels(manifest).items():
        if kernel not in kernels:
            raise BrokenPackageError(
                f"field kernels: no kernel {kernel!r}, which {caller} calls; regenerate the package"
            )
    sizes = {"actuated": len(manifest.actuated), "passive": len(manifest.passive), "params": len(manifest.parameters)}
    for described in kernels.values():
        for item in described.inputs:
            if item.name in sizes and item.shape != (sizes[item.name],):
                raise BrokenPackageError(
                    f"field kernels.inputs.size: {item.shape[0]} values of {item.name!r} in kernel "
                    f"{described.name!r}, where the manifest lists {sizes[item.name]}"
                )
    outputs = {name: {o.name: o.shape for o in kernel.outputs} for name, kernel in kernels.items()}
    caps = manifest.capabilities
    expected: dict[str, dict[str, tuple[int, ...]]] = {
        "singularity_factors": {
            "factors": (len(manifest.singularity_factors),),
            "determinants": (len(manifest.determinants),),
        }
    }
    if caps.inverse is not None:
        expected["inverse_pose"] = {
            "actuated": (len(manifest.actuated),),
            "passive": (len(manifest.passive),),
            "validity": (len(caps.inverse.validity),),
        }
        if "inverse_pose_patterns" in kernels:  # one column per sign pattern
            patterns = len(caps.inverse.patterns)
            expected["inverse_pose_patterns"] = {
                name: (*shape, patterns) for name, shape in expected["inverse_pose"].items()
            }
    if caps.architecture is not None:
        expected["architecture"] = {"measures": (len(caps.architecture.measures),)}
    if caps.drawing is not None:
        expected["drawing"] = {name: (3, count) for name, count in caps.drawing.points.items()}
    for kernel, shapes in expected.items():
        got = outputs[kernel]
        for name, shape in shapes.items():
            # a kernel writes a one-element axis as no axis: (3, 1) as (3,), (1,) as ()
            if name not in got or [n for n in got[name] if n != 1] != [n for n in shape if n != 1]:
                raise BrokenPackageError(
                    f"field kernels.outputs: kernel {kernel!r} has no output {name!r} of shape {shape} "
                    f"(outputs {got}), which the manifest's names call for"
                )
    variables = {v.name for v in (*manifest.actuated, *manifest.passive)}
    parameters = {p.name for p in manifest.parameters}
    references = [
        *(
            (f"capabilities.legs[{k}].joints", leg.joints, variables, "variable")
            for k, leg in enumerate(caps.legs or ())
        ),
        *(
            (f"parameter_groups[{k}].symbols", group.symbols, parameters, "parameter")
            for k, group in enumerate(manifest.parameter_groups)
        ),
        *(
            (f"examples[{k}].parameters", tuple(example.parameters), set(manifest.parameter_names), "parameter")
            for k, example in enumerate(manifest.examples)
        ),
    ]
    if caps.rates is not None:  # factors that vanish for every input where the platform folds
        factors = set(manifest.singularity_factors)
        references.append(("capabilities.rates.input_independent", caps.rates.input_independent, factors, "factor"))
    if caps.statics is not None:
        references.append(("capabilities.statics.stiffness", caps.statics.stiffness, parameters, "parameter"))
    for path, names, known, kind in references:
        unknown = [name for name in names if name not in known]
        if unknown:
            raise _bad(path, list(names), f"names {unknown}, not {kind}s of the manifest")
    elimination = [name for name, method in caps.forward_methods.items() if method.homotopy is None]
    if elimination and caps.inverse is None:
        raise BrokenPackageError(
            f"field capabilities.inverse: null, but the forward method {elimination[0]!r} finds the passive values "
            "of its poses by the inverse; regenerate the package"
        )
    newton = manifest.newton
    if (newton.unknowns, newton.actuated) != (len(manifest.passive), len(manifest.actuated)):
        raise BrokenPackageError(
            f"field c.newton: {newton.unknowns} unknowns and {newton.actuated} actuated values, where the manifest "
            f"lists {len(manifest.passive)} passive and {len(manifest.actuated)} actuated variables"
        )
    if manifest.joints is not None:  # each actuated joint carries one actuated variable, once
        carried = [str(j.variable) for leg in manifest.joints.legs for j in leg.joints if j.actuated]
        actuated_names = manifest.actuated_names
        unknown = [name for name in carried if name not in actuated_names]
        twice = sorted({name for name in carried if carried.count(name) > 1})
        if unknown or twice:
            raise _bad("joints.legs.joints.variable", carried, f"names {unknown or twice}: each actuated joint "
                       f"carries one actuated variable ({', '.join(actuated_names)}), each once")  # fmt: skip
        if manifest.joints.pose_kind != manifest.pose_kind:
            raise _bad("joints.pose_kind", manifest.joints.pose_kind, f"differs from pose_kind {manifest.pose_kind!r}")
    if caps.inverse is not None:
        branches = len(caps.inverse.combinations)
        for k, example in enumerate(manifest.examples):
            if example.branch is not None and example.branch >= branches:
                raise _bad(f"examples[{k}].branch", example.branch, f"is not an inverse branch (0 to {branches - 1})")


__all__ = [
    "Capabilities",
    "Citation",
    "Example",
    "GraphBody",
    "GraphJoint",
    "GraphLeg",
    "GraphLoop",
    "GraphMotion",
    "JointGraph",
    "Kernel",
    "Manifest",
    "Parameter",
    "Variable",
    "unknown_name",
]
