"""A wheel installed into a fresh virtual environment outside the checkout generates and loads a
user's mechanism file: everything lives under the `parakin` namespace."""

import subprocess
import sys
import sysconfig
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _package_files() -> set[str]:
    """Every file of the checkout's package folders (the runtime, the generator with its templates,
    the mechanisms, the generated packages with their C and JSON), by its path in the wheel."""
    folders = {"parakin": "parakin", "generator": "parakin/generator", "mechanisms": "parakin/mechanisms",
               "generated": "parakin/generated"}  # fmt: skip
    return {
        f"{inside}/{path.relative_to(ROOT / folder).as_posix()}"
        for folder, inside in folders.items()
        for path in (ROOT / folder).rglob("*")
        if path.is_file() and "__pycache__" not in path.parts
    }


# not marked slow (~12 s): the only test of the wheel, so it stays in the default run
def test_wheel_generates_and_loads_a_user_mechanism_outside_the_checkout(tmp_path):
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--no-deps",
            "--no-build-isolation",
            "-q",
            "-w",
            str(tmp_path),
            str(ROOT),
        ],
        check=True,
    )
    wheel = next(tmp_path.glob("parakin-*.whl"))
    tops = {name.split("/")[0] for name in zipfile.ZipFile(wheel).namelist()}
    assert {t for t in tops if not t.endswith(".dist-info")} == {"parakin"}, tops
    shipped = {n for n in zipfile.ZipFile(wheel).namelist() if n.startswith("parakin/")}
    assert shipped == _package_files() and {"parakin/py.typed", "parakin/interfaces/viewer.html"} <= shipped, (
        f"missing from the wheel: {sorted(_package_files() - shipped)}; in the wheel but not in the checkout (a "
        f"stale build/ folder: remove it): {sorted(shipped - _package_files())}"
    )
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    python = venv / "bin" / "python"
    subprocess.run([str(python), "-m", "pip", "install", "--no-deps", "-q", str(wheel)], check=True)
    # the dependencies (numpy, casadi, sympy, jinja2, ruff) come from the test's environment, as
    # a plain path entry: its editable finder of the checkout is not run
    site = Path(
        subprocess.check_output(
            [str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"], text=True
        ).strip()
    )
    (site / "deps.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    user = tmp_path / "user"
    user.mkdir()
    (user / "my_chain.py").write_text((ROOT / "mechanisms" / "sphere2r.py").read_text())
    subprocess.run(
        [str(venv / "bin" / "parakin"), "generate", "my_chain.py", "--out", "pkgs/my_chain"], check=True, cwd=user
    )
    code = (
        "import parakin, numpy as np\n"
        f"assert {str(ROOT)!r} not in parakin.__file__, parakin.__file__\n"
        "m = parakin.load('pkgs/my_chain')\n"
        "assert m.name == 'my_chain'\n"
        "w = m.forward_pose(np.deg2rad([30.0, 50.0])).rotation[:, 2]\n"
        "branches = m.inverse_pose(m.forward_pose(np.deg2rad([30.0, 50.0])).pose)\n"
        "assert branches.valid.sum() == 2\n"
    )
    subprocess.run([str(python), "-c", code], check=True, cwd=user)
