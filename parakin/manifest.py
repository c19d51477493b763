"""Typed view of a generated package's ``manifest.json`` (schema 1).

The runtime reads mechanisms only through these objects: which kernels exist and their shapes,
which capabilities a mechanism has, its variables with units and limits, its examples. A feature
that a mechanism lacks is a ``None`` capability here, never a test of its name.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from parakin.errors import NEWTON_STATUS_NAMES, BadInputError

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


@dataclass(frozen=True)
class Forward:
    """Every assembly mode: a univariate polynomial in ``unknown`` of ``degree`` (method
    "polynomial"), or a parameter homotopy with ``degree`` paths (method "homotopy")."""

    unknown: str
    degree: int
    branches: tuple[str, ...]
    combinations: tuple[tuple[int, ...], ...]
    degeneracies: tuple[str, ...]
    method: str = "polynomial"
    homotopy: Homotopy | None = None


@dataclass(frozen=True)
class Leg:
    name: str
    joints: tuple[str, ...]


@dataclass(frozen=True)
class RateModel:
    """A twist = B actuated_rates, twist components named ``twist``."""

    twist: tuple[str, ...]
    input_independent: tuple[str, ...]


@dataclass(frozen=True)
class Architecture:
    measures: tuple[str, ...]
    tolerance: float


@dataclass(frozen=True)
class Drawing:
    """Point sets (name -> number of points) and polylines of (point set, index) pairs."""

    points: dict[str, int]
    polylines: dict[str, tuple[tuple[str, int], ...]]


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


@dataclass(frozen=True)
class Newton:
    """The C Newton driver's layout (shared with ``parakin.compiled``)."""

    symbol: str
    unknowns: int
    actuated: int


@dataclass(frozen=True)
class Abi:
    """The C ABI as the generator wrote it: status code names (their index is the code) and
    the fields (name, type) of the job structures that ``parakin.compiled`` binds."""

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

    @classmethod
    def read(cls, path: Path) -> Manifest:
        """Read and check ``path`` (a manifest.json)."""
        try:
            data = json.loads(Path(path).read_text())
        except (OSError, ValueError) as error:
            raise BadInputError(f"cannot read the manifest {path}: {error}") from error
        return cls.from_dict(data)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> Manifest:
        schema = data.get("schema")
        if schema != SUPPORTED_SCHEMA:
            raise BadInputError(
                f"manifest schema {schema!r} is not supported by this parakin (schema {SUPPORTED_SCHEMA}); regenerate"
            )
        caps = data["capabilities"]
        c = data["c"]
        return cls(
            schema=schema,
            name=data["name"],
            title=data["title"],
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
            pose_kind=data["pose_kind"],
            parameters=tuple(Parameter(**p) for p in data["parameters"]),
            parameter_groups=tuple(
                ParameterGroup(g["name"], tuple(g["shape"]), tuple(g["symbols"])) for g in data["parameter_groups"]
            ),
            actuated=tuple(_variable(v) for v in data["actuated"]),
            passive=tuple(_variable(v) for v in data["passive"]),
            singularity_factors=tuple(data["singularity_factors"]),
            determinants=tuple(data["determinants"]),
            capabilities=Capabilities(
                inverse=_inverse(caps["inverse"]),
                forward=_forward(caps["forward"]),
                legs=tuple(Leg(g["name"], tuple(g["joints"])) for g in caps["legs"]) if caps["legs"] else None,
                rates=RateModel(tuple(caps["rates"]["twist"]), tuple(caps["rates"]["input_independent"]))
                if caps["rates"]
                else None,
                architecture=Architecture(tuple(caps["architecture"]["measures"]), caps["architecture"]["tolerance"])
                if caps["architecture"]
                else None,
                drawing=Drawing(
                    dict(caps["drawing"]["points"]),
                    {k: tuple((s, int(i)) for s, i in v) for k, v in caps["drawing"]["polylines"].items()},
                )
                if caps["drawing"]
                else None,
                statics=Statics(tuple(caps["statics"]["stiffness"])) if caps["statics"] else None,
            ),
            examples=tuple(
                Example(
                    e["name"],
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
            tolerances=dict(data["tolerances"]),
            kernels={
                k["name"]: Kernel(
                    k["name"],
                    k["doc"],
                    int(k["operations"]),
                    tuple(KernelIO(i["name"], (int(i["size"]),)) for i in k["inputs"]),
                    tuple(KernelIO(o["name"], tuple(o["shape"])) for o in k["outputs"]),
                    k["c_symbol"],
                )
                for k in data["kernels"]
            },
            c_sources=tuple(c["sources"]),
            c_header=c["header"],
            c_headers=tuple(c["headers"]),
            newton=Newton(c["newton"]["symbol"], c["newton"]["unknowns"], c["newton"]["actuated"]),
            abi=Abi(
                _newton_status(c["abi"]["newton_status"]),
                tuple(c["abi"]["mode_outcomes"]),
                tuple(c["abi"]["input_status"]),
                tuple(c["abi"]["root_kinds"]),
                tuple((str(n), str(t)) for n, t in c["abi"]["newton_job"]),
                tuple((str(n), str(t)) for n, t in c["abi"]["modes_job"]),
                (c.get("modes") or {}).get("symbol"),
            ),
        )


def _newton_status(names: list[str]) -> tuple[str, ...]:
    if tuple(names) != NEWTON_STATUS_NAMES:
        raise BadInputError(f"the package's Newton status codes {names} differ from this parakin's; regenerate it")
    return tuple(names)


def _limit(value: float | None, default: float) -> float:
    return default if value is None else float(value)


def _variable(data: dict[str, Any]) -> Variable:
    low, high = data["limits"]
    return Variable(
        data["name"], data["kind"], data["unit"], data["home"], (_limit(low, -math.inf), _limit(high, math.inf))
    )


def _inverse(data: dict[str, Any] | None) -> Inverse | None:
    if not data:
        return None
    return Inverse(
        tuple(data["branches"]),
        tuple(tuple(c) for c in data["combinations"]),
        tuple(data["validity"]),
        tuple(tuple(g) for g in data.get("groups", ())),
        tuple(data.get("actuated_groups", ())),
        tuple(data.get("passive_groups", ())),
        tuple(data.get("validity_groups", ())),
        tuple(tuple(s) for s in data.get("patterns", ())),
    )


def _forward(data: dict[str, Any] | None) -> Forward | None:
    if not data:
        return None
    homotopy = None
    if data.get("method") == "homotopy":
        start, alternative = (
            np.array(data[key]["real"], dtype=float) + 1j * np.array(data[key]["imag"], dtype=float)
            for key in ("start", "alternative")
        )
        homotopy = Homotopy(tuple(data["unknowns"]), tuple(data["homogeneous"]), start, alternative)
    return Forward(
        data.get("unknown", ""),
        int(data["degree"]),
        tuple(data["branches"]),
        tuple(tuple(c) for c in data["combinations"]),
        tuple(data["degeneracies"]),
        data.get("method", "polynomial"),
        homotopy,
    )


__all__ = ["Manifest", "Variable", "Kernel", "Example", "Capabilities", "Citation", "Parameter"]
