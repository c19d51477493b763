"""parakin.singularity: the one distance to singularity (1/cond) and the one NEAR_SINGULAR level
that plot labels, sweep maps and the MJCF export warns by. Checked against NumPy's ``cond`` and
closed-form singular values; a batch gives what its configurations give one at a time, and a
sweep's map what the plot's label gives at the same configuration."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import parakin
from parakin.errors import BadInputError
from parakin.results import Configuration
from parakin.singularity import (
    NEAR_SINGULAR,
    inverse_condition,
    is_near_singular,
    singularity_distance,
    singularity_distances,
    type_i_distance,
    type_ii_distance,
)

ROOT = Path(__file__).resolve().parent.parent


def _stacked(configurations: list[Configuration]) -> Configuration:
    return Configuration(*(np.stack([getattr(c, p) for c in configurations]) for p in ("actuated", "passive", "pose")))


def test_inverse_condition_is_one_over_numpys_cond_over_any_batch_shape():
    """sigma_min / sigma_max against numpy.linalg.cond on a (3, 4) batch of 5x5 matrices of
    scales 1e-3 to 1e3, and closed forms: diag(2, 0.5) -> 0.25, a scaled rotation -> 1, a rank-one
    or zero matrix -> 0; NaN for a matrix with a non-finite entry, the others unaffected."""
    rng = np.random.default_rng(7)
    matrices = rng.normal(size=(3, 4, 5, 5)) * 10.0 ** rng.uniform(-3, 3, size=(3, 4, 1, 1))
    measured = inverse_condition(matrices)
    assert measured.shape == (3, 4)
    np.testing.assert_allclose(measured, 1 / np.linalg.cond(matrices), rtol=1e-12)
    angle = 0.3
    rotation = 7.0 * np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    closed = np.array([np.diag([2.0, 0.5]), rotation, np.zeros((2, 2)), [[np.inf, 0.0], [0.0, 1.0]]])
    values = inverse_condition(closed)
    assert values[0] == 0.25 and abs(values[1] - 1.0) < 1e-15 and values[2] == 0.0 and np.isnan(values[3])
    assert inverse_condition([[1.0, 2.0], [2.0, 4.0]]) < 1e-16  # rank one: 0 to rounding
    # a rectangular matrix (a rate model's B of 3 twists by 2 inputs): its two singular values
    assert inverse_condition(np.array([[3.0, 0.0], [0.0, 1.5], [0.0, 0.0]])) == 0.5
    with pytest.raises(BadInputError, match=r"matrices \(\.\.\., r, c\), got shape \(3,\)"):
        inverse_condition(np.ones(3))


def test_a_batch_of_modes_gives_what_each_mode_gives_alone_and_numpys_cond():
    """planar_3rpr's 6 assembly modes of its home input: the batched measures equal the
    one-at-a-time ones bit for bit, and 1/numpy.linalg.cond of the Jacobians the mechanism's
    public methods return (the closure's, the rate model's B) to 1e-12; the near-singular verdicts
    follow from those NumPy numbers alone."""
    m = parakin.load("planar_3rpr", backend="numpy")
    modes = m.forward_pose_all(m.home_actuated)
    configurations = [modes.mode(k) for k in range(int(modes.count))]
    assert len(configurations) == 6
    batch = singularity_distances(m, _stacked(configurations))
    assert list(batch) == ["type II", "type I"] and batch["type II"].shape == (6,)
    alone = [singularity_distance(m, c) for c in configurations]
    for name in ("type II", "type I"):
        assert batch[name].tolist() == [d[name] for d in alone]
    numpy_ii = [1 / np.linalg.cond(m.loop_closure(c.actuated, c.passive)["jacobian"]) for c in configurations]
    numpy_i = [1 / np.linalg.cond(m.rate_jacobians(c)["b"]) for c in configurations]
    np.testing.assert_allclose(batch["type II"], numpy_ii, rtol=1e-12)
    np.testing.assert_allclose(batch["type I"], numpy_i, rtol=1e-12)
    near = [is_near_singular(d) for d in alone]
    assert near == [value < NEAR_SINGULAR for value in numpy_ii]
    assert 0 < sum(near) < 6  # both verdicts occur (modes 2 and 3 are near-singular)


def test_type_i_of_serial_legs_is_the_worst_legs_inverse_condition():
    """SAM (two serial legs, no rate model): type I is the smaller 1/cond of the two 6x6 leg
    Jacobians, against numpy.linalg.cond of each."""
    m = parakin.load("sam", backend="numpy")
    home = m.forward_pose(m.home_actuated)
    legs = m.leg_jacobians(home)
    assert sorted(legs) == ["left", "right"]
    expected = min(1 / np.linalg.cond(j) for j in legs.values())
    assert abs(float(type_i_distance(m, home)) - expected) <= 1e-12 * expected
    assert m.capabilities.rates is None and 0 < expected < 1


def test_a_measure_the_mechanism_lacks_is_left_out_and_a_refused_state_named():
    """sphere2r (no passive joints, no rate model, no legs) has neither measure; a state outside
    the actuated ranges is refused by the batched measures (BadInputError naming the actuator)
    and gives no label."""
    sphere = parakin.load("sphere2r", backend="numpy")
    state = sphere.forward_pose(sphere.home_actuated)
    assert type_ii_distance(sphere, state) is None and type_i_distance(sphere, state) is None
    assert singularity_distances(sphere, state) == {} and singularity_distance(sphere, state) == {}
    m = parakin.load("five_bar", backend="numpy")
    home = m.forward_pose(m.home_actuated)
    low, _ = m.actuated_bounds
    outside = Configuration(np.array([low[0] - 1.0, home.actuated[1]]), home.passive, home.pose)
    with pytest.raises(BadInputError, match=m.actuated_names[0]):
        type_ii_distance(m, outside)
    with pytest.raises(BadInputError, match="must be a Configuration"):
        type_ii_distance(m, home.passive)  # type: ignore[arg-type]
    assert singularity_distance(m, outside) == {}
    assert not is_near_singular({}) and not is_near_singular({"type I": 0.0})


def test_a_sweep_map_holds_the_plot_labels_value_at_each_pose():
    """The five-bar's type II and type I maps on a 5 x 4 grid of tool points: at each reachable
    point, the value is the label ``singularity_distance`` gives the configuration of the first
    valid inverse branch there (the sweep's default branch), bit for bit; NaN where unreachable."""
    pytest.importorskip("xarray")
    pytest.importorskip("dask")
    m = parakin.load("five_bar", backend="numpy")
    xs, ys = np.linspace(-0.2, 0.2, 5), np.linspace(0.15, 0.35, 4)
    quantities = ["reachable", "type_ii_distance", "type_i_distance"]
    result = parakin.sweep(m, quantities, {"x": xs, "y": ys}, scheduler="synchronous")
    checked = 0
    for i, x in enumerate(xs):
        for j, y in enumerate(ys):
            inverse = m.inverse_pose([x, y], strict=False)
            if not bool(result.reachable.values[i, j]):
                assert np.isnan(result.type_ii_distance.values[i, j])
                continue
            low, high = m.actuated_bounds
            usable = inverse.valid & ((inverse.actuated >= low) & (inverse.actuated <= high)).all(-1)
            b = int(np.argmax(usable))
            label = singularity_distance(m, Configuration(inverse.actuated[b], inverse.passive[b], inverse.pose))
            assert result.type_ii_distance.values[i, j] == label["type II"]
            assert result.type_i_distance.values[i, j] == label["type I"]
            checked += 1
    assert checked >= 12


def test_one_level_defines_near_singular():
    """NEAR_SINGULAR is assigned in parakin/results.py only (the foundation: ill_conditioned() and
    the tracker read it; parakin.singularity re-exports it), and every consumer uses it."""
    defined = [
        path.relative_to(ROOT).as_posix()
        for path in sorted((ROOT / "parakin").rglob("*.py"))
        if "NEAR_SINGULAR" in path.read_text()  # parse only the files that name it
        for node in ast.walk(ast.parse(path.read_text()))
        if isinstance(node, ast.Assign | ast.AnnAssign)
        and any(
            isinstance(t, ast.Name) and t.id == "NEAR_SINGULAR"
            for t in (node.targets if isinstance(node, ast.Assign) else [node.target])
        )
    ]
    assert defined == ["parakin/results.py"], defined
    from parakin import mjcf
    from parakin.interfaces import plot
    from parakin.studies import atlas

    assert plot.NEAR_SINGULAR is atlas.NEAR_SINGULAR is mjcf.NEAR_SINGULAR is NEAR_SINGULAR == 0.02
