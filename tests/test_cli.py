"""The command line: list, inspect (text, LaTeX, JSON), ik, fk, demo."""

import json
import subprocess
import sys


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "parakin.cli", *args], capture_output=True, text=True)


def test_list_and_inspect_text():
    assert "sam" in run("list").stdout.split()
    out = run("inspect", "sam").stdout
    assert "Loop-closure equations" in out
    assert "left_leg_determinant" in out and "left_u_joint_aligned" in out
    assert "u_joint_axes_parallel" in out
    assert "degree 2" in out


def test_inspect_json_and_latex():
    data = json.loads(run("inspect", "sam", "--format", "json").stdout)
    assert data["metadata"]["forward"]["degree"] == 2
    assert "L2**2" in data["objects"]["left_leg_determinant"]
    assert "\\sin" in run("inspect", "sam", "--format", "latex").stdout


def test_ik_fk_and_errors():
    out = run("ik", "sam", "--pose-deg", "0.02", "0.03", "0.68", "5", "3", "4").stdout
    assert out.count("valid=True") == 16
    out = run("fk", "sam", "--actuated-deg", "-2.43", "-18.07", "3.76", "-30.35", "10.95", "5.07").stdout
    assert "mode" in out
    failed = run("fk", "sam", "--actuated-deg", "0", "-15", "0", "0", "15", "0")
    assert failed.returncode == 2 and "SingularConfigurationError" in failed.stderr


def test_demo_prints_the_paper_numbers():
    out = run("demo", "sam").stdout
    assert "eq (15)" in out and "Table II" in out and "step 10" in out and "theta_dot" in out


def test_spm_inspect_degree_and_plot(tmp_path):
    out = run("inspect", "spm").stdout
    assert "degree 8" in out and "det_B" in out and "leg1_axes_coplanar" in out
    target = tmp_path / "spm.png"
    done = run("plot", "spm", "--output", str(target))
    assert done.returncode == 0 and target.stat().st_size > 10_000
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
