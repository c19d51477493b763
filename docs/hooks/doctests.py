"""MkDocs hook of the parakin docs: the API reference's Examples are true. Before the pages are
built, every Example of the modules behind the API pages (``docs/api/*.md``) runs as a doctest,
in a subprocess (headless matplotlib, a scratch folder, the NumPy backend the examples ask for);
one that fails, or prints something other than what it shows, fails the build and names it.
The default test suite runs the fast ones (tests/test_docs_reference.py); this runs them all."""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

from mkdocs.config.defaults import MkDocsConfig
from mkdocs.exceptions import PluginError

ROOT = Path(__file__).resolve().parents[2]
#: the modules of the API pages whose docstrings carry Examples
MODULES = (
    "parakin.loading",
    "parakin.mechanism",
    "parakin.pose",
    "parakin.results",
    "parakin.log",
    "parakin.solvers.statics",
    "parakin.solvers.tracker",
    "parakin.studies.sweep",
    "parakin.studies.atlas",
    "parakin.singularity",
    "parakin.solvers.linalg",
    "parakin.interfaces.plot",
    "parakin.validation",
    "parakin.calibration.data",
    "parakin.calibration.fit",
    "parakin.calibration.design",
    "parakin.packages.manifest",
)
SCRIPT = """
import doctest, importlib, sys
import matplotlib
matplotlib.use("Agg")
failed = attempted = 0
for name in sys.argv[1:]:
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS)
    failed += result.failed
    attempted += result.attempted
print(f"reference examples: {attempted - failed} of {attempted} ran as shown")
sys.exit(1 if failed or not attempted else 0)
"""


def on_pre_build(config: MkDocsConfig) -> None:
    environment = {**os.environ, "MPLBACKEND": "Agg", "PARAKIN_PROGRESS": "off", "PARAKIN_LOG": "warning"}
    with tempfile.TemporaryDirectory(prefix="parakin-doctests-") as scratch:
        done = subprocess.run(
            [sys.executable, "-c", SCRIPT, *MODULES],
            cwd=scratch,
            env={**environment, "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))},
            capture_output=True,
            text=True,
            timeout=900,
        )
    if done.returncode:
        raise PluginError(
            f"an Example of the API reference does not run as written:\n{done.stdout[-6000:]}{done.stderr[-2000:]}"
        )
    print(done.stdout.strip(), file=sys.stderr)
