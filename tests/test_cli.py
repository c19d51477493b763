"""The command line: list, inspect (text, LaTeX, JSON), ik, fk (units per variable), demo, plot,
generate; exit codes and closed pipes."""

import json
import subprocess
import sys


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-W", "ignore", "-m", "parakin.cli", *args], capture_output=True, text=True)


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
    assert "L2**2" in data["objects"]["left_leg_determinant"]
    assert "\\sin" in run("inspect", "sam", "--format", "latex").stdout


def test_ik_fk_and_errors():
    out = run("ik", "sam", "--pose-deg", "0.02", "0.03", "0.68", "5", "3", "4").stdout
    assert out.count("valid=True") == 16 and "theta1 [deg]" in out and "L2 [m]" in out
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
        f"{sys.executable} -W ignore -m parakin.cli inspect spm | head -n 1", shell=True, capture_output=True, text=True
    )
    assert "Traceback" not in done.stderr


def test_plot_draws_every_mode(tmp_path):
    target = tmp_path / "spm.png"
    done = run("plot", "spm", "--output", str(target))
    assert done.returncode == 0, done.stderr
    assert target.stat().st_size > 10_000 and target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
