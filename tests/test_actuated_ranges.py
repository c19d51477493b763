"""Actuator strokes are actuated ranges (issue 18, item 9), and a user's own actuators may have
other strokes: ``load(limits={actuated name: (low, high)})`` replaces the declared range for every
solver alike (inverse validity, forward_pose, forward_pose_all, sweeps), as passive joint limits are
replaced. Cases are chosen from the manifests: every actuated variable with a finite upper bound."""

import numpy as np
import pytest

import parakin
from parakin.studies.sweep import sweep


def bounded() -> list[tuple[str, int]]:
    cases = []
    for name in parakin.available():
        manifest = parakin.metadata(name)
        if manifest.capabilities.forward is None:
            continue
        cases += [(name, i) for i, v in enumerate(manifest.actuated) if np.isfinite(v.limits[1])]
    return cases


CASES = bounded()


def test_some_mechanism_declares_a_bounded_actuator():
    assert CASES, "no actuated variable with a finite range: nothing below is checked"


@pytest.mark.parametrize(("name", "index"), CASES)
def test_widened_stroke_is_honoured_by_every_solver(name, index):
    declared = parakin.load(name, backend="numpy")
    variable = declared.manifest.actuated[index]
    low, high = variable.limits
    wide = high + 0.3 * (high - low)
    widened = parakin.load(name, backend="numpy", limits={variable.name: (low, wide)})
    assert widened.actuated_ranges[variable.name] == (low, wide)
    assert declared.actuated_ranges[variable.name] == (low, high)
    # a configuration beyond the declared stroke but inside the widened one: found from home by
    # stretching the one input and solving the forward pose on the widened mechanism
    theta = declared.home_actuated.copy()
    found = None
    for value in np.linspace(high, wide, 12)[1:-1]:
        theta[index] = value
        modes = widened.forward_pose_all(theta)
        if modes.count:
            found = modes.mode(0)
            break
    if found is None:
        pytest.skip(f"{name}: no assembly beyond {variable.name}'s stroke along this line")
    with pytest.raises(parakin.BadInputError, match=variable.name):
        declared.forward_pose_all(found.actuated)
    with pytest.raises(parakin.BadInputError, match=variable.name):
        declared.forward_pose(found.actuated, guess=found.passive)
    again = widened.forward_pose(found.actuated, guess=found.passive)
    assert bool(again.converged)
    inverse_declared = declared.inverse_pose(found.pose, strict=False)
    inverse_widened = widened.inverse_pose(found.pose, strict=False)
    matching = np.abs(inverse_widened.actuated - found.actuated).max(-1) < 1e-7
    assert (inverse_widened.valid & matching).any(), "the widened inverse reaches the configuration"
    assert not (inverse_declared.valid & matching).any()
    assert inverse_declared.failures["actuator_range"][matching].all()


@pytest.mark.parametrize(("name", "index"), CASES[:1])
def test_a_sweep_uses_the_overridden_stroke(name, index):
    declared = parakin.load(name, backend="numpy")
    variable = declared.manifest.actuated[index]
    low, high = variable.limits
    narrowed = parakin.load(name, backend="numpy", limits={variable.name: (low, (low + high) / 2)})
    axis = np.linspace(low, high, 5)
    result = sweep(narrowed, ["modes"], {variable.name: axis})
    status = result["modes_status"].values
    outside = axis > (low + high) / 2
    assert outside.sum() == 2 and np.isnan(result["modes"].values[outside]).all()
    assert (status[outside] == status[outside][0]).all() and (status[~outside] != status[outside][0]).all()


def test_an_unknown_limit_names_actuated_and_passive_choices():
    name, index = CASES[0]
    actuated = parakin.metadata(name).actuated[index].name
    with pytest.raises(parakin.BadInputError, match=actuated) as error:
        parakin.load(name, limits={actuated.upper(): (0.0, 1.0)})
    assert not isinstance(error.value, parakin.UnknownMechanismError)


def test_a_sweep_keeps_the_passive_limits_of_the_mechanism_it_was_given():
    """A sweep's workers once reloaded the package's defaults, dropping ``load(limits=...)``: the
    reachable map of a mechanism with a narrowed passive joint must be its own inverse validity."""
    for name in parakin.available():
        manifest = parakin.metadata(name)
        if (
            manifest.pose_kind in ("planar", "planar_translation")
            and manifest.capabilities.inverse
            and manifest.passive
        ):
            break
    else:
        pytest.skip("no planar mechanism with passive joints")
    free = parakin.load(name, backend="numpy")
    passive = free.passive_names[0]
    home = free.home_passive[0]
    limited = parakin.load(name, backend="numpy", limits={passive: (home - 0.05, home + 0.05)})
    x = np.linspace(-0.2, 0.2, 9) + free.forward_pose(free.home_actuated).pose[0, 3]
    y = np.linspace(-0.2, 0.2, 9) + free.forward_pose(free.home_actuated).pose[1, 3]
    fixed = {"phi": 0.0} if manifest.pose_kind == "planar" else {}
    swept = sweep(limited, ["reachable"], {"x": x, "y": y}, fixed=fixed)["reachable"].values
    grid = np.stack(np.meshgrid(x, y, indexing="ij"), -1)
    pose = np.broadcast_to(np.eye(4), grid.shape[:-1] + (4, 4)).copy()
    pose[..., 0, 3], pose[..., 1, 3] = grid[..., 0], grid[..., 1]
    expected = limited.inverse_pose(pose, strict=False).valid.any(-1)
    unlimited = free.inverse_pose(pose, strict=False).valid.any(-1)
    assert (expected != unlimited).sum() >= 5, "the narrowed limit must change the map for the check to bite"
    assert np.array_equal(np.asarray(swept, dtype=bool), expected)
