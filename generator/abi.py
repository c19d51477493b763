"""The C ABI of every generated package, described once: status codes and the job structures.

The templates print the C declarations from these lists; the manifest carries them, and the
Python compiled backend builds its ``ctypes`` structures and reads its codes from the manifest.
Changing a list here changes the manifest, so bump ``manifest.SCHEMA`` with it.
"""

from __future__ import annotations

#: Newton status per input (forward_pose, polish of every mode)
NEWTON_STATUS = ["ok", "nonfinite", "no_convergence", "singular", "wrong_basin"]

#: what became of one candidate (root x branch) of forward_pose_all; "mode" is a valid mode
MODE_OUTCOMES = [
    "mode",  # a valid assembly mode (polished, closed, within limits, new)
    "no_root",  # the slot has no isolated root (fewer real roots than the degree)
    "back_substitution_undefined",  # the back substitution is not finite at this root
    "not_closed",  # the candidate does not close the loop (another branch of this root does, or none)
    "false_closure",  # it closes only in the residual (a mirror or half-turn: alignment negative)
    "not_converged",  # the Newton polish did not reach the closure tolerance
    "outside_limits",  # closed, but a passive joint is outside its limits
    "duplicate",  # the same pose as an earlier mode (a double root or two branches)
    "input_independent",  # a pose that does not depend on the inputs (flagged, not counted)
    "complex",  # a homotopy path ends at a complex solution (no real pose)
    "at_infinity",  # a homotopy path diverges: the solution went to infinity for these inputs
    "path_failed",  # the homotopy tracker could not follow the path to the end (step too small)
    # a real-looking endpoint that no certified box holds alone, or whose realness the
    # certificate could not decide: not listed (the input is then not certified complete)
    "uncertified",
]

#: per input of forward_pose_all
INPUT_STATUS = [
    "ok",
    "nonfinite",  # an actuated value is NaN or infinite
    "degenerate",  # the elimination degenerates (polynomial vanishing or undefined, or a
    # degeneracy measure at zero) and no isolated mode was found: a self-motion or no solution
]

#: real-root kinds of the isolation (templates/real_roots.h)
ROOT_KINDS = ["simple", "cluster", "near_real", "complex", "at_infinity", "failed"]

NEWTON_JOB = [
    ("n", "int64"),
    ("actuated", "const double*"),
    ("actuated_stride", "int64"),
    ("guess", "const double*"),
    ("guess_stride", "int64"),
    ("params", "const double*"),
    ("max_iterations", "int64"),
    ("tolerance", "double"),
    ("max_step", "double"),
    ("singular_ratio", "double"),
    ("passive", "double*"),
    ("pose", "double*"),
    ("residual", "double*"),
    ("conditioning", "double*"),
    ("orientation", "int32*"),
    ("first_step", "double*"),
    ("iterations", "int32*"),
    ("status", "int32*"),
]

MODES_JOB = [
    ("n", "int64"),
    ("actuated", "const double*"),
    ("actuated_stride", "int64"),
    ("params", "const double*"),
    ("lower", "const double*"),  # passive joint limits, one value per passive variable
    ("upper", "const double*"),
    ("polish_iterations", "int64"),
    ("tolerance", "double"),  # Newton polish tolerance
    ("closure", "double"),  # max |residual| of a closed configuration
    ("candidate", "double"),  # max |residual| of a candidate before polish
    ("duplicate", "double"),
    ("factor_zero", "double"),
    ("singular_ratio", "double"),
    ("validity", "double"),
    ("degenerate", "double"),
    ("leading_tolerance", "double"),
    ("near_tolerance", "double"),
    ("path_tolerance", "double"),  # homotopy: corrector tolerance of the path tracker
    ("real_endpoint", "double"),  # homotopy: relative imaginary part of a real endpoint
    ("near_real_endpoint", "double"),  # homotopy: ... of a near-real candidate
    ("poses", "double*"),  # n x M x 4 x 4
    ("passive", "double*"),  # n x M x n_p
    ("residual", "double*"),  # n x M
    ("conditioning", "double*"),  # n x M: pivot ratio of the closure Jacobian at the mode
    ("roots", "double*"),  # n x M: the root of each slot (inf for a root at infinity)
    ("outcome", "int32*"),  # n x M: MODE_OUTCOMES
    ("root_kind", "int32*"),  # n x M: ROOT_KINDS of the slot's root, -1 when no root
    ("count", "int32*"),  # n: valid modes
    ("real_roots", "int32*"),  # n: distinct finite real roots (simple and clusters)
    ("near_roots", "int32*"),  # n: near-real candidates (complex pairs close to the axis)
    ("at_infinity", "int32*"),  # n: roots at infinity (vanishing leading coefficients)
    ("status", "int32*"),  # n: INPUT_STATUS
    ("endpoints", "double*"),  # n x M x NZ x 2: a homotopy path's complex endpoint (NULL: not wanted)
]

#: C spelling of the field types (ctypes names are derived from the same strings at run time)
C_TYPES = {
    "int64": "long long",
    "double": "double",
    "const double*": "const double*",
    "double*": "double*",
    "int32*": "int*",
}


def describe() -> dict[str, object]:
    """The ABI section of the manifest."""
    return {
        "newton_status": NEWTON_STATUS,
        "mode_outcomes": MODE_OUTCOMES,
        "input_status": INPUT_STATUS,
        "root_kinds": ROOT_KINDS,
        "newton_job": [list(field) for field in NEWTON_JOB],
        "modes_job": [list(field) for field in MODES_JOB],
    }
