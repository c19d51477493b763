"""Command line: ``parakin list | inspect NAME | demo [NAME] | ik NAME | fk NAME | plot NAME``.

Flags ending in ``-deg`` take degrees; everything else is SI (metres, radians).
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

import parakin
from parakin.demos import DEMOS
from parakin.errors import ParakinError
from parakin.plots import PLOTS


def _inspect(name: str, fmt: str) -> None:
    import sympy  # inspect is the one command that needs SymPy

    info = parakin.metadata(name)
    objects = parakin.symbolic(name)
    if fmt == "json":
        print(json.dumps({"metadata": info, "objects": {k: str(v) for k, v in objects.items()}}, indent=1))
        return

    def show(expr: object) -> str:
        if fmt == "latex":
            return str(sympy.latex(expr))
        # pretty-printing is unreadable for long expressions: plain text there
        return str(sympy.pretty(expr)) if sympy.count_ops(expr) < 60 else str(expr)

    print(f"{info['title']}\nreference: {info['reference']}\n")
    print(f"parameters: {info['parameters']}\nactuated: {info['actuated']}\npassive: {info['passive']}\n")
    sections = [
        ("Loop-closure equations (residual = 0)", "loop_closure"),
        *[
            (f"Leg Jacobian, {leg['name']} (eq 9; columns {leg['joints']})", f"leg_jacobian_{leg['name']}")
            for leg in info["legs"]
        ],
    ]
    if "rates" in info:
        twist = info["rates"]["twist"]
        sections += [(f"A of A twist = B theta_dot (twist {twist} in {{B}})", "rate_matrix_A"), ("B", "rate_matrix_B")]
    for title, key in sections:
        print(f"== {title}\n{show(objects[key])}\n")
    print("== Determinants, factored")
    for key in info["determinants"]:
        print(f"{key} = {show(objects[key])}")
    if "architecture" in info:
        print("\n== Architecture singularities (parameters only; zero: singular at every pose)")
        for key in info["architecture"]:
            print(f"{key} = {show(objects['architecture_' + key])}")
    print("\n== Singular conditions (each named factor = 0)")
    for key in info["singularity_factors"]:
        print(f"{key}: {show(objects['factor_' + key])} = 0")
    if "forward" in info:
        forward = info["forward"]
        print(f"\n== Forward-kinematics univariate polynomial in {forward['unknown']}: degree {forward['degree']}")
        print(f"branches {forward['branches']}; degenerate where {forward['degeneracies']} vanish")
        if fmt == "latex":
            print(show(objects["forward_polynomial"]))


def _vector(values: list[float], degrees: bool) -> np.ndarray:
    array = np.array(values, dtype=float)
    return np.deg2rad(array) if degrees else array


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="parakin", description=__doc__)
    commands = parser.add_subparsers(dest="command", required=True)
    commands.add_parser("list", help="available mechanisms")
    inspect = commands.add_parser("inspect", help="symbolic loop closure, Jacobians, determinants, singularities")
    inspect.add_argument("name")
    inspect.add_argument("--format", choices=["text", "latex", "json"], default="text")
    demo = commands.add_parser("demo", help="the paper examples")
    demo.add_argument("name", nargs="?", choices=sorted(DEMOS))
    ik = commands.add_parser("ik", help="inverse pose of {x y z alpha beta gamma}")
    ik.add_argument("name")
    ik.add_argument(
        "--pose-deg", nargs=6, type=float, required=True, metavar="V", help="x y z (m) alpha beta gamma (deg, Z-Y-X)"
    )
    fk = commands.add_parser("fk", help="every assembly mode for actuator angles")
    fk.add_argument("name")
    fk.add_argument("--actuated-deg", nargs="+", type=float, required=True, metavar="DEG")
    plot = commands.add_parser("plot", help="write a figure of the mechanism's solutions (PNG)")
    plot.add_argument("name", choices=sorted(PLOTS))
    plot.add_argument("--output", default=None, help="PNG path (default NAME.png)")
    plot.add_argument("--actuated-deg", nargs="+", type=float, default=None, metavar="DEG")
    args = parser.parse_args(argv)
    np.set_printoptions(precision=6, suppress=True, linewidth=120)
    try:
        if args.command == "list":
            print("\n".join(parakin.available()))
        elif args.command == "inspect":
            _inspect(args.name, args.format)
        elif args.command == "demo":
            for name in [args.name] if args.name else sorted(DEMOS):
                DEMOS[name]()
        elif args.command == "ik":
            m = parakin.load(args.name)
            result = m.inverse_pose(parakin.pose_from_xyz_euler_deg(args.pose_deg), strict=False)
            for k in range(result.actuated.shape[-2]):
                print(
                    f"branch {k:2d} {result.branches[k]} valid={bool(result.valid[k])} actuated(deg)={np.rad2deg(result.actuated[k])} passive={result.passive[k]}"
                )
        elif args.command == "plot":
            path = args.output or f"{args.name}.png"
            PLOTS[args.name](path, args.actuated_deg)
            print(f"wrote {path}")
        elif args.command == "fk":
            m = parakin.load(args.name)
            modes = m.forward_pose_all(_vector(args.actuated_deg, degrees=True))
            for mode in np.nonzero(modes.valid)[0]:
                print(
                    f"mode {mode}: x y z alpha beta gamma (m, deg) = {parakin.xyz_euler_deg_from_pose(modes.poses[mode])} residual {modes.residual[mode]:.1e}"
                )
    except ParakinError as error:
        print(f"parakin: {type(error).__name__}: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
