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


# ------------------------------------------------------------------ generation stages, batch bars
GENERATE_TWO = """
import sys
from pathlib import Path
from parakin.generator.build import generate
mechanisms = Path(sys.argv[2])
sources = {name: mechanisms / f"{name}.py" for name in ("five_bar", "sphere2r")}
generate(None, Path(sys.argv[1]), sources=sources, workers=2)
"""


def generate_two(target, **env: str) -> subprocess.CompletedProcess:
    """five_bar and sphere2r generated into ``target`` by two worker processes (their stages
    reach the display through the queue), stderr captured: not a terminal."""
    from parakin.generator.build import MECHANISMS

    environment = {**os.environ, **env}
    command = [sys.executable, "-c", GENERATE_TWO, str(target), str(MECHANISMS)]
    return subprocess.run(command, capture_output=True, text=True, env=environment, check=True)


def stage_lines(stderr: str, name: str) -> list[tuple[str, float]]:
    import re

    found = [re.fullmatch(rf"parakin: {name}: ([a-z ]+) (\d+\.\d\d) s", line) for line in stderr.splitlines()]
    return [(match[1], float(match[2])) for match in found if match]


def test_generation_reports_every_stage_in_order_with_its_time_and_kept_packages(tmp_path):
    """Without a terminal, each finished stage of each package is a logger line with its seconds,
    in the build's order (``generator.stages.STAGES``; sphere2r, with no loop to close, has no
    polynomial form or automatic homotopy), then one line per package with its time; a second run builds
    nothing and says so in one line per package."""
    from parakin.generator.stages import STAGES

    first = generate_two(tmp_path / "generated").stderr
    own = [s for s in STAGES if s != "own homotopy"]  # neither writes its own polynomial system
    for name, expected in [("five_bar", own), ("sphere2r", [s for s in own if s not in ("polynomial form", "automatic homotopy")])]:  # fmt: skip
        lines = stage_lines(first, name)
        assert [stage for stage, _ in lines] == expected, first
        total = [line for line in first.splitlines() if line.startswith(f"parakin: generated {name} in ")]
        assert len(total) == 1, first
        seconds = float(total[0].split(" in ")[1].removesuffix(" s"))
        # each stage's time is part of the build's (rounded to 0.01 s and 0.1 s)
        assert all(t >= 0 for _, t in lines) and sum(t for _, t in lines) <= seconds + 0.05 + 0.01 * len(lines)
    assert first.index("parakin: five_bar: model") < first.index("parakin: generated five_bar")
    again = generate_two(tmp_path / "generated").stderr.splitlines()
    assert again == ["parakin: five_bar: up to date, kept", "parakin: sphere2r: up to date, kept"]


def test_parakin_log_warning_silences_the_generation_lines(tmp_path):
    assert generate_two(tmp_path / "generated", PARAKIN_LOG="warning").stderr == ""
    assert (tmp_path / "generated" / "five_bar" / "manifest.json").is_file()


def test_a_forced_generation_bar_counts_every_stage_and_times_them_per_package(tmp_path):
    """PARAKIN_PROGRESS=on: one bar over 2 x 8 stages instead of the stage lines, and each
    package's line carries its stages' times."""
    from parakin.generator.stages import STAGES

    stderr = generate_two(tmp_path / "generated", PARAKIN_PROGRESS="on").stderr
    total = 2 * len(STAGES)
    assert total == 16 and "generating 2 packages" in stderr and f"{total}/{total}" in stderr, stderr
    assert stage_lines(stderr, "five_bar") == []
    (line,) = [x for x in stderr.replace("\r", "\n").splitlines() if x.startswith("parakin: generated five_bar in")]
    assert "(model " in line and ", automatic homotopy " in line and ", emit " in line, line


BATCH = """
import sys
import numpy as np
import parakin
m = parakin.load("five_bar")
inputs = m.home_actuated + 0.01 * np.random.default_rng(0).standard_normal((int(sys.argv[1]), 2))
print(int(m.forward_pose_all(inputs).count.sum()))
"""


def batch(count: int, **env: str) -> subprocess.CompletedProcess:
    environment = {**os.environ, **env}
    return subprocess.run(
        [sys.executable, "-c", BATCH, str(count)], capture_output=True, text=True, env=environment, check=True
    )


def test_a_large_batch_shows_a_bar_only_when_forced():
    """forward_pose_all over LARGE_BATCH (1000) inputs: a bar with PARAKIN_PROGRESS=on; nothing
    when stderr is not a terminal (auto, the default, as in a test's captured output), with
    PARAKIN_PROGRESS=off, or for a batch below the threshold even when forced."""
    from parakin.log import LARGE_BATCH

    assert LARGE_BATCH == 1000
    forced = batch(1000, PARAKIN_PROGRESS="on")
    assert "five_bar: every assembly mode" in forced.stderr and "1000/1000" in forced.stderr, forced.stderr
    assert forced.stdout == "2000\n"  # two modes per input, near the home pose
    assert batch(1000).stderr == ""
    assert batch(1000, PARAKIN_PROGRESS="off").stderr == ""
    assert batch(999, PARAKIN_PROGRESS="on").stderr == ""


def test_a_batch_run_in_steps_for_its_bar_gives_the_same_modes(monkeypatch, capfd):
    """With a bar, forward_pose_all runs its batch in steps of BAR_STEP (256) inputs: five_bar's
    'automatic' method (homotopy, certified in NumPy) gives the same arrays as in one step."""
    import numpy as np

    import parakin

    m = parakin.load("five_bar")
    inputs = m.home_actuated + 0.05 * np.random.default_rng(1).standard_normal((1000, 2))
    monkeypatch.setenv("PARAKIN_PROGRESS", "off")
    whole = m.forward_pose_all(inputs, method="automatic")
    monkeypatch.setenv("PARAKIN_PROGRESS", "on")
    stepped = m.forward_pose_all(inputs, method="automatic")
    assert "1000/1000" in capfd.readouterr().err
    assert whole.count.sum() == 2000
    for key in ("poses", "passive", "residual", "count", "outcome", "status", "conditioning"):
        assert np.array_equal(getattr(whole, key), getattr(stepped, key), equal_nan=True), key
    certificates = whole.certificate(), stepped.certificate()
    assert certificates[0]["complete"].all()
    for key in ("certified_roots", "uncertified_paths", "retracked", "roots", "with_modes"):
        assert np.array_equal(certificates[0][key], certificates[1][key]), key


def test_count_modes_chunks_feed_one_bar(monkeypatch, capfd):
    """count_modes calls forward_pose_all per chunk: one bar over the whole batch, none per chunk."""
    import numpy as np

    import parakin

    m = parakin.load("five_bar")
    monkeypatch.setenv("PARAKIN_PROGRESS", "on")
    counts = m.count_modes(m.home_actuated + np.zeros((3000, 2)), chunk=1200)
    err = capfd.readouterr().err
    assert counts["count"].tolist() == [2] * 3000
    assert "five_bar: counting assembly modes" in err and "3000/3000" in err, err
    assert "every assembly mode" not in err


def test_a_sweep_bar_follows_its_progress_argument(monkeypatch, capfd):
    """sweep(progress=True) shows its bar over the grid's points even below LARGE_BATCH points and with
    stderr not a terminal; progress=False never, whatever PARAKIN_PROGRESS says."""
    import numpy as np

    pytest = __import__("pytest")
    pytest.importorskip("dask")
    from parakin.studies.sweep import sweep

    axes = {"x": np.linspace(-0.5, 0.5, 5), "y": np.linspace(-0.3, 0.7, 5)}
    shown = sweep("five_bar", ["reachable"], axes, chunk=5, progress=True)
    err = capfd.readouterr().err
    assert "sweep of five_bar" in err and "point" in err and "25/25" in err, err
    monkeypatch.setenv("PARAKIN_PROGRESS", "on")
    hidden = sweep("five_bar", ["reachable"], axes, chunk=5, progress=False)
    assert capfd.readouterr().err == ""
    assert hidden["reachable"].values.tolist() == shown["reachable"].values.tolist()


def test_a_wrong_parakin_progress_is_a_named_error(monkeypatch):
    import numpy as np
    import pytest

    import parakin

    m = parakin.load("five_bar")
    monkeypatch.setenv("PARAKIN_PROGRESS", "sometimes")
    with pytest.raises(parakin.BadInputError, match="PARAKIN_PROGRESS must be 'auto', 'on' or 'off', got 'sometimes'"):
        m.forward_pose_all(m.home_actuated + np.zeros((3, 2)))
