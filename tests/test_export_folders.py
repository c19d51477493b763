"""``parakin export`` shares folders and never clobbers (issue 31, item 7).

``parakin export A --out c; parakin export B --out c`` overwrote 6 of A's 7 files (the same file
names for every mechanism, exit 0), and a user's own ``kernels.c`` in the folder was overwritten
too. Now every exported file carries the mechanism's prefix (``sam_driver.c``, ``sam_kernels.h``,
... and the public ``sam.h``) with its ``#include`` lines to match, so two mechanisms share one
folder and link into one program (built here with the C compiler: both libraries and both example
programs in one executable, against the Python solvers); ``.parakin-export.json`` records what
export wrote (mechanism and SHA-256 per file), and export refuses a non-empty folder without it,
or a file of its names that it did not write or that changed since, unless ``--force``, which
overwrites those names and keeps every other file.
"""

from __future__ import annotations

import hashlib
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import parakin
from parakin.errors import BadInputError
from parakin.packages.package import EXPORT_RECORD, GeneratedPackage, export_name

COMPILER = shutil.which("gcc") or shutil.which("cc")
PAIR = ("sam", "five_bar")
STRICT = ["-std=c99", "-Wall", "-Wextra", "-Werror", "-O2"]


def snapshot(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


def export(name: str, folder: Path, force: bool = False) -> list[Path]:
    return GeneratedPackage.find(name).export_c(folder, force=force)


def cli(*arguments: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-W", "ignore", "-m", "parakin", "export", *arguments], capture_output=True, text=True
    )


def test_every_exported_file_carries_the_prefix_and_its_includes_match(tmp_path):
    for name in PAIR:
        written = export(name, tmp_path)
        files = {p.name for p in written} - {EXPORT_RECORD}
        assert files == {
            f"{name}.h",
            *(f"{name}_{f}" for f in ("driver.c", "kernels.c", "kernels.h", "real_roots.h", "example_main.c")),
            f"{name}_README_C.md",
        }
        for path in written:
            if path.suffix in (".c", ".h"):
                for included in re.findall(r'^\s*#\s*include\s*"([^"]+)"', path.read_text(), re.MULTILINE):
                    assert included in files, f"{path.name} includes {included}"
        readme = (tmp_path / export_name(name, "README_C.md")).read_text()
        assert f"{name}_driver.c" in readme and f"{name}_example_main.c" in readme


def test_a_second_mechanism_keeps_the_first_and_the_record_lists_both(tmp_path):
    """The reported sequence: ``export sam --out c; export five_bar --out c`` exits 0 both times
    and leaves every file of sam as sam's export wrote it."""
    assert cli("sam", "--out", str(tmp_path)).returncode == 0
    first = snapshot(tmp_path)
    done = cli("five_bar", "--out", str(tmp_path))
    assert done.returncode == 0, done.stderr
    after = snapshot(tmp_path)
    assert {k: v for k, v in after.items() if k.startswith("sam")} == {
        k: v for k, v in first.items() if k.startswith("sam")
    }
    record = json.loads((tmp_path / EXPORT_RECORD).read_text())["files"]
    assert set(record) == set(after) - {EXPORT_RECORD}
    for file, entry in record.items():
        assert entry["mechanism"] == ("sam" if file.startswith("sam") else "five_bar")
        assert entry["sha256"] == hashlib.sha256(after[file]).hexdigest()
    assert "five_bar_README_C.md" in done.stdout  # the hint names the exported files


@pytest.mark.skipif(COMPILER is None, reason="no C compiler")
def test_two_mechanisms_in_one_folder_link_into_one_program(tmp_path):
    """sam and five_bar exported into ONE folder: both libraries and both example programs (their
    ``main`` renamed at compile time) in one executable, without a clashing symbol; each example
    exits 0 and prints the assembly modes the Python solvers find for its input."""
    for name in PAIR:
        export(name, tmp_path)
    objects = []
    for name in PAIR:
        for source, flags in (
            (f"{name}_driver.c", STRICT),
            (f"{name}_kernels.c", ["-std=c99", "-O2"]),  # CasADi's own code
            (f"{name}_example_main.c", [*STRICT, f"-Dmain={name}_example_main"]),
        ):
            target = tmp_path / source.replace(".c", ".o")
            subprocess.run([COMPILER, *flags, "-I.", "-c", source, "-o", target.name], cwd=tmp_path, check=True)
            objects.append(target.name)
    (tmp_path / "both.c").write_text(
        "#include <stdio.h>\n"
        '#include "sam.h"\n#include "five_bar.h"\n'
        + "".join(f"int {name}_example_main(void);\n" for name in PAIR)
        + "int main(void) {\n    int failed = 0;\n"
        + "".join(f'    failed |= {name}_example_main();\n    printf("==\\n");\n' for name in PAIR)
        + "    return failed;\n}\n"
    )
    subprocess.run([COMPILER, *STRICT, "-I.", "both.c", *objects, "-lm", "-o", "both"], cwd=tmp_path, check=True)
    run = subprocess.run(["./both"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr
    outputs = run.stdout.split("==\n")[:2]
    for name, output in zip(PAIR, outputs, strict=True):
        lines = output.splitlines()
        label, actuated_text = lines[0].split(": actuated ")
        assert label == name
        actuated = np.array([float(v) for v in actuated_text.split()])
        count = int(re.match(rf"{name}: (\d+) assembly modes", lines[1]).group(1))  # type: ignore[union-attr]
        modes = parakin.load(name, backend="numpy").forward_pose_all(actuated)
        assert count == int(modes.count) > 0
        printed = [line for line in lines if "position (" in line][:count]
        positions = np.array(
            [[float(v) for v in re.search(r"position \(([^)]*)\)", line).group(1).split(", ")] for line in printed]  # type: ignore[union-attr]
        )
        python = modes.poses[modes.valid][:, :3, 3]
        distance = np.abs(positions[:, None, :] - python[None, :, :]).max(-1)
        assert distance.min(axis=1).max() < 2e-9 and distance.min(axis=0).max() < 2e-9


def test_a_user_folder_is_refused_and_force_keeps_every_other_file(tmp_path):
    """A user's folder (their own ``kernels.c``, a note) is not an export: refused, nothing
    written; with ``--force`` the export's files are added and the user's stay byte for byte."""
    (tmp_path / "kernels.c").write_text("/* my own kernels */\n")
    (tmp_path / "notes.txt").write_text("keep\n")
    before = snapshot(tmp_path)
    done = cli("sam", "--out", str(tmp_path))
    assert done.returncode == 2
    assert "non-empty folder that parakin export did not write" in done.stderr and "--force" in done.stderr
    assert snapshot(tmp_path) == before
    done = cli("sam", "--out", str(tmp_path), "--force")
    assert done.returncode == 0, done.stderr
    after = snapshot(tmp_path)
    assert {k: after[k] for k in before} == before
    assert "sam_driver.c" in after and EXPORT_RECORD in after


def test_a_file_of_an_exported_name_that_export_did_not_write_is_never_overwritten(tmp_path):
    """In an export folder, a user's own ``sam_kernels.c`` (not in the record) and an exported
    ``sam_driver.c`` edited since are refused by name; ``--force`` overwrites them."""
    export("five_bar", tmp_path)
    (tmp_path / "sam_kernels.c").write_text("/* mine */\n")
    with pytest.raises(BadInputError, match="would overwrite sam_kernels.c"):
        export("sam", tmp_path)
    assert (tmp_path / "sam_kernels.c").read_text() == "/* mine */\n"
    assert not (tmp_path / "sam_driver.c").exists()
    export("sam", tmp_path, force=True)
    assert (tmp_path / "sam_kernels.c").read_text() != "/* mine */\n"
    export("sam", tmp_path)  # its own unchanged files: overwritten freely
    with (tmp_path / "sam_driver.c").open("a") as edited:
        edited.write("/* my fix */\n")
    before = snapshot(tmp_path)
    with pytest.raises(BadInputError, match="would overwrite sam_driver.c"):
        export("sam", tmp_path)
    assert snapshot(tmp_path) == before
    done = cli("sam", "--out", str(tmp_path))
    assert done.returncode == 2 and "sam_driver.c" in done.stderr


def test_a_file_another_mechanism_exported_is_not_taken_over(tmp_path):
    """A record entry of another mechanism under one of this export's names is not this export's
    to overwrite (two mechanisms whose names make the same file name)."""
    export("five_bar", tmp_path)
    record = json.loads((tmp_path / EXPORT_RECORD).read_text())
    (tmp_path / "sam_kernels.h").write_text("/* five_bar's, say */\n")
    digest = hashlib.sha256((tmp_path / "sam_kernels.h").read_bytes()).hexdigest()
    record["files"]["sam_kernels.h"] = {"mechanism": "five_bar", "sha256": digest}
    (tmp_path / EXPORT_RECORD).write_text(json.dumps(record))
    with pytest.raises(BadInputError, match="would overwrite sam_kernels.h"):
        export("sam", tmp_path)


@pytest.mark.parametrize("damage", ["{not json", '{"files": []}', '{"files": {"a.c": {"mechanism": 1}}}'])
def test_a_damaged_record_is_refused_unless_forced(tmp_path, damage):
    export("five_bar", tmp_path)
    (tmp_path / EXPORT_RECORD).write_text(damage)
    before = snapshot(tmp_path)
    with pytest.raises(BadInputError, match="is damaged"):
        export("sam", tmp_path)
    assert snapshot(tmp_path) == before
    export("sam", tmp_path, force=True)
    assert set(json.loads((tmp_path / EXPORT_RECORD).read_text())["files"]) == {
        p.name for p in tmp_path.iterdir() if p.name.startswith("sam")
    }


@pytest.mark.parametrize("entry", ["sam_driver.c", EXPORT_RECORD])
def test_links_and_folders_in_the_way_are_refused_even_with_force(tmp_path, entry):
    """The existing checks stay: an exported name (or the record) that is a symbolic link is
    refused, not followed, with or without ``force``; so is a folder of that name."""
    out = tmp_path / "out"
    out.mkdir()
    precious = tmp_path / "precious.txt"
    precious.write_text("keep me\n")
    (out / entry).symlink_to(precious)
    for force in (False, True):
        with pytest.raises(BadInputError, match="symbolic link"):
            export("sam", out, force=force)
    assert precious.read_text() == "keep me\n"
    (out / entry).unlink()
    (out / entry).mkdir()
    with pytest.raises(BadInputError, match="a folder"):
        export("sam", out, force=True)


def test_a_file_in_place_of_the_folder_is_refused(tmp_path):
    (tmp_path / "out").write_text("a file\n")
    with pytest.raises(BadInputError, match="is a file, not a folder"):
        export("sam", tmp_path / "out", force=True)
    assert (tmp_path / "out").read_text() == "a file\n"
