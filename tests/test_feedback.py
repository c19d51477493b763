"""What parakin tells its user while it works: the ``parakin`` logger on stderr (one line when a
package's C library is compiled on first use, with the time; nothing when it comes from the
cache), silenced by PARAKIN_LOG=warning. Run in fresh processes: the logger's handler writes to
the process's real stderr."""

from __future__ import annotations

import os
import subprocess
import sys

LOAD_TWICE = "import parakin; parakin.load('five_bar'); parakin.load('five_bar', backend='compiled')"


def run(code: str, cache, **env: str) -> subprocess.CompletedProcess:
    environment = {**os.environ, "PARAKIN_CACHE": str(cache), **env}
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=environment, check=True)


def test_compiling_says_so_once_with_the_time_and_the_cache_is_silent(tmp_path):
    first = run(LOAD_TWICE, tmp_path)
    lines = first.stderr.splitlines()
    assert [line for line in lines if "compiling" in line] == [
        f"parakin: compiling the C library of five_bar (first use; cached in {tmp_path})"
    ]
    timed = [line for line in lines if line.startswith("parakin: compiled five_bar in ")]
    assert len(timed) == 1 and timed[0].endswith(" s")
    assert run(LOAD_TWICE, tmp_path).stderr == ""  # from the cache: nothing to say


def test_parakin_log_warning_silences_the_notices(tmp_path):
    assert run(LOAD_TWICE, tmp_path, PARAKIN_LOG="warning").stderr == ""
    assert list(tmp_path.glob("five_bar-*.so")), "the library was compiled, silently"


def test_version_and_did_you_mean():
    """``parakin --version`` prints the installed version (exit 0); a misspelt mechanism name is
    answered with the closest names (exit 2 in the CLI, UnknownMechanismError in Python)."""
    from importlib.metadata import version

    import pytest

    import parakin

    shown = subprocess.run([sys.executable, "-m", "parakin", "--version"], capture_output=True, text=True)
    assert shown.returncode == 0 and shown.stdout.strip() == f"parakin {version('parakin')}"
    with pytest.raises(parakin.UnknownMechanismError, match="did you mean 'stewart'"):
        parakin.load("stewert")
    wrong = subprocess.run([sys.executable, "-m", "parakin", "ik", "Sam", "--pose", *"0 0 0.7 0 0 0".split()],
                           capture_output=True, text=True)  # fmt: skip
    assert wrong.returncode == 2 and "did you mean 'sam'" in wrong.stderr


def test_dir_lists_the_public_api_not_the_package_imports():
    import parakin

    names = dir(parakin)
    assert set(parakin.__all__) <= set(names) and {"load", "Mechanism", "sweep", "solvers", "interfaces"} <= set(names)
    assert not {"Any", "Mapping", "os", "math", "warnings", "__main__"} & set(names)


def test_parakin_view_is_the_viewer_command():
    """``parakin view`` hands its arguments to the viewer: its own --help (exit 0) and a named
    error for an unknown mechanism (exit 2)."""
    shown = subprocess.run([sys.executable, "-m", "parakin", "view", "--help"], capture_output=True, text=True)
    assert shown.returncode == 0 and "--port" in shown.stdout
    wrong = subprocess.run([sys.executable, "-m", "parakin", "view", "stewert"], capture_output=True, text=True)
    assert wrong.returncode == 2 and "unknown mechanism 'stewert'" in wrong.stderr
