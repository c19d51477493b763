"""Backend parity: generated NumPy, CasADi (interpreted), compiled C and an exact SymPy
evaluation of the derived expressions agree to 1e-12."""

import numpy as np
import pytest
import sympy as sp

import parakin
from parakin.pose import pose_vector


@pytest.fixture(scope="module")
def backends():
    return {name: parakin.load("sam", backend=name) for name in ["numpy", "casadi", "compiled"]}


@pytest.fixture(scope="module")
def state():
    rng = np.random.default_rng(12)
    return rng.uniform(-1, 1, (5, 6)), np.abs(rng.uniform(0.3, 1.0, (5, 6)))


@pytest.mark.parametrize("kernel", ["platform_pose", "loop_closure", "leg_jacobians", "singularity_factors"])
def test_state_kernels_agree(backends, state, kernel):
    actuated, passive = state
    reference = backends["numpy"].backend.call(kernel, actuated, passive, backends["numpy"].params)
    for name in ["casadi", "compiled"]:
        other = backends[name].backend.call(kernel, actuated, passive, backends[name].params)
        for output, value in reference.items():
            assert np.abs(other[output] - value).max() < 1e-12, (name, output)


def test_inverse_and_forward_polynomial_agree(backends, state):
    actuated, _ = state
    pose = parakin.pose_from_xyz_euler([0.02, 0.03, 0.68, 0.1, 0.05, 0.08])
    results = {name: m.inverse_pose(pose) for name, m in backends.items()}
    polynomials = {name: m.backend.call("forward_polynomial", actuated, m.params) for name, m in backends.items()}
    for name in ["casadi", "compiled"]:
        assert np.abs(results[name].actuated - results["numpy"].actuated).max() < 1e-12
        assert np.abs(results[name].passive - results["numpy"].passive).max() < 1e-12
        scale = np.abs(polynomials["numpy"]["coefficients"]).max()
        assert np.abs(polynomials[name]["coefficients"] - polynomials["numpy"]["coefficients"]).max() < 1e-12 * scale


def test_exact_sympy_evaluation_agrees(backends, state):
    """The derived SymPy objects, evaluated in 30-digit arithmetic, against every backend."""
    symbolic = parakin.symbolic("sam")
    info = parakin.metadata("sam")
    actuated, passive = state
    names = info.actuated_names + info.passive_names + [p.name for p in info.parameters]
    symbols = {s.name: s for obj in symbolic.values() if isinstance(obj, sp.Basic) for s in obj.free_symbols}
    values = np.concatenate([actuated[0], passive[0], [p.default for p in info.parameters]])
    substitution = {symbols[n]: sp.Float(v, 30) for n, v in zip(names, values, strict=True) if n in symbols}
    exact_pose = np.array(symbolic["platform_pose"].evalf(30, subs=substitution), dtype=float)
    exact_left = np.array(symbolic["leg_jacobian_left"].evalf(30, subs=substitution), dtype=float)
    exact_residual = np.array(symbolic["loop_closure"].evalf(30, subs=substitution), dtype=float)[:, 0]
    for m in backends.values():
        assert np.abs(m.platform_pose(actuated[0], passive[0]) - exact_pose).max() < 1e-12
        assert (
            np.abs(
                m.leg_jacobians(parakin.Configuration(actuated[0], passive[0], exact_pose))["left"] - exact_left
            ).max()
            < 1e-12
        )
        assert np.abs(m.loop_closure(actuated[0], passive[0])["residual"] - exact_residual).max() < 1e-12


def test_newton_paths_agree(backends):
    pose = parakin.pose_from_xyz_euler([[0.02, 0.03, 0.68, 0.1, 0.05, 0.08], [-0.05, 0.1, 0.6, -0.2, 0.1, 0.3]])
    config = backends["numpy"].inverse_pose(pose).branch(2)
    guess = config.passive + 0.02
    results = {name: m.forward_pose(config.actuated, guess=guess) for name, m in backends.items()}
    for name in ["casadi", "compiled"]:
        assert np.abs(results[name].pose - results["numpy"].pose).max() < 1e-12
        assert (results[name].iterations == results["numpy"].iterations).all()


def test_compiled_functions_load_through_casadi_external(backends):
    compiled = backends["compiled"].backend
    function = compiled.external("platform_pose")
    actuated, passive = np.full(6, 0.1), np.full(6, 0.5)
    value = np.array(function(actuated, passive, backends["compiled"].params))
    assert np.abs(value - backends["numpy"].platform_pose(actuated, passive)).max() < 1e-14
    assert function.name_in() == ["actuated", "passive", "params"]


def test_pose_vector_layout():
    pose = parakin.pose_from_xyz_euler([1, 2, 3, 0.1, 0.2, 0.3])
    vector = pose_vector(pose)
    assert vector[:9] == pytest.approx(pose[:3, :3].ravel()) and vector[9:] == pytest.approx([1, 2, 3])


def test_single_input_newton_is_thread_safe(backends):
    """forward_pose on one input reuses a buffer per thread; threads must not see each other's."""
    from concurrent.futures import ThreadPoolExecutor

    m = backends["compiled"]
    poses = parakin.pose_from_xyz_euler(
        np.column_stack([np.linspace(-0.1, 0.1, 64), np.zeros(64), np.full(64, 0.7), np.full((64, 3), 0.1)])
    )
    configs = m.inverse_pose(poses).branch(2)

    def solve(i):
        return m.forward_pose(configs.actuated[i], guess=configs.passive[i] + 0.01).pose

    with ThreadPoolExecutor(4) as pool:
        results = list(pool.map(solve, range(64)))
    assert max(np.abs(r - p).max() for r, p in zip(results, poses, strict=True)) < 1e-10
