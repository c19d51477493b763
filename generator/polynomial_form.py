"""The polynomial form of a loop closure, derived: the square polynomial system whose isolated
solutions are the assembly modes, for the all-modes homotopy (``generator/start_systems.py``).

From the closure residual r(passive; actuated, parameters) (``derive``'s, either model style):
* a passive revolute variable phi becomes two unknowns (c_phi, s_phi) with c^2 + s^2 - 1 = 0
  (trigonometric functions of integer combinations of angles are expanded first);
* a square root of an expression in the unknowns becomes an auxiliary unknown w with
  w^2 - E = 0, then eliminated again where an equation is affine in w with a coefficient free of
  unknowns (|d| - l = 0 gives |d|^2 - l^2 = 0);
* quotients are cleared: each equation becomes the numerator of its ``together`` form;
* an angle x that is not an unknown (an actuated revolute variable, an angular parameter) enters
  through a rational parametrisation of the circle that is finite for every real x:
  u = (sin(x/2) - a cos(x/2)) / (sin(x/2) - b cos(x/2)) with fixed complex a, b, so that
  t = tan(x/2) = (a - b u) / (1 - u), cos x = ((1-u)^2 - (a-bu)^2) / D, sin x = 2 (a-bu)(1-u) / D,
  D = (1-u)^2 + (a-bu)^2 (D = 0 only at two complex u, off every path with probability one). The
  family's parameter is u: the homotopy moves on the circle c^2 + s^2 = 1 itself, so the generic
  root count is that of the mechanism, not of a larger family with c and s independent;
* any other non-polynomial expression free of the unknowns (sqrt of parameters, Max, ...) is a
  parameter of the family of its own, computed from the inputs;
* exact constants (sqrt(3), rationals) stay exact.
The family's parameters are the actuated variables, the parameters and those derived ones, each
with its expression in the inputs; the passive variables are read back from a real solution
(phi = atan2(s, c)).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import sympy as sp

from .errors import GenerationError

#: the two complex constants of the circle parametrisation (3 decimals: exact in every printer)
MOEBIUS_A = sp.Rational(317, 1000) + sp.Rational(-1291, 1000) * sp.I
MOEBIUS_B = sp.Rational(-1733, 1000) + sp.Rational(557, 1000) * sp.I


@dataclass
class PolynomialForm:
    """A square polynomial system F(z; p) = 0 in ``unknowns`` whose coefficients are polynomials
    in the ``family`` symbols p; each family symbol has its expression in the actuated variables
    and parameters (the symbol itself for those). ``passive`` gives the passive variables of a
    real solution; ``homogeneous`` lists unknowns that a random patch fixes (ForwardHomotopy)."""

    unknowns: list[sp.Symbol]
    equations: list[sp.Expr]
    family: list[tuple[sp.Symbol, sp.Expr]]
    passive: list[sp.Expr]
    homogeneous: list[sp.Symbol] = field(default_factory=list)
    #: how each unknown and family parameter came about, for the manifest and ``inspect``
    notes: list[str] = field(default_factory=list)
    #: angles that are no unknowns: (u, the angle in the inputs, (C, S, D)): the equations are
    #: homogeneous in (C, S, D) per angle, which stand for (cos, sin, 1) at the inputs and move
    #: on the circle C^2 + S^2 = D^2 through ``circle_parametrisation(u)`` along the homotopy
    circles: list[tuple[sp.Symbol, sp.Expr, tuple[sp.Symbol, sp.Symbol, sp.Symbol]]] = field(default_factory=list)


def circle_parametrisation(u: sp.Expr) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """(numerator of cos, numerator of sin, common denominator) in the circle parameter u."""
    one_minus, a_minus = 1 - u, MOEBIUS_A - MOEBIUS_B * u
    return one_minus**2 - a_minus**2, 2 * a_minus * one_minus, one_minus**2 + a_minus**2


def circle_parameter(angle: sp.Expr) -> sp.Expr:
    """u of a real angle (module docstring): finite for every real angle."""
    half_sin, half_cos = sp.sin(angle / 2), sp.cos(angle / 2)
    return (half_sin - MOEBIUS_A * half_cos) / (half_sin - MOEBIUS_B * half_cos)


def _trig_atoms(expr: sp.Expr) -> list[sp.Expr]:
    """The sines, cosines and tangents in ``expr``, in SymPy's canonical order: the family's
    symbols are named in this order, which must not depend on the process's hash seed."""
    found = {a for a in sp.preorder_traversal(expr) if isinstance(a, (sp.sin, sp.cos, sp.tan))}
    return sorted(found, key=sp.default_sort_key)


def derive(
    residual: list[sp.Expr],
    passive: list[sp.Symbol],
    actuated: list[sp.Symbol],
    parameters: list[sp.Symbol],
    angular: list[sp.Symbol],
) -> PolynomialForm:
    """The polynomial form of ``residual`` (module docstring)."""
    known = set(actuated) | set(parameters)
    unknowns: list[sp.Symbol] = []
    recover: list[sp.Expr] = []
    circle: list[sp.Expr] = []
    notes: list[str] = []
    trig: dict[sp.Expr, sp.Expr] = {}
    for variable in passive:
        if variable in angular:
            c, s = sp.symbols(f"c_{variable} s_{variable}")
            unknowns += [c, s]
            circle.append(c**2 + s**2 - 1)
            trig[sp.cos(variable)], trig[sp.sin(variable)] = c, s
            recover.append(sp.atan2(s, c))
            notes.append(f"{variable}: (c_{variable}, s_{variable}) on the circle c^2 + s^2 = 1")
        else:
            z = sp.Symbol(f"z_{variable}")
            unknowns.append(z)
            recover.append(z)
            trig[variable] = z
    passive_set = set(passive)

    family: list[tuple[sp.Symbol, sp.Expr]] = []
    derived: dict[sp.Expr, sp.Symbol] = {}

    def family_symbol(expression: sp.Expr, prefix: str) -> sp.Symbol:
        if expression not in derived:
            symbol = sp.Symbol(f"{prefix}{len(derived)}")
            derived[expression] = symbol
            family.append((symbol, expression))
        return derived[expression]

    # cos and sin of a known angle as C / D and S / D, symbols until the quotients are cleared
    circle_symbols: dict[sp.Symbol, tuple[sp.Symbol, sp.Symbol, sp.Symbol]] = {}
    equations = []
    for k, entry in enumerate(residual):
        expr = sp.sympify(entry)
        # trigonometric functions of sums of angles into products, one atom at a time
        expand = {a: sp.expand_trig(a) for a in _trig_atoms(expr) if isinstance(a.args[0], sp.Add) or a.args[0].is_Mul}
        expr = expr.xreplace(expand)
        replacements: dict[sp.Expr, sp.Expr] = {}
        for atom in _trig_atoms(expr):
            argument = atom.args[0]
            if argument.free_symbols & passive_set:
                if atom not in trig:
                    raise GenerationError(
                        f"closure row {k}: {atom} is not a sine or cosine of one passive revolute variable; "
                        "write the closure in cos and sin of the joint angles"
                    )
                continue
            if not argument.free_symbols <= known:
                raise GenerationError(f"closure row {k}: {atom} uses {sorted(map(str, argument.free_symbols - known))}")
            u = family_symbol(argument, "u_")
            if u not in circle_symbols:
                circle_symbols[u] = sp.symbols(f"C_{u} S_{u} D_{u}")
            cos_n, sin_n, denominator = circle_symbols[u]
            value = {sp.cos: cos_n / denominator, sp.sin: sin_n / denominator, sp.tan: sin_n / cos_n}[type(atom)]
            replacements[atom] = value
        expr = expr.xreplace(replacements).xreplace(trig)
        equations.append(expr)

    unknown_set = set(unknowns)
    auxiliary: list[tuple[sp.Symbol, sp.Expr]] = []

    def polynomialise(expr: sp.Expr) -> sp.Expr:
        """Non-polynomial atoms replaced: roots of unknown-expressions by auxiliary unknowns,
        anything else free of unknowns by a family parameter."""
        if expr.is_Atom:
            return expr
        if not (expr.free_symbols & unknown_set) and not (expr.free_symbols & {w for w, _ in auxiliary}):
            if _is_rational_in_symbols(expr):
                return expr
            return family_symbol(expr, "p_")
        if isinstance(expr, sp.Pow) and not expr.exp.is_Integer:
            if expr.exp.is_Rational and expr.exp.q == 2:
                base = polynomialise(expr.base)
                existing = [w for w, value in auxiliary if value == base]
                root = existing[0] if existing else sp.Symbol(f"w{len(auxiliary)}")
                if not existing:
                    auxiliary.append((root, base))
                return root ** int(expr.exp.p)
            raise GenerationError(f"cannot make {expr} polynomial: only square roots of the unknowns are supported")
        if isinstance(expr, (sp.Add, sp.Mul, sp.Pow)):
            return expr.func(*(polynomialise(a) for a in expr.args))
        raise GenerationError(
            f"cannot make {type(expr).__name__}({', '.join(map(str, expr.args))[:80]}) of the passive variables "
            "polynomial; write the closure with polynomials, quotients, square roots and cos/sin of joint angles"
        )

    equations = _unit_denominators([polynomialise(e) for e in equations], unknown_set)
    # an auxiliary root fixed by an equation affine in it (|d| - l = 0) is substituted back
    auxiliary_equations = {w: w**2 - value for w, value in auxiliary}
    for w, _ in list(auxiliary):
        for k, equation in enumerate(equations):
            numerator = sp.expand(sp.fraction(sp.together(equation))[0])
            if numerator.has(w) and sp.degree(numerator, w) == 1:
                slope = numerator.coeff(w, 1)
                if not (slope.free_symbols & (unknown_set | set(auxiliary_equations))):
                    value = -numerator.coeff(w, 0) / slope
                    equations[k] = auxiliary_equations.pop(w).subs(w, value)
                    equations = [e.subs(w, value) if i != k else e for i, e in enumerate(equations)]
                    break
    for w, _ in auxiliary:
        if w in auxiliary_equations:
            unknowns.append(w)
            equations.append(auxiliary_equations[w])
            notes.append(f"{w}: auxiliary unknown, {w}^2 = {dict(auxiliary)[w]}")
    equations = [_numerator(e, unknowns) for e in equations] + circle
    if len(equations) != len(unknowns):
        raise GenerationError(f"the polynomial form has {len(equations)} equations for {len(unknowns)} unknowns")
    actuated_or_parameter = [(v, v) for v in list(actuated) + list(parameters)]
    for symbol, expression in family:
        if symbol in circle_symbols:
            notes.append(f"cos, sin of {expression} = (C, S) / D on the circle, parametrised by {symbol}")
        else:
            notes.append(f"{symbol} = {expression}: a parameter of the family")
    circles = [(u, angle, circle_symbols[u]) for u, angle in family if u in circle_symbols]
    free = [(symbol, expression) for symbol, expression in family if symbol not in circle_symbols]
    return PolynomialForm(unknowns, equations, actuated_or_parameter + free, recover, [], notes, circles)


def _unit_denominators(equations: list[sp.Expr], unknowns: set[sp.Symbol]) -> list[sp.Expr]:
    """A denominator that equals 1 on the solutions (|q|^2 of R(q) = q v q* / |q|^2 beside the
    equation q . q - 1 = 0) is replaced by 1: the same solutions at a lower degree."""
    constraints = [
        sp.expand(sp.fraction(sp.together(e))[0]) for e in equations if e.free_symbols and e.free_symbols <= unknowns
    ]

    def is_unit(base: sp.Expr) -> bool:
        if not (base.free_symbols and base.free_symbols <= unknowns):
            return False
        shifted = sp.expand(base - 1)
        for constraint in constraints:
            ratio = sp.cancel(shifted / constraint)
            if ratio.is_number and ratio != 0:
                return True
        return False

    def unit(expr: sp.Expr) -> sp.Expr:
        if isinstance(expr, sp.Pow) and expr.exp.is_Integer and expr.exp < 0 and is_unit(expr.base):
            return sp.Integer(1)
        return expr

    return [e.replace(lambda a: isinstance(a, sp.Pow), unit) for e in equations]


def _is_rational_in_symbols(expr: sp.Expr) -> bool:
    if expr.is_Atom or expr.is_number:
        return True
    if isinstance(expr, sp.Pow):
        return bool(expr.exp.is_Integer) and _is_rational_in_symbols(expr.base)
    if isinstance(expr, (sp.Add, sp.Mul)):
        return all(_is_rational_in_symbols(a) for a in expr.args)
    return bool(expr.is_number)


def _numerator(expr: sp.Expr, unknowns: list[sp.Symbol]) -> sp.Expr:
    """The numerator of ``expr`` over a common denominator, expanded: polynomial in the unknowns
    (a denominator's zeros are no solutions; the runtime checks every mode on the closure)."""
    numerator = sp.expand(sp.fraction(sp.together(expr))[0])
    try:
        sp.Poly(numerator, *unknowns)
    except sp.PolynomialError as error:
        raise GenerationError(
            f"an equation of the polynomial form is not polynomial in the unknowns: {error}"
        ) from None
    return numerator
