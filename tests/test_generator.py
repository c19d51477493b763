"""The generator: factoring, discovery, golden regeneration, atomicity, the manifest, and the
runtime's import hygiene."""

import ast
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
import sympy as sp
from parakin.generator.build import (
    GENERATED,
    GENERATED_INIT,
    GenerationError,
    discover,
    generate,
    generate_file,
    validate_name,
)
from parakin.generator.trigpoly import factor_list, reduce_pythagorean

ROOT = Path(__file__).resolve().parent.parent


def test_trig_factor_uses_the_pythagorean_identity():
    x, y, r = sp.symbols("x y r", real=True)
    expr = sp.expand(r**2 * sp.cos(x) * sp.sin(y) * (sp.sin(x) ** 2 + sp.cos(x) ** 2))
    constant, factors = factor_list(expr)
    assert constant == 1
    assert sorted(factors, key=str) == sorted([(r, 2), (sp.cos(x), 1), (sp.sin(y), 1)], key=str)
    assert reduce_pythagorean(sp.sin(x) ** 2 + sp.cos(x) ** 2 - 1) == 0


def test_mechanisms_are_discovered_not_listed():
    found = discover()
    assert set(found) == {p.stem for p in (ROOT / "mechanisms").glob("*.py") if not p.stem.startswith("_")}
    assert set(found) == {p.name for p in GENERATED.iterdir() if p.is_dir() and not p.name.startswith("_")}


def test_names_are_validated_identifiers():
    assert validate_name("sphere2r_b") == "sphere2r_b"
    for bad in ("2r", "my-robot", "Sam", "a b"):
        with pytest.raises(GenerationError):
            validate_name(bad)


def _files(root: Path, names: list[str] | None) -> list[str]:
    """The files under root: all of them, or the top level's and those of the packages `names`."""
    paths = list(root.rglob("*")) if names is None else [root / "__init__.py"]
    for name in names or []:
        paths += (root / name).rglob("*")
    return sorted(str(p.relative_to(root)) for p in paths if p.is_file() and "__pycache__" not in p.parts)


@pytest.mark.parametrize(
    "names",
    [
        pytest.param(["five_bar", "planar_3rpr", "sphere2r"], id="three-small-mechanisms"),
        pytest.param(None, id="everything", marks=pytest.mark.slow),
    ],
)
def test_regeneration_is_byte_identical(tmp_path, names):
    """Golden test: regenerating into a scratch directory reproduces the committed tree (every
    mechanism: about a minute; by default three that generate in seconds)."""
    target = tmp_path / "generated"
    generate(names, target)
    committed = _files(GENERATED, names)
    assert _files(target, None) == committed
    for name in committed:
        assert (target / name).read_bytes() == (GENERATED / name).read_bytes(), name


def test_partial_rebuild_keeps_a_mechanism_whose_name_extends_another(tmp_path):
    """`generate sphere2r` once deleted the files of `sphere2r_b` (file names were parsed)."""
    sources = {"sphere2r": ROOT / "mechanisms" / "sphere2r.py", "sphere2r_b": ROOT / "mechanisms" / "sphere2r.py"}
    target = tmp_path / "generated"
    generate(None, target, sources=sources, workers=1)
    before = (target / "sphere2r_b" / "manifest.json").read_bytes()
    generate(["sphere2r"], target, sources=sources, workers=1)
    assert (target / "sphere2r_b" / "manifest.json").read_bytes() == before
    assert json.loads(before)["name"] == "sphere2r_b"


def test_generation_is_atomic(tmp_path):
    target = tmp_path / "generated"
    target.mkdir()
    (target / "__init__.py").write_text(GENERATED_INIT)  # a previous (empty) generated tree
    broken = tmp_path / "broken.py"
    broken.write_text("def build():\n    raise RuntimeError('a mistake in the model')\n")
    sources = {"sphere2r": ROOT / "mechanisms" / "sphere2r.py", "broken": broken}
    with pytest.raises(RuntimeError, match="a mistake in the model"):
        generate(None, target, sources=sources, workers=1)
    assert [p.name for p in target.iterdir()] == ["__init__.py"]
    assert (target / "__init__.py").read_text() == GENERATED_INIT
    assert not list(tmp_path.glob(".generated-*"))
    with pytest.raises(GenerationError, match="unknown mechanism"):
        generate(["no_such_mechanism"], target, sources=sources)


def test_manifest_describes_every_kernel_and_variable():
    manifest = json.loads((GENERATED / "sam" / "manifest.json").read_text())
    assert manifest["schema"] == 2 and manifest["name"] == "sam"
    assert manifest["citation"]["authors"] and "shared/papers" not in json.dumps(manifest["citation"])
    kinds = {v["name"]: (v["kind"], v["unit"]) for v in manifest["actuated"] + manifest["passive"]}
    assert kinds["theta1"] == ("revolute", "rad") and kinds["L2"] == ("prismatic", "m")
    numpy_source = (GENERATED / "sam" / "numpy_kernels.py").read_text()
    for kernel in manifest["kernels"]:
        assert f"def {kernel['name']}(" in numpy_source
        assert [i["name"] for i in kernel["inputs"]]


def test_generated_files_have_the_banner_and_no_timestamp():
    for path in GENERATED.rglob("*"):
        if path.suffix not in (".py", ".c", ".h") or path.name == "__init__.py" or "__pycache__" in path.parts:
            continue
        head = path.read_text().splitlines()[0]
        assert "Generated by parakin generator" in head and f"{path.parent.name}.py" in head, path
        assert "2026" not in path.read_text()[:2000]


def test_generated_numpy_module_imports_only_numpy():
    for path in GENERATED.glob("*/numpy_kernels.py"):
        tree = ast.parse(path.read_text())
        imported = {alias.name for node in ast.walk(tree) if isinstance(node, ast.Import) for alias in node.names}
        imported |= {node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)}
        assert imported <= {"numpy", "math"}, path


def test_runtime_never_imports_sympy_or_the_generator():
    code = (
        "import sys, parakin\n"
        "for name in parakin.available():\n"
        "    m = parakin.load(name, backend='numpy')\n"
        "m = parakin.load('sam', backend='compiled')\n"
        "m.forward_pose_all([0.1, -0.2, 0.05, 0.1, 0.3, -0.1], strict=False)\n"
        "bad = [n for n in sys.modules if n.split('.')[0] in ('sympy', 'jinja2', 'casadi') or 'generator' in n]\n"
        "assert not bad, bad\n"
    )
    subprocess.run([sys.executable, "-W", "ignore", "-c", code], check=True, cwd=ROOT)


def _docstrings(tree: ast.AST) -> set[int]:
    """The ids of the docstring nodes of a module's tree (module, classes, functions)."""
    owners = (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)
    return {
        id(node.body[0].value)
        for node in ast.walk(tree)
        if isinstance(node, owners)
        and node.body
        and isinstance(node.body[0], ast.Expr)
        and isinstance(node.body[0].value, ast.Constant)
        and isinstance(node.body[0].value.value, str)
    }


def test_runtime_names_no_mechanism():
    """The design's promise: parakin/ is generic; every mechanism is known through its manifest.
    No code names one: no identifier, no string outside the docstrings (whose examples load a
    shipped mechanism, as users do) and no comment counts."""
    names = set(discover())
    hits = []
    for path in sorted((ROOT / "parakin").rglob("*.py")):
        tree = ast.parse(path.read_text(), str(path))
        docs = _docstrings(tree)
        for node in ast.walk(tree):
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs:
                words = set(re.findall(r"\w+", node.value))
            elif isinstance(node, ast.Name | ast.arg | ast.Attribute):
                words = {getattr(node, "id", None) or getattr(node, "arg", None) or getattr(node, "attr", None)}
            else:
                continue
            if words & names:
                hits.append(f"{path.relative_to(ROOT)}:{node.lineno}: {sorted(words & names)}")
    assert hits == [], "\n".join(hits)
    assert len(names) >= 12


#: per copied file: a pose, its inverse branch to take, and its forward modes must contain the pose
ROUND_TRIP = {
    "sam": ("parakin.pose_from_xyz_euler([0.02, 0.03, 0.68, 0.1, 0.05, 0.08])", 2),
    "five_bar": ("parakin.pose_from_xyz_euler([0.03, 0.3, 0.0, 0.0, 0.0, 0.0])", 1),  # the point, as a transform
}


@pytest.mark.parametrize("original", ["five_bar", pytest.param("sam", marks=pytest.mark.slow)])
def test_a_copied_mechanism_file_gets_everything(tmp_path, original):
    """A mechanism file under a new name (with an underscore) generates, loads and solves with no
    other file edited; here into a package folder outside generated/. (The five-bar generates in
    a second, the SAM in about fifteen.)"""
    copy = f"{original}_copy"
    source = tmp_path / f"{copy}.py"
    shutil.copy(ROOT / "mechanisms" / f"{original}.py", source)
    package = tmp_path / "out" / copy
    generate_file(source, package)
    pose, branch = ROUND_TRIP[original]
    code = (
        "import parakin, numpy as np\n"
        f"m = parakin.load({str(package)!r}, backend='compiled')\n"
        f"assert m.name == {copy!r}\n"
        f"ik = m.inverse_pose({pose})\n"
        f"modes = m.forward_pose_all(ik.actuated[{branch}])\n"
        "assert np.abs(modes.poses[modes.valid] - ik.pose).max(axis=(-2, -1)).min() < 1e-9\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True, cwd=tmp_path)
    cli = [sys.executable, "-m", "parakin"]
    sweep = ["sweep", str(package), "reachable", "type_ii_distance", "--axis", "x=-0.2:0.2:7", "--axis", "y=-0.2:0.2:5"]
    for command in (
        ["demo", str(package)],
        ["inspect", str(package)],
        ["plot", str(package), "--output", "p.png"],
        sweep,
    ):
        done = subprocess.run(cli + command, cwd=tmp_path, capture_output=True, text=True)
        assert done.returncode == 0, (command, done.stderr)
        if command[0] == "demo":  # the copied paper examples reproduce, under the new name
            assert "[ok ]" in done.stdout and "[FAIL" not in done.stdout
        if command[0] == "sweep":  # a design study of the copy, from its manifest alone
            assert "reachable" in done.stdout and "(35/35 defined)" in done.stdout
    assert (tmp_path / "p.png").stat().st_size > 10_000


MUTATIONS = {
    "non_square": (
        "m.closure = dataclasses.replace(m.closure, residual=m.closure.residual.col_join(sp.Matrix([0])))",
        "3 equations for 2 passive unknowns",
    ),
    "inverse_incomplete": (
        "m.passive = m.passive + [sp.Symbol('extra', real=True)]",
        r"the closed-form inverse does not define \['extra'\]",
    ),
    "free_symbol": (
        "m.closure = dataclasses.replace(m.closure, residual=m.closure.residual + sp.Matrix([sp.Symbol('mystery'), 0]))",
        r"uses \['mystery'\], which are neither variables nor parameters",
    ),
    "stray_home": ("m.home[sp.Symbol('ghost')] = 0.0", r"home names \['ghost'\]"),
    "duplicate": ("m.actuated = m.actuated + [m.passive[0]]", "listed twice"),
    "name_error": ("undefined_name + 1", "NameError: name 'undefined_name' is not defined"),
}


@pytest.mark.parametrize("mutation", sorted(MUTATIONS))
def test_ill_posed_models_are_refused_in_one_line(tmp_path, mutation):
    """The five-bar file with one defect: a GenerationError naming the file or mechanism and the
    problem, nothing written, no staging folder left."""
    change, message = MUTATIONS[mutation]
    source = tmp_path / "bad_bar.py"
    source.write_text(
        (ROOT / "mechanisms" / "five_bar.py").read_text()
        + f"\n\nimport dataclasses\n_original = build\n\n\ndef build():\n    m = _original()\n    {change}\n    return m\n"
    )
    with pytest.raises(GenerationError, match=message) as raised:
        generate_file(source, tmp_path / "out" / "bad_bar")
    assert "bad_bar" in str(raised.value) and "\n" not in str(raised.value)
    assert not (tmp_path / "out" / "bad_bar").exists()
    assert not list((tmp_path / "out").glob(".generated-*"))
    cli = subprocess.run(
        [sys.executable, "-m", "parakin", "generate", str(source), "--out", str(tmp_path / "cli")],
        capture_output=True,
        text=True,
    )
    assert cli.returncode == 2 and "Traceback" not in cli.stderr and "bad_bar" in cli.stderr


def test_a_terminated_build_leaves_no_staging_folder(tmp_path):
    import signal
    import time

    out = tmp_path / "out"
    out.mkdir()
    abandoned = out / ".generated-999999999-left"  # a killed build's (no such process)
    abandoned.mkdir()
    process = subprocess.Popen(
        [sys.executable, "-m", "parakin", "generate", str(ROOT / "mechanisms" / "spm.py"), "--out", str(out / "spm")]
    )
    deadline = time.monotonic() + 60
    while not [p for p in out.glob(".generated-*") if p != abandoned] and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not abandoned.exists()  # removed when the new build started
    assert list(out.glob(".generated-*")), "the build never started staging"
    process.send_signal(signal.SIGTERM)
    assert process.wait(timeout=60) != 0
    assert not list(out.glob(".generated-*")) and not (out / "spm").exists()


def test_the_committed_packages_are_up_to_date():
    """Every committed package records the digest of what it was generated from: the current
    mechanism files and generator give the same digests (else `make generate` has not been run
    since a change), and every file is as written."""
    from parakin.generator.build import up_to_date

    sources = discover()
    stale = [name for name in sorted(sources) if not up_to_date(name, sources[name], GENERATED / name)]
    assert not stale, f"out of date: {stale}; run make generate"
    assert len(sources) >= 10


def test_generate_rebuilds_only_what_changed_and_verifies_what_it_keeps(tmp_path):
    """Incremental generation: a second run writes nothing; an edited mechanism file, an edited
    generated file and a mechanism module that a file imports each rebuild exactly the packages
    that depend on them; --force rebuilds everything; the kept packages are byte-identical."""
    from parakin.generator.build import _mechanism_sources, up_to_date

    mechanisms = tmp_path / "mechanisms"
    mechanisms.mkdir()
    for name in ("five_bar", "sphere2r"):
        shutil.copy(ROOT / "mechanisms" / f"{name}.py", mechanisms / f"{name}.py")
    sources = {"five_bar": mechanisms / "five_bar.py", "sphere2r": mechanisms / "sphere2r.py"}
    target = tmp_path / "generated"
    first = generate(None, target, sources=sources, workers=1)
    assert not any(stats.get("up_to_date") for stats in first.values())
    snapshot = {p: p.read_bytes() for p in target.rglob("*") if p.is_file()}
    second = generate(None, target, sources=sources, workers=1)
    assert all(stats.get("up_to_date") for stats in second.values()) and set(second) == set(sources)
    assert {p: p.read_bytes() for p in target.rglob("*") if p.is_file()} == snapshot
    # a changed mechanism file: that package alone
    with open(sources["five_bar"], "a") as handle:
        handle.write("\n# an edit\n")
    third = generate(None, target, sources=sources, workers=1)
    assert not third["five_bar"].get("up_to_date") and third["sphere2r"].get("up_to_date")
    # a generated file edited by hand is caught by its digest and rebuilt
    header = target / "sphere2r" / "sphere2r.h"
    header.write_text(header.read_text() + "// edited\n")
    assert not up_to_date("sphere2r", sources["sphere2r"], target / "sphere2r")
    fourth = generate(None, target, sources=sources, workers=1)
    assert not fourth["sphere2r"].get("up_to_date") and fourth["five_bar"].get("up_to_date")
    assert header.read_bytes() == snapshot[header]
    forced = generate(None, target, sources=sources, workers=1, force=True)
    assert not any(stats.get("up_to_date") for stats in forced.values())
    # a mechanism module imported by another is one of its inputs
    # (and, through it, stewart's accelerator module beside it)
    assert _mechanism_sources(ROOT / "mechanisms" / "rus6.py")[1:] == [
        (ROOT / "mechanisms" / name).resolve() for name in ("_stewart_forward.py", "stewart.py")
    ]
