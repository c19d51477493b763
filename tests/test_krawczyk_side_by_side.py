"""krawczyk.h's faster loops are its one-at-a-time definitions, bit for bit (issue 33).

The certificate's inverse solves the n unit vectors side by side over padded rows, kw_ingredients
and kw_passes run the n rows' rounded-up sums side by side, ldexp, fmax and fmin are replaced by
inline operations, and kw_passes takes the equations' terms in turns. Each must give the same
bits as the definition it replaced (the whole certificate's outputs were compared bit for bit
against the previous code on the jobs of 1,800 forward_pose_all calls and 5,000 perturbed ones).
``tests/krawczyk_side_by_side.c`` checks, compiled with the packages' flags and with plain -O2:
every column of kw_inverse against kw_lu_solve of its unit vector, and Y J~ = I in long double;
kw_ingredients' a, b, c and |Y| against the row-at-a-time formula; kw_ldexp against ldexp over
normal, subnormal and overflowing results; kw_max and kw_min against fmax and fmin with NaN and
infinities; kw_supports' turns (every term once, each equation's terms in order) and degree-2
weights (sum_ij a_i (a_j - [i = j]) = 2, rounded up once or twice)."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

from parakin.packages.compiled import compile_flags

ROOT = Path(__file__).resolve().parent.parent
RUNTIME = ROOT / "generator" / "runtime"
SOURCE = Path(__file__).resolve().parent / "krawczyk_side_by_side.c"
WARNINGS = ["-Wall", "-Wextra", "-Werror", "-Wno-unused-function"]


@pytest.fixture(scope="module", params=["packages", "plain"])
def output(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> list[str]:
    compiler = shutil.which("cc")
    if compiler is None:
        pytest.skip("no C compiler")
    if request.param == "packages":  # the generated libraries' flags (AVX2 where the CPU has it), an executable
        flags = [f for f in compile_flags() if f not in {"-shared", "-fPIC"}]
    else:
        flags = ["-std=c99", "-O2", "-ffp-contract=off"]
    binary = tmp_path_factory.mktemp("krawczyk_side_by_side") / "test"
    subprocess.run([compiler, *flags, *WARNINGS, "-I", str(RUNTIME), str(SOURCE), "-o", str(binary), "-lm"], check=True)
    result = subprocess.run([str(binary)], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout.splitlines()


def test_krawczyk_loops_side_by_side_are_their_definitions(output: list[str]) -> None:
    assert [line for line in output if line.startswith("failed")] == []
    counts = output[-1].split()
    assert counts[0] == "checked"
    checked = dict(zip(counts[1::2], map(int, counts[2::2]), strict=True))
    # 40 random matrices for each n = 1 .. 9 (every padding of the rows to whole vectors)
    assert checked["inverse"] == 360 and checked["ingredients"] == 360
    assert checked["ldexp"] >= 50000 and checked["max"] == 49 and checked["turns"] == 200
