"""The compiled backend's kernel call (issue 33): the short way taken for the solvers' usual
inputs (``CompiledBackend.call``: the thread's pointer arrays filled in place, addresses through
the buffer protocol, a read-only parameter vector's address remembered) gives, bit for bit, what
the broadcasting way gives, and the generated NumPy kernels' values (an independent evaluation of
the same expressions); each thread's call stays its own."""

from __future__ import annotations

import threading

import numpy as np
import pytest

import parakin


@pytest.fixture(scope="module")
def sam() -> tuple[parakin.Mechanism, parakin.Mechanism]:
    return parakin.load("sam", backend="compiled"), parakin.load("sam", backend="numpy")


def shapes_of_inputs(rng: np.random.Generator) -> list[tuple[str, tuple[np.ndarray, np.ndarray]]]:
    """(label, (actuated, passive)) in every form a caller passes: one state, a batch, one row,
    a batch with one shared side, views that are not contiguous, integers, a (2, 3) batch."""
    batch_a, batch_p = rng.uniform(-1, 1, (7, 6)), np.abs(rng.uniform(0.3, 1.0, (7, 6)))
    return [
        ("one state", (batch_a[0].copy(), batch_p[0].copy())),
        ("batch", (batch_a, batch_p)),
        ("one row, 2-D", (batch_a[:1].copy(), batch_p[:1].copy())),
        ("batch and one shared", (batch_a, batch_p[2].copy())),
        ("shared and batch", (batch_a[3].copy(), batch_p)),
        ("one row beside a batch", (batch_a[:1].copy(), batch_p)),
        ("strided view", (batch_a[::2], batch_p[::2])),
        ("column view", (np.asfortranarray(batch_a), batch_p)),
        ("integers", (np.ones(6, dtype=np.int64), batch_p[0].copy())),
        ("read-only batch", (np.frombuffer(batch_a.tobytes()).reshape(7, 6), batch_p)),
        ("(2, 3) batch", (batch_a[:6].reshape(2, 3, 6), batch_p[:6].reshape(2, 3, 6))),
    ]


@pytest.mark.parametrize("kernel", ["loop_closure", "platform_pose", "singularity_factors"])
def test_short_call_equals_broadcast_call_and_numpy_kernels(sam, kernel: str) -> None:
    compiled, numpy_model = sam
    backend = compiled.backend
    rng = np.random.default_rng(5)
    checked = 0
    for label, (actuated, passive) in shapes_of_inputs(rng):
        got = backend.call(kernel, actuated, passive, compiled.params)
        broadcast = backend._call_broadcast(kernel, (actuated, passive, compiled.params))
        reference = numpy_model.backend.call(kernel, actuated, passive, numpy_model.params)
        assert got.keys() == broadcast.keys() == reference.keys()
        for name, value in got.items():
            assert value.shape == broadcast[name].shape == np.shape(reference[name]), (label, name)
            assert value.tobytes() == broadcast[name].tobytes(), (label, name)
            np.testing.assert_allclose(value, reference[name], rtol=1e-12, atol=1e-12, err_msg=f"{label} {name}")
            checked += 1
    assert checked >= 11  # every form of input, every output


def test_outputs_are_fresh_and_parameters_read_again(sam) -> None:
    """Each call allocates its outputs (a later call never writes into an earlier answer), and a
    read-only parameter vector whose address is remembered is the one passed: another vector
    with other values gives the other values' closure (compared with the NumPy kernels)."""
    compiled, numpy_model = sam
    backend = compiled.backend
    rng = np.random.default_rng(8)
    actuated, passive = rng.uniform(-1, 1, 6), np.abs(rng.uniform(0.3, 1.0, 6))
    first = backend.call("loop_closure", actuated, passive, compiled.params)
    kept = {name: value.copy() for name, value in first.items()}
    backend.call("loop_closure", actuated + 0.1, passive, compiled.params)
    for name, value in first.items():
        assert value.tobytes() == kept[name].tobytes(), name
    checked = 0
    for scale in (0.9, 1.1, 1.3):
        other = np.array(compiled.params) * scale
        other.flags.writeable = False
        got = backend.call("loop_closure", actuated, passive, other)
        expected = numpy_model.backend.call("loop_closure", actuated, passive, other)
        np.testing.assert_allclose(got["residual"], expected["residual"], rtol=1e-12, atol=1e-12)
        assert np.abs(got["residual"] - first["residual"]).max() > 1e-6  # the other geometry's answer
        checked += 1
    assert checked == 3


def test_threads_call_side_by_side(sam) -> None:
    """Four threads call the same kernel at once, each with its own inputs, many times: every
    answer equals that thread's answer computed alone (each thread fills its own pointer arrays)."""
    compiled, _ = sam
    backend = compiled.backend
    rng = np.random.default_rng(9)
    inputs = [(rng.uniform(-1, 1, (3, 6)), np.abs(rng.uniform(0.3, 1.0, (3, 6)))) for _ in range(4)]
    alone = [backend.call("loop_closure", a, p, compiled.params)["residual"].copy() for a, p in inputs]
    wrong: list[int] = []
    done: list[int] = []

    def work(k: int) -> None:
        a, p = inputs[k]
        for _ in range(300):
            if backend.call("loop_closure", a, p, compiled.params)["residual"].tobytes() != alone[k].tobytes():
                wrong.append(k)
        done.append(k)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert sorted(done) == [0, 1, 2, 3] and not wrong
