"""Mechanism files as descriptions (issue 32, item 4): a hand elimination lives in an optional
accelerator module beside the mechanism file (``_``-prefixed, skipped by ``discover``), the
package's input digest covers it, and a user's file outside ``mechanisms/`` may import one from
its own folder."""

from __future__ import annotations

import ast
import importlib
import io
import shutil
import sys
import tokenize
from pathlib import Path
from typing import NamedTuple

import pytest
from parakin.generator.build import MECHANISMS, discover, input_digest, load_definition
from parakin.generator.model import Example

#: the mechanisms whose hand derivations moved to an accelerator, with the accelerator each imports
DESCRIPTIONS = {
    "sps": "_sps_forward",
    "gough": "_gough_forward",
    "sam": "_sam_forward",
    "spm": "_spm_forward",
    "planar_3rpr": "_planar_3rpr_forward",
    "delta": "_delta_forward",
    "five_bar": "_five_bar_forward",
    "stewart": "_stewart_forward",
    "sphere2r": "_sphere2r_inverse",
}
#: what only an accelerator writes: a hand elimination, a hand forward system or a hand inverse
HAND_NAMES = {
    "ForwardElimination",
    "ForwardHomotopy",
    "InverseSolution",
    "biquadratic_resultant",
    "half_angle_grid",
    "remove_spurious_factors",
}
#: lines of model code (``model_lines``: the model part, before the examples marker) of each
#: mechanism file at most. Whole files before the descriptions: sps 290, gough 185, prs3 138, sam
#: 141, rus6 142, spm 153, planar_3rpr 123, delta 122, five_bar 109, planar_3rrr 86, stewart 95,
#: sphere2r 78. Whole files (model and examples together, this counter) at 96a3846: sps 114, gough
#: 100, prs3 112, sam 89, rus6 142, spm 79, planar_3rpr 53, delta 85, five_bar 79, planar_3rrr 86,
#: stewart 77, sphere2r 45, rps3 49, tricept 71 (1181); at 7940229: 1060.
MODEL_LINES = {
    "sps": 62,
    "gough": 53,
    "prs3": 40,
    "sam": 55,
    "rus6": 57,
    "spm": 65,
    "planar_3rpr": 37,
    "delta": 49,
    "five_bar": 36,
    "planar_3rrr": 46,
    "stewart": 55,
    "sphere2r": 45,
    "rps3": 37,
    "tricept": 42,
}
#: a mechanism file added since: a description as long as the longest above at most
NEW_MODEL_LINES = max(MODEL_LINES.values())
#: lines of the shipped files' examples parts together at most (the papers' and constructed
#: inputs and expected values: bounded overall, never shortened by dropping an example)
EXAMPLE_LINES = 344


#: the comment line that ends a mechanism file's model and begins its examples (the papers' and
#: constructed inputs, their expected values, EXAMPLES); only model code stands before it
EXAMPLES_MARKER = "# Examples"


class Lines(NamedTuple):
    """Lines of code of a mechanism file before its examples marker and after it."""

    model: int
    examples: int


def _marker_line(source: str) -> int | None:
    """The line number of the examples marker (a whole line, at column 0), or None."""
    lines = [n for n, line in enumerate(source.splitlines(), 1) if line.rstrip() == EXAMPLES_MARKER]
    assert len(lines) <= 1, f"{len(lines)} lines {EXAMPLES_MARKER!r}"
    return lines[0] if lines else None


def model_lines(path: Path) -> Lines:
    """Lines of code of a Python file, not blank, comment, docstring or import lines: those before
    the examples marker (all of them when it has none) and those after it."""
    source = path.read_text()
    tree = ast.parse(source)
    skipped: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import | ast.ImportFrom):
            skipped.update(range(node.lineno, (node.end_lineno or node.lineno) + 1))
        body = getattr(node, "body", None)
        if isinstance(node, ast.Module | ast.FunctionDef | ast.ClassDef) and body:
            first = body[0]
            if (
                isinstance(first, ast.Expr)
                and isinstance(first.value, ast.Constant)
                and isinstance(first.value.value, str)
            ):
                skipped.update(range(first.lineno, (first.end_lineno or first.lineno) + 1))
    code: set[int] = set()
    ignored = {tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT, tokenize.ENDMARKER}
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type not in ignored:
            code.update(range(token.start[0], token.end[0] + 1))
    code -= skipped
    marker = _marker_line(source) or len(source.splitlines()) + 1
    return Lines(sum(n < marker for n in code), sum(n > marker for n in code))


def _bound(node: ast.stmt) -> set[str]:
    """The names a top-level statement binds: an assignment's targets, a function or a class."""
    if isinstance(node, ast.FunctionDef | ast.ClassDef):
        return {node.name}
    targets = node.targets if isinstance(node, ast.Assign) else [getattr(node, "target", None)]
    return {n.id for t in targets if t is not None for n in ast.walk(t) if isinstance(n, ast.Name)}


def _reads(nodes: list[ast.stmt]) -> set[str]:
    return {n.id for node in nodes for n in ast.walk(node) if isinstance(n, ast.Name) and isinstance(n.ctx, ast.Load)}


def example_names(path: Path) -> tuple[set[str], set[str], set[str]]:
    """The names the examples part binds; those of them the model part reads; and the names the
    model part binds that only the examples read (example data standing in the model)."""
    source = path.read_text()
    marker = _marker_line(source)
    if marker is None:
        return set(), set(), set()
    body = ast.parse(source).body
    model, examples = [n for n in body if n.lineno < marker], [n for n in body if n.lineno > marker]
    bound = set().union(*map(_bound, examples))
    in_model = set().union(*map(_bound, model))
    return bound, _reads(model) & bound, (in_model & _reads(examples)) - _reads(model)


def test_model_lines_counts_code_only(tmp_path):
    source = tmp_path / "sample.py"
    source.write_text(
        '"""Doc\nstring."""\n\nimport math\n\n# a comment\nX = [\n    1,\n    2,\n]\n\n\ndef f():\n    """Doc."""\n    return math.pi\n'
    )
    assert model_lines(source) == (6, 0)  # X = [ 1, 2, ] (4 lines), def f, return
    assert example_names(source) == (set(), set(), set())
    source.write_text(
        '"""Doc."""\n\nA = 1\n\n\ndef build():\n    return A, EXAMPLES\n\n\n# Examples\nB: int = A + 1  # its own\nEXAMPLES = [\n    B,\n]\n'
    )
    assert model_lines(source) == (3, 4)  # A =, def build, return | B =, EXAMPLES = [ B, ]
    assert example_names(source) == ({"B", "EXAMPLES"}, {"EXAMPLES"}, set())
    source.write_text(
        '"""Doc."""\n\nP = 2\n\n\ndef build():\n    return B\n\n\n# Examples\nB, C = 1, P\n\n\ndef d():\n    return C\n'
    )
    # the model reads an example's name, B; the examples alone read P, a name the model binds
    assert example_names(source) == ({"B", "C", "d"}, {"B"}, {"P"})


@pytest.mark.parametrize("name", sorted(DESCRIPTIONS))
def test_a_description_imports_its_accelerator_and_holds_no_elimination(name):
    tree = ast.parse((MECHANISMS / f"{name}.py").read_text())
    imported = {alias.name for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) for alias in node.names}
    modules = {node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
    assert DESCRIPTIONS[name] in imported or f"parakin.mechanisms.{DESCRIPTIONS[name]}" in modules
    names = {node.id for node in ast.walk(tree) if isinstance(node, ast.Name)} | imported
    assert not names & HAND_NAMES, f"{name}.py writes {sorted(names & HAND_NAMES)}: an accelerator's job"


def test_every_mechanism_file_is_a_short_description():
    """Conventions once, in a docstring of at most 20 lines (the derivation prose lives in
    docs/derivations/NAME.md, linked from the site's navigation), and no more model code than
    recorded: the model part of each file, before its examples marker, and the examples of all
    files together."""
    navigation = (MECHANISMS.parent / "mkdocs.yml").read_text()
    assert set(MODEL_LINES) <= set(discover())
    examples = 0
    for name, path in discover().items():
        docstring = ast.get_docstring(ast.parse(path.read_text())) or ""
        assert 0 < len(docstring.splitlines()) <= 20, f"{name}.py: {len(docstring.splitlines())} docstring lines"
        bound, lines = MODEL_LINES.get(name, NEW_MODEL_LINES), model_lines(path)
        assert lines.model <= bound, f"{name}.py: {lines.model} lines of model code, at most {bound}"
        examples += lines.examples
        if name in MODEL_LINES and name not in ("rps3", "tricept"):  # those two: descriptions from the start
            assert f"docs/derivations/{name}.md" in docstring.replace("``", "")
            assert (MECHANISMS.parent / "docs" / "derivations" / f"{name}.md").is_file()
            assert f"derivations/{name}.md" in navigation
    assert examples <= EXAMPLE_LINES, f"{examples} lines of examples, at most {EXAMPLE_LINES}"


@pytest.mark.parametrize("name", sorted(MODEL_LINES))
def test_a_mechanism_file_is_its_model_then_its_examples(name):
    """Each shipped file: the model (symbols, parameters, joints, home, citation, build()), then the
    marker, then the examples; the model reads no name the examples bind but EXAMPLES, which
    build() hands to the Mechanism (read when build() is called, the module loaded), and binds
    none that only the examples read. Read from the source and the imported module (build() is
    not called: generating takes seconds; the golden tests compare what it builds)."""
    path = MECHANISMS / f"{name}.py"
    assert model_lines(path).model > 0 and _marker_line(path.read_text()) is not None
    bound, read, data = example_names(path)
    assert read <= {"EXAMPLES"}, f"{name}.py: the model reads {sorted(read - {'EXAMPLES'})} of the examples"
    assert not data, f"{name}.py: {sorted(data)} stand in the model but only the examples read them"
    assert "build" not in bound
    build = next(n for n in ast.parse(path.read_text()).body if isinstance(n, ast.FunctionDef) and n.name == "build")
    handed = [k.value for n in ast.walk(build) if isinstance(n, ast.Call) for k in n.keywords if k.arg == "examples"]
    if name == "sphere2r":  # its paper prints no numbers: an examples part with none
        assert bound == set() and handed == []
    else:
        assert [ast.dump(v) for v in handed] == [ast.dump(ast.Name("EXAMPLES", ast.Load()))]
        examples = importlib.import_module(f"parakin.mechanisms.{name}").EXAMPLES
        assert examples and all(isinstance(e, Example) for e in examples)


def test_discover_skips_the_accelerators():
    accelerators = sorted(p.stem for p in MECHANISMS.glob("_*.py") if p.stem != "__init__")
    assert set(DESCRIPTIONS.values()) <= set(accelerators)
    assert not set(discover()) & set(accelerators)
    assert set(DESCRIPTIONS) <= set(discover())


def test_the_input_digest_covers_the_accelerator(tmp_path, monkeypatch):
    """The shipped folder copied with sps and its accelerator (standing for parakin.mechanisms):
    editing the accelerator changes the package's input digest (the package is out of date); an
    unrelated file beside it does not. A user's copy of sps.py elsewhere depends on the shipped
    accelerator, the module it imports."""
    from parakin.generator import build

    assert build._mechanism_sources(MECHANISMS / "sps.py") == [
        (MECHANISMS / n).resolve() for n in ("sps.py", "_sps_forward.py")
    ]
    copy = tmp_path / "user" / "sps.py"
    copy.parent.mkdir()
    shutil.copy(MECHANISMS / "sps.py", copy)
    assert build._mechanism_sources(copy)[1:] == [(MECHANISMS / "_sps_forward.py").resolve()]
    shipped = tmp_path / "mechanisms"
    shipped.mkdir()
    for source in (MECHANISMS / "sps.py", MECHANISMS / "_sps_forward.py"):
        shutil.copy(source, shipped / source.name)
    monkeypatch.setattr(build, "MECHANISMS", shipped)
    before = input_digest("sps", shipped / "sps.py")
    (shipped / "_unrelated.py").write_text("X = 1\n")
    assert input_digest("sps", shipped / "sps.py") == before
    with (shipped / "_sps_forward.py").open("a") as accelerator:
        accelerator.write("# edited\n")
    assert input_digest("sps", shipped / "sps.py") != before


USER_FILE = '''"""A five-bar whose title comes from its accelerator beside it."""
import _mine_forward

from parakin.mechanisms.five_bar import build as five_bar


def build():
    mechanism = five_bar()
    mechanism.title = _mine_forward.TITLE
    return mechanism
'''


def _user_folder(folder: Path, title: str) -> Path:
    folder.mkdir()
    (folder / "mine.py").write_text(USER_FILE)
    (folder / "_mine_forward.py").write_text(f"TITLE = {title!r}\n")
    return folder / "mine.py"


def test_a_users_file_imports_the_accelerator_beside_it(tmp_path):
    """Two folders, each a mine.py with its own _mine_forward.py: each file loads its own
    accelerator (none left cached or on the import path), and each digest covers its own."""
    first, second = _user_folder(tmp_path / "a", "first five-bar"), _user_folder(tmp_path / "b", "second five-bar")
    assert load_definition(first)[0].title == "first five-bar"
    assert load_definition(second)[0].title == "second five-bar"
    assert "_mine_forward" not in sys.modules
    assert str(tmp_path / "a") not in sys.path and str(tmp_path / "b") not in sys.path
    before = input_digest("mine", first)
    (tmp_path / "a" / "_mine_forward.py").write_text("TITLE = 'renamed'\n")
    assert input_digest("mine", first) != before
    assert load_definition(first)[0].title == "renamed"
    (tmp_path / "a" / "_mine_forward.py").write_text("from _mine_helper import TITLE\n")
    (tmp_path / "a" / "_mine_helper.py").write_text("TITLE = 'helper'\n")
    with_helper = input_digest("mine", first)
    (tmp_path / "a" / "_mine_helper.py").write_text("TITLE = 'helper, edited'\n")
    assert input_digest("mine", first) != with_helper  # transitively
    assert load_definition(first)[0].title == "helper, edited"


@pytest.mark.slow
def test_parakin_generate_of_a_users_file_with_an_accelerator(tmp_path):
    """``parakin generate`` end to end: the package carries the accelerator's title and is up to
    date until the accelerator changes."""
    from parakin.generator.build import generate_file, up_to_date

    import parakin

    source = _user_folder(tmp_path / "src", "five-bar with an accelerator")
    package = tmp_path / "mine_package"
    generate_file(source, package)
    assert parakin.load(package).manifest.title == "five-bar with an accelerator"
    assert up_to_date("mine", source, package)
    (tmp_path / "src" / "_mine_forward.py").write_text("TITLE = 'changed'\n")
    assert not up_to_date("mine", source, package)


PLAIN_FIVE_BAR = """\"\"\"The shipped five-bar without its accelerator.\"\"\"
import dataclasses

from parakin.mechanisms import five_bar


def build():
    return dataclasses.replace(five_bar.build(), forward=None)
"""


def test_an_accelerator_is_optional(tmp_path):  # about 2 s
    """The five-bar generated without its accelerator (forward=None: the generator's own polynomial
    form) finds the same assembly modes as the shipped package with the hand two-circle
    elimination, at 40 seeded inputs near the home."""
    import numpy as np
    from parakin.generator.build import generate_file

    import parakin

    source = tmp_path / "five_bar_plain.py"
    source.write_text(PLAIN_FIVE_BAR)
    generate_file(source, tmp_path / "plain")
    plain, shipped = parakin.load(tmp_path / "plain", backend="numpy"), parakin.load("five_bar", backend="numpy")
    rng = np.random.default_rng(32)
    checked = 0
    for _ in range(40):
        actuated = shipped.home_actuated + rng.uniform(-0.3, 0.3, 2)
        modes = [m.forward_pose_all(actuated) for m in (plain, shipped)]
        assert (modes[0].method, modes[1].method) == ("automatic", "elimination")
        found = [np.sort(m.passive[m.valid], axis=0) for m in modes]
        assert found[0].shape == found[1].shape, (actuated, found)
        assert np.allclose(found[0], found[1], atol=1e-9, rtol=0), (actuated, found)
        checked += len(found[0]) > 0
    assert checked >= 30
