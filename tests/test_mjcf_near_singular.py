"""The MJCF export warns of keyframes near a type II singularity (issue 36's review: stewart's
near-singular keyframes drift in simulation and the file did not say so).

The measure is the one ``parakin plot`` labels "type II" (``parakin.singularity.
singularity_distance``: 1/cond of the closure Jacobian d closure / d passive); here it is checked
against an independent computation: central finite differences of the closure residual and
NumPy's ``cond``. Which modes are near-singular is decided from the finite differences alone.
"""

from __future__ import annotations

import re

import numpy as np
import pytest

import parakin
from parakin.errors import NearSingularModeWarning
from parakin.singularity import NEAR_SINGULAR, singularity_distance

mujoco = pytest.importorskip("mujoco")
from parakin import mjcf  # noqa: E402
from parakin import mujoco_bridge as bridge  # noqa: E402

#: central-difference step on the passive values (m, quaternion components)
STEP = 1e-6


def finite_difference_measure(m: parakin.Mechanism, actuated: np.ndarray, passive: np.ndarray) -> np.ndarray:
    """1 / numpy.linalg.cond of the closure residual's Jacobian in the passive values, by central
    differences, for each row of ``passive`` (k, n_p): independent of the generated Jacobian."""
    k, n = passive.shape
    shifts = STEP * np.eye(n)
    ahead = passive[:, None, :] + shifts  # (k, n, n): column j shifted
    behind = passive[:, None, :] - shifts
    theta = np.broadcast_to(actuated, (k * n, actuated.size))
    plus = m.loop_closure(theta, ahead.reshape(k * n, n))["residual"].reshape(k, n, -1)
    minus = m.loop_closure(theta, behind.reshape(k * n, n))["residual"].reshape(k, n, -1)
    jacobian = np.swapaxes((plus - minus) / (2 * STEP), 1, 2)  # (k, residuals, passive)
    return 1.0 / np.linalg.cond(jacobian)


@pytest.fixture(scope="module")
def stewart():
    """Dietmaier's Stewart platform at its home inputs: 40 modes, their measure by differences."""
    m = parakin.load("stewart")
    modes = m.forward_pose_all(m.home_actuated)
    passive = np.stack([np.asarray(modes.mode(k).passive) for k in range(int(modes.count))])
    return m, modes, finite_difference_measure(m, np.asarray(m.home_actuated), passive)


def comment_before(text: str, k: int) -> str | None:
    """The XML comment on the line before ``<key name="mode{k}"``, or None."""
    lines = text.splitlines()
    index = next(i for i, line in enumerate(lines) if f'<key name="mode{k}"' in line)
    previous = lines[index - 1].strip()
    return previous[4:-3].strip() if previous.startswith("<!--") and previous.endswith("-->") else None


def test_the_measure_is_one_over_cond_of_the_closure_jacobian(stewart):
    """The plot's type II measure at each of the 40 modes equals 1/cond of the finite-difference
    closure Jacobian (numpy) to 1e-4 relative, over values from ~1e-5 to ~0.16."""
    m, modes, measured = stewart
    ours = np.array([singularity_distance(m, modes.mode(k))["type II"] for k in range(int(modes.count))])
    assert ours.size == 40
    np.testing.assert_allclose(ours, measured, rtol=1e-4)
    assert measured.min() < 1e-4 and measured.max() > 0.1  # both kinds are present


def test_a_near_singular_keyframe_carries_the_warning_and_a_regular_one_does_not(stewart):
    """The worst- and best-conditioned modes (by finite differences) exported: the first's keyframe
    has the comment with its value (to its 2 printed digits) and the warning names it; the
    second's has no comment and the warning does not name it."""
    m, _, measured = stewart
    bad, good = int(np.argmin(measured)), int(np.argmax(measured))
    assert measured[bad] < NEAR_SINGULAR < measured[good]
    with pytest.warns(NearSingularModeWarning) as caught:
        text = mjcf.to_mjcf(m, modes=[bad, good])
    assert mujoco.MjModel.from_xml_string(text).nkey == 2
    note = comment_before(text, bad)
    assert note is not None and "near a type II (parallel) singularity" in note and "1/cond" in note
    printed = float(re.search(r"d passive = ([0-9.e+-]+),", note).group(1))
    assert printed == pytest.approx(measured[bad], rel=0.05)
    assert comment_before(text, good) is None
    message = " ".join(str(w.message) for w in caught)
    assert f"mode{bad}" in message and f"mode{good}" not in re.findall(r"mode\d+", message)


def test_command_line_warns_on_stderr_of_exactly_the_near_singular_modes(stewart, tmp_path, capsys):
    """``parakin mjcf stewart``: one ``parakin: warning:`` line naming exactly the modes whose
    finite-difference measure is below NEAR_SINGULAR (25 of Dietmaier's 40), and one comment per
    such keyframe in the file; the file still loads in MuJoCo with all 40 keyframes."""
    m, _, measured = stewart
    from parakin.interfaces.cli import main

    out = tmp_path / "stewart.xml"
    assert main(["mjcf", "stewart", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    warned = [line for line in err.splitlines() if line.startswith("parakin: warning:")]
    assert len(warned) == 1 and "near a type II (parallel) singularity" in warned[0], err
    expected = {k for k in range(measured.size) if measured[k] < NEAR_SINGULAR}
    named = {int(k) for k in re.findall(r"\bmode(\d+)\b", warned[0])}
    assert named == expected and len(expected) == 25
    text = out.read_text()
    commented = {k for k in range(measured.size) if comment_before(text, k) is not None}
    assert commented == expected
    assert mujoco.MjModel.from_xml_path(str(out)).nkey == 40


@pytest.mark.slow
def test_near_singular_keyframes_drift_and_regular_ones_settle_under_stiff_servos(stewart):
    """What the warning says, in MuJoCo: the five worst- and five best-conditioned keyframes (by
    finite differences), servos stiff enough not to dominate (kp 1e6 N/m), gravity, 10 s. Measured
    on all 40: the 15 regular ones 14 settled, median drift 2 mm; the 25 near-singular 3 settled,
    median drift 97 mm (with the default kp 1e4 both drift: 219 and 486 mm). Here: the best five
    5 settled, drifts 0.1-1.6 mm; the worst five none, drifts 1.6-888 mm (median 54 mm)."""
    import warnings

    m, _, measured = stewart
    order = np.argsort(measured)
    worst, best = order[:5].tolist(), order[-5:].tolist()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", NearSingularModeWarning)
        model = mujoco.MjModel.from_xml_string(mjcf.to_mjcf(m, kp=1e6))
    data = mujoco.MjData(model)
    chain = bridge.closed_chain(model, m.actuated_names, "platform")
    drift, settled = {}, {}
    for k in worst + best:
        mujoco.mj_resetDataKeyframe(model, data, k)
        start = bridge.platform_pose(chain, data)[:3, 3]
        done = bridge.settle(chain, data, duration=10.0)
        drift[k], settled[k] = float(np.linalg.norm(done.pose[:3, 3] - start)), done.settled
    assert sum(settled[k] for k in best) >= 4 and np.median([drift[k] for k in best]) < 0.01, (drift, settled)
    assert sum(settled[k] for k in worst) <= 1 and np.median([drift[k] for k in worst]) > 0.02, (drift, settled)


def test_the_readme_names_the_warning_and_its_level():
    """The README's mjcf row says which keyframes get the comment and the warning, at the level
    the export uses (NEAR_SINGULAR)."""
    from pathlib import Path

    readme = (Path(__file__).resolve().parent.parent / "README.md").read_text()
    (row,) = [line for line in readme.splitlines() if line.startswith("| `parakin mjcf ")]
    assert f"1/cond of the closure Jacobian below {NEAR_SINGULAR:g}" in row
    assert "XML comment" in row and "`parakin: warning:`" in row


def _home_mode(m: parakin.Mechanism, modes) -> tuple[int, object]:
    """The mode of the home inputs that is the home (its pose equal to forward_pose from the
    manifest's home, 1e-9), and that configuration."""
    home = m.forward_pose(m.home_actuated, guess=m.home_passive)
    found = [k for k in range(int(modes.count)) if np.abs(modes.mode(k).pose - home.pose).max() < 1e-9]
    assert len(found) == 1, found
    return found[0], home


def _qpos0_line(text: str) -> str:
    header = text.partition("-->")[0]
    lines = [line.strip() for line in header.splitlines() if line.strip().startswith("qpos0: ")]
    assert len(lines) == 1, header
    return lines[0]


def test_the_header_names_the_home_keyframe_says_it_is_near_singular_and_gives_no_foreign_gap(stewart):
    """The MJCF header once said "qpos0: the home" without saying that the home's keyframe is one
    of the flagged near-singular ones, and gave a loop gap "about 0.03 mm and 0.003 deg (a 10 kg
    load on a 0.6 m Stewart platform)": another model's figure. Now the qpos0 line names the home's
    keyframe and, where the finite-difference measure of the home is below NEAR_SINGULAR
    (Dietmaier's home: about 0.011), says it is near a type II singularity with its value; the
    five-bar's home (measure about 0.67) is not called so; no header gives a gap figure."""
    m, modes, measured = stewart
    k, home = _home_mode(m, modes)
    at_home = float(finite_difference_measure(m, np.asarray(home.actuated), np.asarray(home.passive)[None])[0])
    assert at_home == pytest.approx(measured[k], rel=1e-6) and at_home < NEAR_SINGULAR
    good = int(np.argmax(measured))
    with pytest.warns(NearSingularModeWarning):
        text = mjcf.to_mjcf(m, modes=[k, good])
    line = _qpos0_line(text)
    assert line.startswith(f"qpos0: the home (keyframe mode{k}), near a type II (parallel) singularity"), line
    assert float(re.search(r"Jacobian = ([0-9.e+-]+),", line).group(1)) == pytest.approx(at_home, rel=0.05)
    header = text.partition("-->")[0]
    assert "a 0.6 m Stewart platform" not in header and not re.search(r"\d mm|\d um|\d(\.\d+)? deg", header), header

    five_bar = parakin.load("five_bar")
    both = five_bar.forward_pose_all(five_bar.home_actuated)
    j, home = _home_mode(five_bar, both)
    regular = float(finite_difference_measure(five_bar, np.asarray(home.actuated), np.asarray(home.passive)[None])[0])
    assert regular > NEAR_SINGULAR
    text = mjcf.to_mjcf(five_bar)
    assert _qpos0_line(text) == f"qpos0: the home (keyframe mode{j})."
    assert not re.search(r"\d mm|\d um", text.partition("-->")[0])
