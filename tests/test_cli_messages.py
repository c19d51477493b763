"""What the runtime and the command line say (new-user review): one notion of "near a type II
singularity", a command's own usage and suggestions, ``fk --method``, a serial chain listed with
its forward, JSON keys that do not depend on how the input was typed, and a tracker that says
where its assembly mode ends. Values are checked against an independent computation (the
singularity module's measure, a fresh ``forward_pose_all``, the hand-worked five-bar points),
never against the printing code's own output. Every test runs in well under a second."""

import dataclasses
import json

import numpy as np
import pytest

import parakin
from parakin.interfaces import cli
from parakin.singularity import NEAR_SINGULAR, is_near_singular, singularity_distance


def test_ill_conditioned_is_the_near_singular_of_plot_and_mjcf():
    """stewart at home: 40 modes, 25 of them with a type II distance below NEAR_SINGULAR (0.02)
    as parakin.singularity measures each mode afresh (the measure plot and the MJCF export use).
    ill_conditioned() flags exactly those; its old default (1e-10) flagged none, though five
    modes lie at 1.1e-5 .. 6.4e-5."""
    m = parakin.load("stewart")
    modes = m.forward_pose_all(m.home_actuated)
    assert int(modes.count) == 40
    near = [is_near_singular(singularity_distance(m, mode)) for mode in modes]
    flagged = modes.ill_conditioned()[modes.valid].tolist()
    assert flagged == near and sum(near) == 25, (sum(flagged), sum(near))
    assert not modes.ill_conditioned(level=1e-10).any()  # an explicit level still applies
    assert NEAR_SINGULAR == 0.02


def _error(args: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    with pytest.raises(SystemExit) as exit_:
        cli.main(args)
    assert exit_.value.code == 2
    return capsys.readouterr().err


def test_an_unknown_option_of_fk_gets_fk_usage_and_fk_suggestions(capsys):
    """`fk five_bar --mode 0`: fk has no --mode (plot has); the error shows fk's usage and
    suggests only fk's own options (--method), never plot's --mode or --output."""
    err = _error(["fk", "five_bar", "--backend", "numpy", "--mode", "0", "--actuated", "1.5", "1.5"], capsys)
    assert err.startswith("usage: parakin fk ") and "parakin fk: error: unrecognized arguments: --mode 0" in err
    assert err.rstrip().endswith("did you mean '--method'?")
    err = _error(["fk", "five_bar", "--backend", "numpy", "--outptu", "x.png", "--actuated", "1.5", "1.5"], capsys)
    assert err.startswith("usage: parakin fk ") and "did you mean" not in err  # --output is plot's


def test_a_format_given_as_an_option_names_format(capsys):
    """`inspect prs3 --json`: inspect writes formats through --format; the error says so (fk's
    own --json stays what a near miss of it suggests)."""
    err = _error(["inspect", "prs3", "--json"], capsys)
    assert err.startswith("usage: parakin inspect ")
    assert err.rstrip().endswith("did you mean '--format json'?")
    err = _error(["fk", "five_bar", "--backend", "numpy", "--jsn", "--actuated", "1.5", "1.5"], capsys)
    assert err.rstrip().endswith("did you mean '--json'?")


def test_fk_method_automatic_certifies_the_hand_worked_five_bar(capsys):
    """theta = (pi/2, pi/2): P = (0, 0) and (0, 0.4) by hand (circles of radius 0.25 m about
    (-0.15, 0.2) and (0.15, 0.2)). The default elimination has no certificate; --method
    automatic (a homotopy) finds the same two points, certified complete."""
    half_pi = repr(np.pi / 2)
    args = ["fk", "five_bar", "--backend", "numpy", "--json", "--actuated", half_pi, half_pi]
    assert cli.main(args) == 0
    default = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert cli.main([*args, "--method", "automatic"]) == 0
    lines = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert default[0]["certified_complete"] is None and len(lines) == 2
    assert all(line["certified_complete"] is True for line in lines)
    points = sorted((line["x [m]"], line["y [m]"]) for line in lines)
    np.testing.assert_allclose(points, [(0.0, 0.0), (0.0, 0.4)], atol=1e-9)
    err = _error_status(["fk", "five_bar", "--backend", "numpy", "--method", "newton", "--actuated", "1", "1"], capsys)
    assert err == "parakin: BadInputError: --method 'newton': five_bar's forward methods are 'elimination', 'automatic'"


def _error_status(args: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    assert cli.main(args) == 2
    return capsys.readouterr().err.strip()


def test_list_gives_the_serial_chain_its_forward(capsys):
    """sphere2r (no passive joint) has its forward pose by evaluating the chain, certified
    complete (one mode): list says forward, and fk answers one certified mode."""
    assert cli.main(["list"]) == 0
    line = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("sphere2r "))
    assert "forward(chain)" in line.split("[")[-1], line
    assert cli.main(["fk", "sphere2r", "--backend", "numpy", "--json", "--actuated", "0.5", "1.0"]) == 0
    (record,) = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert record["modes"] == 1 and record["certified_complete"] is True


def test_fk_json_keys_and_values_are_radians_however_the_input_was_typed(capsys):
    """sphere2r at (30, 60) deg and at (pi/6, pi/3) rad: the same JSON keys ("[rad]") and the
    same values; the text output with --actuated-deg labels its angles [deg] (30 deg = pi/6)."""
    common = ["fk", "sphere2r", "--backend", "numpy", "--json"]
    assert cli.main([*common, "--actuated-deg", "30", "60"]) == 0
    typed_deg = json.loads(capsys.readouterr().out)
    assert cli.main([*common, "--actuated", repr(np.pi / 6), repr(np.pi / 3)]) == 0
    typed_rad = json.loads(capsys.readouterr().out)
    assert list(typed_deg) == list(typed_rad) and not any("[deg]" in key for key in typed_deg)
    for key, value in typed_rad.items():
        assert typed_deg[key] == pytest.approx(value, abs=1e-12), key
    assert cli.main(["fk", "sphere2r", "--backend", "numpy", "--actuated-deg", "30", "60"]) == 0
    text = capsys.readouterr().out
    assert "theta1 = 30 deg" in text and "alpha [deg]" in text


def test_a_tracker_at_a_fold_says_its_mode_ends_at_a_type_ii_singularity():
    """five_bar from home along theta + s (1, -1): its two modes merge near s = 0.229 (a fresh
    forward_pose_all finds 2 modes at 0.229, none at 0.2295). Tracked in steps of 0.001 the
    tracker fails past the fold: the message says the mode ends at a type II singularity with
    the kept solution's conditioning (below NEAR_SINGULAR), not "try a closer guess"; a single
    tracker's message has no batch index, and its conditioning is a 0-d value."""
    m = parakin.load("five_bar", backend="numpy")
    direction = np.array([1.0, -1.0])
    assert int(m.forward_pose_all(m.home_actuated + 0.229 * direction).count) == 2
    assert int(m.forward_pose_all(m.home_actuated + 0.2295 * direction).count) == 0
    tracker = m.tracker(m.forward_pose(m.home_actuated))
    assert np.shape(tracker.conditioning) == ()
    steps = 0
    with pytest.raises(parakin.ConvergenceError) as error:
        for s in np.arange(0.2, 0.3, 0.001):
            tracker.solve(m.home_actuated + s * direction)
            steps += 1
    message = str(error.value)
    assert steps >= 25 and message.startswith("tracker: the assembly mode ends at a type II singularity near here")
    assert "closer guess" not in message and "batch index" not in message
    kept = float(tracker.conditioning)
    assert np.shape(tracker.conditioning) == () and kept < NEAR_SINGULAR
    assert f"conditioning is {kept:.3g}" in message
    fresh = m.forward_pose_all(tracker.actuated[0]).conditioning
    assert kept == pytest.approx(float(np.nanmin(fresh)), rel=1e-6)  # the merging modes' measure


def test_tracker_messages_name_a_batch_index_in_one_form():
    """Every batched message names an entry as `at batch index (i,)` (parakin.errors.at_index):
    a batch of two planar_3rpr trackers whose second entry is sent across a type II singularity
    (1.6 (1, -0.5, 0.3) from home, as test_tracking does) says "(1,)" (it said "batch index 1");
    a tracker of one configuration names no index (it said "batch index 0"). A five-bar batch
    whose second entry leaves the workspace: the same form for a ConvergenceError."""
    m = parakin.load("planar_3rpr", backend="numpy")
    home, direction = m.home_actuated, np.array([1.0, -0.5, 0.3])
    batch = m.tracker(m.forward_pose(np.stack([home, home])))
    with pytest.raises(parakin.AssemblyModeChangeError) as crossed:
        batch.solve(np.stack([home, home + 1.6 * direction]))
    assert str(crossed.value).startswith("tracker at batch index (1,): ") and crossed.value.index == 1
    single = m.tracker(m.forward_pose(home))
    with pytest.raises(parakin.AssemblyModeChangeError) as crossed:
        single.solve(home + 1.6 * direction)
    assert str(crossed.value).startswith("tracker: ") and "batch index" not in str(crossed.value)
    bar = parakin.load("five_bar", backend="numpy")
    start = bar.home_actuated
    tracker = bar.tracker(bar.forward_pose(np.stack([start, start])))
    assert np.shape(tracker.conditioning) == (2,)
    with pytest.raises(parakin.ConvergenceError) as error:
        tracker.solve(np.stack([start + [0.05, 0.0], start + [1.5, 0.0]]))
    assert str(error.value).startswith("tracker at batch index (1,)"), str(error.value)


def test_inspect_gives_each_parameter_its_meaning_one_per_line(capsys):
    """`parakin inspect five_bar`: the header once had one `parameters: ...` line without
    meanings (stewart's ran to ~1200 characters). Now one line per parameter, `name = value
    unit: meaning`, the meaning and value as the manifest gives them, every header line within
    the width (100), the citation wrapped too."""
    assert cli.main(["inspect", "five_bar"]) == 0
    header = capsys.readouterr().out.partition("\n== ")[0].splitlines()
    manifest = parakin.metadata("five_bar")
    start = header.index("parameters:")
    for k, p in enumerate(manifest.parameters, start + 1):
        assert header[k] == f"  {p.name} = {p.default:g} {p.unit}: {p.description}", header[k]
    assert max(len(line) for line in header) <= 100


def test_home_values_that_are_rounding_noise_print_as_0():
    """rus6's home cranks are 0 up to rounding (theta1 = 2.88e-16 rad in the manifest): shown as
    `theta1 = 0 rad (0 deg)` and named in the note; a value at 1e-12 of its unit's scale or above
    is kept (rule: |v| < 1e-12 max(1, the largest |value| in that unit))."""
    from parakin.interfaces.inspect import NOISE, _home_values, _scales

    manifest = parakin.metadata("rus6")
    raw = [float(v.home) for v in manifest.actuated]
    assert all(0.0 < abs(v) < 1e-15 for v in raw[:1]), raw  # the noise is really there
    noise: list[str] = []
    shown = _home_values(manifest.actuated, _scales(manifest), noise)
    assert shown[0] == "theta1 = 0 rad (0 deg)" and noise[0] == "theta1"
    scales = _scales(manifest)
    assert scales["rad"] >= 1.0 and scales["m"] == max(
        [1.0] + [abs(p.default) for p in manifest.parameters if p.unit == "m"]
        + [abs(float(v.home)) for v in manifest.passive if v.unit == "m" and v.home is not None]
    )  # fmt: skip
    kept: list[str] = []
    variable = dataclasses.replace(manifest.actuated[0], home=3 * NOISE)
    assert _home_values([variable], {"rad": 1.0}, kept) == [
        f"theta1 = {3 * NOISE:.6g} rad ({np.degrees(3 * NOISE):.6g} deg)"
    ]
    assert kept == []


def test_the_mode_table_legend_names_the_type_ii_distance():
    """repr(modes) above its table: the conditioning column is the type II distance, 1 far from,
    0 at a singularity (it read "conditioning: 1 well conditioned, 0 singular", like a count next
    to "2 assembly modes"); five_bar's two home modes have type II distance 0.6662 as
    parakin.singularity measures them (0.6662, its docstring example), printed to 3 digits."""
    m = parakin.load("five_bar", backend="numpy")
    modes = m.forward_pose_all(m.home_actuated)
    lines = repr(modes).splitlines()
    assert lines[1].endswith("; conditioning (type II distance): 1 far from, 0 at a singularity"), lines[1]
    assert "well conditioned" not in repr(modes)
    measured = [round(singularity_distance(m, mode)["type II"], 3) for mode in modes]  # printed to 3 digits
    assert [float(row.split()[-1]) for row in lines[4:]] == measured == [0.666, 0.666]


def test_ik_json_keys_are_radians_however_the_pose_was_typed(capsys):
    """delta at p = (0, 0, -1.2): `--pose-deg` (no angle in a translation pose) and `--pose` give
    the same JSON keys and values, its revolute inputs in radians ("theta1 [rad]"); branch 7's
    theta = -2 atan(8) = -2.892883 rad by hand (the manifest's example)."""
    answers = []
    for flag in ("--pose", "--pose-deg"):
        assert cli.main(["ik", "delta", "--backend", "numpy", flag, "0", "0", "-1.2", "--json"]) == 0
        answers.append([json.loads(line) for line in capsys.readouterr().out.splitlines()])
    assert answers[0] == answers[1] and len(answers[0]) == 8
    assert answers[1][7]["theta1 [rad]"] == pytest.approx(-2 * np.arctan(8.0), abs=1e-9)
