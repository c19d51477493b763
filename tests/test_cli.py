"""The command line: list, inspect (text, LaTeX, JSON), ik, fk (units per variable), demo, plot,
generate; exit codes and closed pipes."""

import json
import subprocess
import sys
from types import SimpleNamespace

import numpy as np
import pytest

import parakin
from parakin.errors import BadInputError
from parakin.interfaces import cli


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-W", "ignore", "-m", "parakin.interfaces.cli", *args], capture_output=True, text=True
    )


def test_list_has_titles_and_inspect_text_is_line_broken():
    listed = run("list").stdout
    assert "sam" in listed.split() and "Williams & Poling" in listed
    out = run("inspect", "sam").stdout
    assert "Loop-closure equations" in out
    assert "left_leg_determinant" in out and "left_u_joint_aligned" in out
    assert "u_joint_axes_parallel" in out
    assert "degree 2" in out
    assert max(len(line) for line in out.splitlines()) < 200
    assert "more lines (full: parakin inspect sam --format latex|json)" in out


def test_inspect_json_and_latex():
    data = json.loads(run("inspect", "sam", "--format", "json").stdout)
    assert data["manifest"] == "sam"
    assert "L2**2" in data["objects"]["left_leg_determinant"]["value"]  # objects are typed (parakin.interfaces.inspect)
    assert "\\sin" in run("inspect", "sam", "--format", "latex").stdout


def test_ik_fk_and_errors():
    out = run("ik", "sam", "--pose-deg", "0.02", "0.03", "0.68", "5", "3", "4").stdout
    heading = "sam at x = 0.02 m, y = 0.03 m, z = 0.68 m, alpha = 5 deg, beta = 3 deg, gamma = 4 deg"
    assert out.startswith(f"{heading}: 16 inverse branches, 16 valid") and "theta1 [deg]" in out and "L2 [m]" in out
    out = run("fk", "sam", "--actuated-deg", "-2.43", "-18.07", "3.76", "-30.35", "10.95", "5.07").stdout
    assert "mode" in out
    failed = run("fk", "sam", "--actuated-deg", "0", "-15", "0", "0", "15", "0")
    assert failed.returncode == 2 and "SelfMotionError" in failed.stderr  # eq (15): a self-motion


def test_degree_flags_convert_revolute_variables_only():
    """`fk sps --actuated-deg 0.78 0.57 1.32` once read leg lengths in metres as degrees."""
    metres = run("fk", "sps", "--actuated", "0.78", "0.57", "1.32", "--json")
    flagged = run("fk", "sps", "--actuated-deg", "0.78", "0.57", "1.32", "--json")
    assert metres.returncode == 0 and metres.stdout.count("\n") >= 1
    assert [json.loads(line)["residual"] < 1e-9 for line in flagged.stdout.splitlines()]
    assert len(metres.stdout.splitlines()) == len(flagged.stdout.splitlines())
    leg = json.loads(run("ik", "gough", "--pose", "1", "2", "30", "0", "0", "0", "--json").stdout.splitlines()[0])
    assert "l1 [m]" in leg and 29 < leg["l1 [m]"] < 31


def test_no_solution_exits_non_zero_with_a_message():
    out = run("fk", "sps", "--actuated", "0.1", "0.1", "0.1")
    assert out.returncode in (1, 2) and out.stderr.startswith("parakin:")


def test_parameters_and_backend_flags():
    out = run("ik", "sam", "--pose", "0", "0", "0.664", "0", "0", "0", "--param", "L4=0.3", "--backend", "numpy")
    assert out.returncode == 0
    bad = run("ik", "sam", "--pose", "0", "0", "0.664", "0", "0", "0", "--param", "nope=1")
    assert bad.returncode == 2 and "unknown parameter" in bad.stderr


def test_closed_pipe_prints_no_traceback():
    done = subprocess.run(
        f"{sys.executable} -W ignore -m parakin.interfaces.cli inspect spm | head -n 1",
        shell=True,
        capture_output=True,
        text=True,
    )
    assert "Traceback" not in done.stderr


def test_plot_draws_every_mode(tmp_path):
    target = tmp_path / "spm.png"
    done = run("plot", "spm", "--output", str(target))
    assert done.returncode == 0, done.stderr
    assert target.stat().st_size > 10_000 and target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_reader_that_leaves_early_is_a_quiet_exit_0():
    """`parakin demo sam | head -1` once ended with "BrokenPipeError", exit 2 (the OSError
    branch caught it first), or "Exception ignored" at the final flush. A real pipe: the
    reading end is closed before parakin writes, so every write fails with EPIPE."""
    process = subprocess.Popen(
        [sys.executable, "-W", "ignore", "-m", "parakin.interfaces.cli", "demo", "sam"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    process.stdout.close()
    stderr = process.stderr.read().decode()
    assert process.wait(timeout=120) == 0, stderr
    assert stderr == ""
    shell = subprocess.run(
        [
            "bash",
            "-c",
            f"{sys.executable} -W ignore -m parakin.interfaces.cli demo sam | head -1; exit ${{PIPESTATUS[0]}}",
        ],
        capture_output=True,
        text=True,
    )
    assert shell.returncode == 0 and shell.stderr == "" and shell.stdout.count("\n") == 1


def test_an_unexpected_exception_is_one_line_and_exit_3(monkeypatch, capsys):
    """A bug once printed a traceback and exited 1, which the README documents as "no
    solution"; now one line saying "please report" and the distinct status 3."""

    def broken(args):
        raise RuntimeError("an invariant\nthat broke")

    monkeypatch.setitem(cli.COMMANDS, "list", broken)
    assert cli.main(["list"]) == cli.INTERNAL_ERROR == 3
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "RuntimeError: an invariant that broke" in err and "please report" in err


def test_param_sets_mechanism_parameters_only():
    """`--param limits=...` was once passed to load as its `limits` keyword; a --param is a
    mechanism parameter (named in the manifest), anything else is refused naming the valid ones."""
    pose = ["--pose", "0", "0", "0.664", "0", "0", "0", "--backend", "numpy"]
    for name, value in (("limits", '{"L2": [0, 0.1]}'), ("backend", '"numpy"')):
        done = run("ik", "sam", *pose, "--param", f"{name}={value}")
        assert done.returncode == 2, done.stdout
        assert f"unknown parameter '{name}' for 'sam'; valid: ['L1', 'L4']" in done.stderr
    done = run("ik", "sam", *pose, "--param", "l1=0.5")
    assert done.returncode == 2 and "did you mean 'L1'?" in done.stderr


def test_generate_passes_force(monkeypatch, tmp_path):
    """`parakin generate FILE --out DIR --force` hands force=True to generate_file (False without)."""
    import parakin.generator.build as build

    calls = []

    def fake(path, package, force=False):
        calls.append((str(path), str(package), force))
        return {"seconds": 0.0}

    monkeypatch.setattr(build, "generate_file", fake)
    out = str(tmp_path / "pkg")
    assert cli.main(["generate", "robot.py", "--out", out, "--force"]) == 0
    assert cli.main(["generate", "robot.py", "--out", out]) == 0
    assert calls == [("robot.py", out, True), ("robot.py", out, False)]


def test_sweep_fixed_help_names_every_kind_of_coordinate():
    assert "a fixed coordinate: pose, actuated input or parameter" in " ".join(run("sweep", "--help").stdout.split())


def test_planar_translation_poses_take_x_y():
    """A planar_translation pose is two values x y (m): ^B_P T = [I, (x, y, 0)]; three values
    are refused with the expected count."""
    manifest = SimpleNamespace(name="planar_robot", pose_kind="planar_translation")
    pose = cli._pose_from_cli(manifest, [0.1, 0.4], degrees=False)
    expected = np.eye(4)
    expected[:3, 3] = [0.1, 0.4, 0.0]
    np.testing.assert_array_equal(pose, expected)
    assert cli._describe_pose(manifest, pose, degrees=True) == {"x [m]": 0.1, "y [m]": 0.4}
    with pytest.raises(BadInputError, match=r"planar_robot poses \(planar_translation\) take 2 values: x y.*got 3"):
        cli._pose_from_cli(manifest, [0.0, 0.4, 0.1], degrees=False)


def test_planar_translation_mechanisms_on_the_command_line():
    """Every shipped mechanism of pose kind planar_translation: `ik NAME --pose x y` at its home
    position works (a valid branch, exit 0) and three values exit 2 naming the count."""
    names = [n for n in parakin.available() if parakin.metadata(n).pose_kind == "planar_translation"]
    if not names:
        pytest.skip("no shipped mechanism has the pose kind planar_translation yet")
    for name in names:
        m = parakin.load(name, backend="numpy")
        x, y = m.forward_pose(m.home_actuated).pose[:2, 3]
        done = run("ik", name, "--pose", repr(float(x)), repr(float(y)), "--json")
        assert done.returncode == 0 and '"valid": true' in done.stdout, done.stderr
        refused = run("ik", name, "--pose", repr(float(x)), repr(float(y)), "0.1")
        assert refused.returncode == 2 and "take 2 values" in refused.stderr


@pytest.mark.slow
def test_generate_force_on_the_command_line(tmp_path):
    """`--out userdir` (a folder with the user's notes) exits 2 naming --force and writes
    nothing; with --force the package is written next to the notes (one generation, ~10 s)."""
    from pathlib import Path

    user = tmp_path / "userdir"
    user.mkdir()
    (user / "notes.txt").write_text("mine\n")
    (tmp_path / "my_robot.py").write_text(
        (Path(__file__).resolve().parent.parent / "mechanisms" / "sphere2r.py").read_text()
    )
    command = [sys.executable, "-W", "ignore", "-m", "parakin", "generate", "my_robot.py", "--out", "userdir"]
    refused = subprocess.run(command, cwd=tmp_path, capture_output=True, text=True)
    assert refused.returncode == 2 and "--force" in refused.stderr
    assert sorted(p.name for p in user.iterdir()) == ["notes.txt"]
    forced = subprocess.run([*command, "--force"], cwd=tmp_path, capture_output=True, text=True)
    assert forced.returncode == 0, forced.stderr
    assert (user / "notes.txt").read_text() == "mine\n"
    assert parakin.load(user, backend="numpy").name == "my_robot"


def test_sweep_fixed_passes_actuated_inputs_through(tmp_path):
    """`--fixed theta1=...` (an actuated input not swept) reaches sweep(): the CLI's grid equals
    sweep(..., fixed={"theta1": value}) and count_modes at that value, and differs from the
    default theta1 (the home input); more than one number is refused. The value is one whose
    mode counts on the grid differ from the home's (found by count_modes, not by the sweep: the
    counts near home do not change with theta1, so a value that gives the home's counts would
    not show that the value arrived)."""
    from parakin.studies.sweep import sweep

    xr = pytest.importorskip("xarray")
    m = parakin.load("sam", backend="numpy")
    axes = {"theta2": np.linspace(-0.3, 0.3, 3), "theta5": np.linspace(-0.3, 0.3, 3)}
    mesh = np.meshgrid(*axes.values(), indexing="ij")

    def counts(theta1: float) -> np.ndarray:
        theta = np.tile(m.home_actuated, (*mesh[0].shape, 1))
        theta[..., 0], theta[..., 1], theta[..., 4] = theta1, *mesh
        counted = m.count_modes(theta)
        return np.where(counted["status"] == 0, counted["count"], np.nan)  # the sweep's missing values

    home = counts(m.home_actuated[0])
    value = next((v for v in (0.5, 1.0, -1.0, 1.5, -1.5) if not np.array_equal(counts(v), home, equal_nan=True)), None)
    assert value is not None, f"theta1 changes no mode count on the grid: {home.tolist()}"
    command = ["sweep", "sam", "modes", "--axis", "theta2=-0.3:0.3:3", "--axis", "theta5=-0.3:0.3:3"]
    done = run(*command, "--fixed", f"theta1={value!r}", "--backend", "numpy", "--netcdf", str(tmp_path / "s.nc"))
    assert done.returncode == 0, done.stderr
    saved = xr.load_dataset(tmp_path / "s.nc").modes.values
    fixed = sweep("sam", ["modes"], axes, fixed={"theta1": value}, backend="numpy").modes.values
    default = sweep("sam", ["modes"], axes, backend="numpy").modes.values
    np.testing.assert_array_equal(saved, fixed)
    np.testing.assert_array_equal(fixed, counts(value))
    np.testing.assert_array_equal(default, home)
    assert not np.array_equal(fixed, default, equal_nan=True)
    refused = run(*command, "--fixed", "theta1=0.1,0.2")
    assert refused.returncode == 2 and "one number" in refused.stderr


def test_inspect_prints_a_large_expression_with_its_repeated_parts_named_and_defined():
    """A large expression prints its repeated subtrees once, by name, each defined below it:
    read back, the rows with the definitions substituted are the expression itself."""
    import sympy as sp

    from parakin.interfaces.inspect import SHARE_ABOVE, _text

    x, y = sp.symbols("x y")
    inner = sum((x + k * y) ** k * sp.sin(k * x) for k in range(1, 40))
    expr = sp.Matrix([inner * x + 1, inner * y])
    assert sp.count_ops(expr) > SHARE_ABOVE
    text = _text(sp, expr, 10**6, 10**6, "demo")
    rows, definitions = text.split("\n  where\n")
    values = [sp.sympify(line.split("] ", 1)[1]) for line in rows.splitlines()]
    named = [line.strip().split(" = ", 1) for line in definitions.splitlines()]
    assert named and all(name.startswith("shared_") for name, _ in named)
    substitutions = {}
    for name, value in named:
        substitutions[sp.Symbol(name)] = sp.sympify(value).xreplace(substitutions)
    assert [v.xreplace(substitutions) for v in values] == list(expr)
    assert len(text) < len(str(expr))  # the repeated sum is printed once
