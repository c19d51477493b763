"""What the command line and the tables print (issue 36, text output): only the pose kind's
columns, aligned ik/fk tables with unreachable branches shown as such, one-line warnings,
did-you-mean for mistyped commands and options, Ctrl-C as ``parakin: interrupted`` with exit 130,
and a demo that needs no compiled library. Values are checked against hand-worked numbers or
an independent Euler decomposition (SciPy), never against the printing code's own output."""

import dataclasses
import json
import os
import select
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import parakin
from parakin.interfaces import cli
from parakin.results import modes_html, modes_table
from parakin.tables import pose_headers


def run(*args: str, env: dict[str, str] | None = None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "parakin.interfaces.cli", *args],
        capture_output=True,
        text=True,
        env={**os.environ, **(env or {})},
    )


def _rows(text: str) -> tuple[list[str], list[list[str]]]:
    """The header and rows of the first table in ``text`` (the lines after a rule of dashes)."""
    lines = text.splitlines()
    rule = next(i for i, line in enumerate(lines) if line.strip() and set(line.strip()) <= {"-", " "})
    body = []
    for line in lines[rule + 1 :]:
        if not line.strip():
            break
        body.append(line.split())
    return lines[rule - 1].split(), body


@pytest.fixture(scope="module")
def spm_modes():
    m = parakin.load("spm", backend="numpy")
    return m, m.forward_pose_all(np.deg2rad([105.0, 60.0, 105.0]))


def test_a_spherical_mode_table_has_angles_only_and_they_are_the_zyx_angles(spm_modes):
    """spm (pose kind rotation): no x, y, z columns (they were all 0); each row's angles are
    the Z-Y-X Euler angles of the mode's rotation, as SciPy decomposes it."""
    m, modes = spm_modes
    kind = m.manifest.pose_kind
    assert kind == "rotation"
    text = modes_table(dataclasses.replace(modes, pose_kind=kind))
    header, rows = _rows(text)
    assert header == ["mode", "alpha", "[deg]", "beta", "[deg]", "gamma", "[deg]", "conditioning"]
    assert "x [m]" not in text and "position" not in text.splitlines()[0]
    assert len(rows) == int(modes.count) == 8
    for k, row in enumerate(rows):
        expected = Rotation.from_matrix(modes.mode(k).rotation).as_euler("ZYX", degrees=True)
        np.testing.assert_allclose([float(v) for v in row[1:4]], expected, atol=1e-3)
    html = modes_html(dataclasses.replace(modes, pose_kind=kind))  # the notebook's repr: radians
    assert "<th>alpha [rad]</th>" in html and "<th>x [m]</th>" not in html


def test_unknown_pose_kind_keeps_all_six_columns(spm_modes):
    """A result made without its pose kind (``pose_kind=""``) shows the six transform columns."""
    _, modes = spm_modes
    header, _ = _rows(modes_table(dataclasses.replace(modes, pose_kind="")))
    assert header[:4] == ["mode", "x", "[m]", "y"] and "gamma" in header


def test_five_bar_fk_table_is_the_two_hand_worked_points():
    """theta = (pi/2, pi/2) at the defaults: elbows (-0.15, 0.2) and (0.15, 0.2), circles of radius
    0.25 m meeting at P = (0, 0) and (0, 0.4) (0.15^2 + 0.2^2 = 0.25^2). Pose kind
    planar_translation: columns x and y only."""
    done = run("fk", "five_bar", "--backend", "numpy", "--actuated", repr(np.pi / 2), repr(np.pi / 2))
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("five_bar at theta1 = 1.5708 rad, theta2 = 1.5708 rad: 2 assembly modes")
    header, rows = _rows(done.stdout)
    assert header == ["mode", "slot", "x", "[m]", "y", "[m]", "residual"]
    points = sorted((float(r[2]), float(r[3])) for r in rows)
    np.testing.assert_allclose(points, [(0.0, 0.0), (0.0, 0.4)], atol=1e-6)


def test_planar_fk_has_x_y_phi_and_they_close_the_legs():
    """planar_3rpr, rho = (14.98, 15.38, 12): six modes; each printed (x, y, phi) puts every
    platform joint at its leg's length from its base joint (to the printed digits)."""
    rho = [14.98, 15.38, 12.0]
    done = run("fk", "planar_3rpr", "--backend", "numpy", "--actuated", *map(str, rho))
    assert done.returncode == 0, done.stderr
    header, rows = _rows(done.stdout)
    assert header == ["mode", "slot", "x", "[m]", "y", "[m]", "phi", "[rad]", "residual"]
    assert len(rows) == 6
    p = parakin.load("planar_3rpr", backend="numpy").parameters
    for row in rows:
        x, y, phi = map(float, row[2:5])
        c, s = np.cos(phi), np.sin(phi)
        for i in range(3):
            a = np.array([p[f"base_x{i + 1}"], p[f"base_y{i + 1}"]])
            b = np.array([p[f"platform_x{i + 1}"], p[f"platform_y{i + 1}"]])
            joint = np.array([x + c * b[0] - s * b[1], y + s * b[0] + c * b[1]])
            assert np.linalg.norm(joint - a) == pytest.approx(rho[i], abs=1e-4)


def test_ik_table_shows_the_hand_worked_delta_branches():
    """delta at p = (0, 0, -1.2): branch 0 has theta = 0 on every leg, branch 7 theta = -2 atan(8)
    = -2.892883 rad (the manifest's examples, worked by hand); aligned columns, one per input."""
    done = run("ik", "delta", "--backend", "numpy", "--pose", "0", "0", "-1.2")
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("delta at x = 0 m, y = 0 m, z = -1.2 m: 8 inverse branches, 8 valid")
    header, rows = _rows(done.stdout)
    assert header[:2] == ["branch", "signs"] and header[-1] == "valid"
    by_branch = {int(r[0]): r for r in rows}
    np.testing.assert_allclose([float(v) for v in by_branch[0][4:7]], [0.0, 0.0, 0.0], atol=1e-9)
    np.testing.assert_allclose([float(v) for v in by_branch[7][4:7]], [-2 * np.arctan(8.0)] * 3, atol=1e-5)
    assert by_branch[7][1:4] == ["-", "-", "-"] and by_branch[7][-1] == "yes"
    lines = done.stdout.splitlines()
    column = lines[1].index("theta2")  # aligned: every row's second input starts under its header
    assert all(line[column - 1] == " " and line[column] != " " for line in lines[3 : 3 + len(rows)])
    assert max(len(line) for line in lines) < 120


def test_an_unreachable_branch_shows_no_numbers():
    """rus6 with the platform 0.9 m up: out of every leg's reach (the solver returns clipped,
    made-up angles there), so every branch reads '-' and names the failed conditions."""
    done = run("ik", "rus6", "--backend", "numpy", "--pose", "0", "0", "0.9", "0", "0", "0")
    assert done.returncode == 1
    header, rows = _rows(done.stdout)
    assert len(rows) == 64
    theta = [i for i, h in enumerate(header) if h.startswith("theta")]
    for row in rows:
        assert row[7:13] == ["-"] * 6, row
        assert " ".join(row).endswith("no, failed: leg1-6_reachable")
    assert len(theta) == 6
    assert "q0 []" not in done.stdout and "q0" in done.stdout


def test_a_warning_is_one_line_without_source_path():
    """gough's section 5.4 geometry is architecturally singular: load warns. Once a raw Python
    warning with parakin's source path and code line."""
    done = run("demo", "gough")
    warned = [line for line in done.stderr.splitlines() if "warning" in line]
    assert warned == [
        line for line in done.stderr.splitlines() if line.startswith("parakin: warning: gough geometry is")
    ]
    assert len(warned) == 1 and ".py" not in done.stderr and "parakin.load(" not in done.stderr


@pytest.mark.parametrize(
    ("args", "suggestion"),
    [
        (["plto", "sam"], "did you mean 'plot'?"),
        (["plot", "sam", "--outptu", "x.png"], "did you mean '--output'?"),
        (["fk", "sam", "--acutated", "0", "0", "0", "0", "0", "0"], "did you mean '--actuated'?"),  # "required"
    ],
)
def test_did_you_mean(args, suggestion, capsys):
    with pytest.raises(SystemExit) as exit_:
        cli.main(args)
    assert exit_.value.code == 2
    assert capsys.readouterr().err.rstrip().endswith(suggestion)


def test_interrupt_in_process_is_exit_130(monkeypatch, capsys):
    def interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setitem(cli.COMMANDS, "list", interrupted)
    assert cli.main(["list"]) == 130
    assert capsys.readouterr().err.strip() == "parakin: interrupted"


def test_ctrl_c_in_a_running_sweep_ends_within_two_seconds():
    """A sweep of stewart's modes (homotopy: minutes) interrupted once its bar shows: once a
    25-line traceback, about 20 s later; now one line and exit 130 within 2 s."""
    axes = ["--axis", "l1=0.9:1.1:40", "--axis", "l2=0.6:0.7:40"]
    fixed = [f"--fixed=l{i}={v}" for i, v in zip(range(3, 7), (1.086284, 1.503439, 1.281933, 0.771071), strict=True)]
    process = subprocess.Popen(
        [sys.executable, "-m", "parakin.interfaces.cli", "sweep", "stewart", "modes", *axes, *fixed]
        + ["--backend", "numpy", "--chunk", "50", "--progress"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        env={**os.environ, "PARAKIN_PROGRESS": "on"},
    )
    try:
        ready, _, _ = select.select([process.stderr], [], [], 60)  # the bar: the sweep is running
        assert ready, "the sweep showed no progress within 60 s"
        time.sleep(0.5)
        start = time.perf_counter()
        process.send_signal(signal.SIGINT)
        code = process.wait(timeout=30)
        elapsed = time.perf_counter() - start
    finally:
        if process.poll() is None:
            process.kill()
    stderr = process.stderr.read().decode()
    assert code == 130, stderr
    assert elapsed <= 2.0
    assert stderr.rstrip().endswith("parakin: interrupted") and "Traceback" not in stderr


def test_demo_compiles_nothing(tmp_path):
    """`parakin demo` runs on NumPy by default: a fresh cache stays empty (once it compiled 12 C
    libraries one after another before the last result, 35 s on an idle machine)."""
    cache = tmp_path / "cache"
    done = run("demo", "delta", env={"PARAKIN_CACHE": str(cache)})
    assert done.returncode == 0, done.stderr
    assert not cache.exists() or not any(cache.iterdir())
    assert "compiling" not in done.stderr
    # the comparison lines: a zero printed value has no "digits" (once "0.0 digits" for 8.9e-16)
    line = next(line for line in done.stdout.splitlines() if "actuated (branch 0)" in line)
    assert "ours (0, 0, 0), printed (0, 0, 0)" in line and "digits" not in line


def test_work_over_a_second_says_what_runs(monkeypatch, capsys):
    """`parakin plot rus6` once printed nothing for minutes: work wrapped in ``_Busy`` names itself
    and its elapsed time after its delay (where bars show: PARAKIN_PROGRESS=on here), and ends
    with the time taken; work that ends before the delay prints nothing."""
    monkeypatch.setenv("PARAKIN_PROGRESS", "on")
    with cli._Busy("quick", delay=0.5):
        pass
    assert capsys.readouterr().err == ""
    with cli._Busy("rus6: every assembly mode", delay=0.05):
        time.sleep(0.3)
    lines = capsys.readouterr().err.split("\r")
    assert lines[1].startswith("parakin: rus6: every assembly mode ... 0 s")
    done = float(lines[-1].removeprefix("parakin: rus6: every assembly mode: done in ").removesuffix(" s\n"))
    assert 0.25 <= done < 5
    monkeypatch.setenv("PARAKIN_PROGRESS", "off")
    with cli._Busy("silent", delay=0.0):
        time.sleep(0.1)
    assert capsys.readouterr().err == ""


def test_ctrl_c_stops_the_viewer_as_any_command():
    """`parakin view` serves until Ctrl-C; it once exited 0 without a word: now as every command,
    'parakin: interrupted' and 130, within 2 s."""
    process = subprocess.Popen(
        [sys.executable, "-m", "parakin.interfaces.cli", "view", "five_bar", "--port", "0", "--backend", "numpy"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        url = process.stdout.readline().strip()
        assert url.startswith("http://127.0.0.1:"), url
        start = time.perf_counter()
        process.send_signal(signal.SIGINT)
        code = process.wait(timeout=30)
        elapsed = time.perf_counter() - start
    finally:
        if process.poll() is None:
            process.kill()
    assert code == 130 and elapsed <= 2.0
    assert process.stderr.read().strip() == "parakin: interrupted"


@pytest.mark.parametrize(("name", "actuated"), [("stewart", None), ("planar_3rrr", [0.0, 0.0, 0.0])])
def test_fk_says_whether_its_modes_are_certified_complete(name, actuated, capsys):
    """``fk`` prints the certificate's verdict (a new user's Hexaglide printed 4 modes, exit 0, and
    nothing about 8 of its 80 paths failing) in the heading and as ``certified_complete`` per JSON
    line, the same verdict as the API's certificate at the same input."""
    m = parakin.load(name)
    values = m.home_actuated if actuated is None else np.array(actuated)
    certificate = m.forward_pose_all(values).certificate()
    words = [f"{v!r}" for v in values.tolist()]
    assert cli.main(["fk", name, "--actuated", *words]) == 0
    heading = capsys.readouterr().out.splitlines()[0]
    expected = "certified complete" if certificate["complete"] else "not certified complete"
    assert heading.endswith(expected) or f"; {expected}:" in heading, heading
    assert cli.main(["fk", name, "--actuated", *words, "--json"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == certificate["with_modes"] >= 2
    assert all(json.loads(line)["certified_complete"] is bool(certificate["complete"]) for line in lines)


def _stewart_has_no_mode_with_legs(length: float) -> bool:
    """No 6-SPS pose closes with every leg ``length`` where two platform joints are farther apart, or
    nearer, than their base joints allow (triangle inequality: | |B_i - B_j| - |P_i - P_j| | <= 2
    length), from the default parameters alone."""
    p = parakin.load("stewart", backend="numpy").parameters
    base = np.array([[p[f"base_{c}{i}"] for c in "xyz"] for i in range(1, 7)])
    platform = np.array([[p[f"platform_{c}{i}"] for c in "xyz"] for i in range(1, 7)])
    gaps = [
        abs(np.linalg.norm(base[i] - base[j]) - np.linalg.norm(platform[i] - platform[j]))
        for i in range(6)
        for j in range(i)
    ]
    return bool(max(gaps) > 2 * length)


@pytest.mark.parametrize(
    ("name", "actuated", "certified"),
    [
        # elbows at (-0.15 - 0.2, 0) and (0.15 + 0.2, 0): 0.7 m apart, the distal links reach 0.25 + 0.25
        ("five_bar", ["3.141592653589793", "0"], None),
        ("stewart", ["0.1"] * 6, True),  # _stewart_has_no_mode_with_legs(0.1)
    ],
)
def test_fk_json_with_no_mode_is_one_summary_object_and_exit_1(name, actuated, certified, capsys):
    """``parakin fk NAME ... --json`` with no mode once printed nothing on stdout (exit 1, a line on
    stderr): a JSON reader got no answer to parse. Now one object: modes 0, certified_complete
    (null for an elimination, which has no certificate; true for the 6-SPS homotopy's certificate)
    and the verdict in words; exit status 1 (no solution) as documented in ``fk --help``. That no
    mode exists is shown independently (the five-bar's elbows too far apart; the 6-SPS's triangle
    inequality)."""
    if name == "stewart":
        assert _stewart_has_no_mode_with_legs(0.1)
    assert cli.main(["fk", name, "--backend", "numpy", "--actuated", *actuated, "--json"]) == 1
    out, err = capsys.readouterr()
    lines = out.splitlines()
    assert len(lines) == 1, out
    answer = json.loads(lines[0])
    assert set(answer) == set(cli.FK_SUMMARY_KEYS) and answer["modes"] == 0
    assert answer["certified_complete"] is certified
    expected = (
        "certified complete" if certified else "not certified complete: elimination (the real roots of a degree-2"
    )
    assert answer["verdict"].startswith(expected)
    # a certificate proves that none exists, and the stderr line says so in those words
    said = "proven: none exists (certified complete)" if certified else answer["verdict"]
    assert err.startswith(f"parakin: no real assembly mode of {name} for these inputs; {said}")
    with pytest.raises(SystemExit):
        cli.main(["fk", "--help"])
    helped = " ".join(capsys.readouterr().out.split())
    assert '{"modes": 0, "certified_complete": ..., "verdict": ...} and exit status 1' in helped


def test_fk_prints_the_same_keys_and_a_verdict_for_an_elimination_and_a_homotopy(capsys):
    """An elimination's modes (five_bar's quadratic, Gosselin & Angeles' circle intersection) once
    carried no completeness statement: no ``certified_complete`` key and no verdict in the heading,
    where a homotopy's (stewart) had both. Now every mechanism's lines have the same keys besides
    the pose and passive columns, and the heading always ends with the verdict; the elimination is
    not called complete (null: nothing certifies it). The five-bar at theta = (pi/2, pi/2): the two
    hand-worked points P = (0, 0) and (0, 0.4) (0.15^2 + 0.2^2 = 0.25^2)."""
    keys = {}
    for name, actuated in (("five_bar", [repr(np.pi / 2)] * 2), ("stewart", None)):
        m = parakin.load(name, backend="numpy")
        words = actuated or [repr(v) for v in m.home_actuated.tolist()]
        assert cli.main(["fk", name, "--backend", "numpy", "--actuated", *words]) == 0
        heading = capsys.readouterr().out.splitlines()[0]
        assert cli.main(["fk", name, "--backend", "numpy", "--actuated", *words, "--json"]) == 0
        records = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
        assert records and all(r["verdict"] == records[0]["verdict"] for r in records)
        assert heading.endswith(f"assembly modes; {records[0]['verdict']}"), heading
        columns = {*(cli._header(v, False) for v in m.manifest.passive), *pose_headers(m.manifest.pose_kind, False)}
        keys[name] = {frozenset(set(r) - columns) for r in records}
        if name == "five_bar":
            assert all(r["certified_complete"] is None and r["modes"] == 2 for r in records)
            assert records[0]["verdict"].startswith("not certified complete: elimination")
            points = sorted((r["x [m]"], r["y [m]"]) for r in records)
            np.testing.assert_allclose(points, [(0.0, 0.0), (0.0, 0.4)], atol=1e-12)
        else:
            assert all(r["certified_complete"] is True and r["modes"] == 40 for r in records)  # Dietmaier's 40
    assert keys["five_bar"] == keys["stewart"] == {frozenset({"mode", "slot", "residual", *cli.FK_SUMMARY_KEYS})}


def test_the_repr_of_modes_and_the_command_line_print_the_same_radians(spm_modes, capsys):
    """``print(modes)`` once showed Z-Y-X angles in degrees where ``parakin fk`` shows radians
    (the API's unit). Now both print radians, labelled rad, the same numbers: the spherical SPM's
    8 modes at theta = (105, 60, 105) deg, each row equal to SciPy's Z-Y-X decomposition of the
    mode's rotation in radians (1e-5); the notebook's HTML too; degrees only where labelled deg
    (``fk --actuated-deg``)."""
    m, modes = spm_modes
    header, rows = _rows(repr(modes))
    assert header == ["mode", "alpha", "[rad]", "beta", "[rad]", "gamma", "[rad]", "conditioning"]
    assert len(rows) == int(modes.count) == 8
    for k, row in enumerate(rows):
        expected = Rotation.from_matrix(modes.mode(k).rotation).as_euler("ZYX")
        np.testing.assert_allclose([float(v) for v in row[1:4]], expected, atol=1e-5)
    words = [repr(v) for v in np.deg2rad([105.0, 60.0, 105.0]).tolist()]
    assert cli.main(["fk", "spm", "--backend", "numpy", "--actuated", *words]) == 0
    cli_header, cli_rows = _rows(capsys.readouterr().out)
    assert cli_header[2:8] == header[1:7]
    assert [r[2:5] for r in cli_rows] == [r[1:4] for r in rows]
    assert "<th>gamma [rad]</th>" in modes._repr_html_()
    assert cli.main(["fk", "spm", "--backend", "numpy", "--actuated-deg", "105", "60", "105"]) == 0
    assert "alpha [deg]" in capsys.readouterr().out
