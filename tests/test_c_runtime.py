"""The C runtime (generator/runtime/) on its own: its C unit tests compiled with the system
compiler and run (the complex LU, the Hermite predictor, the tracker on homotopies with
closed-form paths), and each tracked path compared with the NumPy reference
``parakin.solvers.path_tracking.track_hermite`` on the same homotopy: the same endpoint, the same
step attempts, rejections and evaluations. Every homotopy package's driver prints these sources
(generator/emit.py): the packages' drivers are checked to hold them verbatim."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import parakin
from parakin.solvers import path_tracking as homotopy

ROOT = Path(__file__).resolve().parent.parent
RUNTIME = ROOT / "generator" / "runtime"
GENERATED = ROOT / "generated"


@pytest.fixture(scope="module")
def runtime_output(tmp_path_factory: pytest.TempPathFactory) -> list[str]:
    compiler = shutil.which("cc")
    if compiler is None:
        pytest.skip("no C compiler")
    binary = tmp_path_factory.mktemp("runtime") / "test_runtime"
    flags = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-ffp-contract=off"]
    subprocess.run([compiler, *flags, str(RUNTIME / "test_runtime.c"), "-o", str(binary), "-lm"], check=True)
    result = subprocess.run([str(binary)], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout.splitlines()


def _system(kind: int, a: np.ndarray) -> homotopy.System:
    """test_runtime.c's homotopies as a sparse system: kind 0, z_k^2 - ((1 - s) a_k + s); kind 1,
    s z_k - 1 (each equation in its own unknown)."""
    if kind == 0:
        exponents = np.array([[2, 0], [0, 0], [0, 2], [0, 0]])
        table = np.array([[[1, -a[0], 1, -a[1]], [0, a[0] - 1, 0, a[1] - 1]]], dtype=complex)
    else:
        exponents = np.array([[1, 0], [0, 0], [0, 1], [0, 0]])
        table = np.array([[[0, -1, 0, -1], [1, 0, 1, 0]]], dtype=complex)
    return homotopy.sparse_system(table, exponents, np.array([0, 0, 1, 1]), 1)


def test_c_runtime_unit_tests_pass(runtime_output: list[str]) -> None:
    assert not [line for line in runtime_output if line.startswith("failed")]
    assert sum(line.startswith("path ") for line in runtime_output) == 5


def test_c_two_lane_tracker_is_the_one_path_tracker(runtime_output: list[str]) -> None:
    """track_paths (two paths advanced together, newton_step2, c_solve2) ran its comparisons with
    track_path one path at a time (test_runtime.c: every status, endpoint and count bit for bit,
    checked there; a mismatch prints "failed"), on 4, 3 (one lane alone at the end) and 3
    diverging paths; and its counts are the one-path runs' sums printed by the "path" lines."""
    assert not [line for line in runtime_output if line.startswith("failed")]
    paths = {
        (int(f[1]), int(f[2])): [int(v) for v in f[-4:]]
        for f in (line.split() for line in runtime_output if line.startswith("path "))
    }
    paired = [[int(v) for v in line.split()[1:]] for line in runtime_output if line.startswith("paired ")]
    assert [p[0] for p in paired] == [4, 3, 3]
    for (count, steps, evaluations, factorisations), chosen in zip(paired[:2], ([0, 1, 2, 3], [2, 0, 3]), strict=True):
        assert count == len(chosen)
        assert steps == sum(paths[(0, p)][0] for p in chosen)
        assert evaluations == factorisations == sum(paths[(0, p)][2] for p in chosen)
    # the escaping paths (from starts 2, 0, 3): compared with track_path in C alone
    assert paired[2][2] == paired[2][3] > 0


def test_c_tracker_as_the_numpy_reference(runtime_output: list[str]) -> None:
    a = np.array([4.0 + 1.0j, -9.0 + 0.5j])  # test_runtime.c's roots homotopy
    starts = np.array([[1, 1], [-1, 1], [1, -1], [-1, -1]], dtype=complex)
    checked = 0
    for line in runtime_output:
        if not line.startswith("path "):
            continue
        fields = line.split()
        kind, label, status = (int(v) for v in fields[1:4])
        z = np.array([float(fields[4 + 2 * k]) + 1j * float(fields[5 + 2 * k]) for k in range(2)])
        steps, rejected, evaluations, factorisations = (int(v) for v in fields[8:12])
        reference = homotopy.track_hermite(_system(kind, a), starts[label : label + 1], 1e-7)
        assert status == int(reference.status[0])
        if kind == 0:  # the closed form: z_k^2 = a_k, the start's sign kept
            np.testing.assert_allclose(z**2, a, rtol=1e-13)
            assert (np.real(z / starts[label]) > 0).all()
        np.testing.assert_allclose(z, reference.z[0], rtol=1e-12)
        assert (steps, rejected) == (reference.steps[0], reference.rejected[0])
        if kind == 0:
            assert evaluations == reference.evaluations[0]
        else:
            # z = 1/s is a simple pole, which the rational predictor follows exactly: its
            # corrections are rounding noise at |z| up to ESCAPE, where the C LU and LAPACK's
            # round apart, and one step's first correction falls either side of the tolerance
            assert abs(evaluations - reference.evaluations[0]) <= 1
        assert factorisations == evaluations
        checked += 1
    assert checked == 5


@pytest.fixture(scope="module")
def krawczyk_output(tmp_path_factory: pytest.TempPathFactory) -> list[str]:
    compiler = shutil.which("cc")
    if compiler is None:
        pytest.skip("no C compiler")
    binary = tmp_path_factory.mktemp("krawczyk") / "test_krawczyk"
    flags = ["-std=c99", "-O2", "-Wall", "-Wextra", "-Werror", "-ffp-contract=off"]
    subprocess.run([compiler, *flags, str(RUNTIME / "test_krawczyk.c"), "-o", str(binary), "-lm"], check=True)
    result = subprocess.run([str(binary)], capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stdout + result.stderr
    return result.stdout.splitlines()


def test_c_krawczyk_unit_tests_pass(krawczyk_output: list[str]) -> None:
    """krawczyk.h's C tests: outward rounding against exact rounding errors (TwoSum, fma), the
    univariate and projective certificates against closed-form roots, realness decided by the one
    test (a real centre, the box widened to hold the conjugate, the projective mirror) and never
    for a conjugate pair 2^-21 from the real space, the refused jobs."""
    assert not [line for line in krawczyk_output if line.startswith("failed")]
    checked = [int(line.split()[1]) for line in krawczyk_output if line.startswith("checked ")]
    assert checked and checked[0] >= 946


def test_c_krawczyk_constants_are_the_numpy_references() -> None:
    """krawczyk.h's NEAR, MULTIPLIERS, NEWTON_STEPS, SETTLED and FLOOR are certify.py's."""
    from parakin.solvers import certify

    text = (RUNTIME / "krawczyk.h").read_text()
    assert f"#define KW_NEAR {certify.NEAR!r}" in text
    assert "kw_multipliers[KW_RADII] = {" + ", ".join(map(repr, certify.MULTIPLIERS.tolist())) + "}" in text
    assert f"#define KW_RADII {certify.MULTIPLIERS.size}" in text
    assert f"#define KW_NEWTON_STEPS {certify.NEWTON_STEPS}" in text
    assert f"#define KW_SETTLED {certify.SETTLED!r}" in text
    assert certify.FLOOR == 2.0**-600 and "#define KW_FLOOR 0x1p-600" in text


@pytest.mark.parametrize("name", [n for n in parakin.available() if (GENERATED / n / "driver.c").is_file()])
def test_homotopy_drivers_hold_the_runtime(name: str) -> None:
    """A homotopy package's driver holds each runtime header verbatim (self-contained: nothing
    to include from parakin); a closed-form one holds only the certificate (krawczyk.h), which
    every package exports."""
    driver = (GENERATED / name / "driver.c").read_text()
    homotopy_package = parakin.metadata(name).capabilities.forward is not None and (
        parakin.metadata(name).capabilities.forward.homotopy is not None  # type: ignore[union-attr]
    )
    for header in sorted(RUNTIME.glob("*.h")):
        expected = homotopy_package or header.name == "krawczyk.h"
        assert (header.read_text().rstrip() in driver) == expected, header.name
    assert f"int {name}_certify_roots(const {name}_certify_job* job)" in driver


def test_c_runtime_test_constants_are_the_numpy_references() -> None:
    """test_runtime.c tracks with the constants of parakin.solvers.path_tracking (what every
    package's driver prints, generator/emit.py), so that the C-against-NumPy comparison above
    runs the shipped step control."""
    from parakin.generator.emit import TRACKER_CONSTANTS

    text = (RUNTIME / "test_runtime.c").read_text()
    for name in TRACKER_CONSTANTS:
        line = next(line for line in text.splitlines() if line.startswith(f"#define {name} "))
        assert float(line.split()[2]) == float(getattr(homotopy, name)), name
    assert len(TRACKER_CONSTANTS) >= 15


#: c_solve's harness: tracker.h for NZ unknowns with a homotopy that is never called, and the
#: solve exported with its arrays as interleaved doubles (cplx)
_LU_HARNESS = """
#include <math.h>
#include <string.h>
#include "complex.h"
#define NZ {size}
{constants}
enum {{ PATH_REACHED = 0, PATH_FAILED = 1, PATH_DIVERGED = 2 }};
typedef struct {{ int unused; }} sparse_system;
typedef struct {{ int unused; }} coefficients_at;
static void coefficients(const sparse_system* system, double s, coefficients_at* at) {{ (void)system; (void)s; (void)at; }}
static int homotopy_eval(const coefficients_at* at, const cplx* z, cplx* value, cplx* jacobian, cplx* rate) {{
    (void)at; (void)z; (void)value; (void)jacobian; (void)rate;
    return 0;
}}
#include "tracker.h"
int lu_solve(double* a, double* b, double* c) {{ return c_solve((cplx*)a, (cplx*)b, (cplx*)c); }}
int lu_solve2(double* a, double* b, double* c, double* a2, double* b2, double* c2) {{
    return c_solve2((cplx*)a, (cplx*)b, (cplx*)c, (cplx*)a2, (cplx*)b2, (cplx*)c2);
}}
"""


def _textbook_solve(
    a: list[list[tuple[float, float]]], rhs: list[list[tuple[float, float]]]
) -> list[list[tuple[float, float]]] | None:
    """Gaussian elimination with partial pivoting in Python's floats (IEEE double, each operation
    rounded once), complex numbers as (re, im) pairs: the pivot the first row of largest |re| +
    |im|, 1/p = (re / |p|^2, -im / |p|^2), a_rj -= (a_rk / p) a_kj, the back substitution's sum
    from j = k + 1 up and times 1/p. None when singular."""

    def mul(x: tuple[float, float], y: tuple[float, float]) -> tuple[float, float]:
        return (x[0] * y[0] - x[1] * y[1], x[0] * y[1] + x[1] * y[0])

    def sub(x: tuple[float, float], y: tuple[float, float]) -> tuple[float, float]:
        return (x[0] - y[0], x[1] - y[1])

    n = len(a)
    a = [row[:] for row in a]
    rhs = [column[:] for column in rhs]
    inverses = []
    for k in range(n):
        best, largest = k, abs(a[k][k][0]) + abs(a[k][k][1])
        for r in range(k + 1, n):
            if abs(a[r][k][0]) + abs(a[r][k][1]) > largest:
                best, largest = r, abs(a[r][k][0]) + abs(a[r][k][1])
        if not largest > 0.0:
            return None
        a[k], a[best] = a[best], a[k]
        for column in rhs:
            column[k], column[best] = column[best], column[k]
        size = a[k][k][0] * a[k][k][0] + a[k][k][1] * a[k][k][1]
        inverse = (a[k][k][0] / size, -a[k][k][1] / size)
        inverses.append(inverse)
        for r in range(k + 1, n):
            f = mul(a[r][k], inverse)
            for j in range(k + 1, n):
                a[r][j] = sub(a[r][j], mul(f, a[k][j]))
            for column in rhs:
                column[r] = sub(column[r], mul(f, column[k]))
    for k in reversed(range(n)):
        for column in rhs:
            total = column[k]
            for j in range(k + 1, n):
                total = sub(total, mul(a[k][j], column[j]))
            column[k] = mul(total, inverses[k])
    return rhs


@pytest.mark.parametrize("size", [3, 8])
def test_c_solve_is_the_textbook_elimination_bit_for_bit(size: int, tmp_path: Path) -> None:
    """tracker.h's c_solve against Gaussian elimination written out in Python's floats, bit for
    bit (a layout for the compiler must keep every operation), on random systems, systems whose
    entries tie in |re| + |im| (the first row of the largest must win) and with zeros, with one
    and with two right-hand sides; singular ones refused; the solutions solve the systems
    (LAPACK's, to rounding)."""
    import ctypes

    from parakin.generator.emit import TRACKER_CONSTANTS

    compiler = shutil.which("cc")
    if compiler is None:
        pytest.skip("no C compiler")
    constants = "\n".join(f"#define {name} {getattr(homotopy, name)!r}" for name in TRACKER_CONSTANTS)
    source = tmp_path / "lu.c"
    source.write_text(_LU_HARNESS.format(size=size, constants=constants))
    library = tmp_path / "lu.so"
    flags = ["-std=c99", "-O3", "-shared", "-fPIC", "-Wall", "-Wextra", "-Werror", "-Wno-unused-function"]
    subprocess.run([compiler, *flags, "-ffp-contract=off", f"-I{RUNTIME}", str(source), "-o", str(library)], check=True)
    solve = ctypes.CDLL(str(library)).lu_solve
    pointer = np.ctypeslib.ndpointer(dtype=np.complex128, flags="C_CONTIGUOUS")
    solve.argtypes = [pointer, pointer, ctypes.c_void_p]
    # c_solve2: this case's system beside the previous one (each c_solve's, the pair's verdicts)
    solve2 = ctypes.CDLL(str(library)).lu_solve2
    solve2.argtypes = [pointer, pointer, ctypes.c_void_p, pointer, pointer, ctypes.c_void_p]
    previous: tuple[np.ndarray, np.ndarray, list[list[tuple[float, float]]] | None] | None = None
    rng = np.random.default_rng(size)
    ties = np.array([1.0, -1.0, 1j, -1j, 0.5 + 0.5j, -0.25 - 0.75j, 0.0])
    checked = refused = pairs_checked = 0
    for case in range(150):
        if case % 3 == 0:  # entries tying in |re| + |im| = 1, and zeros
            a = rng.choice(ties, (size, size)) * 2.0 ** rng.integers(-2, 3)
        else:
            a = rng.normal(size=(size, size)) + 1j * rng.normal(size=(size, size))
            a *= 10.0 ** rng.uniform(-3, 3, size=(size, 1))
        if case % 25 == 24:
            a[:, rng.integers(size)] = 0.0  # singular: a column of zeros
        b, c = rng.normal(size=(2, size)) + 1j * rng.normal(size=(2, size))
        two = case % 4 != 0
        pairs = [[(float(v.real), float(v.imag)) for v in row] for row in a]
        columns = [[(float(v.real), float(v.imag)) for v in column] for column in ([b, c] if two else [b])]
        expected = _textbook_solve(pairs, columns)
        a_c, b_c, c_c = a.copy(), b.copy(), c.copy()
        status = solve(a_c, b_c, c_c.ctypes.data if two else None)
        if previous is not None:
            a2, b2, expected2 = previous[0].copy(), previous[1].copy(), previous[2]
            a1, b1, c1 = a.copy(), b.copy(), c.copy()
            both = solve2(a1, b1, c1.ctypes.data if two else None, a2, b2, None)
            assert both == (expected is not None) | (expected2 is not None) << 1
            if expected is not None:
                assert b1.tolist() == [complex(*v) for v in expected[0]]
                assert not two or c1.tolist() == [complex(*v) for v in expected[1]]
            if expected2 is not None:
                assert b2.tolist() == [complex(*v) for v in expected2[0]]
            pairs_checked += 1
        previous = (a, b, _textbook_solve(pairs, columns[:1]))
        if expected is None:
            assert status == 0
            refused += 1
            continue
        assert status == 1
        for got, want in zip([b_c, c_c] if two else [b_c], expected, strict=True):
            assert got.tolist() == [complex(*v) for v in want]
            if np.linalg.cond(a) < 1e8:
                np.testing.assert_allclose(
                    a @ got, b if got is b_c else c, rtol=0, atol=1e-7 * np.abs(a).max() * np.abs(got).max()
                )
        checked += 1
    assert checked >= 120 and refused >= 6 and pairs_checked == 149
