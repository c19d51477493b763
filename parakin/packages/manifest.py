"""Typed view of a generated package's ``manifest.json`` (schema 2).

The runtime reads mechanisms only through these objects: which kernels exist and their shapes,
which capabilities a mechanism has, its variables with units and limits, its examples. A feature
that a mechanism lacks is a ``None`` capability here, never a test of its name.

A manifest is untrusted text until read: every name in it (mechanism, parameters, variables,
kernels, C symbols, ...) must be a Python identifier, because names become file names, module
names and C symbols; every file entry (``c.sources``, ``c.headers``, ``c.header``) must be a plain
file name inside the package folder. Anything else is a BadInputError naming the field.
"""

from __future__ import annotations

import difflib
import json
import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from parakin.errors import NEWTON_STATUS_NAMES, BadInputError
from parakin.pose import POSE_KINDS

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
    tolerances: dict[str, float]
    kernels: dict[str, Kernel]
    c_sources: tuple[str, ...]
    c_header: str
    c_headers: tuple[str, ...]
    newton: Newton
    abi: Abi

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
        """Read and check ``path`` (a manifest.json): every name an identifier, every file
        entry a plain file name that resolves inside the package folder."""
        path = Path(path)
        try:
            data = json.loads(path.read_text())
        except (OSError, ValueError) as error:
            raise BadInputError(f"cannot read the manifest {path}: {error}") from error
        try:
            manifest = cls.from_dict(data)
        except BadInputError as error:
            raise BadInputError(f"manifest {path}: {error}") from error
        folder = path.parent.resolve()
        for name in manifest.files:
            if not (folder / name).resolve().is_relative_to(folder):  # a symbolic link out of the folder
                raise BadInputError(f"manifest {path}: file {name!r} resolves outside the package folder {folder}")
        return manifest

    @classmethod
    def from_dict(cls, data: object) -> Manifest:
        """The typed manifest of a parsed manifest.json, or BadInputError naming the field that
        is missing, of the wrong type, or not a valid name or file name."""
        if not isinstance(data, dict):
            raise BadInputError(f"a manifest is a JSON object, got {type(data).__name__}")
        schema = data.get("schema")
        if schema != SUPPORTED_SCHEMA:
            raise BadInputError(
                f"manifest schema {schema!r} is not supported by this parakin (schema {SUPPORTED_SCHEMA}); regenerate"
            )
        try:
            return cls._from_dict(data)
        except BadInputError:
            raise
        except KeyError as error:
            raise BadInputError(f"malformed manifest: field {error} is missing; regenerate the package") from error
        except (TypeError, ValueError, AttributeError, IndexError) as error:
            raise BadInputError(
                f"malformed manifest ({type(error).__name__}: {error}); regenerate the package"
            ) from error

    @classmethod
    def _from_dict(cls, data: dict[str, Any]) -> Manifest:
        caps = data["capabilities"]
        forward, forward_methods = _forward_methods(caps["forward"])
        c = data["c"]
        return cls(
            schema=data["schema"],
            name=_name(data["name"], "name"),
            title=str(data["title"]),
            citation=Citation(
                tuple(data["citation"]["authors"]),
                data["citation"]["title"],
                data["citation"]["year"],
                data["citation"]["venue"],
                data["citation"]["doi"],
            ),
            conventions=data["conventions"],
            generator_version=data["generator"]["version"],
            source=data["generator"]["source"],
            pose_kind=_pose_kind(data["pose_kind"]),
            parameters=tuple(_parameter(p) for p in data["parameters"]),
            parameter_groups=tuple(
                ParameterGroup(
                    _name(g["name"], "parameter_groups.name"),
                    tuple(int(n) for n in g["shape"]),
                    _names(g["symbols"], "parameter_groups.symbols"),
                )
                for g in data["parameter_groups"]
            ),
            actuated=tuple(_variable(v, "actuated") for v in data["actuated"]),
            passive=tuple(_variable(v, "passive") for v in data["passive"]),
            singularity_factors=_names(data["singularity_factors"], "singularity_factors"),
            determinants=_names(data["determinants"], "determinants"),
            capabilities=Capabilities(
                inverse=_inverse(caps["inverse"]),
                forward=forward,
                forward_methods=forward_methods,
                legs=tuple(
                    Leg(_name(g["name"], "capabilities.legs.name"), _names(g["joints"], "capabilities.legs.joints"))
                    for g in caps["legs"]
                )
                if caps["legs"]
                else None,
                rates=RateModel(
                    _names(caps["rates"]["twist"], "capabilities.rates.twist"),
                    _names(caps["rates"]["input_independent"], "capabilities.rates.input_independent"),
                    int(caps["rates"].get("constraints", 0)),
                )
                if caps["rates"]
                else None,
                architecture=Architecture(
                    _names(caps["architecture"]["measures"], "capabilities.architecture.measures"),
                    float(caps["architecture"]["tolerance"]),
                )
                if caps["architecture"]
                else None,
                drawing=_drawing(caps["drawing"]) if caps["drawing"] else None,
                statics=Statics(_names(caps["statics"]["stiffness"], "capabilities.statics.stiffness"))
                if caps["statics"]
                else None,
            ),
            examples=tuple(
                Example(
                    _name(e["name"], "examples.name"),
                    e["description"],
                    e["pose"],
                    tuple(e["actuated"]) if e["actuated"] is not None else None,
                    e["branch"],
                    dict(e["parameters"]),
                    dict(e["expected"]),
                    float(e["tolerance"]),
                )
                for e in data["examples"]
            ),
            tolerances={_name(k, "tolerances"): v for k, v in dict(data["tolerances"]).items()},
            kernels={
                k["name"]: Kernel(
                    _name(k["name"], "kernels.name"),
                    k["doc"],
                    int(k["operations"]),
                    tuple(KernelIO(_name(i["name"], "kernels.inputs.name"), (int(i["size"]),)) for i in k["inputs"]),
                    tuple(KernelIO(_name(o["name"], "kernels.outputs.name"), tuple(o["shape"])) for o in k["outputs"]),
                    _name(k["c_symbol"], "kernels.c_symbol"),
                )
                for k in data["kernels"]
            },
            c_sources=tuple(_file_name(f, "c.sources") for f in c["sources"]),
            c_header=_file_name(c["header"], "c.header"),
            c_headers=tuple(_file_name(f, "c.headers") for f in c["headers"]),
            newton=Newton(
                _name(c["newton"]["symbol"], "c.newton.symbol"), c["newton"]["unknowns"], c["newton"]["actuated"]
            ),
            abi=Abi(
                _newton_status(c["abi"]["newton_status"]),
                _names(c["abi"]["mode_outcomes"], "c.abi.mode_outcomes"),
                _names(c["abi"]["input_status"], "c.abi.input_status"),
                _names(c["abi"]["root_kinds"], "c.abi.root_kinds"),
                tuple((_name(n, "c.abi.newton_job"), str(t)) for n, t in c["abi"]["newton_job"]),
                tuple((_name(n, "c.abi.modes_job"), str(t)) for n, t in c["abi"]["modes_job"]),
                _optional_name((c.get("modes") or {}).get("symbol"), "c.modes.symbol"),
            ),
        )


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


def _name(value: object, field: str) -> str:
    """A name from the manifest: a Python identifier (names become module names, file names
    and C symbols, so nothing else may pass)."""
    if not (isinstance(value, str) and value.isidentifier() and value.isascii()):
        raise BadInputError(f"field {field}: {value!r} is not a name (an ASCII Python identifier)")
    return value


def _names(values: Iterable[object], field: str) -> tuple[str, ...]:
    if isinstance(values, str | bytes):
        raise BadInputError(f"field {field}: {values!r} is not a list of names")
    return tuple(_name(v, field) for v in values)


def _optional_name(value: object, field: str) -> str | None:
    return None if value is None else _name(value, field)


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
        raise BadInputError(f"field {field}: {value!r} is not a plain file name inside the package folder")
    return value


def _pose_kind(value: object) -> str:
    if value not in POSE_KINDS:
        raise BadInputError(f"field pose_kind: {value!r} is not a pose kind of this parakin ({sorted(POSE_KINDS)})")
    return str(value)


def _parameter(data: dict[str, Any]) -> Parameter:
    return Parameter(
        _name(data["name"], "parameters.name"),
        float(data["default"]),
        str(data["unit"]),
        str(data["description"]),
        str(data.get("domain", "real")),
    )


def _drawing(data: dict[str, Any]) -> Drawing:
    points = {_name(k, "capabilities.drawing.points"): int(v) for k, v in dict(data["points"]).items()}
    polylines = {
        _name(k, "capabilities.drawing.polylines"): tuple(
            (_name(s, "capabilities.drawing.polylines"), int(i)) for s, i in v
        )
        for k, v in dict(data["polylines"]).items()
    }
    parts = {_name(k, "capabilities.drawing.parts"): str(v) for k, v in dict(data["parts"]).items()}
    if set(parts) != set(polylines) or not set(parts.values()) <= set(DRAWING_PARTS):
        raise BadInputError(
            f"capabilities.drawing.parts {parts}: one of {', '.join(DRAWING_PARTS)} for each polyline "
            f"({', '.join(polylines)})"
        )
    fixed = tuple(_name(k, "capabilities.drawing.fixed") for k in data["fixed"])
    if not set(fixed) <= set(points):
        raise BadInputError(f"capabilities.drawing.fixed {list(fixed)} names point sets the drawing lacks")
    return Drawing(points, polylines, parts, fixed)


def _newton_status(names: list[str]) -> tuple[str, ...]:
    if tuple(names) != NEWTON_STATUS_NAMES:
        raise BadInputError(f"the package's Newton status codes {names} differ from this parakin's; regenerate it")
    return tuple(names)


def _limit(value: float | None, default: float) -> float:
    return default if value is None else float(value)


def _variable(data: dict[str, Any], field: str) -> Variable:
    low, high = data["limits"]
    return Variable(
        _name(data["name"], f"{field}.name"),
        str(data["kind"]),
        str(data["unit"]),
        data["home"],
        (_limit(low, -math.inf), _limit(high, math.inf)),
    )


def _inverse(data: dict[str, Any] | None) -> Inverse | None:
    if not data:
        return None
    return Inverse(
        _names(data["branches"], "capabilities.inverse.branches"),
        tuple(tuple(c) for c in data["combinations"]),
        _names(data["validity"], "capabilities.inverse.validity"),
        tuple(tuple(g) for g in data.get("groups", ())),
        tuple(data.get("actuated_groups", ())),
        tuple(data.get("passive_groups", ())),
        tuple(data.get("validity_groups", ())),
        tuple(tuple(s) for s in data.get("patterns", ())),
    )


def _forward_methods(data: dict[str, Any] | None) -> tuple[Forward | None, dict[str, Forward]]:
    """The default method and every method, by name."""
    if not data:
        return None, {}
    methods = {name: _forward(name, entry) for name, entry in dict(data["methods"]).items()}
    return methods[str(data["default"])], methods


def _forward(method: str, data: dict[str, Any]) -> Forward:
    homotopy = None
    if "start" in data:
        start, alternative = (
            np.array(data[key]["real"], dtype=float) + 1j * np.array(data[key]["imag"], dtype=float)
            for key in ("start", "alternative")
        )
        terms = data["terms"]
        proof = data["root_count"]
        instances = (
            np.array(data[key]["real"], dtype=float) + 1j * np.array(data[key]["imag"], dtype=float)
            for key in ("start_instance", "alternative_instance")
        )
        homotopy = Homotopy(
            _names(data["unknowns"], "capabilities.forward.unknowns"),
            tuple(data["homogeneous"]),
            start,
            alternative,
            np.array([e for _, e in terms], dtype=np.int64).reshape(len(terms), -1),
            np.array([k for k, _ in terms], dtype=np.int64),
            data.get("patch_equation"),
            RootCount(
                int(proof["count"]),
                str(proof["method"]),
                float(proof["trace_deviation"]),
                float(proof["tolerance"]),
                int(proof["witnesses"]),
                bool(proof.get("proven", True)),
                int(proof.get("bezout_paths", 0)),
                tuple(int(k) for k in proof.get("regular_endpoints", ())),
            ),
            int(data["powers"]),
            tuple(str(v) for v in data["free"]),
            tuple(str(v) for v in data["circles"]),
            (complex(*data["circle_constants"][0]), complex(*data["circle_constants"][1])),
            *instances,
        )
    unknown = data.get("unknown", "")
    return Forward(
        unknown and _name(unknown, "capabilities.forward.unknown"),
        int(data["degree"]),
        _names(data["branches"], "capabilities.forward.branches"),
        tuple(tuple(c) for c in data["combinations"]),
        _names(data["degeneracies"], "capabilities.forward.degeneracies"),
        method,
        homotopy,
    )


__all__ = ["Manifest", "Variable", "Kernel", "Example", "Capabilities", "Citation", "Parameter", "unknown_name"]
