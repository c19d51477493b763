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
    univariate and projective certificates against closed-form roots, the refused jobs."""
    assert not [line for line in krawczyk_output if line.startswith("failed")]
    checked = [int(line.split()[1]) for line in krawczyk_output if line.startswith("checked ")]
    assert checked and checked[0] >= 800


def test_c_krawczyk_constants_are_the_numpy_references() -> None:
    """krawczyk.h's NEAR, MULTIPLIERS, NEWTON_STEPS and FLOOR are certify.py's."""
    from parakin.solvers import certify

    text = (RUNTIME / "krawczyk.h").read_text()
    assert f"#define KW_NEAR {certify.NEAR!r}" in text
    assert "kw_multipliers[KW_RADII] = {" + ", ".join(map(repr, certify.MULTIPLIERS.tolist())) + "}" in text
    assert f"#define KW_RADII {certify.MULTIPLIERS.size}" in text
    assert f"#define KW_NEWTON_STEPS {certify.NEWTON_STEPS}" in text
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
