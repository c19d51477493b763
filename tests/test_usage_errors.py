"""Bad arguments found by a new-user review: each is a usage error (exit 2, one line naming the
option and what it takes), never a traceback or an internal error; and an empty batch prints."""

import json
import re

import numpy as np
import pytest

import parakin
from parakin.interfaces.cli import main


@pytest.mark.parametrize(
    ("arguments", "words"),
    [
        (["view", "five_bar", "--port", "99999"], "not a port number (0 to 65535"),
        (["view", "five_bar", "--port", "-1"], "not a port number (0 to 65535"),
        (["inspect", "five_bar", "--width", "-5"], "--width: -5 must be at least 1"),
        (["inspect", "five_bar", "--lines", "0"], "--lines: 0 must be at least 1"),
        (["inspect", "five_bar", "--lines", "many"], "'many' is not a whole number"),
    ],
)
def test_a_bad_number_is_a_usage_error(arguments, words, capsys):
    with pytest.raises(SystemExit) as stop:
        main(arguments)
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert words in err and "Traceback" not in err and "internal error" not in err, err


def test_the_command_list_names_every_command(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    description = out[out.index("Command line:") :].split("\n\n")[0]  # the summary, not the usage line
    assert all(command in description for command in ("calibrate", "mjcf", "sweep", "view", "export", "generate"))


def test_an_empty_batch_of_modes_prints():
    m = parakin.load("five_bar", backend="numpy")
    modes = m.forward_pose_all(np.zeros((0, 2)))
    assert "an empty batch" in repr(modes) and "an empty batch" in modes._repr_html_()


def test_degrees_given_as_radians_are_pointed_out(caplog):
    """90 for a crank is legal (radians, 14 turns) but most often meant as degrees: a one-line
    warning names the inputs and the -deg flags; the answer is still given (exit 0)."""
    assert main(["fk", "five_bar", "--actuated", "90", "90"]) == 0
    assert "theta1 = 90, theta2 = 90 rad: more than a full turn" in caplog.text and "-deg" in caplog.text
    caplog.clear()
    assert main(["fk", "five_bar", "--actuated-deg", "90", "90"]) in (0, 1)
    assert "more than a full turn" not in caplog.text


def test_an_output_path_that_cannot_be_written_is_named(tmp_path, capsys):
    missing = tmp_path / "no" / "such" / "folder" / "x.png"
    assert main(["plot", "five_bar", "--out", str(missing)]) == 2
    err = capsys.readouterr().err
    assert err.strip() == f"parakin: cannot use {missing}: No such file or directory", err


def test_a_misspelt_keyword_of_a_method_suggests_the_closest():
    """The review's misspellings: each a parakin error (and a TypeError, as Python answers a call
    its signature refuses) naming the keyword and the one meant."""
    m = parakin.load("five_bar", backend="numpy")
    calls = {
        "guess": lambda: m.forward_pose(m.home_actuated, gues=None),
        "method": lambda: m.forward_pose_all(m.home_actuated, methd="automatic"),
        "strict": lambda: m.tracker(m.forward_pose(m.home_actuated), strikt=True),
    }
    for meant, call in calls.items():
        with pytest.raises(parakin.UnknownKeywordError, match=f"did you mean '{meant}'") as raised:
            call()
        assert isinstance(raised.value, TypeError) and isinstance(raised.value, parakin.BadInputError)
    with pytest.raises(parakin.UnknownKeywordError, match="inverse_pose: missing a required argument: 'pose'"):
        m.inverse_pose()
    assert len(calls) == 3


def test_negative_values_in_exponent_notation_are_values(capsys):
    """``-1e-3`` (and ``-3.5e-17``, as ``fk`` prints a home at x = 0) read as numbers, not options:
    the command's result equals the API's at the same pose."""
    assert main(["ik", "five_bar", "--pose", "-1e-3", "3.3E-1", "--json"]) == 0
    printed = capsys.readouterr().out
    m = parakin.load("five_bar")
    expected = m.inverse_pose([-0.001, 0.33]).actuated
    for branch, line in enumerate(printed.strip().splitlines()):
        row = json.loads(line)
        got = [row["theta1 [rad]"], row["theta2 [rad]"]]
        np.testing.assert_allclose(got, expected[branch], rtol=0, atol=1e-12)
    assert branch == 3  # four branches checked


@pytest.mark.parametrize("value", ["-inf", "nan"])
def test_a_non_finite_pose_value_is_named_in_the_command_line_terms(value, capsys):
    assert main(["ik", "five_bar", "--pose", value, "0.3"]) == 2
    err = capsys.readouterr().err
    assert f"pose value 1 of 2 (x y (m)) is {float(value)}" in err and "index" not in err, err


def test_failed_paths_without_a_mode_are_not_called_a_self_motion(monkeypatch):
    """An input whose homotopy paths partly fail, with every certified root non-real and no
    self-motion near home, is refused saying what is proven (a user's Hexaglide on shared rails:
    8 of 80 paths failed, 72 roots certified complex), not "the platform is not determined by the
    actuators". The pipeline's outcome is forced here: 3 of stewart's 40 paths failed, the rest
    complex."""
    m = parakin.load("stewart", backend="numpy")
    real = m._every_mode_here

    def forced(info, flat, exact):
        out = real(info, flat, exact)
        outcomes = m.manifest.abi.mode_outcomes
        out["outcome"][:] = outcomes.index("complex")
        out["outcome"][:, :3] = outcomes.index("path_failed")
        out["count"][:] = 0
        out["certified"][:] = 37
        out["status"][:] = m.manifest.abi.code("input_status", "degenerate")
        return out

    monkeypatch.setattr(m, "_every_mode_here", forced)
    with pytest.raises(parakin.SingularConfigurationError) as error:
        m.forward_pose_all(m.home_actuated)
    message = str(error.value)
    assert "3 homotopy path(s) failed, 37 of 40 roots certified (none real)" in message, message
    assert "not determined" not in message and "batch index" not in message, message
    # continuation from home and its perturbations finds some of stewart's 40 isolated modes
    assert re.search(
        r"; ([1-9]|[1-3][0-9]|40) isolated configuration\(s\) near the home pose that continuation", message
    ), message
