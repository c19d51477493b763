"""A loaded mechanism's model is fixed (issue 33 item 5: an immutable model): assigning to its
parameters, limits or actuator ranges raises FixedModelError (it changed nothing before: the
solvers had read them at load time, an ignored option), and its parameter vector is read-only;
another model is loaded with other values, and copies and pickles keep the values and the rule."""

from __future__ import annotations

import copy
import json
import pickle

import numpy as np
import pytest

import parakin
from parakin import FixedModelError


def test_assignments_to_a_loaded_model_are_refused():
    m = parakin.load("five_bar", backend="numpy")
    d = m.parameters["d"]

    def gap(mechanism):
        return np.abs(mechanism.loop_closure(m.home_actuated, m.home_passive)["residual"]).max()

    assert gap(m) < 1e-12
    with pytest.raises(FixedModelError, match="parakin.load"):
        m.parameters["d"] = 0.3
    with pytest.raises(FixedModelError):
        m.parameters.update(d=0.3)
    with pytest.raises(FixedModelError):
        m.limits["x"] = (0.0, 1.0)
    with pytest.raises(FixedModelError):
        m.actuated_ranges.pop("theta1")
    with pytest.raises(ValueError, match="read-only"):
        m.params[0] = 0.3
    with pytest.raises(FixedModelError, match="five_bar.parameters is fixed"):
        m.parameters = {"d": 0.3}
    with pytest.raises(FixedModelError):
        m.params = np.zeros(5)
    assert m.parameters["d"] == d and m.params[m.manifest.parameter_names.index("d")] == d
    assert gap(m) < 1e-12
    wider = parakin.load("five_bar", backend="numpy", d=d + 0.01)  # the way to other values
    assert wider.parameters["d"] == d + 0.01 and gap(wider) > 1e-3


def test_the_fixed_values_read_copy_and_serialise_as_a_dict():
    m = parakin.load("five_bar", backend="numpy")
    assert json.loads(json.dumps(m.parameters)) == dict(m.parameters)
    for twin in (copy.deepcopy(m.parameters), pickle.loads(pickle.dumps(m.parameters))):
        assert twin == m.parameters
        with pytest.raises(FixedModelError):
            twin["d"] = 1.0
    assert {**m.parameters, "d": 1.0}["d"] == 1.0  # a new dict is the caller's
