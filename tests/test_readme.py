"""The README says what is true: its Python example and every command line run as written, its
mechanism table lists what `parakin list` shows, its command table gives each command's flags as
the parser has them, and the manifest schema it names is the one packages carry."""

import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import parakin
from parakin.interfaces import cli
from parakin.packages.manifest import SUPPORTED_SCHEMA

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text()
SHARED_FLAGS = ("--param", "--backend", "--json")


def test_readme_example_runs():
    block = re.search(r"```python\n(.*?)```", README, re.S)
    assert block is not None
    namespace: dict = {}
    exec(compile(block.group(1), "README.md", "exec"), namespace)
    assert namespace["fk"].converged and namespace["modes"].count >= 1


def shell_blocks() -> list[list[str]]:
    """The lines of each ```sh block, comments removed."""
    blocks = re.findall(r"```sh\n(.*?)```", README, re.S)
    return [[line.split("  #")[0].strip() for line in block.splitlines() if line.strip()] for block in blocks]


def command_lines() -> list[str]:
    """Every `parakin ...` line of the blocks that need no generated package of the user's."""
    return [
        line
        for block in shell_blocks()
        if not any("generate" in x for x in block)
        for line in block
        if line.startswith("parakin ") and not line.startswith("parakin view ")
    ]


def test_the_readme_view_line_serves_the_viewer():
    """``parakin view NAME`` serves until interrupted: run as written, it prints the page's URL,
    and the page answers."""
    import subprocess
    import sys
    import urllib.request

    (line,) = [line for block in shell_blocks() for line in block if line.startswith("parakin view ")]
    argv = [sys.executable, "-m", "parakin", *shlex.split(line)[1:], "--port", "0"]
    server = subprocess.Popen(argv, stdout=subprocess.PIPE, text=True)
    try:
        url = server.stdout.readline().strip()
        assert url.startswith("http://127.0.0.1:"), url
        with urllib.request.urlopen(url, timeout=30) as page:
            assert page.status == 200 and b"<canvas" in page.read()
    finally:
        server.terminate()
        server.wait(timeout=30)


def test_the_readme_has_command_lines_for_every_command():
    commands = {line.split()[1] for block in shell_blocks() for line in block if "parakin " in line}
    commands |= {line.split()[2] for block in shell_blocks() for line in block if line.startswith("PARAKIN_PATH")}
    assert commands >= set(cli.COMMANDS), set(cli.COMMANDS) - commands


@pytest.mark.parametrize("line", command_lines())
def test_every_readme_command_line_runs(line, tmp_path, monkeypatch, capsys):
    """Each command line of the README, in a fresh folder, exits 0 (`parakin ik sam --pose-deg
    x y z a b g` once was such a line); outputs it names are written."""
    monkeypatch.chdir(tmp_path)
    argv = shlex.split(line)[1:]
    status = cli.main(argv)
    out, err = capsys.readouterr()
    assert status == 0, (line, err[-2000:])
    assert out.strip(), line
    for flag in ("--output", "--out"):
        if flag in argv:
            assert (tmp_path / argv[argv.index(flag) + 1]).exists(), line


@pytest.mark.slow
def test_the_outside_a_checkout_block_runs(tmp_path):
    """`parakin generate my_robot.py --out packages/my_robot`, the `python -c` load and the
    `PARAKIN_PATH=packages parakin demo my_robot` line, with a copy of a shipped mechanism file as
    my_robot.py (about 10 s: one generation)."""
    (block,) = [b for b in shell_blocks() if any("generate" in x for x in b)]
    shutil.copy(ROOT / "mechanisms" / "sphere2r.py", tmp_path / "my_robot.py")
    for line in block:
        environment = dict(os.environ)
        words = shlex.split(line)
        while "=" in words[0]:
            key, _, value = words.pop(0).partition("=")
            environment[key] = value
        program = {"parakin": [sys.executable, "-m", "parakin"], "python": [sys.executable]}[words[0]]
        done = subprocess.run([*program, *words[1:]], cwd=tmp_path, env=environment, capture_output=True, text=True)
        assert done.returncode == 0, (line, done.stderr[-2000:])
    assert (tmp_path / "packages" / "my_robot" / "manifest.json").is_file()


def test_mechanism_table_lists_every_available_mechanism():
    """The README's table once listed 6 of the 9 mechanisms `parakin list` shows."""
    table = README[README.index("| name | paper | what |") :]
    listed = re.findall(r"^\| `(\w+)` \|", table, re.M)
    assert listed == sorted(parakin.available())


def test_command_table_gives_each_commands_shared_flags_as_the_parser_has_them():
    """ "every command takes --param/--backend/--json" was false for inspect, export and
    generate; the table's flag columns are checked against the parser, command by command."""
    rows = re.findall(r"^\| `parakin (\w+)[^`]*` \| [^|]+ \|(.*)\|\s*$", README, re.M)
    assert {command for command, _ in rows} == set(cli.COMMANDS)
    subparsers = next(a for a in cli._parser()._actions if a.dest == "command").choices
    for command, cells in rows:
        marks = [cell.strip() for cell in cells.split("|")]
        documented = {flag for flag, mark in zip(SHARED_FLAGS, marks, strict=True) if mark == "yes"}
        options = {option for action in subparsers[command]._actions for option in action.option_strings}
        assert documented == options & set(SHARED_FLAGS), command


def test_manifest_schema_named_in_the_readme_is_the_packages_schema():
    """The README once said "schema 1" where manifests carry schema 2."""
    (named,) = re.findall(r"`manifest.json` \(schema (\d+)", README)
    assert int(named) == SUPPORTED_SCHEMA == parakin.metadata("sam").schema


def test_exit_statuses_in_the_readme_are_the_clis():
    flat = " ".join(README.split())
    assert f"{cli.INTERNAL_ERROR} an internal error" in flat
    assert '1 "no solution"' in flat and "2 an error" in flat


def test_the_joints_guide_file_generates_a_working_mechanism(tmp_path):
    """The README's mechanism file written as joints, as a new user would save it: it generates,
    its inverse reproduces a pose, and forward_pose_all finds that pose among certified modes."""
    (source,) = [b for b in re.findall(r"```python\n(.*?)```", README, re.S) if "joints.DistanceMechanism" in b]
    (tmp_path / "my_robot.py").write_text(source)
    from parakin.generator.build import generate_file

    generate_file(tmp_path / "my_robot.py", tmp_path / "packages" / "my_robot")
    m = parakin.load(tmp_path / "packages" / "my_robot")
    pose = np.eye(4)
    pose[:2, 3] = [0.55, 0.35]
    state = m.inverse_pose(pose).branch(0)
    np.testing.assert_allclose(m.platform_pose(state.actuated, state.passive), pose, atol=1e-12)
    modes = m.forward_pose_all(state.actuated)
    assert bool(modes.certificate()["complete"])
    assert np.abs(modes.poses[modes.valid] - pose).max(axis=(-2, -1)).min() < 1e-9
    # a point list by its group name (parameter_groups), as the README's loading section says
    wide = parakin.load(tmp_path / "packages" / "my_robot", base=[[0, 0], [1.4, 0], [0.7, 1.2]])
    assert (wide.parameters["base_x2"], wide.parameters["base_y3"]) == (1.4, 1.2)
