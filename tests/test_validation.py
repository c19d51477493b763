"""Every input answered: the defects of the reliability review, each with the result or the named
error it now gets, on every backend where it applies."""

from __future__ import annotations

import warnings

import contract_helpers as h
import numpy as np
import pytest

import parakin
from parakin.studies.sampling import sample_configurations

BACKENDS = ["compiled", "numpy", "casadi"]
WITH_AB_RATES = [n for n in parakin.available() if parakin.metadata(n).capabilities.rates is not None]


def _load(name: str, backend: str = "compiled", **parameters) -> parakin.Mechanism:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", parakin.ArchitectureSingularityWarning)
        return parakin.load(name, backend=backend, **parameters)


@pytest.mark.parametrize(
    ("name", "parameters", "message"),
    [
        ("sphere2r", {"alpha1": float("nan")}, "must be finite"),
        ("sphere2r", {"alpha1": float("inf")}, "must be finite"),
        ("sps", {"chi": 0}, r"must be \+1 or -1"),
        ("sps", {"b12": -1.0}, "must be > 0"),
        ("sam", {"L1": "0.1"}, "must be a real number"),
        ("sam", {"L1": 1j}, "must be a real number"),
        ("planar_3rpr", {"base": [[0, 0], [1, 0], [np.nan, 1]]}, "non-finite"),
        ("gough", {"t11": 0.0}, "must be != 0"),
    ],
)
def test_bad_parameters_are_refused_at_load(name, parameters, message):
    with pytest.raises(parakin.BadInputError, match=message):
        _load(name, **parameters)


def test_bad_joint_limits_are_refused_at_load():
    with pytest.raises(parakin.BadInputError, match="low < high"):
        parakin.load("sam", limits={"L2": (1.0, 0.5)})
    with pytest.raises(parakin.BadInputError, match="pair"):
        parakin.load("sam", limits={"L2": 0.5})
    with pytest.raises(parakin.BadInputError, match="finite"):
        parakin.load("sam", limits={"L2": (float("nan"), 1.0)})


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize(
    "value",
    [
        np.array([0.1, 0.2, 0.3, 0.1, 0.2, 0.3]) + 1e-3j,
        ["0.1", "0.2", "0.3", "0.1", "0.2", "0.3"],
        np.array([0.1] * 6, dtype=object),
        [True, False, True, False, True, False],
        "0.1 0.2",
        None,
        [[0.1, 0.2], [0.3]],
    ],
)
def test_non_real_inputs_are_refused(backend, value):
    m = _load("sam", backend)
    with pytest.raises(parakin.BadInputError):
        m.forward_pose(value)


@pytest.mark.parametrize("backend", BACKENDS)
def test_actuated_values_outside_their_range_are_refused(backend):
    """Leg lengths are declared >= 0: a negative one is no input, on every solver."""
    m = _load("planar_3rpr", backend)
    with pytest.raises(parakin.BadInputError, match=r"rho3 = -1.* outside its range \[0, 1e\+09\]"):
        m.forward_pose_all([17.5, 13.7, -1.0])
    with pytest.raises(parakin.BadInputError, match="at batch index"):
        m.forward_pose([[17.5, 13.7, 1.0], [17.5, 13.7, -1.0]])


def test_rotation_helper_refuses_non_finite_angles():
    with pytest.raises(parakin.BadInputError, match="alpha"):
        parakin.euler_zyx_to_rotation(np.inf, 0.0, 0.0)
    with pytest.raises(parakin.BadInputError):
        parakin.euler_zyx_to_rotation(0.0, 1j, 0.0)


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize(
    ("option", "value"),
    [
        ("max_iterations", 2**32 + 3),
        ("max_iterations", -1),
        ("max_iterations", 3.5),
        ("tolerance", -1e-12),
        ("tolerance", float("nan")),
        ("max_step", 0.0),
    ],
)
def test_newton_options_are_checked_the_same_on_every_backend(backend, option, value):
    m = _load("sam", backend)
    with pytest.raises(parakin.BadInputError, match=option):
        m.forward_pose(m.home_actuated, **{option: value})


@pytest.mark.parametrize("backend", BACKENDS)
def test_forward_pose_results_have_the_same_types_on_every_backend(backend):
    m = _load("sam", backend)
    sample = sample_configurations(m, 3, seed=4)
    one = m.forward_pose(sample.actuated[0], guess=sample.passive[0])
    assert isinstance(one.residual, np.ndarray) and one.residual.shape == ()
    assert isinstance(one.iterations, np.ndarray) and one.iterations.shape == ()
    many = m.forward_pose(sample.actuated, guess=sample.passive)
    assert many.residual.shape == (3,) and many.passive.shape == (3, 6)


@pytest.mark.parametrize("name", WITH_AB_RATES)
@pytest.mark.parametrize("backend", ["compiled", "numpy"])
def test_damping_is_honoured_by_every_rate_model(name, backend):
    """inverse_rate(damping=l) = B^T (B B^T + l^2 I)^-1 A twist, computed here independently by
    a regularised least-squares solve, and it tends to the exact rates as l -> 0."""
    m = _load(name, backend)
    state = sample_configurations(m, 4, seed=3)
    if state.actuated.shape[0] == 0:
        pytest.skip(f"{name}: no closed configuration near home with default parameters")
    rng = np.random.default_rng(1)
    twist = h.feasible_twist(m, state, rng.standard_normal(state.actuated.shape[:-1] + (m.manifest.twist_size,)))
    jacobians = m.rate_jacobians(state)
    exact = m.inverse_rate(state, twist)
    for damping in (1e-1, 1e-3):
        damped = m.inverse_rate(state, twist, damping=damping)
        for k in range(state.actuated.shape[0]):
            a, b = jacobians["a"][k], jacobians["b"][k]
            n = b.shape[1]
            # min |B x - A w|^2 + l^2 |x|^2, as a stacked least-squares problem
            stacked = np.vstack([b, damping * np.eye(n)])
            target = np.concatenate([a @ twist[k], np.zeros(n)])
            expected = np.linalg.lstsq(stacked, target, rcond=None)[0]
            np.testing.assert_allclose(damped.actuated[k], expected, rtol=1e-8, atol=1e-10)
        assert not np.allclose(damped.actuated, exact.actuated, rtol=1e-12, atol=0)
    np.testing.assert_allclose(m.inverse_rate(state, twist, damping=1e-9).actuated, exact.actuated, rtol=1e-6)


@pytest.mark.parametrize("damping", [float("nan"), -1.0, 0.0, "0.1"])
def test_bad_damping_is_refused(damping):
    m = _load("spm")
    state = sample_configurations(m, 1, seed=3)
    with pytest.raises(parakin.BadInputError, match="damping"):
        m.inverse_rate(state, np.zeros((1, 3)), damping=damping)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_batch_of_twists_broadcasts_against_one_state(backend):
    m = _load("sam", backend)
    sample = sample_configurations(m, 1, seed=4)
    state = parakin.Configuration(sample.actuated[0], sample.passive[0], sample.pose[0])
    twists = np.random.default_rng(2).standard_normal((5, 6)) * 0.01
    batched = m.inverse_rate(state, twists)
    assert batched.actuated.shape == (5, 6)
    for k in range(5):
        np.testing.assert_allclose(batched.actuated[k], m.inverse_rate(state, twists[k]).actuated, rtol=1e-12)


def test_missing_capabilities_raise_one_named_error():
    spm = _load("spm")
    state = sample_configurations(spm, 1, seed=3)
    with pytest.raises(parakin.UnsupportedOperationError, match="leg_jacobians"):
        spm.leg_jacobians(state)
    sam = _load("sam")
    with pytest.raises(parakin.UnsupportedOperationError, match="rate_jacobians"):
        sam.rate_jacobians(sample_configurations(sam, 1, seed=4))


@pytest.mark.parametrize("backend", BACKENDS)
def test_one_pose_guess_broadcasts_against_a_batch_of_inputs(backend):
    m = _load("sam", backend)
    sample = sample_configurations(m, 4, seed=4)
    solved = m.forward_pose(sample.actuated, guess=sample.pose[0], strict=False)
    assert solved.passive.shape == sample.passive.shape
    np.testing.assert_allclose(solved.passive[0], sample.passive[0], atol=1e-9)
