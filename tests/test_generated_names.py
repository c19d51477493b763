"""A mechanism's symbols may be named like the generated kernels' own locals (issue 31
follow-up: a parameter named ``a`` or ``b`` was shadowed in the rate Jacobians' kernels, whose
outputs are the matrices A and B). The shipped five-bar, its parameters renamed ``a``, ``b``,
``shape``, ``params`` and ``actuated``, generated with ``parakin generate``, must give the shipped
package's values on every Python backend."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import parakin

ROOT = Path(__file__).resolve().parents[1]
#: the five-bar's symbol names -> names the templates use for their own locals
RENAMED = {"d": "shape", "a1": "a", "a2": "params", "b1": "b", "b2": "actuated"}


@pytest.fixture(scope="module")
def renamed(tmp_path_factory) -> Path:
    source = (ROOT / "mechanisms" / "five_bar.py").read_text()
    source = source.replace('sp.Symbol("d", positive=True)', f'sp.Symbol("{RENAMED["d"]}", positive=True)')
    source = source.replace(
        'sp.symbols("a1 a2", positive=True)', f'sp.symbols("{RENAMED["a1"]} {RENAMED["a2"]}", positive=True)'
    )
    source = source.replace(
        'sp.symbols("b1 b2", positive=True)', f'sp.symbols("{RENAMED["b1"]} {RENAMED["b2"]}", positive=True)'
    )
    source = re.sub(r'name="five_bar"', 'name="five_bar_names"', source)
    folder = tmp_path_factory.mktemp("names")
    (folder / "five_bar_names.py").write_text(source)
    out = folder / "five_bar_names"
    done = subprocess.run(
        [sys.executable, "-m", "parakin", "generate", str(folder / "five_bar_names.py"), "--out", str(out)],
        capture_output=True, text=True, cwd=ROOT,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    return out


@pytest.mark.parametrize("backend", ["numpy", "casadi"])
def test_symbols_named_like_kernel_locals_keep_their_values(renamed, backend):
    shipped = parakin.load("five_bar", backend=backend)
    mine = parakin.load(str(renamed), backend=backend)
    assert [p.name for p in mine.manifest.parameters] == [RENAMED[p.name] for p in shipped.manifest.parameters]
    rng = np.random.default_rng(7)
    theta = shipped.home_actuated + rng.uniform(-0.2, 0.2, (12, 2))
    passive = shipped.home_passive + rng.uniform(-0.05, 0.05, (12, 2))
    checked = 0
    for kernel in ("loop_closure", "rate_jacobians", "parameter_jacobians", "singularity_factors"):
        a = shipped.backend.call(kernel, theta, passive, shipped.params)
        b = mine.backend.call(kernel, theta, passive, mine.params)
        for key in a:
            np.testing.assert_allclose(np.asarray(b[key]), np.asarray(a[key]), rtol=1e-13, atol=1e-14)
            checked += 1
    assert checked >= 8
    ours, theirs = mine.forward_pose_all(shipped.home_actuated), shipped.forward_pose_all(shipped.home_actuated)
    np.testing.assert_allclose(ours.passive[ours.valid], theirs.passive[theirs.valid], atol=1e-12)
