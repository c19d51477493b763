"""The API reference in the NumPy convention (issue 36, item 1): every public function shown on
an API page (``docs/api/*.md``, the objects named by its ``:::`` directives, as mkdocstrings
renders them) has Parameters (when it takes any), Returns (or Yields; not for ``-> None``),
Raises and Examples sections; and the Examples of the modules behind the pages run as written
(doctest on the NumPy backend: five-bar, 3-RRR and the other fast loads)."""

from __future__ import annotations

import doctest
import functools
import re
from pathlib import Path

import griffe
import pytest
import yaml

ROOT = Path(__file__).resolve().parent.parent
API = ROOT / "docs" / "api"
#: the site's default filters (mkdocs.yml): names starting with an underscore are not shown
DEFAULT_FILTERS = ["!^_"]
#: functions shown on the pages that raise nothing a caller can cause, so carry no Raises section
NO_RAISES = {
    "parakin.loading.available",  # skips an unreadable package with a warning (its Warns section)
    "parakin.mechanism.Mechanism.architecture",  # reads the loaded (already checked) parameters
    "parakin.studies.sweep.home_branch",  # reads the loaded mechanism's own home
    "parakin.mechanism.Mechanism.is_architecturally_singular",
    "parakin.log.Progress.update",  # a bar's counters: nothing to refuse
    "parakin.log.Progress.restart",
    "parakin.log.Progress.describe",
    "parakin.log.Progress.close",
    "parakin.results.AssemblyModes.complete",  # readers of a finished result
    "parakin.results.AssemblyModes.ill_conditioned",
    "parakin.results.AssemblyModes.certificate",
    "parakin.calibration.data.CalibrationData.frame_values",  # readers of checked measurements
    "parakin.calibration.data.CalibrationData.free_frames",
    "parakin.calibration.fit.CalibrationResult.summary",  # formats a finished result
}


def _directives() -> list[tuple[str, dict]]:
    """(identifier, options) of every ``::: identifier`` directive of the API pages."""
    found = []
    for page in sorted(API.glob("*.md")):
        lines = page.read_text().splitlines()
        for k, line in enumerate(lines):
            if not line.startswith(":::"):
                continue
            block = []
            for following in lines[k + 1 :]:
                if following.strip() and not following.startswith("    "):
                    break
                block.append(following[4:])
            options = (yaml.safe_load("\n".join(block)) or {}).get("options", {}) or {}
            found.append((line[3:].strip(), options))
    return found


def _passes(name: str, filters: list[str]) -> bool:
    """mkdocstrings' ``filters``: a name is shown unless a "!pattern" matches it, and, where
    positive patterns are given, only if one of them matches."""
    negative = [f[1:] for f in filters if f.startswith("!")]
    positive = [f for f in filters if not f.startswith("!")]
    if any(re.search(pattern, name) for pattern in negative):
        return False
    return not positive or any(re.search(pattern, name) for pattern in positive)


@functools.cache
def _shown_functions() -> dict[str, griffe.Function]:
    """Every function the API pages render (public, with a docstring), by its full path."""
    loader = griffe.GriffeLoader(search_paths=[str(ROOT)], docstring_parser=griffe.Parser.numpy)
    package = loader.load("parakin")
    loader.resolve_aliases(implicit=False, external=False)
    shown: dict[str, griffe.Function] = {}

    def visit(obj: griffe.Object | griffe.Alias, members: object, filters: list[str]) -> None:
        if isinstance(obj, griffe.Alias):
            obj = obj.final_target
        if isinstance(obj, griffe.Function):
            if obj.docstring and "property" not in obj.labels:
                shown[obj.path] = obj
            return
        if not (obj.is_class or obj.is_module) or members is False:
            return
        exported = set(obj.exports or ()) if obj.is_module else None
        for name, member in obj.members.items():
            if isinstance(members, list) and name not in members:
                continue
            if not _passes(name, filters) or (member.is_alias and (exported is None or name not in exported)):
                continue
            visit(member, None, filters)

    for identifier, options in _directives():
        target = package if identifier == "parakin" else package[identifier.removeprefix("parakin.")]
        visit(target, options.get("members"), options.get("filters", DEFAULT_FILTERS))
    return shown


def _missing(function: griffe.Function) -> list[str]:
    assert function.docstring is not None
    kinds = {section.kind.value for section in function.docstring.parse(griffe.Parser.numpy)}
    wanted = []
    if any(p.name not in ("self", "cls") for p in function.parameters):
        wanted.append("parameters")
    if str(function.returns) != "None" and "yields" not in kinds:
        wanted.append("returns")
    if function.path not in NO_RAISES:
        wanted.append("raises")
    wanted.append("examples")
    return [kind for kind in wanted if kind not in kinds]


def test_every_function_of_the_api_pages_has_the_numpy_sections():
    shown = _shown_functions()
    # the pages show the library's API: at least the Mechanism's 29 methods, load and its
    # friends, the pose helpers, the results, statics, tracker, sweep and plotting functions
    assert len(shown) >= 70, sorted(shown)
    assert {"parakin.mechanism.Mechanism.forward_pose_all", "parakin.loading.load"} <= set(shown)
    missing = {path: kinds for path, function in shown.items() if (kinds := _missing(function))}
    assert not missing, missing


def test_the_section_check_catches_a_missing_section():
    """The check itself: a docstring with every section passes, each section taken out fails."""
    full = """Add.

    Parameters
    ----------
    x : float
        A length (m).

    Returns
    -------
    float
        x + 1.

    Raises
    ------
    BadInputError
        x not finite.

    Examples
    --------
    >>> 1 + 1
    2
    """
    for removed in ("", "Parameters", "Returns", "Raises", "Examples"):
        text = full if not removed else re.sub(rf"    {removed}\n.*?(?=\n    [A-Z]\w+\n    -|\Z)", "", full, flags=re.S)
        function = griffe.Function(
            "f", parameters=griffe.Parameters(griffe.Parameter("x")), returns="float", docstring=griffe.Docstring(text)
        )
        assert _missing(function) == ([removed.lower()] if removed else [])


#: the modules behind the API pages whose Examples the default suite runs (parakin.interfaces.plot
#: and parakin.results: tests/test_docs_site.py); ``make docs`` runs them all (docs/hooks/doctests.py)
MODULES = (
    "parakin.mechanism",
    "parakin.loading",
    "parakin.pose",
    "parakin.log",
    "parakin.solvers.statics",
    "parakin.solvers.tracker",
    "parakin.studies.sweep",
    "parakin.studies.atlas",
    "parakin.singularity",
    "parakin.validation",
    "parakin.calibration.data",
    "parakin.calibration.fit",
    "parakin.calibration.design",
    "parakin.packages.manifest",
)
#: modules of the API pages that other tests cover (their owners' examples and dependencies)
OTHERS = ("parakin.dynamics", "parakin.mujoco_bridge", "parakin.errors")
#: Examples left to the docs build: slower than the default suite's budget allows
SLOW_EXAMPLES = {"parakin.loading.symbolic"}  # derives the SymPy model: about 1.5 s


@pytest.mark.parametrize("module", MODULES)
def test_the_reference_examples_run(module, tmp_path, monkeypatch):
    """Every Example of the module's docstrings runs and prints what it shows."""
    import importlib

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("PARAKIN_PROGRESS", "auto")
    finder = doctest.DocTestFinder()
    runner = doctest.DocTestRunner(optionflags=doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS)
    tests = [t for t in finder.find(importlib.import_module(module)) if t.examples and t.name not in SLOW_EXAMPLES]
    try:
        for test in tests:
            runner.run(test)
    finally:
        plt.close("all")
    result = runner.summarize(verbose=False)
    assert result.failed == 0 and result.attempted >= 3, result


def test_the_docs_build_runs_every_reference_example():
    """``make docs`` runs the Examples of every module behind the API pages (the hook), the slow
    ones included: a module whose docstrings carry Examples is in the hook's list."""
    import importlib.util

    assert "docs/hooks/doctests.py" in (ROOT / "mkdocs.yml").read_text()
    spec = importlib.util.spec_from_file_location("doctests_hook", ROOT / "docs" / "hooks" / "doctests.py")
    hook = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(hook)
    shown = {function.module.path for function in _shown_functions().values()}
    # every module of ours the pages show is run (dynamics and the MuJoCo bridge keep their own
    # tests)
    ours = {module for module in shown if not module.startswith(OTHERS)}
    assert ours <= set(hook.MODULES), sorted(ours - set(hook.MODULES))
    assert set(MODULES) <= set(hook.MODULES)
