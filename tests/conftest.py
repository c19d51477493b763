import functools
import os
import sys
from pathlib import Path

import numpy as np
import pytest

import parakin

# the paper walkthroughs in examples/ are importable modules: `import gough_architecture`
EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
if str(EXAMPLES) not in sys.path:
    sys.path.insert(0, str(EXAMPLES))

BACKENDS = ["numpy", "casadi", "compiled"]


def pytest_addoption(parser):
    parser.addoption(
        "--run-slow",
        action="store_true",
        help="also run the tests marked slow (full-size versions of sampled checks, a full regeneration, "
        "a million inputs); PARAKIN_SLOW=1 or any -m expression does the same",
    )


def pytest_collection_modifyitems(config, items):
    """Tests marked slow are skipped (with a reason) unless asked for: --run-slow, PARAKIN_SLOW=1,
    or a -m expression (then that expression alone selects, e.g. -m slow). Every feature they check
    also has a smaller default test."""
    if config.getoption("--run-slow") or os.environ.get("PARAKIN_SLOW") == "1" or config.getoption("markexpr"):
        return
    skip = pytest.mark.skip(reason="slow: run with --run-slow, PARAKIN_SLOW=1 or -m slow")
    heavy = pytest.mark.skip(
        reason=f"slow: the all-modes solver of {', '.join(sorted(_heavy_families()))} tracks more than "
        f"{HEAVY_PATHS} paths, in NumPy orchestration off the compiled backend and in the second run its "
        "certificate asks for; its own test file runs every time, the generic cases with --run-slow"
    )
    orchestrated = pytest.mark.skip(
        reason=f"slow: the all-modes solver of "
        f"{', '.join(sorted(_heavy_families(ORCHESTRATED_PATHS) - _heavy_families()))} tracks more than "
        f"{ORCHESTRATED_PATHS} paths, orchestrated in NumPy on this backend; the compiled case and the "
        "mechanism's own test file run every time"
    )
    for item in items:
        if "slow" in item.keywords:
            item.add_marker(skip)
            continue
        params = getattr(getattr(item, "callspec", None), "params", {})
        name = params.get("name")
        if isinstance(name, str) and name in _heavy_families():
            item.add_marker(heavy)
        elif (
            isinstance(name, str)
            and params.get("backend") in ("numpy", "casadi")
            and name in _heavy_families(ORCHESTRATED_PATHS)
        ):
            item.add_marker(orchestrated)


#: a mechanism whose default all-modes homotopy has more paths than this is checked by the generic
#: tests parametrised by name only with --run-slow; its own test file runs every time
HEAVY_PATHS = 40
#: ... and its NumPy and CasADi cases only with --run-slow above this many paths (prs3, stewart)
ORCHESTRATED_PATHS = 16


@functools.cache
def _heavy_families(paths: int = HEAVY_PATHS) -> frozenset[str]:
    """The mechanisms whose default all-modes homotopy tracks more than ``paths`` paths and that
    have a test file of their own (``tests/test_NAME.py``): a user's package on $PARAKIN_PATH has
    none, so every generic case runs for it."""
    heavy = set()
    for name in parakin.available():
        if not (Path(__file__).parent / f"test_{name}.py").is_file():
            continue
        forward = parakin.load(name, backend="numpy").capabilities.forward
        if forward is not None and forward.homotopy is not None and forward.homotopy.start.shape[0] > paths:
            heavy.add(name)
    return frozenset(heavy)


@pytest.fixture(scope="session", params=BACKENDS)
def sam(request):
    return parakin.load("sam", backend=request.param)


@pytest.fixture(scope="session")
def sam_numpy():
    return parakin.load("sam", backend="numpy")


@pytest.fixture(scope="session")
def sam_compiled():
    return parakin.load("sam", backend="compiled")


def random_reachable_poses(rng: np.random.Generator, count: int) -> np.ndarray:
    """Poses around the working region of section 4: the platform above the actuators, within
    +-0.15 m laterally and +-25 deg in each Euler angle."""
    values = np.column_stack(
        [
            rng.uniform(-0.15, 0.15, count),
            rng.uniform(-0.15, 0.15, count),
            rng.uniform(0.5, 0.9, count),
            *(rng.uniform(-0.45, 0.45, count) for _ in range(3)),
        ]
    )
    return parakin.pose_from_xyz_euler(values)
