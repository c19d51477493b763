"""``make generate``: rebuild ``generated/`` from ``mechanisms/``, deterministically and atomically.

Everything is written to a temporary directory next to ``generated/`` and swapped in only when
every mechanism succeeded, so a failure leaves the previous tree intact.
"""

from __future__ import annotations

import importlib
import math
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import casadi

from generator import emit
from generator.derive import derive
from generator.model import Mechanism
from generator.program import LoweredProgram

ROOT = Path(__file__).resolve().parent.parent
GENERATED = ROOT / "generated"


def _metadata(mechanism: Mechanism, derived: dict[str, Any]) -> dict[str, Any]:
    def bound(value: float) -> float | None:
        return None if math.isinf(value) else value

    return {
        "name": mechanism.name,
        "title": mechanism.title,
        "reference": mechanism.reference,
        "parameters": {str(k): v for k, v in mechanism.parameters.items()},
        "actuated": [str(s) for s in mechanism.actuated],
        "passive": [str(s) for s in mechanism.passive],
        "angular": [str(s) for s in mechanism.angular],
        "home": {str(k): v for k, v in mechanism.home.items()},
        "limits": {str(k): [bound(lo), bound(hi)] for k, (lo, hi) in mechanism.limits.items()},
        **derived,
    }


def _c_sources(name: str, casadi_source: str, programs: list[LoweredProgram]) -> tuple[str, str, str]:
    """CasADi C code generation of every function, plus the batched driver."""
    namespace: dict[str, Any] = {}
    exec(compile(casadi_source, f"{name}_casadi.py", "exec"), namespace)  # noqa: S102
    functions = namespace["build_functions"]()
    with tempfile.TemporaryDirectory() as scratch:
        generator = casadi.CodeGenerator(f"{name}_casadi", {"with_header": True})
        for function in functions.values():
            generator.add(function)
        generator.generate(scratch + "/")
        c_text = Path(scratch, f"{name}_casadi.c").read_text()
        h_text = Path(scratch, f"{name}_casadi.h").read_text()

    def sizes(*names: str) -> dict[str, int]:
        fs = [functions[n] for n in names]
        return {
            "arg": max(f.sz_arg() for f in fs),
            "res": max(f.sz_res() for f in fs),
            "iw": max(f.sz_iw() for f in fs),
            "w": max(f.sz_w() for f in fs),
        }

    described = []
    for p in programs:
        described.append(
            {
                "name": p.name,
                "inputs": [(group, len(symbols)) for group, symbols in p.source.inputs],
                "outputs": [(o.name, o.shape[0], o.shape[1] if len(o.shape) == 2 else 1) for o in p.outputs],
                "sizes": sizes(p.name),
            }
        )
    loop = next(p for p in programs if p.name == "loop_closure")
    newton = {
        "unknowns": len(loop.source.inputs[1][1]),
        "pairs": next(o.shape[0] for o in loop.outputs if o.name == "alignment"),
        "outputs": {o.name: index for index, o in enumerate(loop.outputs)},
        "actuated": len(loop.source.inputs[0][1]),
        "residual": "loop_closure",
        "pose": "platform_pose",
        "sizes": sizes("loop_closure", "platform_pose"),
        "pose_sizes": sizes("platform_pose"),
    }
    driver = emit.render_c_driver(name, programs, described, newton)
    header = emit.banner(name, "casadi.CodeGenerator", programs, "//")
    return header + c_text, header + h_text, driver


def generate_mechanism(name: str, target: Path) -> dict[str, float]:
    started = time.perf_counter()
    module = importlib.import_module(f"mechanisms.{name}")
    mechanism: Mechanism = module.build()
    derivation = derive(mechanism)
    lowered = [program.lower() for program in derivation.programs]
    metadata = _metadata(mechanism, derivation.metadata)
    numpy_source = emit.render_numpy(name, lowered, metadata)
    casadi_source = emit.render_casadi(name, lowered)
    c_source, h_source, driver_source = _c_sources(name, casadi_source, lowered)
    (target / f"{name}_numpy.py").write_text(numpy_source)
    (target / f"{name}_casadi.py").write_text(casadi_source)
    (target / f"{name}_symbolic.py").write_text(emit.render_symbolic(name, derivation.symbolic))
    (target / f"{name}_casadi.c").write_text(c_source)
    (target / f"{name}_casadi.h").write_text(h_source)
    (target / f"{name}_driver.c").write_text(driver_source)
    return {"seconds": time.perf_counter() - started}


def _format(directory: Path) -> None:
    python_files = sorted(str(p) for p in directory.glob("*.py"))
    subprocess.run(
        [sys.executable, "-m", "ruff", "format", "--quiet", "--line-length", "100", *python_files], check=True
    )


def generate(names: list[str], destination: Path = GENERATED) -> dict[str, dict[str, float]]:
    """Regenerate ``destination`` for ``names`` (other mechanisms' files are kept); atomic: all
    mechanisms or nothing."""
    destination.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(prefix=".generated-", dir=destination.parent))
    staging.chmod(0o755)
    try:
        (staging / "__init__.py").write_text(
            '"""Generated code only: written by `make generate`, never edited by hand."""\n'
        )
        report = {name: generate_mechanism(name, staging) for name in names}
        _format(staging)
        if destination.exists():  # a partial rebuild keeps the other mechanisms' files
            for path in destination.iterdir():
                if path.is_file() and not (staging / path.name).exists() and path.name.split("_")[0] not in names:
                    shutil.copy2(path, staging / path.name)
        if destination.exists():
            retired = destination.with_name(destination.name + ".old")
            shutil.rmtree(retired, ignore_errors=True)
            destination.rename(retired)
            staging.rename(destination)
            shutil.rmtree(retired)
        else:
            staging.rename(destination)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    return report
