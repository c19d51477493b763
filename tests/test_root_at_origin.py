"""A root at the origin is real (new-user review: a user's linear delta, a translating platform at
its home, whose root there has coordinates of rounding size, 1e-16, with imaginary parts as large;
its exported C found 1 of its 2 modes). An endpoint's imaginary part is measured against its own
size or the input's typical root size, the median over its reached endpoints of max |z_k|,
whichever is larger: in NumPy (``typical_root_size``, ``phase_normalised``) and in the C driver
(``kw_median``, ``phase_normalise``; the user's package, slow)."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from parakin.solvers.path_tracking import phase_normalised, typical_root_size

FIXTURES = Path(__file__).parent / "fixtures"


def test_a_root_at_the_origin_is_measured_against_the_inputs_roots():
    z = np.array(
        [
            [[1.2e-16 + 3.4e-16j, -4.0e-16 + 2.0e-16j, 0.9165], [1.3 + 0.2j, 0.1, 0.5 - 0.1j], [0.2, 0.4, 0.6]],
            [[1e-16 + 1e-16j, 0.0, 0.0], [np.nan, np.nan, np.nan], [np.nan, np.nan, np.nan]],
        ]
    )
    reached = np.array([[True, True, True], [True, False, False]])
    typical = typical_root_size(np.abs(z).max(-1), reached)
    sizes = np.abs(z[0]).max(-1)
    assert typical[0] == np.median(sizes) and typical[1] == np.abs(z[1, 0]).max()
    _, imaginary = phase_normalised(z.reshape(-1, 3), [], np.repeat(typical, 3))
    assert typical[0] == 0.9165  # the sizes 0.9165, |1.3 + 0.2i| and 0.6
    # the first input's origin root: 3.4e-16 against 0.9165 (not against its own 4.5e-16)
    assert imaginary[0] == pytest.approx(3.4e-16 / 0.9165, rel=1e-12)
    assert imaginary[1] == pytest.approx(0.2 / abs(1.3 + 0.2j), rel=1e-12)  # its own size is the larger
    assert imaginary[2] == 0.0
    # an input whose only root is at the origin has no other size to go by: as before
    assert imaginary[3] == pytest.approx(1e-16 / np.abs(1e-16 + 1e-16j), rel=1e-12)


@pytest.mark.slow
def test_the_linear_deltas_exported_c_finds_both_modes_at_home(tmp_path: Path) -> None:
    compiler = shutil.which("cc")
    if compiler is None:
        pytest.skip("no C compiler")
    run = [sys.executable, "-m", "parakin"]
    subprocess.run([*run, "generate", str(FIXTURES / "linear_delta.py"), "--out", str(tmp_path / "pkg")], check=True)
    subprocess.run([*run, "export", str(tmp_path / "pkg"), "--out", str(tmp_path / "c")], check=True)
    sources = [f"linear_delta_{part}.c" for part in ("example_main", "driver", "kernels")]
    subprocess.run(
        [compiler, "-std=c99", "-O2", "-I.", *sources, "-lm", "-o", "example"], cwd=tmp_path / "c", check=True
    )
    out = subprocess.run(["./example"], cwd=tmp_path / "c", capture_output=True, text=True, check=True).stdout
    assert "linear_delta: 2 assembly modes (2 real roots" in out, out
