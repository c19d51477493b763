"""``forward_pose_all`` of a few inputs measures its modes' conditioning when it is first read
(issue 33: the SVD per mode is most of the Python around the C for one input, and a control
loop picking its mode never reads it). What is read is the type II distance at each mode, as
the Jacobian's condition number gives it independently, and the array an immediate measurement
gives, bit for bit; copies, pickles and threads each read the same."""

from __future__ import annotations

import copy
import pickle
import threading

import numpy as np
import pytest

import parakin
import parakin.mechanism

#: planar 3-RRR inputs (rad) with real modes (the paper example of test_planar_3rrr, and a step off it)
INPUTS = np.deg2rad([[-54.0, 174.0, -105.0], [-50.0, 170.0, -100.0]])


@pytest.fixture(scope="module")
def planar() -> parakin.Mechanism:
    return parakin.load("planar_3rrr", backend="compiled")


def test_read_conditioning_is_the_jacobians_inverse_condition_number(planar) -> None:
    checked = 0
    for theta in INPUTS:
        modes = planar.forward_pose_all(theta)
        assert "conditioning" in modes.__dict__["_deferred"]  # not measured yet
        conditioning = modes.conditioning
        assert "conditioning" not in modes.__dict__["_deferred"] and modes.conditioning is conditioning
        assert np.isnan(conditioning[~modes.valid]).all()
        for slot in np.flatnonzero(modes.valid):
            jacobian = planar.loop_closure(theta, modes.passive[slot])["jacobian"]
            expected = 1.0 / np.linalg.cond(jacobian)  # sigma_min / sigma_max, by NumPy's cond
            assert conditioning[slot] == pytest.approx(expected, rel=1e-10)
            checked += 1
    assert checked >= 4


def test_deferred_equals_measured_at_once(planar, monkeypatch) -> None:
    """The same inputs with the measurement made at once (a batch above DEFER_CONDITIONING):
    every field equal, conditioning bit for bit, for one input and for a (2,) batch."""
    deferred_one = [planar.forward_pose_all(theta) for theta in INPUTS]
    deferred_batch = planar.forward_pose_all(INPUTS)
    monkeypatch.setattr(parakin.mechanism, "DEFER_CONDITIONING", 0)
    at_once_one = [planar.forward_pose_all(theta) for theta in INPUTS]
    at_once_batch = planar.forward_pose_all(INPUTS)
    assert "_deferred" not in at_once_batch.__dict__
    for deferred, at_once in [*zip(deferred_one, at_once_one, strict=True), (deferred_batch, at_once_batch)]:
        assert deferred.conditioning.tobytes() == at_once.conditioning.tobytes()
        assert deferred.conditioning.shape == at_once.conditioning.shape
        assert deferred.valid.tobytes() == at_once.valid.tobytes()
    assert int(at_once_batch.count.sum()) >= 4


def test_copies_pickles_and_threads_read_the_same(planar) -> None:
    reference = planar.forward_pose_all(INPUTS[0]).conditioning
    original = planar.forward_pose_all(INPUTS[0])
    copied = copy.copy(original)
    assert copied.conditioning.tobytes() == reference.tobytes()  # the copy reads first
    assert original.conditioning.tobytes() == reference.tobytes()  # the original still can
    unread = planar.forward_pose_all(INPUTS[0])
    assert "conditioning" in unread.__dict__["_deferred"]
    restored = pickle.loads(pickle.dumps(unread))
    # the pickle holds the values, not the Jacobians: as small as a result read before pickling
    assert not restored.__dict__.get("_deferred") and restored.__dict__["conditioning"].tobytes() == reference.tobytes()
    read = planar.forward_pose_all(INPUTS[0])
    assert read.conditioning.tobytes() == reference.tobytes()
    assert len(pickle.dumps(planar.forward_pose_all(INPUTS[0]))) < 1.1 * len(pickle.dumps(read))  # no Jacobians
    shared = planar.forward_pose_all(INPUTS[0])
    read: list[bytes] = []
    threads = [threading.Thread(target=lambda: read.append(shared.conditioning.tobytes())) for _ in range(4)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert read == [reference.tobytes()] * 4
    with pytest.raises(AttributeError, match="conditionin"):
        _ = shared.conditionin  # a misspelt attribute is still no attribute
