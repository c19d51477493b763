"""Generation never loses a user's file and is atomic under a kill (issue 18 items 1, 2; the
generator's parts of 12, 14 and 17).

Every claim is checked against the file system itself: the exact names and bytes of every file
before and after, a fresh generation into a new folder as the reference for what a package holds,
and real builds killed with SIGKILL inside each step of the swap (the ``PARAKIN_TEST_PAUSE_SWAP``
test hook widens the window)."""

import json
import os
import py_compile
import shutil
import signal
import subprocess
import sys
from pathlib import Path

import pytest
from parakin.generator import build
from parakin.generator.build import GENERATED, GenerationError, generate, generate_file, package_files

ROOT = Path(__file__).resolve().parent.parent
FIVE_BAR = ROOT / "mechanisms" / "five_bar.py"
SPHERE2R = ROOT / "mechanisms" / "sphere2r.py"
GCC = shutil.which("gcc")
C_FLAGS = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-O2", "-c", "-o", os.devnull]


def snapshot(root: Path) -> dict[str, bytes]:
    """Every file under ``root`` (relative name -> bytes; folders as b'<dir>'), Python's
    ``__pycache__`` left out: the state a test compares before and after."""
    state = {}
    for path in sorted(root.rglob("*")):
        if "__pycache__" in path.parts:
            continue
        state[str(path.relative_to(root))] = b"<dir>" if path.is_dir() else path.read_bytes()
    return state


def user_folder(folder: Path) -> dict[str, bytes]:
    """A user's folder: a note, a sub-folder with a file, and a mechanism file of their own."""
    (folder / "sub").mkdir(parents=True)
    (folder / "notes.txt").write_text("my notes\n")
    (folder / "sub" / "data.csv").write_text("1,2,3\n")
    shutil.copy(FIVE_BAR, folder / "my_robot.py")
    return snapshot(folder)


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> Path:
    """The five-bar file as ``my_robot.py``, generated into a new folder: what a package holds."""
    root = tmp_path_factory.mktemp("reference")
    shutil.copy(FIVE_BAR, root / "my_robot.py")
    generate_file(root / "my_robot.py", root / "package")
    return root / "package"


# item 1: never delete, move or overwrite a file the generator did not write


def test_out_dot_is_refused_and_the_working_directory_is_untouched(tmp_path):
    """`parakin generate my_robot.py --out .` once deleted the working directory, the user's
    my_robot.py included."""
    before = user_folder(tmp_path)
    done = subprocess.run(
        [sys.executable, "-m", "parakin", "generate", "my_robot.py", "--out", "."],
        cwd=tmp_path,
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2, done.stderr
    assert "--force" in done.stderr and "new folder" in done.stderr and "Traceback" not in done.stderr
    assert snapshot(tmp_path) == before
    hidden = [p.name for p in tmp_path.parent.iterdir() if p.name.startswith((f".{tmp_path.name}", ".generated-"))]
    assert hidden == []  # nothing moved or staged next to it either


def test_a_user_folder_is_refused_and_force_writes_next_to_its_files(tmp_path, reference):
    """`--out userdir` once wiped userdir/notes.txt. Refused (nothing written); with force the
    package's files are written into it, equal to a fresh generation, and every other file stays."""
    folder = tmp_path / "userdir"
    before = user_folder(folder)
    with pytest.raises(GenerationError, match=r"non-empty folder that is not a generated package.*--force"):
        generate_file(folder / "my_robot.py", folder)
    assert snapshot(folder) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["userdir"]

    generate_file(folder / "my_robot.py", folder, force=True)
    after = snapshot(folder)
    assert {name: after[name] for name in before} == before  # the user's files, byte for byte
    assert set(after) - set(before) == set(package_files("my_robot"))
    for name in package_files("my_robot"):
        assert after[name] == (reference / name).read_bytes(), name
    assert sorted(p.name for p in tmp_path.iterdir()) == ["userdir"]  # no staging folder left

    # still not a package (the user's files are in it): refused again without force, so the
    # folder is never swapped away; with force again, the package's files only are rewritten
    with pytest.raises(GenerationError, match="--force"):
        generate_file(folder / "my_robot.py", folder)
    (folder / "kernels.c").write_text("stale")
    generate_file(folder / "my_robot.py", folder, force=True)
    assert snapshot(folder) == after


def test_a_file_in_place_of_the_folder_is_refused_before_anything_is_written(tmp_path):
    """`--out existing_file` once wrote the package, hid the file as .existing_file.old and
    exited with NotADirectoryError."""
    shutil.copy(FIVE_BAR, tmp_path / "my_robot.py")
    (tmp_path / "existing_file").write_text("precious")
    before = snapshot(tmp_path)
    for force in (False, True):
        with pytest.raises(GenerationError, match="is a file, not a folder"):
            generate_file(tmp_path / "my_robot.py", tmp_path / "existing_file", force=force)
        assert snapshot(tmp_path) == before
    done = subprocess.run(
        [sys.executable, "-m", "parakin", "generate", "my_robot.py", "--out", "existing_file"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2 and "is a file" in done.stderr and "Traceback" not in done.stderr
    assert snapshot(tmp_path) == before


def test_a_generated_package_is_replaced_and_one_with_a_user_file_is_not(tmp_path, reference):
    """A package folder (even with the __pycache__ an import of it writes) is replaced by the new package
    as a whole; once the user put a file of their own into it, it is a user folder."""
    shutil.copy(SPHERE2R, tmp_path / "my_robot.py")  # another model under the same name
    (tmp_path / "out").mkdir()
    package = tmp_path / "out" / "package"
    shutil.copytree(reference, package)
    py_compile.compile(str(package / "numpy_kernels.py"), doraise=True)  # as an import of it would
    assert (package / "__pycache__").is_dir()

    generate_file(tmp_path / "my_robot.py", package)
    fresh = tmp_path / "fresh"
    generate_file(tmp_path / "my_robot.py", fresh)
    assert snapshot(package) == snapshot(fresh) != snapshot(reference)
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["package"]

    (package / "notes.txt").write_text("mine")
    before = snapshot(package)
    with pytest.raises(GenerationError, match="--force"):
        generate_file(tmp_path / "my_robot.py", package)
    assert snapshot(package) == before


def test_an_empty_folder_is_filled(tmp_path, reference):
    shutil.copy(FIVE_BAR, tmp_path / "my_robot.py")
    (tmp_path / "empty").mkdir()
    generate_file(tmp_path / "my_robot.py", tmp_path / "empty")
    assert snapshot(tmp_path / "empty") == snapshot(reference)


def test_generate_refuses_a_destination_with_files_it_did_not_write(tmp_path):
    """The `make generate` driver with a destination: a folder holding anything but a generated
    tree is refused before any build; nothing in it changes."""
    target = tmp_path / "generated"
    target.mkdir()
    (target / "keep.txt").write_text("mine")
    (target / "__init__.py").write_text("# a user's package, not a generated tree\n")
    before = snapshot(tmp_path)
    with pytest.raises(GenerationError, match=r"did not write \(__init__.py, keep.txt\).*new folder"):
        generate(None, target, sources={"five_bar": FIVE_BAR}, workers=1)
    assert snapshot(tmp_path) == before
    (tmp_path / "file").write_text("a file")
    with pytest.raises(GenerationError, match="not a folder"):
        generate(None, tmp_path / "file", sources={"five_bar": FIVE_BAR}, workers=1)
    assert (tmp_path / "file").read_text() == "a file"


# item 2: a kill at any instant of the swap leaves the previous or the new tree, or one the next
# run restores by itself

KILLED_BUILD = """
import sys
from pathlib import Path
from parakin.generator import build
if sys.argv[1] == "renames":  # the fallback of systems without an atomic exchange
    build._renameat2 = None
if sys.argv[2] == "generate":  # a partial rebuild of `alpha`; `beta` must survive
    build.generate(["alpha"], Path(sys.argv[3]), sources={"alpha": Path(sys.argv[4]), "beta": Path(sys.argv[5])}, workers=1)
else:
    build.generate_file(Path(sys.argv[4]), Path(sys.argv[3]))
"""

#: per swap mode: its steps, and whether the tree at that instant is the new one
STEPS = {
    "exchange": {"staged": False, "exchanged": True},
    "renames": {"staged": False, "retired": False, "renamed": True},
}


def kill_inside(step: str, *arguments: str) -> None:
    """Run a real build that pauses at each step of its swap, SIGKILL it at ``step``."""
    environment = dict(os.environ, **{build.PAUSE_SWAP: f"{step}:120"})
    process = subprocess.Popen(
        [sys.executable, "-c", KILLED_BUILD, *arguments], stderr=subprocess.PIPE, text=True, env=environment
    )
    seen = []
    try:
        assert process.stderr is not None
        for line in process.stderr:
            seen.append(line.strip())
            if line.strip() == f"parakin-test-pause {step}":
                break
        else:
            pytest.fail(f"the build ended before the swap step {step!r}: {seen}")
    finally:
        process.send_signal(signal.SIGKILL)
        process.wait(timeout=60)


@pytest.fixture(scope="module")
def trees(tmp_path_factory) -> Path:
    """Folders `old` and `new`: the previous and the new complete tree of a partial rebuild of
    `alpha` (the five-bar, then the spherical 2R under the same name) next to `beta` (the
    five-bar, in both)."""
    root = tmp_path_factory.mktemp("trees")
    generate(None, root / "old", sources={"alpha": FIVE_BAR, "beta": FIVE_BAR}, workers=1)
    generate(None, root / "new", sources={"alpha": SPHERE2R, "beta": FIVE_BAR}, workers=1)
    old, new = snapshot(root / "old"), snapshot(root / "new")
    assert old["alpha/manifest.json"] != new["alpha/manifest.json"]
    assert {k: v for k, v in old.items() if k.startswith("beta")} == {
        k: v for k, v in new.items() if k.startswith("beta")
    }
    return root


CASES = [
    pytest.param(
        mode,
        step,
        marks=[] if (mode, step) in {("exchange", "exchanged"), ("renames", "retired")} else pytest.mark.slow,
    )
    for mode, steps in STEPS.items()
    for step in steps
]


@pytest.mark.parametrize("mode, step", CASES)
def test_a_build_killed_inside_the_swap_loses_nothing(tmp_path, trees, mode, step):
    """SIGKILL at each step of the swap of a partial rebuild: at that instant the destination is
    the previous or the new complete tree, or (two renames, between them) missing with the
    previous tree retired next to it; the next run, here a partial rebuild of the *other*
    package, restores it first and keeps every package; the user's file next to it and nothing
    else is there afterwards. (Once, a kill between the renames left no generated/, the next
    partial rebuild kept only its own package and the one after deleted the old copy.)"""
    if mode == "exchange" and build._renameat2 is None:
        pytest.skip("no renameat2 on this system: the two-rename swap is the one in use")
    target = tmp_path / "generated"
    shutil.copytree(trees / "old", target)
    (tmp_path / "notes.txt").write_text("the user's, next to the tree")
    kill_inside(step, mode, "generate", str(target), str(SPHERE2R), str(FIVE_BAR))

    retired = tmp_path / ".generated.parakin-old"
    expected = snapshot(trees / ("new" if STEPS[mode][step] else "old"))
    if step == "retired":
        assert not target.exists() and snapshot(retired) == snapshot(trees / "old")
    else:
        assert snapshot(target) == expected

    generate(["beta"], target, sources={"alpha": SPHERE2R, "beta": FIVE_BAR}, workers=1)
    assert snapshot(target) == expected
    assert sorted(p.name for p in tmp_path.iterdir()) == ["generated", "notes.txt"]
    assert (tmp_path / "notes.txt").read_text() == "the user's, next to the tree"


@pytest.mark.parametrize("mode", ["renames", pytest.param("exchange", marks=pytest.mark.slow)])
def test_a_killed_parakin_generate_is_restored_by_the_next_run(tmp_path, reference, mode):
    """`parakin generate` killed inside the swap of an existing package folder: the next run
    (here one that then fails on a broken file) first restores the previous package."""
    if mode == "exchange" and build._renameat2 is None:
        pytest.skip("no renameat2 on this system")
    package = tmp_path / "my_robot"
    shutil.copytree(reference, package)
    shutil.copy(SPHERE2R, tmp_path / "my_robot.py")
    before = snapshot(tmp_path)
    step = "retired" if mode == "renames" else "exchanged"
    kill_inside(step, mode, "file", str(package), str(tmp_path / "my_robot.py"))
    broken = tmp_path / "broken" / "my_robot.py"
    broken.parent.mkdir()
    broken.write_text("def build():\n    raise RuntimeError('a mistake in the model')\n")
    with pytest.raises(GenerationError, match="a mistake in the model"):
        generate_file(broken, package)
    shutil.rmtree(broken.parent)
    after = snapshot(tmp_path)
    if mode == "renames":  # killed between the renames: the previous package, restored
        assert after == before
    else:  # killed after the exchange: the new package, whole; the previous one cleared
        assert {k: v for k, v in after.items() if not k.startswith("my_robot/")} == {
            k: v for k, v in before.items() if not k.startswith("my_robot/")
        }
        generate_file(tmp_path / "my_robot.py", tmp_path / "fresh")
        assert snapshot(package) == snapshot(tmp_path / "fresh") != snapshot(reference)


# item 12 (part): an error in a user's mechanism file names its file and line


def _line_of(text: str, fragment: str) -> int:
    return next(number for number, line in enumerate(text.splitlines(), 1) if fragment in line)


@pytest.mark.parametrize(
    "defect, fragment, error",
    [
        ("\nINFO = ParamterInfo\n", "ParamterInfo", "NameError: name 'ParamterInfo' is not defined"),
        (
            "\n_original = build\n\n\ndef build():\n    import sympy\n    sympy.Matrix([[1, 2]]) * sympy.Matrix([[1, 2]])\n"
            "    return _original()\n",
            "sympy.Matrix([[1, 2]]) *",
            "ShapeError: Matrix size mismatch",
        ),
        ("\ndef helper(:\n    pass\n", "def helper(:", "SyntaxError: "),
    ],
    ids=["module-level-name-error", "error-raised-inside-sympy", "syntax-error"],
)
def test_an_error_in_a_mechanism_file_names_its_file_and_line(tmp_path, defect, fragment, error):
    source = tmp_path / "my_robot.py"
    text = FIVE_BAR.read_text() + defect
    source.write_text(text)
    where = f"{source}, line {_line_of(text, fragment)}: {error}"
    with pytest.raises(GenerationError) as raised:
        generate_file(source, tmp_path / "out")
    assert str(raised.value).startswith(where) and "\n" not in str(raised.value)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["my_robot.py"]
    if "NameError" in error:  # as the user sees it
        done = subprocess.run(
            [sys.executable, "-m", "parakin", "generate", "my_robot.py", "--out", "out"],
            cwd=tmp_path,
            capture_output=True,
            text=True,
        )
        assert done.returncode == 2 and f"my_robot.py, line {_line_of(text, fragment)}" in done.stderr


# item 17 (part): no formatter cache in the user's directory


def test_generate_leaves_no_ruff_cache_in_the_working_directory(tmp_path, monkeypatch, reference):
    monkeypatch.chdir(tmp_path)
    shutil.copy(FIVE_BAR, tmp_path / "my_robot.py")
    generate_file(Path("my_robot.py"), Path("out"))
    assert sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*")) == sorted(
        ["my_robot.py", "out", *(f"out/{name}" for name in package_files("my_robot"))]
    )
    assert snapshot(tmp_path / "out") == snapshot(reference)  # the formatting is the same from anywhere


# item 14 (part): kernels.c compiles under -Wall -Wextra -Werror


@pytest.mark.skipif(GCC is None, reason="gcc not installed")
def test_a_generated_kernels_c_compiles_without_warnings(reference):
    """CasADi's code generator leaves unused parameters (iw, w, mem) in every function."""
    kernels = reference / "kernels.c"
    done = subprocess.run([GCC, *C_FLAGS, f"-I{reference}", str(kernels)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    # the same code: CasADi's text for the package's own functions, verbatim, between the pragmas
    casadi_text, _, _ = build._c_sources("my_robot", (reference / "casadi_functions.py").read_text(), [])
    assert kernels.read_text().endswith(build.C_WARNINGS_OFF + casadi_text + build.C_WARNINGS_ON)
    assert "casadi_f0(" in casadi_text


@pytest.mark.skipif(GCC is None, reason="gcc not installed")
@pytest.mark.parametrize("name", sorted(p.name for p in GENERATED.iterdir() if (p / "manifest.json").is_file()))
def test_every_committed_kernels_c_compiles_without_warnings(name):
    package = GENERATED / name
    flags = [*C_FLAGS[:4], "-fsyntax-only"]  # warnings only (an -O2 build of stewart's takes 10 s)
    done = subprocess.run([GCC, *flags, f"-I{package}", str(package / "kernels.c")], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[:2000]
    assert json.loads((package / "manifest.json").read_text())["name"] == name
