"""The exported C library: two mechanisms compiled into one program with gcc -std=c99 -Wall
-Werror (parakin's own files), run, and compared with the Python results; the example program
of every mechanism builds and runs."""

from __future__ import annotations

import json
import re
import shutil
import subprocess

import numpy as np
import pytest

import parakin
from parakin.studies.sampling import sample_configurations

COMPILER = shutil.which("gcc") or shutil.which("cc")
pytestmark = pytest.mark.skipif(COMPILER is None, reason="no C compiler")
STRICT = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-O2"]
PAIR = ("sam", "spm")

PROGRAM = r"""
#include <stdio.h>
#include <stdlib.h>
#include "sam/sam.h"
#include "spm/spm.h"

#define RUN(P, UP, NA, NQ)                                                                          \
    do {                                                                                            \
        P##_params params = UP##_PARAMS_DEFAULT;                                                    \
        enum { M = UP##_MAX_MODES };                                                                \
        double actuated[NA], poses[M * 16], passive[M * NQ], residual[M], conditioning[M], roots[M]; \
        int outcome[M], kind[M], count, real_roots, near_roots, at_infinity, status;                \
        double lower[NQ], upper[NQ];                                                                \
        for (int k = 0; k < NQ; ++k) { lower[k] = -1e300; upper[k] = 1e300; }                       \
        for (int k = 0; k < NA; ++k) actuated[k] = atof(*argv++);                                   \
        P##_modes_job job = {1, actuated, 0, (const double*)&params, lower, upper, 8, 1e-13, 1e-9, \
            1e-4, 1e-7, 1e-9, 1e-10, 1e-9, 1e-9, 1e-13, 1e-9, 1e-7, 1e-8, 1e-4, poses, passive, residual, \
            conditioning, roots, outcome, kind, &count, &real_roots, &near_roots, &at_infinity,     \
            &status, NULL};                                                                         \
        P##_forward_pose_all(&job);                                                                 \
        printf("%s %d\n", #P, count);                                                               \
        for (int s = 0; s < M; ++s)                                                                 \
            if (outcome[s] == UP##_OUTCOME_MODE)                                                    \
                printf("%.17g %.17g %.17g %.17g\n", poses[s * 16 + 0], poses[s * 16 + 3],           \
                       poses[s * 16 + 7], poses[s * 16 + 11]);                                      \
    } while (0)

int main(int argc, char** argv) {
    (void)argc;
    ++argv;
    RUN(sam, SAM, SAM_NUM_ACTUATED, SAM_NUM_PASSIVE);
    RUN(spm, SPM, SPM_NUM_ACTUATED, SPM_NUM_PASSIVE);
    return 0;
}
"""


def _build(tmp_path):
    objects = []
    for name in PAIR:
        folder = tmp_path / name
        parakin.load(name).package.export_c(folder)  # type: ignore[attr-defined]
        # exported names carry the mechanism's prefix; the kernels are CasADi's own file
        for source, flags in ((f"{name}_driver.c", STRICT), (f"{name}_kernels.c", ["-std=c99", "-O2"])):
            target = tmp_path / f"{source}.o"
            subprocess.run(
                [COMPILER, *flags, "-I", str(folder), "-c", str(folder / source), "-o", str(target)], check=True
            )
            objects.append(str(target))
    program = tmp_path / "two.c"
    program.write_text(PROGRAM)
    binary = tmp_path / "two"
    subprocess.run(
        [COMPILER, *STRICT, "-I", str(tmp_path), str(program), *objects, "-lm", "-o", str(binary)], check=True
    )
    return binary


def test_two_mechanisms_link_into_one_program_and_agree_with_python(tmp_path):
    binary = _build(tmp_path)
    checked = 0
    for seed in range(3):
        inputs = {}
        for name in PAIR:
            m = parakin.load(name)
            sample = sample_configurations(m, 1, seed=seed)
            inputs[name] = sample.actuated[0]
        arguments = [repr(float(v)) for name in PAIR for v in inputs[name]]
        lines = subprocess.run([str(binary), *arguments], check=True, capture_output=True, text=True).stdout.split("\n")
        cursor = 0
        for name in PAIR:
            label, count = lines[cursor].split()
            assert label == name
            count = int(count)
            c_poses = np.array([[float(x) for x in lines[cursor + 1 + k].split()] for k in range(count)])
            cursor += 1 + count
            for backend in ("compiled", "numpy"):
                modes = parakin.load(name, backend=backend).forward_pose_all(inputs[name])
                assert int(modes.count) == count, (name, backend)
                python = modes.poses[modes.valid][:, [0, 0, 1, 2], [0, 3, 3, 3]]
                assert np.abs(python - c_poses).max() < 1e-9
                checked += 1
            assert count > 0
    assert checked == 12


SANITIZED = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-O1", "-g", "-fsanitize=address,undefined"]
NUMBER = r"[-+]?(?:\d+\.?\d*(?:e[-+]?\d+)?|nan|inf)"
POSE = re.compile(rf"position \(({NUMBER}), ({NUMBER}), ({NUMBER})\), z axis \(({NUMBER}), ({NUMBER}), ({NUMBER})\)")


def _printed_pose(line: str) -> np.ndarray:
    """(position, z axis of {P}) as example_main.c prints them (9 decimals)."""
    match = POSE.search(line)
    assert match, line
    return np.array([float(v) for v in match.groups()])


def _python_pose(pose: np.ndarray) -> np.ndarray:
    return np.concatenate([pose[..., :3, 3], pose[..., :3, 2]], axis=-1)


def _sanitized_slow(name: str) -> bool:
    """More than 32 homotopy paths under AddressSanitizer and UBSan: about a minute (stewart)."""
    forward = parakin.metadata(name).capabilities.forward
    return forward is not None and forward.homotopy is not None and forward.degree > 32


@pytest.mark.parametrize(
    "name", [pytest.param(n, marks=pytest.mark.slow) if _sanitized_slow(n) else n for n in parakin.available()]
)
def test_exported_example_program_runs(tmp_path, name):
    """Every export compiles with -Wall -Wextra -Werror under AddressSanitizer and UBSan (every
    file: kernels.c too), runs the configuration chosen at generation time, exits 0, and prints
    what the Python solvers (NumPy backend) find for the same input: the same number of assembly
    modes at the same poses, and Newton from the same guess to the same pose (9 printed decimals)."""
    folder = tmp_path / name
    m = parakin.load(name, backend="numpy")
    m.package.export_c(folder)  # type: ignore[attr-defined]
    sources = [f"{name}_example_main.c", f"{name}_driver.c", f"{name}_kernels.c"]
    subprocess.run([COMPILER, *SANITIZED, "-I", ".", *sources, "-lm", "-o", "example"], cwd=folder, check=True)
    environment = {"ASAN_OPTIONS": "detect_leaks=0", "UBSAN_OPTIONS": "halt_on_error=1"}
    run = subprocess.run(["./example"], cwd=folder, capture_output=True, text=True, env=environment, timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "runtime error" not in run.stderr and "Sanitizer" not in run.stderr, run.stderr
    lines = run.stdout.splitlines()
    label, actuated_text = lines[0].split(": actuated ")
    assert label == name
    actuated = np.array([float(v) for v in actuated_text.split()])
    chosen = json.loads((m.package.path / "manifest.json").read_text())["c"]["example"]  # type: ignore[attr-defined]
    assert chosen["verified"] and np.array_equal(actuated, chosen["actuated"])
    if m.manifest.capabilities.forward is not None:
        count = int(re.match(rf"{name}: (\d+) assembly modes", lines[1]).group(1))  # type: ignore[union-attr]
        assert count > 0 and "input status 0" in lines[1]
        printed = np.array([_printed_pose(line) for line in lines[2 : 2 + count]])
        modes = m.forward_pose_all(actuated)
        assert int(modes.count) == count
        python = _python_pose(modes.poses[modes.valid])
        # every printed mode is a Python mode and the reverse (printed to 9 decimals)
        distance = np.abs(printed[:, None, :] - python[None, :, :]).max(axis=-1)
        assert distance.min(axis=1).max() < 2e-9 and distance.min(axis=0).max() < 2e-9
    # the certificate of z^2 - 2 near its closed-form roots +-sqrt 2: both unique and real
    assert "certificate of z^2 - 2: unique 1 1, real 1 1" in lines[-2], lines[-2]
    newton = lines[-1]
    assert newton.startswith("forward_pose from the guess: status 0"), newton
    solved = m.forward_pose(actuated, np.array(chosen["guess"]) if chosen["guess"] else None)
    assert np.abs(_printed_pose(newton) - _python_pose(solved.pose)).max() < 2e-9
