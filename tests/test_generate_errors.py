"""A mechanism file that exits at import (issue 31 item 14). At 44aede2 ``sys.exit(0)`` in the
file made ``parakin generate`` exit 0 with no package and no message (``sys.exit(1)``: exit 1,
documented as "no solution"). Now any exception the file raises while it is imported or built,
SystemExit included, is an error: exit 2, naming the file and the line; an interrupt (Ctrl-C,
SIGTERM) still interrupts, leaving nothing behind."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("sympy")

from parakin.generator.build import generate_file, load_definition  # noqa: E402
from parakin.generator.errors import GenerationError  # noqa: E402

FIVE_BAR = Path(__file__).resolve().parent.parent / "mechanisms" / "five_bar.py"


def _generate(tmp_path: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "parakin", "generate", "my_robot.py", "--out", "out"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )


@pytest.mark.parametrize(
    "call, shown",
    [
        ("sys.exit(0)", "SystemExit: sys.exit(0)"),
        ("sys.exit(1)", "SystemExit: sys.exit(1)"),
        ("sys.exit('no thanks')", "SystemExit: sys.exit('no thanks')"),
        ("raise SystemExit", "SystemExit: sys.exit(None)"),
        ("exit()", "SystemExit: sys.exit(None)"),
    ],
)
def test_an_exit_at_import_is_an_error_naming_the_file_and_line(tmp_path, call, shown):
    source = tmp_path / "my_robot.py"
    source.write_text(f"import sys\n\n{call}\n")
    done = _generate(tmp_path)
    assert done.returncode == 2, (done.returncode, done.stderr)
    assert f"my_robot.py, line 3: {shown}" in done.stderr, done.stderr
    assert "Traceback" not in done.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["my_robot.py"]  # no package, no staging


def test_an_exit_inside_build_is_an_error_naming_its_line(tmp_path):
    source = tmp_path / "my_robot.py"
    text = FIVE_BAR.read_text() + "\n\n_original = build\n\n\ndef build():\n    raise SystemExit(0)\n"
    source.write_text(text)
    line = len(text.splitlines())
    with pytest.raises(GenerationError, match=rf"my_robot.py, line {line}: SystemExit: sys.exit\(0\)"):
        load_definition(source)
    with pytest.raises(GenerationError):
        generate_file(source, tmp_path / "out")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["my_robot.py"]


class Custom(BaseException):
    """An exception outside Exception that a file could raise."""


def test_any_base_exception_but_an_interrupt_is_an_error(tmp_path):
    source = tmp_path / "my_robot.py"
    source.write_text(f"from {__name__} import Custom\nraise Custom('odd')\n")
    sys.path.insert(0, str(Path(__file__).parent))
    try:
        with pytest.raises(GenerationError, match=r"my_robot.py, line 2: Custom: odd"):
            load_definition(source)
    finally:
        sys.path.remove(str(Path(__file__).parent))
    source.write_text("raise KeyboardInterrupt\n")
    with pytest.raises(KeyboardInterrupt):  # never turned into an error: it interrupts
        load_definition(source)


@pytest.mark.parametrize(
    "signum, status", [(signal.SIGINT, 128 + signal.SIGINT), (signal.SIGTERM, 128 + signal.SIGTERM)]
)
def test_an_interrupt_during_the_import_still_interrupts(tmp_path, signum, status):
    """Ctrl-C (SIGINT) or SIGTERM while the file is being imported ends `parakin generate` at
    once, as an interrupt (not exit 2), and nothing is left next to --out."""
    source = tmp_path / "my_robot.py"
    ready = tmp_path / "importing"
    source.write_text(f"import pathlib, time\npathlib.Path({str(ready)!r}).write_text('')\ntime.sleep(60)\n")
    process = subprocess.Popen(
        [sys.executable, "-m", "parakin", "generate", "my_robot.py", "--out", "out"],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 60
    while not ready.exists():
        assert process.poll() is None and time.monotonic() < deadline, process.communicate()
        time.sleep(0.05)
    started = time.monotonic()
    os.kill(process.pid, signum)
    _, err = process.communicate(timeout=30)
    assert time.monotonic() - started < 20  # not the file's 60 s sleep
    assert process.returncode == status, (process.returncode, err)
    if signum == signal.SIGINT:  # Ctrl-C: the command line's one line, as every command (exit 130)
        assert err.strip().splitlines()[-1] == "parakin: interrupted", err
    assert "GenerationError" not in err and "BadInputError" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["importing", "my_robot.py"]
