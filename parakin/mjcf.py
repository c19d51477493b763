"""A mechanism as a MuJoCo model (MJCF) with its loops closed and every assembly mode a keyframe.

``to_mjcf(m)`` writes the MJCF text of a loaded mechanism from its joint graph (the manifest's
``joints``: legs of joints from the base to the platform), generically over mechanisms:

* **Tree and cuts.** Each leg is a serial chain of bodies hanging from the world (the base {B}
  is MuJoCo's world frame), one body per link of the graph (named as the graph names them,
  ``leg1_link1``...), carried by its joint: R a hinge, P a slide (along the leg's line A -> C
  where the graph gives no axis), C a hinge and a slide, U two hinges (the first axis fixed to
  the body before), S a ball, planar two slides and a hinge. The platform is a free body
  (``platform``, a free joint of that name) unless a leg ends rigidly in it (kind F: the
  platform then ends that leg) or every leg meets it at one point (a point has no orientation:
  the platform then ends the first leg). Every other leg is cut where it meets the platform, by
  ``<connect site1=... site2=...>`` (never the ``anchor`` form): a spherical joint by one
  connect, a revolute joint by two along its axis (``{leg}_cut``, ``{leg}_cut_axis``), a
  universal joint by a cross body (``{leg}_cross``, a point of ``link_mass``) hinged to the leg's
  last link about its first axis and cut as a revolute joint about its second (fixed in the
  platform: the graph's axis, or both axes normal to the link at the home), a cylindrical or
  prismatic joint by a slider body (``{leg}_slider``) along its axis, cut as a revolute joint (C)
  or rigidly by three connects (P). A planar joint at the platform is refused
  (UnsupportedOperationError).
* **Serial chains** (a leg whose joints sit at site "chain", placed by products of exponentials
  from their screws at the chain's zero): R and P joints only, each body at its joint's home
  point and axis (the exponentials of the joints before it at their home values), the chain cut
  from a free platform at its last joint, a revolute one (two connects along its axis).
* **Parallelograms** (kind Pa) are four bars, not one: the short side at the elbow (on the body
  before), two bars hinged to it about the normal of the parallelogram's plane, and the short
  side at the platform (the graph's body) hinged to the first bar; the second bar is cut from it
  by two connects along the hinge axis. Its short sides are ``PARALLELOGRAM_WIDTH`` times the
  bars' length (the kinematics do not depend on it).
* **Idle spins removed.** A link between two spherical joints (S-S, or S-P-S along the line)
  spins about itself without moving anything else; its first S is exported as a U (axes normal
  to the link at the home), so that MuJoCo's mobility nv - rank(J_c) is the mechanism's.
* **Joint values.** The bodies are laid out at the home configuration (polished by
  ``forward_pose``). An actuated hinge or slide is named after its actuated variable and its
  position is that variable's value (same origin, sign and unit: its ``ref`` is the home value);
  every passive joint is 0 (a ball the identity) at the home. qpos0 is the home.
* **Assembly modes.** One ``<key name="mode{k}">`` per real assembly mode k of the chosen
  actuated values (``m.forward_pose_all(actuated).mode(k)``; default: the home values), with
  ``ctrl`` the actuated values: the platform placed at the mode's pose and every leg's passive
  joints solved by Newton (from the home) so that each cut closes (residual <= 1e-12 m).
* **Near-singular modes.** A keyframe whose mode is near a type II (parallel) singularity, its
  ``type II`` distance (``parakin.singularity.type_ii_distance``: 1/cond of the closure Jacobian
  d closure / d passive, the measure ``parakin plot`` labels and ``parakin sweep`` maps) below
  ``parakin.singularity.NEAR_SINGULAR`` (0.02), carries an XML comment with the measure and what
  it means, and ``to_mjcf`` warns once (``parakin.errors.NearSingularModeWarning``, one
  ``parakin: warning:`` line from ``parakin mjcf``): there the actuators barely hold the
  platform, which a small load moves far, so the simulation may drift or not come to rest. The
  header's qpos0 line names the keyframe that is the home and says so too where the home is
  near-singular.
* **Simulation presets** (``accuracy``): "fast", 1 ms steps and connects of time constant two
  steps (``solref``), ``implicitfast``; "accurate", 0.2 ms and a stiff ``solimp`` (0.99 0.999).
  The gap the loops open under load depends on the model (masses, servos, geometry), so the
  file's header gives no figure for it; measured on a regular Stewart platform with 1 kg links
  under 10 kg: about 0.03 mm / 0.003 deg fast, 0.1 um / 1e-5 deg accurate; lighter links open
  wider gaps: 0.18 mm / 0.015 deg fast with 0.1 kg links (``PRESETS``). Gravity is -9.80665 m/s^2 along -z, or
  along -y for a planar mechanism (its motion is in z = 0). No contacts (every geom has
  ``contype`` and ``conaffinity`` 0).
* **Inertia** (documented defaults, the graph carries no values yet): every link a uniform thin
  rod of ``link_mass`` kg along its segment (or, ``link_mass`` a mapping, each body its own mass
  or ``RigidInertia``: the forms of ``parakin.dynamics``' ``leg_inertias``, one robot in both) (a body of no length: a point of that mass with a
  radius of gyration of 1 cm), the platform ``platform_mass`` kg with the inertia of a solid
  sphere of radius ``platform_radius`` about its origin, and a separate body ``payload`` fixed
  at the platform's origin with ``payload`` kg (none when 0).
* **Actuators**: "position" servos (``kp``; damping ``kv`` = kp / 50) or "motor"s, named after
  the actuated variables, on the actuated joints.

Example
-------
>>> import parakin
>>> from parakin.mjcf import to_mjcf
>>> m = parakin.load("five_bar")
>>> xml = to_mjcf(m)  # every assembly mode of the home actuated values a keyframe
>>> import mujoco
>>> model = mujoco.MjModel.from_xml_string(xml)
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from parakin.errors import (
    BadInputError,
    ConvergenceError,
    NearSingularModeWarning,
    SingularConfigurationError,
    UnsupportedOperationError,
)
from parakin.packages.expression import evaluate
from parakin.packages.manifest import GraphJoint, GraphLeg, JointGraph
from parakin.pose import axis_rotation
from parakin.results import Configuration
from parakin.singularity import NEAR_SINGULAR, type_ii_distance

if TYPE_CHECKING:
    from parakin.solvers.loaded import LoadedMechanism as Mechanism

#: the short sides of a parallelogram, relative to its bars' length
PARALLELOGRAM_WIDTH = 0.2
#: the two sites of a revolute cut lie this far apart along its axis, relative to the
#: mechanism's size (the largest distance of a joint from the base origin at the home)
AXIS_SPACING = 0.1
#: the loop residual (m) a keyframe's Newton solve reaches
KEY_TOLERANCE = 1e-12
#: the random starts a keyframe's leg gets where Newton from the home does not close it, and
#: their seed (the export is deterministic)
KEY_STARTS = 200
KEY_SEED = 20261128
#: MuJoCo's default solimp (the "fast" preset keeps it)
DEFAULT_SOLIMP = (0.9, 0.95, 0.001, 0.5, 2.0)
#: gravity (m/s^2): standard gravity, as ``parakin.dynamics.STANDARD_GRAVITY`` (the exported
#: model and ``inverse_dynamics`` with its default gravity describe one robot)
GRAVITY = 9.80665
PLANAR_KINDS = ("planar", "planar_translation")
#: a link mass (kg) for every link, or body name -> mass or rigid body (``to_mjcf``'s link_mass)
LinkMass = float | Mapping[str, Any]


@dataclass(frozen=True)
class Preset:
    """A simulation preset: the timestep (s), the connects' solimp, the integrator, and the loop
    gap measured under load (text for the file's header)."""

    timestep: float
    solimp: tuple[float, ...]
    integrator: str
    gap: str


#: ``accuracy`` presets; the gaps measured (tests/test_mjcf.py) on the exported regular 6-UPS
#: Stewart platform (0.5 m / 0.3 m joint circles, 0.6 m high) with 1 kg links and 10 kg payload,
#: settled 1 s on its servos: pose against forward_pose at the settled leg lengths
PRESETS = {
    "fast": Preset(
        1e-3, DEFAULT_SOLIMP, "implicitfast", "about 0.03 mm and 0.003 deg (a 10 kg load on a 0.6 m Stewart platform)"
    ),
    "accurate": Preset(
        2e-4, (0.99, 0.999, 0.001, 0.5, 2.0), "implicitfast",
        "about 0.1 um and 1e-5 deg (a 10 kg load on a 0.6 m Stewart platform)",
    ),
}  # fmt: skip


@dataclass
class _Joint:
    name: str
    kind: str  # hinge, slide, ball, free
    axis: np.ndarray | None = None  # world, at the home
    ref: float = 0.0
    actuated: bool = False


@dataclass
class _Body:
    name: str
    parent: str | None  # None: the world
    position: np.ndarray  # frame origin, world, at the home
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))  # frame, world, at the home
    joints: list[_Joint] = field(default_factory=list)
    sites: list[tuple[str, np.ndarray]] = field(default_factory=list)  # world positions
    segments: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)  # geoms, world
    mass: float = 0.0
    centre: np.ndarray | None = None  # world
    inertia: np.ndarray | None = None  # about the centre, world axes
    comment: str = ""


@dataclass
class _Model:
    bodies: list[_Body] = field(default_factory=list)
    connects: list[tuple[str, str, str]] = field(default_factory=list)  # name, site1, site2
    notes: list[str] = field(default_factory=list)

    def body(self, name: str) -> _Body:
        return next(b for b in self.bodies if b.name == name)


def _unit(vector: np.ndarray, what: str) -> np.ndarray:
    norm = float(np.linalg.norm(vector))
    if not norm > 1e-12:
        raise BadInputError(f"{what} has zero length at the home configuration")
    return vector / norm


def _normal(direction: np.ndarray) -> np.ndarray:
    """A unit vector normal to the unit ``direction``."""
    other = np.eye(3)[int(np.argmin(np.abs(direction)))]
    return _unit(np.cross(direction, other), "a normal")


def _rod(mass: float, start: np.ndarray, end: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centre and inertia (about it) of a uniform thin rod, or of a point of 1 cm gyration."""
    span = end - start
    length = float(np.linalg.norm(span))
    inertia = mass * 1e-4 * np.eye(3)
    if length > 1e-9:
        d = span / length
        inertia = inertia + mass * length**2 / 12 * (np.eye(3) - np.outer(d, d))
    return (start + end) / 2, inertia


class _Geometry:
    """The graph's expressions evaluated at the mechanism's parameters and home."""

    def __init__(self, m: Mechanism, graph: JointGraph, actuated: np.ndarray, passive: np.ndarray) -> None:
        self.values = {name: float(v) for name, v in m.parameters.items()}
        self.joint_values = {
            **dict(zip(m.actuated_names, actuated.tolist(), strict=True)),
            **dict(zip(m.passive_names, passive.tolist(), strict=True)),
        }
        pose = np.asarray(m.platform_pose(actuated, passive), dtype=float)
        self.rotation, self.origin = pose[:3, :3], pose[:3, 3]

    def configuration(self, m: Mechanism) -> Configuration:
        """The configuration the bodies are laid out at (qpos0)."""
        actuated = np.array([self.joint_values[name] for name in m.actuated_names])
        passive = np.array([self.joint_values[name] for name in m.passive_names])
        pose = np.eye(4)
        pose[:3, :3], pose[:3, 3] = self.rotation, self.origin
        return Configuration(actuated, passive, pose)

    def scalar(self, text: str) -> float:
        return evaluate(text, self.values)

    def vector(self, texts: Sequence[str] | None, what: str) -> np.ndarray:
        if texts is None:
            raise BadInputError(f"{what} has no point or axis in the joint graph")
        return np.array([self.scalar(t) for t in texts], dtype=float)

    def variable(self, joint: GraphJoint, leg: str) -> float:
        if joint.variable is None or joint.variable not in self.joint_values:
            raise UnsupportedOperationError(
                f"leg {leg}: its first joint ({joint.kind}) moves the elbow but carries no variable of the "
                f"mechanism ({joint.variable!r}): the elbow cannot be placed"
            )
        return self.joint_values[joint.variable]


@dataclass
class _Leg:
    """A leg's sites at the home, in {B}: A, E (None: no elbow), C, and the first body's turn."""

    base: np.ndarray
    elbow: np.ndarray | None
    end: np.ndarray
    carried: np.ndarray


def _place(leg: GraphLeg, geometry: _Geometry) -> _Leg:
    first = leg.joints[0]
    base = geometry.vector(first.point, f"leg {leg.name}'s base joint")
    local = geometry.vector(leg.joints[-1].point, f"leg {leg.name}'s platform joint")
    end = geometry.origin + geometry.rotation @ local
    carried, elbow = np.eye(3), None
    if leg.link is not None:
        q = geometry.variable(first, leg.name)
        axis = _unit(geometry.vector(first.axis, f"leg {leg.name}'s first joint"), f"leg {leg.name}'s first axis")
        if first.kind == "R":
            if leg.reach is None:
                raise BadInputError(f"leg {leg.name}: a crank (R then a link) without its reach in the joint graph")
            carried = axis_rotation(axis, q)
            zero = geometry.vector(leg.reach[1], f"leg {leg.name}'s reach")
            elbow = base + geometry.scalar(leg.reach[0]) * (carried @ zero)
        elif first.kind == "P":
            elbow = base + q * axis
        else:
            raise UnsupportedOperationError(
                f"leg {leg.name}: an elbow moved by a {first.kind} joint (R or P only)"
            )  # fmt: skip
    return _Leg(base, elbow, end, carried)


def _chain(leg: GraphLeg, geometry: _Geometry) -> list[tuple[np.ndarray, np.ndarray]]:
    """A serial chain's joints at the home: (point, unit axis) in {B}, from their screws at the
    chain's zero (the graph's point and axis) moved by the product of exponentials of the joints
    before: T_k = exp([S_1] q_1) ... exp([S_(k-1)] q_(k-1)) (space frame; R: a turn by q about the
    axis through the point, P: a slide by q along the axis)."""
    turn, shift = np.eye(3), np.zeros(3)
    out = []
    for k, joint in enumerate(leg.joints):
        what = f"leg {leg.name}'s joint {k + 1} ({joint.kind})"
        point0 = geometry.vector(joint.point, what)
        axis0 = _unit(geometry.vector(joint.axis, what), what)
        out.append((turn @ point0 + shift, _unit(turn @ axis0, what)))
        if joint.variable is None or joint.variable not in geometry.joint_values:
            raise UnsupportedOperationError(
                f"{what} of a serial chain carries no variable of the mechanism ({joint.variable!r}): the chain "
                "cannot be placed by its product of exponentials"
            )
        q = geometry.joint_values[joint.variable]
        if joint.kind == "R":
            rotation = axis_rotation(axis0, q)
            step_turn, step_shift = rotation, point0 - rotation @ point0
        elif joint.kind == "P":
            step_turn, step_shift = np.eye(3), q * axis0
        else:
            raise UnsupportedOperationError(f"{what}: a serial chain of R and P joints only is exported")
        turn, shift = turn @ step_turn, turn @ step_shift + shift
    return out


def _axis(joint: GraphJoint, placed: _Leg, geometry: _Geometry, what: str) -> np.ndarray | None:
    if joint.axis is None:
        return None
    axis = geometry.vector(joint.axis, what)
    if joint.site == "platform":
        axis = geometry.rotation @ axis
    elif joint.site == "elbow":
        axis = placed.carried @ axis
    return _unit(axis, what)


def _idle_spin(leg: GraphLeg) -> int | None:
    """The index of an S joint whose link spins idly (S ... S with only slides along the line
    between): exported as a U."""
    if leg.joints[-1].kind != "S":
        return None
    for k in range(len(leg.joints) - 2, -1, -1):
        joint = leg.joints[k]
        if joint.kind == "P" and joint.axis is None:
            continue
        return k if joint.kind == "S" else None
    return None


class _Builder:
    def __init__(self, m: Mechanism, graph: JointGraph, geometry: _Geometry) -> None:
        self.m, self.graph, self.geometry = m, graph, geometry
        self.model = _Model()
        self.chains = {leg.name: _chain(leg, geometry) for leg in graph.legs if leg.serial}
        self.placed = {
            leg.name: _place(leg, geometry) if not leg.serial else _Leg(
                self.chains[leg.name][0][0], None, self.chains[leg.name][-1][0], np.eye(3)
            )
            for leg in graph.legs
        }  # fmt: skip
        points = [np.zeros(3)] + [p for placed in self.placed.values() for p in (placed.base, placed.end)]
        self.size = max(float(np.linalg.norm(p)) for p in points) or 1.0
        self.spacing = AXIS_SPACING * self.size

    def joint_name(self, body: str, index: int) -> str:
        return f"{body}_j{index}"

    def add_body(self, body: _Body) -> _Body:
        self.model.bodies.append(body)
        return body

    def leg(self, leg: GraphLeg, carries_platform: bool) -> tuple[str, np.ndarray]:
        """The leg's bodies up to its last link; returns that body's name and C."""
        if leg.serial:
            return self.serial(leg, carries_platform)
        placed = self.placed[leg.name]
        start = placed.elbow if placed.elbow is not None else placed.base
        line = placed.end - start  # made a unit vector where a joint slides along it
        spin = _idle_spin(leg)
        parent: str | None = None
        last = len(leg.joints) - 1
        for k, joint in enumerate(leg.joints[:last]):
            name = leg.bodies[k]
            what = f"leg {leg.name}'s joint {k + 1} ({joint.kind})"
            point = {"base": placed.base, "elbow": start, "platform": placed.end}[joint.site]
            axis = _axis(joint, placed, self.geometry, what)
            origin = point
            if joint.kind == "P" and k == 0 and placed.elbow is not None:
                origin = placed.elbow  # the slider carrying the elbow
            nxt = leg.joints[k + 1]
            following = {"base": placed.base, "elbow": start, "platform": placed.end}[nxt.site]
            if nxt.kind == "Pa":
                following = start
            segment = (origin, following)
            if float(np.linalg.norm(following - origin)) < 1e-12 and nxt.kind == "P" and nxt.axis is None:
                segment = (origin, (origin + placed.end) / 2)  # the cylinder of a line's slide
            if joint.kind == "P" and joint.axis is None:
                segment = ((placed.base + placed.end) / 2 if k > 0 else origin, placed.end)
            body = _Body(name, parent, origin, segments=[segment])
            ref = self.geometry.variable(joint, leg.name) if joint.actuated else 0.0
            jname = str(joint.variable) if joint.actuated else self.joint_name(name, 0)
            if joint.kind == "Pa":
                body = self.parallelogram(leg, k, parent, start, placed.end, axis)
            elif joint.kind == "R":
                body.joints.append(_Joint(jname, "hinge", axis, ref, joint.actuated))
            elif joint.kind == "P":
                along = _unit(line, f"leg {leg.name}'s line") if axis is None else axis
                body.joints.append(_Joint(jname, "slide", along, ref, joint.actuated))
            elif joint.kind == "C":
                assert axis is not None
                body.joints += [_Joint(jname, "hinge", axis), _Joint(self.joint_name(name, 1), "slide", axis)]
            elif joint.kind == "U" or (joint.kind == "S" and k == spin):
                towards = _unit(placed.end - point, f"leg {leg.name}'s link")
                first = axis if joint.kind == "U" and axis is not None else _normal(towards)
                second = _unit(np.cross(first, towards), f"leg {leg.name}'s universal joint")
                body.joints += [_Joint(jname, "hinge", first), _Joint(self.joint_name(name, 1), "hinge", second)]
                if joint.kind == "S":
                    self.model.notes.append(
                        f"leg {leg.name}: its S joint {k + 1} exported as a U (the link's spin about itself is idle)"
                    )
            elif joint.kind == "S":
                body.joints.append(_Joint(jname, "ball"))
            elif joint.kind == "planar":
                assert axis is not None
                e1 = _normal(axis)
                body.joints += [
                    _Joint(jname, "slide", e1),
                    _Joint(self.joint_name(name, 1), "slide", np.cross(axis, e1)),
                    _Joint(self.joint_name(name, 2), "hinge", axis),
                ]
            else:
                raise UnsupportedOperationError(f"{what}: a rigid attachment inside a leg is not exported")
            if joint.kind != "Pa":
                self.add_body(body)
            parent = body.name
        end_body = self.model.body(str(parent))
        if not carries_platform:
            self.cut(leg, end_body, placed, line)
        return end_body.name, placed.end

    def serial(self, leg: GraphLeg, carries_platform: bool) -> tuple[str, np.ndarray]:
        """A serial chain's bodies (R and P joints at their home points and axes, ``_chain``),
        cut from the platform at its last joint (an R: two connects along its axis)."""
        frames = self.chains[leg.name]
        if carries_platform or leg.joints[-1].kind != "R":
            raise UnsupportedOperationError(
                f"leg {leg.name} is a serial chain ending in a {leg.joints[-1].kind} joint"
                + (" that carries the platform" if carries_platform else "")
                + ": only a chain cut from the platform at a revolute joint is exported"
            )
        parent: str | None = None
        for k, joint in enumerate(leg.joints[:-1]):
            point, axis = frames[k]
            body = _Body(leg.bodies[k], parent, point, segments=[(point, frames[k + 1][0])])
            name = str(joint.variable) if joint.actuated else self.joint_name(leg.bodies[k], 0)
            ref = self.geometry.variable(joint, leg.name) if joint.actuated else 0.0
            kind = {"R": "hinge", "P": "slide"}.get(joint.kind)
            if kind is None:
                raise UnsupportedOperationError(
                    f"leg {leg.name}: a {joint.kind} joint in a serial chain (R and P only are exported)"
                )
            body.joints.append(_Joint(name, kind, axis, ref, joint.actuated))
            parent = self.add_body(body).name
        end_body = self.model.body(str(parent))
        end, axis = frames[-1]
        platform = self.model.body("platform")
        for suffix, offset in (("", np.zeros(3)), ("_axis", self.spacing * axis)):
            end_body.sites.append((f"{leg.name}_end{suffix}", end + offset))
            platform.sites.append((f"{leg.name}_platform{suffix}", end + offset))
            self.model.connects.append(
                (f"{leg.name}_cut{suffix}", f"{leg.name}_end{suffix}", f"{leg.name}_platform{suffix}")
            )
        return end_body.name, end

    def parallelogram(
        self, leg: GraphLeg, k: int, parent: str | None, elbow: np.ndarray, end: np.ndarray, axis: np.ndarray | None
    ) -> _Body:
        """The four bars of a Pa joint; returns the short side at the platform (the graph's body)."""
        assert axis is not None and parent is not None
        bars = _unit(end - elbow, f"leg {leg.name}'s parallelogram")
        length = float(np.linalg.norm(end - elbow))
        normal = _unit(np.cross(axis, bars), f"leg {leg.name}'s parallelogram plane")
        half = PARALLELOGRAM_WIDTH * length / 2 * axis
        upper = self.model.body(parent)
        upper.segments.append((elbow - half, elbow + half))
        name = leg.bodies[k]
        first = self.add_body(
            _Body(f"{name}_bar1", parent, elbow + half, joints=[_Joint(f"{name}_bar1_j0", "hinge", normal)],
                  segments=[(elbow + half, end + half)])
        )  # fmt: skip
        second = self.add_body(
            _Body(f"{name}_bar2", parent, elbow - half, joints=[_Joint(f"{name}_bar2_j0", "hinge", normal)],
                  segments=[(elbow - half, end - half)])
        )  # fmt: skip
        lower = self.add_body(
            _Body(name, first.name, end + half, joints=[_Joint(self.joint_name(name, 0), "hinge", normal)],
                  segments=[(end + half, end - half)])
        )  # fmt: skip
        for suffix, offset in (("", np.zeros(3)), ("_axis", self.spacing * normal)):
            second.sites.append((f"{name}_bar2_tip{suffix}", end - half + offset))
            lower.sites.append((f"{name}_bar2{suffix}", end - half + offset))
            self.model.connects.append((f"{name}_bar2_cut{suffix}", f"{name}_bar2_tip{suffix}", f"{name}_bar2{suffix}"))
        self.model.notes.append(
            f"leg {leg.name}: its parallelogram as four bars ({upper.name}, {first.name}, {name}, {second.name}); "
            f"short sides {PARALLELOGRAM_WIDTH:g} x the bars' length, the second bar cut from {name}"
        )
        return lower

    def cut(self, leg: GraphLeg, end_body: _Body, placed: _Leg, line: np.ndarray) -> None:
        """Cut the leg from the platform at its last joint: S by one connect, R by two along its
        axis, U by a cross body hinged to the leg's last link and cut as an R from the platform,
        C by a slider along the axis cut as an R, P by a slider along the axis cut rigidly (three
        connects not on one line)."""
        joint = leg.joints[-1]
        platform = self.model.body("platform")
        offsets = [("", np.zeros(3))]
        what = f"leg {leg.name}'s platform joint"
        if joint.kind == "R":
            axis = _axis(joint, placed, self.geometry, what)
            assert axis is not None
            offsets.append(("_axis", self.spacing * axis))
        elif joint.kind == "U":
            end_body, axis = self.cross(leg, end_body, placed, line)
            offsets.append(("_axis", self.spacing * axis))
        elif joint.kind in ("C", "P"):
            axis = _axis(joint, placed, self.geometry, what)
            if axis is None:
                raise BadInputError(f"{what} ({joint.kind}) has no axis in the joint graph")
            end_body = self.slider(leg, end_body, placed, axis, joint.kind)
            offsets.append(("_axis", self.spacing * axis))
            if joint.kind == "P":  # a third point off the axis: no turn about it either
                offsets.append(("_side", self.spacing * _normal(axis)))
        elif joint.kind != "S":
            raise UnsupportedOperationError(
                f"leg {leg.name} meets the platform with a {joint.kind} joint: only S (one connect), R (two "
                "connects along its axis), U, C, P (a cross body or slider and two or three connects) and F (the "
                "platform ends the leg) are cut"
            )
        for suffix, offset in offsets:
            end_body.sites.append((f"{leg.name}_end{suffix}", placed.end + offset))
            platform.sites.append((f"{leg.name}_platform{suffix}", placed.end + offset))
            self.model.connects.append(
                (f"{leg.name}_cut{suffix}", f"{leg.name}_end{suffix}", f"{leg.name}_platform{suffix}")
            )

    def slider(self, leg: GraphLeg, end_body: _Body, placed: _Leg, axis: np.ndarray, kind: str) -> _Body:
        """A C or P joint at the platform: a slider ``{leg}_slider`` (a body at the joint sliding
        on the leg's last link along the axis, fixed in the platform: the graph's, in {P})."""
        body = self.add_body(
            _Body(f"{leg.name}_slider", end_body.name, placed.end.copy(),
                  joints=[_Joint(self.joint_name(f"{leg.name}_slider", 0), "slide", axis)])
        )  # fmt: skip
        cut = "as a revolute joint (two connects along the axis)" if kind == "C" else "rigidly (three connects)"
        self.model.notes.append(
            f"leg {leg.name}: its {kind} joint at the platform as a slider ({body.name}) on {end_body.name}, cut "
            f"from the platform {cut}"
        )
        return body

    def cross(self, leg: GraphLeg, end_body: _Body, placed: _Leg, line: np.ndarray) -> tuple[_Body, np.ndarray]:
        """A universal joint at the platform: its cross ``{leg}_cross`` (a body at the joint,
        hinged to the leg's last link about the first axis) and the second axis, fixed in the
        platform (the graph's axis, in {P}; without one both axes are normal to the link at the
        home, so that the link cannot spin about itself). Returns the cross and that axis."""
        what = f"leg {leg.name}'s platform joint (U)"
        towards = _unit(line, f"leg {leg.name}'s link")
        given = _axis(leg.joints[-1], placed, self.geometry, what)
        if given is None:
            first = _normal(towards)
            second = _unit(np.cross(first, towards), what)
        else:
            second = given
            first = _unit(np.cross(towards, second), f"{what}: its axis along the link")
        body = self.add_body(
            _Body(f"{leg.name}_cross", end_body.name, placed.end.copy(),
                  joints=[_Joint(self.joint_name(f"{leg.name}_cross", 0), "hinge", first)])
        )  # fmt: skip
        self.model.notes.append(
            f"leg {leg.name}: its U joint at the platform as a cross body ({body.name}) hinged to {end_body.name}, "
            "cut from the platform by two connects along its second axis"
        )
        return body, second


def _carrier(graph: JointGraph, builder: _Builder) -> tuple[GraphLeg | None, str]:
    """The leg that ends in the platform, and why (None: the platform is a free body)."""
    fixed = [leg for leg in graph.legs if leg.joints[-1].kind == "F"]
    if len(fixed) > 1:
        raise UnsupportedOperationError(
            f"legs {[leg.name for leg in fixed]} all end rigidly in the platform: only one can carry it"
        )
    if fixed:
        return fixed[0], f"the platform ends leg {fixed[0].name} (rigidly attached: F)"
    ends = [builder.placed[leg.name].end for leg in graph.legs]
    if len(ends) > 1 and all(float(np.linalg.norm(e - ends[0])) < 1e-12 * builder.size for e in ends):
        leg = graph.legs[0]
        return leg, f"every leg meets the platform at one point: the platform (a point) ends leg {leg.name}"
    return None, "the platform is a free body"


def _format(value: float) -> str:
    """The shortest text that reads back as the same double (0.9, not 0.90000000000000002)."""
    text = repr(float(value))
    text = text[:-2] if text.endswith(".0") else text
    return "0" if text in ("-0", "0") else text


def _numbers(values: Iterable[float]) -> str:
    return " ".join(_format(v) for v in values)


def _quaternion(rotation: np.ndarray) -> np.ndarray:
    """(w, x, y, z) of a rotation matrix (Shepperd's method)."""
    r = rotation
    trace = float(np.trace(r))
    if trace > 0:
        s = 2 * math.sqrt(trace + 1)
        q = [s / 4, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2 * math.sqrt(max(1 + r[i, i] - r[j, j] - r[k, k], 0.0))
        q = [0.0] * 4
        q[0] = (r[k, j] - r[j, k]) / s
        q[1 + i] = s / 4
        q[1 + j] = (r[j, i] + r[i, j]) / s
        q[1 + k] = (r[k, i] + r[i, k]) / s
    quaternion = np.array(q)
    return quaternion / np.linalg.norm(quaternion)


def _xml_body(model: _Model, body: _Body, indent: int) -> list[str]:
    pad = "  " * indent
    parent = model.body(body.parent) if body.parent is not None else None
    parent_rotation = parent.rotation if parent is not None else np.eye(3)
    parent_origin = parent.position if parent is not None else np.zeros(3)
    position = parent_rotation.T @ (body.position - parent_origin)
    relative = parent_rotation.T @ body.rotation
    attributes = f'name="{body.name}" pos="{_numbers(position)}"'
    if not np.allclose(relative, np.eye(3), atol=0, rtol=0):
        attributes += f' quat="{_numbers(_quaternion(relative))}"'
    lines = [f"{pad}<body {attributes}>"]
    if body.comment:
        lines.append(f"{pad}  <!-- {body.comment} -->")
    local = body.rotation.T
    for joint in body.joints:
        if joint.kind == "free":
            lines.append(f'{pad}  <freejoint name="{joint.name}"/>')
            continue
        text = f'{pad}  <joint name="{joint.name}" type="{joint.kind}"'
        if joint.axis is not None:
            text += f' axis="{_numbers(local @ joint.axis)}"'
        if joint.ref:
            text += f' ref="{_format(joint.ref)}"'
        lines.append(text + "/>")
    if body.mass > 0:
        assert body.centre is not None and body.inertia is not None
        centre = local @ (body.centre - body.position)
        inertia = local @ body.inertia @ local.T
        full = [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[0, 2], inertia[1, 2]]
        lines.append(
            f'{pad}  <inertial pos="{_numbers(centre)}" mass="{_format(body.mass)}" fullinertia="{_numbers(full)}"/>'
        )
    for start, end in body.segments:
        if float(np.linalg.norm(end - start)) > 1e-9:
            ends = np.concatenate([local @ (start - body.position), local @ (end - body.position)])
            lines.append(f'{pad}  <geom type="capsule" fromto="{_numbers(ends)}"/>')
        else:
            lines.append(f'{pad}  <geom type="sphere" pos="{_numbers(local @ (start - body.position))}"/>')
    for name, point in body.sites:
        lines.append(f'{pad}  <site name="{name}" pos="{_numbers(local @ (point - body.position))}"/>')
    for child in model.bodies:
        if child.parent == body.name:
            lines += _xml_body(model, child, indent + 1)
    lines.append(f"{pad}</body>")
    return lines


def _build(
    m: Mechanism, graph: JointGraph, reference: Configuration | None, link_mass: LinkMass, platform_mass: float,
    platform_radius: float, payload: float,
) -> tuple[_Model, str, _Geometry]:  # fmt: skip
    """The tree of bodies at the reference (default the home), its cuts, how the platform is held."""
    if reference is None:
        try:
            reference = m.forward_pose(m.home_actuated, guess=m.home_passive)  # the home, polished
        except (ConvergenceError, SingularConfigurationError) as error:
            raise type(error)(
                f"{m.name}: the manifest's home does not close at these parameters ({error}); pass reference=, a "
                "closed configuration of them (from forward_pose or inverse_pose), to lay the bodies out at"
            ) from error
    elif not isinstance(reference, Configuration):
        raise BadInputError(f"reference must be a Configuration (from a solver), got {type(reference).__name__}")
    actuated = np.asarray(reference.actuated, dtype=float).reshape(-1)
    passive = np.asarray(reference.passive, dtype=float).reshape(-1)
    if actuated.shape != (len(m.actuated_names),) or passive.shape != (len(m.passive_names),):
        raise BadInputError("reference must be one configuration (no batch) of this mechanism")
    geometry = _Geometry(m, graph, actuated, passive)
    builder = _Builder(m, graph, geometry)
    carrier, how = _carrier(graph, builder)
    platform = _Body("platform", None, geometry.origin, geometry.rotation)
    platform.sites.append(("platform", geometry.origin))
    platform.mass = platform_mass
    platform.centre = geometry.origin
    platform.inertia = platform_mass * 0.4 * platform_radius**2 * np.eye(3)
    if carrier is None:
        platform.joints.append(_Joint("platform", "free"))
        builder.add_body(platform)
    else:
        platform.parent, _ = builder.leg(carrier, carries_platform=True)
        builder.add_body(platform)
    for leg in graph.legs:
        if leg is not carrier:
            builder.leg(leg, carries_platform=False)
    if payload > 0:
        builder.add_body(
            _Body("payload", "platform", geometry.origin, geometry.rotation, mass=payload, centre=geometry.origin,
                  inertia=payload * 1e-6 * np.eye(3), comment=f"{payload:g} kg at the platform's origin")
        )  # fmt: skip
    links = [body for body in builder.model.bodies if body.name not in ("platform", "payload")]
    if isinstance(link_mass, Mapping):
        unknown = sorted(set(map(str, link_mass)) - {body.name for body in links})
        if unknown:
            raise BadInputError(
                f"link masses name {unknown}, which are not link bodies of {m.name} (bodies: {[b.name for b in links]})"
            )
    for body in links:
        value = link_mass.get(body.name, 0.0) if isinstance(link_mass, Mapping) else link_mass
        if isinstance(value, int | float) and not isinstance(value, bool):
            _check_mass(f"the mass of {body.name}", value)
            if value > 0:
                start, end = body.segments[0] if body.segments else (body.position, body.position)
                body.mass = float(value)
                body.centre, body.inertia = _rod(float(value), start, end)
            continue
        try:  # a rigid body in the body's frame (parakin.dynamics.RigidInertia)
            mass = float(value.mass)
            centre, inertia = np.asarray(value.centre, dtype=float), np.asarray(value.inertia, dtype=float)
        except (AttributeError, TypeError, ValueError):
            raise BadInputError(
                f"the inertia of {body.name} must be a mass (kg) or a parakin.dynamics.RigidInertia, got {value!r}"
            ) from None
        if centre.shape != (3,) or inertia.shape != (3, 3):
            raise BadInputError(f"the inertia of {body.name} must be a parakin.dynamics.RigidInertia, got {value!r}")
        _check_mass(f"the mass of {body.name}", mass)
        body.mass = mass
        body.centre = body.rotation @ centre + body.position
        body.inertia = body.rotation @ inertia @ body.rotation.T
    return builder.model, how, geometry


def _check_mass(name: str, value: object) -> None:
    if not (isinstance(value, int | float) and not isinstance(value, bool) and math.isfinite(value) and value >= 0):
        raise BadInputError(f"{name} must be a finite number >= 0 (kg), got {value!r}")


def _servo_gain(model: _Model, joint: str, load: float, step: float) -> float:
    """The default servo stiffness of an actuated joint: 1e4 N/m (slide) or 1e3 N m/rad (hinge)
    per kg of platform and payload (at least 1 kg), at most 0.25 m_eff / step^2 (the body it
    carries: its mass, or its inertia about the hinge), so that the explicit spring stays stable
    (omega step <= 0.5)."""
    body = next(b for b in model.bodies if any(j.name == joint for j in b.joints))
    moved = next(j for j in body.joints if j.name == joint)
    per_kg = 1e3 if moved.kind == "hinge" else 1e4
    gain = per_kg * max(load, 1.0)
    if body.mass > 0 and body.centre is not None and body.inertia is not None:
        effective = body.mass
        if moved.kind == "hinge" and moved.axis is not None:
            r = body.centre - body.position
            about = body.inertia + body.mass * (float(r @ r) * np.eye(3) - np.outer(r, r))
            effective = float(moved.axis @ about @ moved.axis)
        gain = min(gain, 0.25 * effective / step**2)
    return gain


def _compile(text: str) -> Any:
    from parakin.mujoco_bridge import _mujoco

    mujoco = _mujoco()
    return mujoco, mujoco.MjModel.from_xml_string(text)


class _Residual:
    """The rows a keyframe's Newton solve zeroes: the connects (site1 - site2, m) and, where a
    leg carries the platform, the platform site's position and rotation against a target."""

    def __init__(self, mujoco: Any, model: Any, rotates: bool) -> None:
        self.mujoco, self.model, self.rotates = mujoco, model, rotates
        self.site = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, "platform")
        self.connects = [(int(model.eq_obj1id[e]), int(model.eq_obj2id[e])) for e in range(model.neq)]

    def __call__(self, data: Any, connects: Sequence[int], target: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
        mujoco, model = self.mujoco, self.model
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        rows, jac = [np.zeros(0)], [np.zeros((0, model.nv))]
        for index in connects:
            a, b = self.connects[index]
            ja, jb = np.zeros((3, model.nv)), np.zeros((3, model.nv))
            mujoco.mj_jacSite(model, data, ja, None, a)
            mujoco.mj_jacSite(model, data, jb, None, b)
            rows.append(data.site_xpos[a] - data.site_xpos[b])
            jac.append(ja - jb)
        if target is not None:
            jp, jr = np.zeros((3, model.nv)), np.zeros((3, model.nv))
            mujoco.mj_jacSite(model, data, jp, jr, self.site)
            rows.append(data.site_xpos[self.site] - target[:3, 3])
            jac.append(jp)
            if self.rotates:  # R - R_target, row by row: zero only at the target (no angle wraps)
                current = np.asarray(data.site_xmat[self.site]).reshape(3, 3)
                rows.append((current - target[:3, :3]).ravel())
                turn = np.zeros((3, 3, model.nv))  # d R / d qvel = [jr_i]x R
                turn[0, 1], turn[0, 2], turn[1, 2] = -jr[2], jr[1], -jr[0]
                turn[1, 0], turn[2, 0], turn[2, 1] = jr[2], -jr[1], jr[0]
                jac.append(np.einsum("ikn,kj->ijn", turn, current).reshape(9, model.nv))
        return np.concatenate(rows), np.concatenate(jac)


def _newton(
    residual: _Residual, data: Any, dofs: np.ndarray, connects: Sequence[int], target: np.ndarray | None
) -> float:
    """Gauss-Newton on ``dofs`` (least-squares steps, at most 0.5 per entry) from ``data.qpos``."""
    gap = math.inf
    for _ in range(60):
        value, jacobian = residual(data, connects, target)
        gap = float(np.abs(value).max(initial=0.0))
        if gap <= KEY_TOLERANCE or not math.isfinite(gap):
            break
        step = np.linalg.lstsq(jacobian[:, dofs], -value, rcond=None)[0]
        largest = float(np.abs(step).max(initial=0.0))
        if largest > 0.5:
            step *= 0.5 / largest
        full = np.zeros(residual.model.nv)
        full[dofs] = step
        residual.mujoco.mj_integratePos(residual.model, data.qpos, full, 1.0)
    return gap


def _solve_key(mujoco: Any, model: Any, data: Any, actuated: Sequence[int], target: np.ndarray, rotates: bool) -> float:
    """Close every leg at the platform pose ``target`` with the actuated dofs held: leg by leg (a
    leg is the subtree of one child of the world; the leg carrying the platform first, its rows
    the platform site's pose), Newton on its passive dofs from ``data.qpos`` (the home) and, if
    that fails, from up to ``KEY_STARTS`` seeded random starts. Returns the largest residual (m)."""
    residual = _Residual(mujoco, model, rotates)
    roots = [int(model.body_rootid[b]) for b in range(model.nbody)]
    platform_root = roots[int(model.site_bodyid[residual.site])]
    carried = model.body_dofnum[model.body("platform").id] == 0 and platform_root != 0
    legs = sorted({r for r in roots if r != 0}, key=lambda r: r != platform_root or not carried)
    held = set(actuated)
    rng = np.random.default_rng(KEY_SEED)
    worst = 0.0
    for root in legs:
        bodies = [b for b in range(model.nbody) if roots[b] == root]
        dofs = np.array(
            [d for b in bodies for d in range(model.body_dofadr[b], model.body_dofadr[b] + model.body_dofnum[b])
             if d not in held and model.body_dofnum[b] > 0],
            dtype=np.intp,
        )  # fmt: skip
        connects = [e for e, (a, _) in enumerate(residual.connects) if roots[int(model.site_bodyid[a])] == root]
        goal = target if carried and root == platform_root else None
        joints = [j for j in range(model.njnt) if roots[int(model.jnt_bodyid[j])] == root]
        home = data.qpos.copy()
        gap = _newton(residual, data, dofs, connects, goal)
        for _ in range(KEY_STARTS):
            if gap <= KEY_TOLERANCE:
                break
            data.qpos[:] = home
            for j in joints:
                address, kind = int(model.jnt_qposadr[j]), int(model.jnt_type[j])
                if int(model.jnt_dofadr[j]) in held:
                    continue
                if kind == int(mujoco.mjtJoint.mjJNT_HINGE):
                    data.qpos[address] = rng.uniform(-math.pi, math.pi)
                elif kind == int(mujoco.mjtJoint.mjJNT_BALL):
                    quaternion = rng.normal(size=4)
                    data.qpos[address : address + 4] = quaternion / np.linalg.norm(quaternion)
            gap = _newton(residual, data, dofs, connects, goal)
        worst = max(worst, gap)
    return worst


def _modes_wanted(modes: object, count: int) -> list[int]:
    if modes is None or (isinstance(modes, str) and modes == "none"):
        return []
    if isinstance(modes, str):
        if modes != "all":
            raise BadInputError(f"modes must be 'all', 'none' or mode numbers, got {modes!r}")
        return list(range(count))
    try:
        wanted = [int(k) for k in modes]  # type: ignore[attr-defined]
    except (TypeError, ValueError):
        raise BadInputError(f"modes must be 'all', 'none' or mode numbers, got {modes!r}") from None
    bad = [k for k in wanted if not 0 <= k < count]
    if bad:
        raise BadInputError(f"modes {bad} are not assembly modes of these actuated values (0 to {count - 1})")
    return wanted


def to_mjcf(
    m: Mechanism,
    actuated: ArrayLike | None = None,
    modes: str | Sequence[int] | None = "all",
    reference: Configuration | None = None,
    timestep: float | None = None,
    accuracy: str = "fast",
    actuator: str = "position",
    kp: float | None = None,
    link_mass: LinkMass = 1.0,
    platform_mass: float = 1.0,
    platform_radius: float = 0.05,
    payload: float = 0.0,
) -> str:
    """The MJCF text of ``m``: its legs as bodies, its loops cut by site connects, the home as
    qpos0 and every assembly mode of ``actuated`` a keyframe (module docstring).

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism whose package carries its joint graph (the manifest's ``joints``).
    actuated : array_like (n_a,), optional
        The actuated values (rad, m) whose assembly modes become keyframes; default those of
        ``reference`` (the home).
    modes : "all", "none" or sequence of int
        Which modes of ``m.forward_pose_all(actuated)`` become ``<key name="mode{k}">``.
    reference : Configuration, optional
        The closed configuration the bodies are laid out at, qpos0 (from ``forward_pose``,
        ``inverse_pose``...); default the home (``m.home_actuated``, ``m.home_passive``,
        polished by ``forward_pose``). Every passive joint is 0 there.
    timestep : float, optional
        The simulation step (s); default the preset's. The connects' time constant is two steps.
    accuracy : {"fast", "accurate"}
        The preset (``PRESETS``).
    actuator : {"position", "motor"}
        Position servos (``kp``, ``kv`` = kp / 50) holding the keyframe's ``ctrl``, or motors.
    kp : float, optional
        The servos' stiffness (N m/rad on hinges, N/m on slides); default 1e3 and 1e4 per kg of
        platform and payload, capped where the explicit spring would be unstable on the body it
        moves (``_servo_gain``).
    link_mass : float or mapping
        Each link's mass (kg, a uniform thin rod along its segment), or a mapping body name ->
        mass (that body a rod) or ``parakin.dynamics.RigidInertia`` (its mass, centre and
        inertia in the body's frame: origin at its first joint, axes those of {B} at the home);
        bodies not named are massless. The same forms and meaning as ``leg_inertias`` of
        ``parakin.dynamics.inverse_dynamics``: one robot in both.
    platform_mass, payload : float
        Masses (kg): the platform (a solid sphere of ``platform_radius`` m), the payload body at
        the platform's origin (none when 0).
    platform_radius : float
        m.

    Returns
    -------
    str
        The MJCF document.

    Raises
    ------
    UnsupportedOperationError
        The package carries no joint graph (regenerate it with a generator that writes one), a
        leg of a kind not exported (a serial chain of other joints than R and P, or not ending in an
        R; a planar joint at the platform;
        several legs ending rigidly in it), or the mujoco module is missing.
    BadInputError
        Bad ``actuated``, ``modes``, ``timestep``, ``accuracy``, ``actuator`` or masses.
    ConvergenceError
        A mode's legs could not be assembled from the home (the residual and the mode named).

    Warns
    -----
    NearSingularModeWarning
        Keyframes of modes near a type II singularity (1/cond of the closure Jacobian below
        ``NEAR_SINGULAR``), named; each carries an XML comment with its value.

    Examples
    --------
    >>> import parakin
    >>> xml = to_mjcf(parakin.load("stewart"), accuracy="accurate", payload=10.0)
    """
    graph = m.manifest.joints
    if graph is None:
        raise UnsupportedOperationError(
            f"{m.name}: its package carries no joint graph (the manifest's 'joints' field), which the MJCF export "
            "builds the bodies from; regenerate the package with a generator that writes it"
        )
    if accuracy not in PRESETS:
        raise BadInputError(f"accuracy must be one of {list(PRESETS)}, got {accuracy!r}")
    if actuator not in ("position", "motor"):
        raise BadInputError(f"actuator must be 'position' or 'motor', got {actuator!r}")
    preset = PRESETS[accuracy]
    step = preset.timestep if timestep is None else timestep
    for name, value in (("timestep", step), ("platform_radius", platform_radius)):
        if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
            raise BadInputError(f"{name} must be a finite number > 0, got {value!r}")
    for name, value in (("platform_mass", platform_mass), ("payload", payload)):
        _check_mass(name, value)
    if not isinstance(link_mass, Mapping):
        _check_mass("link_mass", link_mass)
    if kp is not None and not (isinstance(kp, int | float) and math.isfinite(kp) and kp > 0):
        raise BadInputError(f"kp must be a finite number > 0, got {kp!r}")
    if (isinstance(link_mass, Mapping) and not link_mass or link_mass == 0) and platform_mass == 0:
        raise BadInputError("link_mass and platform_mass are both 0: MuJoCo needs mass on a moving body")
    model, how, geometry = _build(m, graph, reference, link_mass, platform_mass, platform_radius, payload)
    laid_out = geometry.configuration(m)  # qpos0
    default = [geometry.joint_values[name] for name in m.actuated_names]  # the reference's
    chosen = np.asarray(default if actuated is None else m._actuated(actuated), dtype=float).reshape(-1)
    planar = m.manifest.pose_kind in PLANAR_KINDS
    gravity = (0.0, -GRAVITY, 0.0) if planar else (0.0, 0.0, -GRAVITY)
    solref = f"{_format(2 * step)} 1"
    masses = platform_mass + payload
    lines = [
        f'<mujoco model="{m.name}">',
        '  <compiler angle="radian" autolimits="true"/>',
        f'  <option timestep="{_format(step)}" gravity="{_numbers(gravity)}" integrator="{preset.integrator}"/>',
        "  <default>",
        '    <geom contype="0" conaffinity="0" size="0.01" mass="0"/>',
        '    <site size="0.005"/>',
        f'    <equality solref="{solref}" solimp="{_numbers(preset.solimp)}"/>',
        "  </default>",
        "  <worldbody>",
    ]
    for body in model.bodies:
        if body.parent is None:
            lines += _xml_body(model, body, 2)
    lines.append("  </worldbody>")
    lines.append("  <equality>")
    lines += [f'    <connect name="{n}" site1="{a}" site2="{b}"/>' for n, a, b in model.connects]
    lines.append("  </equality>")
    lines.append("  <actuator>")
    kinds = {j.name: j.kind for b in model.bodies for j in b.joints if j.actuated}
    for name in m.actuated_names:
        if name not in kinds:
            raise UnsupportedOperationError(f"{m.name}: the actuated variable {name} is on no joint of the graph")
        if actuator == "motor":
            lines.append(f'    <motor name="{name}" joint="{name}"/>')
            continue
        gain = kp if kp is not None else _servo_gain(model, name, masses, step)
        lines.append(f'    <position name="{name}" joint="{name}" kp="{_format(gain)}" kv="{_format(gain / 50)}"/>')
    lines.append("  </actuator>")
    keys, home_key = _keys(m, "\n".join(lines + ["</mujoco>"]) + "\n", chosen, modes, actuator, laid_out)
    qpos0 = "the home" if reference is None else "the reference configuration"
    if home_key is not None:
        qpos0 += f" (keyframe mode{home_key})"
    home_measure = type_ii_distance(m, laid_out)
    if home_measure is not None and float(home_measure) < NEAR_SINGULAR:
        qpos0 += (
            f", near a type II (parallel) singularity: 1/cond of the closure Jacobian = {float(home_measure):.2g}, below "
            f"{NEAR_SINGULAR:g}, where the actuators barely hold the platform and a simulation may drift"
        )
    head = [
        f"<!-- {m.name}: {m.manifest.title}, exported by parakin.mjcf.to_mjcf from its joint graph.",
        f"     Parameters: {', '.join(f'{k} = {v:g}' for k, v in m.parameters.items())} (SI units).",
        f"     Actuated joints (qpos = parakin's actuated values, rad or m): {', '.join(m.actuated_names)}.",
        f"     Base {{B}} = the world frame; platform frame {{P}} = site 'platform'; {how}.",
        f"     qpos0: {qpos0}.",
        f"     Keyframes mode<k>: assembly mode k of the actuated values {_numbers(chosen)}.",
        f"     Preset '{accuracy}': timestep {step:g} s, connects' solref {solref} (time constant two steps), "
        f"solimp {_numbers(preset.solimp)}.",
        "     Loop gap under load: not estimated for this model (it depends on its masses, servos and geometry); "
        "measure it by settling a keyframe (parakin.mujoco_bridge.settle) against forward_pose at the settled inputs.",
        *(f"     {note}." for note in model.notes),
        "-->",
    ]
    head = ["<!-- " + head[0][5:].replace("--", "- -"), *(line.replace("--", "- -") for line in head[1:-1]), head[-1]]
    if not keys:
        return "\n".join(head + lines + ["</mujoco>"]) + "\n"
    return "\n".join(head + lines + ["  <keyframe>", *keys, "  </keyframe>", "</mujoco>"]) + "\n"


def _keys(
    m: Mechanism, xml: str, chosen: np.ndarray, modes: object, actuator: str, home: Configuration
) -> tuple[list[str], int | None]:
    """One <key> per wanted assembly mode of ``chosen`` (near-singular ones with a comment), and
    which of them is the configuration ``home`` (qpos0), None if none is."""
    if modes is None or modes == "none":
        return [], None
    found = m.forward_pose_all(chosen)
    wanted = _modes_wanted(modes, int(found.count))
    mujoco, model = _compile(xml)
    actuated_qpos = [int(model.jnt_qposadr[model.joint(n).id]) for n in m.actuated_names]
    actuated_dofs = [int(model.jnt_dofadr[model.joint(n).id]) for n in m.actuated_names]
    free_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, "platform")
    twist = m.manifest.capabilities.rates.twist if m.manifest.capabilities.rates is not None else ("wx",)
    rotates = any(name.startswith("w") for name in twist)
    ctrl = _numbers(chosen) if actuator == "position" else _numbers(np.zeros(len(chosen)))
    keys: list[str] = []
    configurations = [found.mode(k) for k in wanted]
    home_key = next(
        (
            k
            for k, c in zip(wanted, configurations, strict=True)
            if np.abs(np.asarray(c.actuated) - np.asarray(home.actuated)).max() < 1e-9
            and np.abs(np.asarray(c.pose) - np.asarray(home.pose)).max() < 1e-9
        ),
        None,
    )
    # every wanted mode's type II distance at once (none for a mechanism without a loop to close)
    measured = type_ii_distance(m, _stacked(configurations)) if configurations else None
    distances = dict(zip(wanted, measured.tolist(), strict=True)) if measured is not None else {}
    near: dict[int, float] = {}  # mode -> its type II distance, where below NEAR_SINGULAR
    for k, configuration in zip(wanted, configurations, strict=True):
        pose = np.asarray(configuration.pose, dtype=float)
        data = mujoco.MjData(model)
        data.qpos[actuated_qpos] = chosen
        if free_id >= 0:
            address = int(model.jnt_qposadr[free_id])
            data.qpos[address : address + 3] = pose[:3, 3]
            data.qpos[address + 3 : address + 7] = _quaternion(pose[:3, :3])
        residual = _solve_key(mujoco, model, data, actuated_dofs, pose, rotates)
        if not residual <= KEY_TOLERANCE * 10:
            raise ConvergenceError(
                f"{m.name}: assembly mode {k} of the actuated values {chosen.tolist()} could not be assembled in "
                f"MuJoCo from the home (loop residual {residual:.3g} m); leave it out with modes=[...]",
                residual=residual,
            )
        data.qpos[actuated_qpos] = chosen
        if distances.get(k, math.nan) < NEAR_SINGULAR:  # NaN (a Jacobian not finite): no verdict
            near[k] = distances[k]
            keys.append(f"    <!-- {_near_singular_note(k, distances[k])} -->")
        keys.append(f'    <key name="mode{k}" qpos="{_numbers(data.qpos)}" ctrl="{ctrl}"/>')
    if near:
        values = sorted(near.values())
        span = f"{values[0]:.2g}" if len(values) == 1 else f"from {values[0]:.2g} to {values[-1]:.2g}"
        warnings.warn(
            NearSingularModeWarning(
                f"{m.name}: {len(near)} of {len(wanted)} keyframes ({', '.join(f'mode{k}' for k in near)}) are near a "
                f"type II (parallel) singularity: 1/cond of the closure Jacobian d closure / d passive {span}, below "
                f"{NEAR_SINGULAR:g} (1 far from, 0 at a singularity; the 'type II' of parakin plot). There the "
                "actuators barely hold the platform: a small load moves it far, and the simulation may drift or not "
                "come to rest. Each such keyframe's comment in the file gives its value."
            ),
            stacklevel=3,
        )
    return keys, home_key


def _stacked(configurations: Sequence[Configuration]) -> Configuration:
    """Configurations of one input, one after the other along a new first axis: a batch (k, ...)."""
    return Configuration(
        *(np.stack([np.asarray(getattr(c, part)) for c in configurations]) for part in ("actuated", "passive", "pose"))
    )


def _near_singular_note(k: int, measure: float) -> str:
    """The XML comment before the keyframe of mode ``k``, near a type II singularity (``measure``:
    its 1/cond of the closure Jacobian, below ``NEAR_SINGULAR``)."""
    return (
        f"mode{k} is near a type II (parallel) singularity: 1/cond of the closure Jacobian d closure / d passive "
        f"= {measure:.2g}, below {NEAR_SINGULAR:g} (1 far from, 0 at a singularity; the 'type II' of parakin plot). "
        "The actuators barely hold the platform here: a small load moves it far, and the simulation may drift "
        "or not come to rest."
    )


# ---------------------------------------------------------------- the command line
def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``parakin mjcf NAME``."""
    parser.add_argument("name", metavar="NAME", help="a mechanism's name or a generated package's folder")
    parser.add_argument("--out", metavar="FILE.xml", help="where to write the MJCF (default: standard output)")
    group = parser.add_mutually_exclusive_group()
    group.add_argument(
        "--actuated", nargs="+", type=float, metavar="V",
        help="actuated values (m, rad) whose assembly modes become keyframes (default: the home's)",
    )  # fmt: skip
    group.add_argument(
        "--actuated-deg", nargs="+", type=float, metavar="V", help="the same, revolute in degrees, prismatic in m"
    )
    parser.add_argument("--accuracy", choices=list(PRESETS), default="fast", help="simulation preset (default fast)")
    parser.add_argument("--timestep", type=float, help="simulation step in s (default: the preset's)")
    parser.add_argument("--payload", type=float, default=0.0, help="payload mass in kg (default 0)")
    parser.add_argument(
        "--link-mass", type=float, default=1.0, metavar="KG",
        help="each link's mass, a uniform thin rod (default 1; inverse_dynamics' leg_inertias=KG is the same robot)",
    )  # fmt: skip
    parser.add_argument(
        "--platform-mass", type=float, default=1.0, metavar="KG", help="the platform's mass (default 1)"
    )
    parser.add_argument("--no-modes", action="store_true", help="write no keyframes")


def run(args: argparse.Namespace, m: Mechanism) -> int:
    """``parakin mjcf``: write the MJCF of ``m`` (loaded by the command line from ``args.name``);
    0 on success."""
    actuated = args.actuated  # in SI units (the command line converts --actuated-deg)
    text = to_mjcf(
        m, actuated=actuated, modes="none" if args.no_modes else "all", timestep=args.timestep,
        accuracy=args.accuracy, payload=args.payload, link_mass=args.link_mass, platform_mass=args.platform_mass,
    )  # fmt: skip
    if not args.no_modes and "<key " not in text:
        print(
            f"parakin: no real assembly mode of {m.name} for these inputs, so no keyframe to write; "
            "choose reachable inputs (parakin fk), or --no-modes for the model alone",
            file=sys.stderr,
        )
        return 1
    if args.out:
        Path(args.out).write_text(text)
        print(f"wrote {args.out}: {m.name} with {text.count('<key ')} assembly modes as keyframes")
    else:
        sys.stdout.write(text)
    return 0


__all__ = ["PRESETS", "Preset", "add_arguments", "run", "to_mjcf"]
