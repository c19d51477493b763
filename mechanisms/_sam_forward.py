"""Accelerator of ``sam.py`` (optional): the SAM's forward pose in closed form (not in the paper,
which uses Newton only), a quadratic on the line of a linear equation, 2 x 2 modes. Without it
the generator finds the forward pose by its automatic homotopy. Derivation:
``docs/derivations/sam.md``.
"""

from __future__ import annotations

import sympy as sp
from parakin.generator.frames import homogeneous
from parakin.generator.model import ForwardElimination, SerialChain


def forward_elimination(left: SerialChain, right: SerialChain, L4: sp.Symbol) -> ForwardElimination:
    """Closed-form forward pose (not in the paper, which uses Newton only).

    In Table I, z4 = z5 (alpha4 = 0) depends on the S-joint angles only, and z6 of both legs is the
    platform Z axis; the U joint makes z6 normal to z5. So Z_P = sign * (z4_L x z4_R) / |.|.
    The U joints are U_L = S_L + L2 x3_L and U_R = S_R + L3 x3_R (x3 is the leg line), and
    U_R - U_L = 2 L4 Y_P with Y_P normal to Z_P: one linear equation (dot with Z_P) and one
    quadratic (|U_R - U_L| = 2 L4). On the line (L2, L3) = p0 + t d of the linear equation the
    quadratic becomes a univariate quadratic in t. Both signs of Z_P give a pose: 2 x 2 modes.
    """
    frames_left, frames_right = left.frames(), right.frames()
    z4_left, z4_right = frames_left[4][:3, 2], frames_right[4][:3, 2]
    x3_left, x3_right = frames_left[3][:3, 0], frames_right[3][:3, 0]
    s_left, s_right = left.base[:3, 3], right.base[:3, 3]
    t, sign = sp.symbols("t sigma", real=True)
    normal = sp.Matrix(sp.symbols("n_x n_y n_z", real=True))
    # the linear equation a L2 + b L3 + c = 0 (dot with the unnormalised normal)
    a_lin, b_lin, c_lin = sp.symbols("a_lin b_lin c_lin", real=True)
    line_norm2 = sp.Symbol("line_norm2", positive=True)
    normal_norm = sp.Symbol("normal_norm", positive=True)
    length_left, length_right = sp.symbols("L2_t L3_t", real=True)
    normal_expr = z4_left.cross(z4_right)
    span = (s_right - s_left) + length_right * x3_right - length_left * x3_left
    # coefficients of |span|^2 - (2 L4)^2 in t, with L2 = p0_2 + t d_2, L3 = p0_3 + t d_3
    base_point = sp.Matrix([-c_lin * a_lin, -c_lin * b_lin]) / line_norm2
    direction = sp.Matrix([b_lin, -a_lin])
    on_line = {length_left: base_point[0] + t * direction[0], length_right: base_point[1] + t * direction[1]}
    quadratic = sp.expand((span.dot(span) - (2 * L4) ** 2).subs(on_line))
    coefficients = [quadratic.coeff(t, k) for k in range(3)]
    auxiliary = [
        (normal[0], normal_expr[0]),
        (normal[1], normal_expr[1]),
        (normal[2], normal_expr[2]),
        (a_lin, -x3_left.dot(normal)),
        (b_lin, x3_right.dot(normal)),
        (c_lin, (s_right - s_left).dot(normal)),
        (line_norm2, a_lin**2 + b_lin**2),
        (normal_norm, sp.sqrt(normal.dot(normal))),
    ]
    # back substitution: pose from the root t and the sign of Z_P
    y_axis_sym = sp.Matrix(sp.symbols("yP_x yP_y yP_z", real=True))
    z_axis_sym = sp.Matrix(sp.symbols("zP_x zP_y zP_z", real=True))
    u_left_sym = sp.Matrix(sp.symbols("UL_x UL_y UL_z", real=True))
    back = [
        (length_left, on_line[length_left]),
        (length_right, on_line[length_right]),
    ]
    back += [(z_axis_sym[k], sign * normal[k] / normal_norm) for k in range(3)]
    u_left = s_left + length_left * x3_left
    back += [(u_left_sym[k], u_left[k]) for k in range(3)]
    back += [(y_axis_sym[k], span[k] / (2 * L4)) for k in range(3)]
    x_axis = y_axis_sym.cross(z_axis_sym)
    origin = u_left_sym + L4 * y_axis_sym  # left U joint sits at y = -L4 in {P}
    pose = homogeneous(sp.Matrix.hstack(x_axis, y_axis_sym, z_axis_sym), origin)
    return ForwardElimination(
        unknown=t,
        coefficients=coefficients,
        branches=[sign],
        auxiliary=auxiliary,
        back_substitution=back,
        pose=pose,
        degeneracies={"u_joint_axes_parallel": normal_norm, "legs_parallel_to_platform": line_norm2},
    )
