"""Legs given as serial chains of joints (modified-DH tables), their inverse derived by decomposition.

A leg is a ``model.SerialChain``: ^B_P T = base * prod(link transforms) * tool (Craig's modified
DH, ``frames.ModifiedDHLink``), from the base frame {B} to the platform frame {P}, with its
actuated joints marked (``chain_leg``). The generator reads the chain's structure from its table:

* a *group*: consecutive revolute joints whose axes meet in one point, its centre (a = d = 0 in the
  rows after the group's first: each axis passes through the origin of the frame before it),
  consecutive axes not parallel (sin alpha != 0); 3 joints make a spherical group (kind "s"), 2 a
  universal group (kind "u");
* one prismatic joint between two groups, moving the platform-side centre along a fixed line
  through the base-side centre: its value is the distance of the centres (less a fixed offset);
* fixed rows (no joint) anywhere outside the groups.

Supported: S-P-U and U-P-S (a group of 3 and a group of 2 joined by the prismatic joint: six
joints, a 6-dof leg). With A the fixed transform to the base-side centre, M(L) the rows between
the groups (the prismatic one) and C the fixed rows after them to {P}, the chain is
T = A Rot_1 M(L) Rot_2 C (Rot_k the groups' rotations about their centres), and the inverse of a
pose T, with W = A^-1 T C^-1, is three subproblems:

* the prismatic value from |W p| (p the origin), the distance of the centres;
* the universal group *points* a known vector b to a known vector a (Rz(t1) Rx(alpha) Rz(t2) b
  = a; two solutions): the leg line seen from the platform (U at the platform) or from the base
  (U at the base). Branch sign +1: the solution where b, turned by t2, has a non-negative
  component along the common normal of the two axes (the x axis of the first joint's frame).
  Validity ``<leg>_u_joint_not_aligned``: the distance of b from the second axis (zero: the leg
  along that axis, the first angle undetermined); where the pointing is not always possible,
  ``<leg>_u_joint_reachable`` as well;
* the spherical group realises a known rotation N = Rz(t1) Rx(alpha1) Rz(t2) Rx(alpha2) Rz(t3)
  (an Euler decomposition; two solutions). Branch sign +1: sin(t2) >= 0, t2 the middle row's
  theta. Validity ``<leg>_s_joint_not_locked``: |sin(t2)| (zero: gimbal lock, the first and
  third axes aligned).

Per leg the branch signs are (pointing, Euler) in that order, the inverse's order of solution.
Each joint's angle comes from one atan2 and lies in (-pi, pi].

The mechanism (``ChainMechanism``) derives besides:

* the leg determinants' factors named by the joints they hold: ``<leg>_leg_length`` (the
  prismatic value), ``<leg>_s_joint_gimbal_lock``, ``<leg>_u_joint_aligned``;
* for two legs, the closed-loop (type II) factors: the 6 x 6 matrix of the passive joints'
  twists, written in {P} about the first leg's platform-side centre with each joint's later joints
  only (the platform-side axes are then the same vectors in both legs), is expanded by Laplace
  into the 3 x 3 blocks of its linear and angular rows. Where one product survives its factors
  are named: the angular block ``<kind>_joint_axes_parallel`` (the three rotation axes parallel to
  one plane), the linear block ``legs_coplanar_with_platform_<axis>`` (the two leg lines and the
  moment arm's direction, a platform axis), the parameters' factor ``platform_span`` (the moment
  arm: the distance of the platform-side centres); otherwise the whole determinant is one factor,
  ``closed_loop_dependent``;
* the drawing: the base-side centres (``base``), the platform-side centres as each leg's own
  chain reaches them (``<kind>_joints``), each leg as the line between them, and the platform's
  centres from the first leg's pose (two legs: a bar, with a marker at half its length from its
  middle along the first platform axis normal to it, which shows its roll about the bar);
* the limits: the prismatic value is at least minus its fixed offset (the distance is >= 0).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import sympy as sp

from .blocks import block_laplace_det
from .errors import GenerationError
from .frames import ModifiedDHLink, homogeneous, inverse_transform, rot_x, rot_z
from .graph import Chain, Joint, JointGraph
from .model import POSE_POSITION, POSE_ROTATION, Drawing, InverseSolution, SerialChain, pose_matrix
from .trigpoly import factor_list

KINDS = {3: "s", 2: "u"}
SUPPORTED = (
    "supported: a spherical group of 3 and a universal group of 2 revolute joints, each group's axes meeting "
    "in one point (a = d = 0 in the rows after its first), joined by one prismatic joint along the line of "
    "their centres (S-P-U or U-P-S), fixed rows anywhere outside the groups"
)


@dataclass(frozen=True)
class Group:
    """Consecutive revolute joints whose axes meet at one centre: the rows ``rows`` of the table."""

    rows: tuple[int, ...]

    @property
    def kind(self) -> str:
        return KINDS[len(self.rows)]


@dataclass
class ChainLeg:
    """A serial-chain leg and the structure read from its table (module docstring): the base-side
    and platform-side groups, the prismatic row, A (^B of the base-side centre's frame, before
    the group turns), M(L) (the rows between the groups), C (the rows after them and the tool)."""

    chain: SerialChain
    actuated: tuple[sp.Symbol, ...]
    base_group: Group
    platform_group: Group
    prismatic: int
    before: sp.Matrix
    between: sp.Matrix
    after: sp.Matrix
    #: the prismatic line in the base-side group's frame: c(L) = (L + offset) direction
    direction: sp.Matrix
    offset: sp.Expr
    signs: tuple[sp.Symbol, sp.Symbol]

    @property
    def name(self) -> str:
        return self.chain.name

    @property
    def length(self) -> sp.Symbol:
        joint = self.chain.links[self.prismatic].joint
        assert joint is not None
        return joint

    @property
    def passive(self) -> list[sp.Symbol]:
        return [link.joint for link in self.chain.links if link.joint is not None and link.joint not in self.actuated]

    @property
    def pointing(self) -> Group:
        """The universal group: it points the leg line."""
        return self.base_group if self.base_group.kind == "u" else self.platform_group

    @property
    def euler(self) -> Group:
        """The spherical group: it realises the rotation left."""
        return self.base_group if self.base_group.kind == "s" else self.platform_group

    def platform_centre(self) -> sp.Matrix:
        """The platform-side centre in {P}."""
        return inverse_transform(self.after)[:3, 3]

    def angle(self, row: int) -> sp.Expr:
        """theta of a group's row: the joint plus its offset."""
        return self.chain.links[row].theta

    def alpha(self, row: int) -> sp.Expr:
        return self.chain.links[row].alpha


def _rotation(leg_rows: list[ModifiedDHLink], rows: Sequence[int], angles: Sequence[sp.Expr]) -> sp.Matrix:
    """Rz(t_0) Rx(alpha_1) Rz(t_1) ...: a group's rotation about its centre."""
    result = rot_z(angles[0])
    for row, angle in zip(rows[1:], angles[1:], strict=True):
        result = result * rot_x(leg_rows[row].alpha) * rot_z(angle)
    return result


def _fixed(links: list[ModifiedDHLink], rows: range) -> sp.Matrix:
    result = sp.eye(4)
    for row in rows:
        result = result * links[row].transform()
    return result


def _prefix(link: ModifiedDHLink) -> sp.Matrix:
    """A group's first row without its turn: Rx(alpha) Tx(a) Tz(d) (Rz and Tz commute)."""
    return homogeneous(rot_x(link.alpha), [link.a, 0, 0]) * homogeneous(sp.eye(3), [0, 0, link.d])


def chain_leg(chain: SerialChain, actuated: Sequence[sp.Symbol], signs: Sequence[str] | None = None) -> ChainLeg:
    """A leg given by its modified-DH chain (base to platform) with its ``actuated`` joints;
    ``signs`` names its two branch signs (pointing, Euler; default sigma_<leg>_u, sigma_<leg>_s).
    Raises GenerationError naming what the table holds where it is not a supported structure
    (module docstring)."""
    links = chain.links
    kinds = "".join(link.kind()[0].upper() for link in links)  # R, P or F (fixed)
    moving = [k for k, link in enumerate(links) if link.joint is not None]
    found = f"leg {chain.name}: rows {kinds} (R revolute, P prismatic, F fixed; base to platform)"
    pattern = "".join(kinds[k] for k in moving)
    if pattern not in ("RRRPRR", "RRPRRR"):
        raise GenerationError(f"{found}, joints {pattern}; {SUPPORTED}")
    first = 3 if pattern == "RRRPRR" else 2
    groups = [tuple(moving[:first]), tuple(moving[first + 1 :])]
    for rows in groups:
        if list(rows) != list(range(rows[0], rows[-1] + 1)):
            raise GenerationError(f"{found}: a fixed row inside the group of rows {rows}; {SUPPORTED}")
        for row in rows:
            link = links[row]
            offset = sp.simplify(link.theta - link.joint)
            if offset.has(link.joint) or link.a.has(link.joint) or link.d.has(link.joint):
                raise GenerationError(f"{found}: row {row + 1} turns by {link.theta}, not its joint plus a constant")
        for row in rows[1:]:
            link = links[row]
            if link.a != 0 or link.d != 0 or sp.sin(link.alpha) == 0:
                raise GenerationError(
                    f"{found}: the axes of rows {row} and {row + 1} do not meet in the group's centre (row {row + 1}: "
                    f"alpha = {link.alpha}, a = {link.a}, d = {link.d}; a = d = 0 and alpha not 0 or pi); {SUPPORTED}"
                )
    prismatic = moving[first]
    base_rows, platform_rows = groups
    before = chain.base * _fixed(links, range(base_rows[0])) * _prefix(links[base_rows[0]])
    between = _fixed(links, range(base_rows[-1] + 1, platform_rows[0])) * _prefix(links[platform_rows[0]])
    after = _fixed(links, range(platform_rows[-1] + 1, len(links))) * chain.tool
    length = links[prismatic].joint
    centre = between[:3, 3]
    direction = sp.simplify(sp.diff(centre, length))
    at_zero = sp.simplify(centre.subs(length, 0))
    if (
        direction.has(length)
        or sp.simplify(direction.dot(direction) - 1) != 0
        or sp.simplify(at_zero.cross(direction)) != sp.zeros(3, 1)
    ):
        raise GenerationError(
            f"{found}: the prismatic row {prismatic + 1} moves the platform-side centre to {list(centre)} in the "
            f"base-side group's frame, not along a line through the base-side centre; {SUPPORTED}"
        )
    names = signs or (f"sigma_{chain.name}_u", f"sigma_{chain.name}_s")
    if len(names) != 2:
        raise GenerationError(f"leg {chain.name}: signs names the pointing and the Euler sign, got {list(names)}")
    unknown = [joint for joint in actuated if joint not in [links[k].joint for k in moving]]
    if unknown:
        raise GenerationError(f"leg {chain.name}: actuated {unknown} are not joints of its chain")
    return ChainLeg(
        chain, tuple(actuated), Group(base_rows), Group(platform_rows), prismatic, before, between, after,
        direction, sp.simplify(at_zero.dot(direction)), (sp.Symbol(names[0], real=True), sp.Symbol(names[1], real=True)),
    )  # fmt: skip


def _atan2_joint(sine: sp.Expr, cosine: sp.Expr, offset: sp.Expr) -> sp.Expr:
    """The joint q = t - offset of the angle t = atan2(sine, cosine) (any common positive scale):
    atan2 of the rotated pair, so that q lies in (-pi, pi]."""
    c, s = sp.cos(offset), sp.sin(offset)
    return sp.atan2(sine * c - cosine * s, cosine * c + sine * s)


def _joint(leg: ChainLeg, row: int) -> tuple[sp.Symbol, sp.Expr]:
    link = leg.chain.links[row]
    assert link.joint is not None
    return link.joint, sp.simplify(link.theta - link.joint)


def _named(prefix: str, vector: sp.Matrix) -> tuple[sp.Matrix, list[tuple[sp.Symbol, sp.Expr]]]:
    """A vector as step symbols <prefix>_x.. (entries that are a number or a symbol kept as they are)."""
    entries, steps = [], []
    for axis, value in zip("xyz", vector, strict=True):
        if value.is_Atom:
            entries.append(value)
        else:
            symbol = sp.Symbol(f"{prefix}_{axis}", real=True)
            entries.append(symbol)
            steps.append((symbol, value))
    return sp.Matrix(entries), steps


def _pointing(
    leg: ChainLeg, group: Group, a: sp.Matrix, b: sp.Matrix, sign: sp.Symbol
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], dict[str, sp.Expr]]:
    """Rz(t1) Rx(alpha) Rz(t2) b = a for the group's two joints (module docstring)."""
    tag = f"{leg.name}_{group.kind}"
    alpha = leg.alpha(group.rows[1])
    bs, steps = _named(f"b_{tag}", b)
    a_s, a_steps = _named(f"a_{tag}", a)
    steps += a_steps
    rho, along = sp.symbols(f"rho_{tag} along_{tag}", real=True)
    # the second joint turns b to (along, k, b_z): its y component is fixed by a's z component
    k = sp.simplify((a[2] - sp.cos(alpha) * bs[2]) / sp.sin(alpha))
    steps.append((rho, sp.sqrt(bs[0] ** 2 + bs[1] ** 2)))
    validity = {f"{tag}_joint_not_aligned": rho}
    if k == 0:
        steps.append((along, sign * rho))
    else:
        height, disc = sp.symbols(f"k_{tag} disc_{tag}", real=True)
        steps += [(height, k), (disc, rho**2 - height**2), (along, sign * sp.sqrt(sp.Max(0, disc)))]
        validity[f"{tag}_joint_reachable"] = disc / bs.dot(bs)
        k = height
    second, second_offset = _joint(leg, group.rows[1])
    first, first_offset = _joint(leg, group.rows[0])
    steps.append((second, _atan2_joint(bs[0] * k - bs[1] * along, bs[0] * along + bs[1] * k, second_offset)))
    w = rot_x(alpha) * sp.Matrix([along, k, bs[2]])
    steps.append((first, _atan2_joint(w[0] * a_s[1] - w[1] * a_s[0], w[0] * a_s[0] + w[1] * a_s[1], first_offset)))
    return steps, validity


def _euler(
    leg: ChainLeg, group: Group, target: sp.Matrix, sign: sp.Symbol
) -> tuple[list[tuple[sp.Symbol, sp.Expr]], dict[str, sp.Expr]]:
    """Rz(t1) Rx(alpha1) Rz(t2) Rx(alpha2) Rz(t3) = target for the group's three joints."""
    tag = f"{leg.name}_{group.kind}"
    alpha1, alpha2 = leg.alpha(group.rows[1]), leg.alpha(group.rows[2])
    c1, s1, c2, s2 = sp.cos(alpha1), sp.sin(alpha1), sp.cos(alpha2), sp.sin(alpha2)
    n = sp.Matrix(3, 3, lambda i, j: sp.Symbol(f"n{i + 1}{j + 1}_{tag}", real=True))
    used = [(0, 2), (1, 2), (2, 2), (2, 0), (2, 1)]
    steps = [(n[i, j], target[i, j]) for i, j in used]
    cosine, size = sp.symbols(f"cos_{tag} sin_abs_{tag}", real=True)
    # the third axis in the first joint's frame: Rz(t1) (u1, u2, u3), u3 = N33 gives cos(t2)
    steps.append((cosine, (c1 * c2 - n[2, 2]) / (s1 * s2)))
    u2 = -(c1 * s2 * cosine + s1 * c2)
    squared = n[0, 2] ** 2 + n[1, 2] ** 2 - u2**2
    steps.append((size, sp.sqrt(squared if u2 == 0 else sp.Max(0, squared)) / sp.Abs(s2)))
    (first, o1), (middle, o2), (last, o3) = (_joint(leg, row) for row in group.rows)
    sine = sign * size
    steps.append((middle, _atan2_joint(sine, cosine, o2)))
    u1 = s2 * sine
    steps.append((first, _atan2_joint(u1 * n[1, 2] - u2 * n[0, 2], u1 * n[0, 2] + u2 * n[1, 2], o1)))
    # the third row of N: (v1, v2) turned by -t3
    v1, v2 = s1 * sine, s1 * c2 * cosine + c1 * s2
    steps.append((last, _atan2_joint(v2 * n[2, 0] - v1 * n[2, 1], v1 * n[2, 0] + v2 * n[2, 1], o3)))
    return steps, {f"{tag}_joint_not_locked": size}


def _leg_inverse(leg: ChainLeg) -> tuple[list[tuple[sp.Symbol, sp.Expr]], dict[str, sp.Expr]]:
    """The leg's joints from the pose symbols: distance, pointing, Euler (module docstring)."""
    tag = leg.name
    w = inverse_transform(leg.before) * pose_matrix() * inverse_transform(leg.after)
    span, steps = _named(f"span_{tag}", w[:3, 3])
    steps.append((leg.length, sp.sqrt(span.dot(span)) - leg.offset))
    line = leg.between[:3, 3]  # c(L): the platform-side centre in the base-side group's frame
    turn = leg.between[:3, :3]
    rotation = w[:3, :3]
    if leg.platform_group.kind == "u":  # seen from the platform: Rot_2 (W^-1 p) = M^-1 p
        point_steps, validity = _pointing(leg, leg.platform_group, -turn.T * line, -rotation.T * span, leg.signs[0])
        platform_turn = _rotation(
            leg.chain.links, leg.platform_group.rows, [leg.angle(r) for r in leg.platform_group.rows]
        )
        target = rotation * platform_turn.T * turn.T
    else:  # seen from the base: Rot_1 c(L) = W p
        point_steps, validity = _pointing(leg, leg.base_group, span, line, leg.signs[0])
        base_turn = _rotation(leg.chain.links, leg.base_group.rows, [leg.angle(r) for r in leg.base_group.rows])
        target = turn.T * base_turn.T * rotation
    euler_steps, locked = _euler(leg, leg.euler, target, leg.signs[1])
    return steps + point_steps + euler_steps, validity | locked


def graph_leg(leg: ChainLeg) -> Chain:
    """A leg's table as the joint graph's serial chain: each joint R or P with its axis and point
    in {B} at zero joint values (the frames of the table there), its variable and actuated mark.

    Parameters
    ----------
    leg : ChainLeg
        The leg (``chain_leg``).

    Returns
    -------
    Chain
        Its joints, site "chain" (placed by their products of exponentials).
    """
    zero = {joint: 0 for joint in leg.chain.joints}
    frames = leg.chain.frames()
    joints = []
    for index, link in enumerate(leg.chain.links, start=1):
        if link.joint is None:
            continue
        frame = frames[index].xreplace(zero)
        kind = link.kind()
        axis = (
            frames[index - 1][:3, 0].xreplace(zero)
            if kind == "P" and link.prismatic_axis() == "x_prev"
            else frame[:3, 2]
        )
        joints.append(Joint(kind, "chain", frame[:3, 3], axis, link.joint, actuated=link.joint in leg.actuated))
    return Chain(leg.name, tuple(joints))


@dataclass
class ChainMechanism:
    """A platform held by serial-chain legs (``chain_leg``): the derivations of the module
    docstring. Pass ``fields()`` to ``model.Mechanism``, with the file's parameters, examples,
    citation and home."""

    legs: list[ChainLeg]

    @property
    def actuated(self) -> list[sp.Symbol]:
        return [joint for leg in self.legs for joint in leg.actuated]

    @property
    def passive(self) -> list[sp.Symbol]:
        return [joint for leg in self.legs for joint in leg.passive]

    def inverse(self) -> InverseSolution:
        """Each leg's closed form; branch signs (pointing, Euler) per leg, in leg order."""
        steps: list[tuple[sp.Symbol, sp.Expr]] = []
        validity: dict[str, sp.Expr] = {}
        for leg in self.legs:
            leg_steps, leg_validity = _leg_inverse(leg)
            steps += leg_steps
            validity |= leg_validity
        return InverseSolution(steps, [sign for leg in self.legs for sign in leg.signs], validity)

    def serial_factor_names(self) -> dict[sp.Expr, str]:
        """Each leg determinant's factors named by the joints they hold (module docstring)."""
        names: dict[sp.Expr, str] = {}
        for leg in self.legs:
            joints = {
                "leg_length": {leg.length},
                f"{leg.euler.kind}_joint_gimbal_lock": {leg.chain.links[r].joint for r in leg.euler.rows},
                f"{leg.pointing.kind}_joint_aligned": {leg.chain.links[r].joint for r in leg.pointing.rows},
            }
            for factor, _ in leg.chain.factored_determinant[1]:
                held = factor.free_symbols & set(leg.chain.joints)
                named = [name for name, group in joints.items() if held and held <= group]
                if len(named) == 1:
                    names[factor] = f"{leg.name}_{named[0]}"
        return names

    def parallel_factors(self) -> dict[str, sp.Expr]:
        """The closed-loop (type II) determinant's named factors (module docstring)."""
        if len(self.legs) != 2:
            raise GenerationError(
                f"closed-loop factors of serial-chain legs are derived for two legs, got {len(self.legs)}"
            )
        reference = self.legs[0].platform_centre()
        columns = []
        for sign, leg in zip((1, -1), self.legs, strict=True):
            jacobian = leg.chain.platform_jacobian(reference)
            columns += [sign * jacobian[:, k] for k, joint in enumerate(leg.chain.joints) if joint in leg.passive]
        matrix = sp.Matrix.hstack(*columns)
        if matrix.cols != 6:
            raise GenerationError(f"closed-loop factors need 6 passive joints in all, got {matrix.cols}")
        terms = []
        for chosen in itertools.combinations(range(6), 3):
            rest = [k for k in range(6) if k not in chosen]
            linear, angular = matrix.extract([0, 1, 2], list(chosen)), matrix.extract([3, 4, 5], rest)
            pair = (sp.expand(linear.det()), sp.expand(angular.det()))
            if pair[0] != 0 and pair[1] != 0:
                terms.append((chosen, (-1) ** (sum(chosen) + 3), *pair))
        if len(terms) != 1:
            return {"closed_loop_dependent": block_laplace_det(matrix.T)}
        chosen, sign, linear, angular = terms[0]
        constant, parameters = sp.Integer(sign), sp.Integer(1)
        named: dict[str, sp.Expr] = {}
        state = set(self.actuated) | set(self.passive)
        for block, name in ((angular, self._angular_name(chosen)), (linear, self._linear_name(matrix, chosen))):
            block_constant, factors = factor_list(block)
            constant *= block_constant
            moving = [factor**power for factor, power in factors if factor.free_symbols & state]
            parameters *= sp.Mul(*(factor**power for factor, power in factors if not factor.free_symbols & state))
            for k, factor in enumerate(moving):
                named[name if len(moving) == 1 else f"{name}_{k + 1}"] = factor
        if parameters != 1:
            named["platform_span"] = constant * parameters
        else:  # no parameter factor: the constant goes with the first factor
            first = next(iter(named))
            named[first] = constant * named[first]
        return named

    def _angular_name(self, chosen: tuple[int, ...]) -> str:
        rest = [k for k in range(6) if k not in chosen]
        kinds = sorted({self._group_of(k).kind for k in rest})
        return f"{'_'.join(kinds)}_joint_axes_parallel"

    def _group_of(self, column: int) -> Group:
        """The group of the passive joint of a column of the closed-loop matrix."""
        joints = self.legs[0].passive + self.legs[1].passive
        leg = self.legs[0] if column < len(self.legs[0].passive) else self.legs[1]
        row = next(k for k, link in enumerate(leg.chain.links) if link.joint == joints[column])
        return leg.base_group if row in leg.base_group.rows else leg.platform_group

    def _linear_name(self, matrix: sp.Matrix, chosen: tuple[int, ...]) -> str:
        """legs_coplanar_with_platform_<axis> where the columns are the prismatic lines and one
        moment along a platform axis; translations_dependent otherwise."""
        lines = {self.legs[0].length, self.legs[1].length}
        joints = self.legs[0].passive + self.legs[1].passive
        axes = []
        for k in chosen:
            if joints[k] in lines:
                continue
            column = matrix[:3, k]
            if column.free_symbols & (set(self.actuated) | set(self.passive)):
                return "translations_dependent"
            unit = [axis for axis in range(3) if column[axis] != 0]
            if len(unit) != 1:
                return "translations_dependent"
            axes.append("xyz"[unit[0]])
        return f"legs_coplanar_with_platform_{'_'.join(axes)}" if len(axes) == 1 else "translations_dependent"

    def drawing(self) -> Drawing:
        """Base-side centres, platform-side centres (each leg's own chain), the legs between them
        and the platform (module docstring)."""
        count = len(self.legs)
        centres = f"{self.legs[0].platform_group.kind}_joints"
        reached = []
        for leg in self.legs:
            frames = leg.chain.frames()
            reached.append(frames[leg.platform_group.rows[0] + 1][:3, 3])
        on_platform = [leg.platform_centre() for leg in self.legs]
        outline = list(range(count))
        if count == 2:
            bar = on_platform[1] - on_platform[0]
            normal = next((axis for axis in sp.eye(3).columnspace() if sp.simplify(axis.dot(bar)) == 0), None)
            if normal is not None:
                on_platform.append((on_platform[0] + on_platform[1]) / 2 + sp.sqrt(bar.dot(bar)) / 2 * normal)
                outline = [0, 2, 1]
        pose = self.legs[0].chain.end_transform()
        platform = (pose * sp.Matrix.vstack(sp.Matrix.hstack(*on_platform), sp.ones(1, len(on_platform))))[:3, :]
        polylines = {"base": [("base", k) for k in range(count)]}
        polylines |= {f"{leg.name}_leg": [("base", k), (centres, k)] for k, leg in enumerate(self.legs)}
        polylines["platform"] = [("platform", k) for k in [*outline, outline[0]]]
        points = {
            "base": sp.Matrix.hstack(*(leg.before[:3, 3] for leg in self.legs)),
            centres: sp.Matrix.hstack(*reached),
            "platform": platform,
        }
        return Drawing(points=points, polylines=polylines)

    def limits(self) -> dict[sp.Symbol, tuple[float, float]]:
        """Each prismatic value is at least minus its offset (a distance is >= 0)."""
        return {leg.length: (float(-leg.offset), float("inf")) for leg in self.legs if leg.offset.is_number}

    def home_at(
        self, rotation: sp.Matrix, position: sp.Matrix, branch: int, parameters: dict[sp.Symbol, float]
    ) -> dict[sp.Symbol, float]:
        """The actuated and passive values of a pose on inverse branch ``branch``."""
        values = self.inverse().at(rotation, position, branch, parameters)
        return {v: values[v] for v in (*self.actuated, *self.passive)}

    def graph(self) -> JointGraph:
        """The legs as the joint graph's serial chains (``graph_leg``), the platform where the
        first leg reaches it, its coordinates the passive joints."""
        pose = self.legs[0].chain.end_transform()
        chains = [graph_leg(leg) for leg in self.legs]
        return JointGraph("transform", tuple(self.passive), pose[:3, :3], pose[:3, 3], chains)

    def fields(self) -> dict[str, object]:
        """The ``model.Mechanism`` fields the legs determine."""
        revolute = [j for leg in self.legs for j in (*leg.actuated, *leg.passive) if j != leg.length]
        angular = [j for j in self.actuated if j in revolute] + [j for j in self.passive if j in revolute]
        return {
            "actuated": self.actuated,
            "passive": self.passive,
            "legs": [leg.chain for leg in self.legs],
            "inverse": self.inverse(),
            "serial_factor_names": self.serial_factor_names(),
            "parallel_factors": self.parallel_factors(),
            "angular": angular,
            "limits": self.limits(),
            "drawing": self.drawing(),
            "joint_graph": self.graph(),
        }


__all__ = ["ChainLeg", "ChainMechanism", "Group", "POSE_POSITION", "POSE_ROTATION", "chain_leg"]
