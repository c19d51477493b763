"""The compiled backend's flags (issue 33): where the CPU has AVX2 the library is built with it
(``compiled.WIDE_FLAGS``), which must not change one bit of any result: the wide build of a
homotopy package against the plain build (``compiled.FLAGS``, the reference), forward_pose_all on
inputs around the home, every output array compared bit for bit."""

from __future__ import annotations

import os
import shutil

import numpy as np
import pytest

import parakin
from parakin.packages import compiled
from parakin.studies.sampling import sample_configurations

NAME = "tricept"  # the smallest package with a path tracker: quick to compile
pytestmark = pytest.mark.skipif(shutil.which(os.environ.get("CC", "cc")) is None, reason="no C compiler")


def test_the_flags_name_the_library(tmp_path, monkeypatch):
    monkeypatch.setenv("PARAKIN_CACHE", str(tmp_path))
    package = parakin.load(NAME, backend="numpy").package
    monkeypatch.setattr(compiled, "_has_avx2", lambda: False)
    plain = compiled.library_target(package)
    monkeypatch.setattr(compiled, "_has_avx2", lambda: True)
    wide = compiled.library_target(package)
    assert plain[1] == compiled.FLAGS and wide[1] == [*compiled.FLAGS, *compiled.WIDE_FLAGS]
    assert plain[2] != wide[2] and plain[2].parent == wide[2].parent == tmp_path


@pytest.mark.skipif(not compiled._has_avx2(), reason="this CPU has no AVX2")
def test_the_wide_build_gives_the_plain_builds_bits(tmp_path, monkeypatch):
    wide = parakin.load(NAME, backend="compiled")  # the usual cache's library (other tests build it too)
    monkeypatch.setenv("PARAKIN_CACHE", str(tmp_path))
    monkeypatch.setattr(compiled, "_has_avx2", lambda: False)
    plain = parakin.load(NAME, backend="compiled")
    assert len(list(tmp_path.glob(f"{NAME}-*.so"))) == 1  # built here with the plain flags
    inputs = np.asarray(sample_configurations(plain, 24, seed=5, spread=0.05).actuated)
    assert len(inputs) >= 20
    checked = 0
    for theta in inputs:
        a, b = plain.forward_pose_all(theta, strict=False), wide.forward_pose_all(theta, strict=False)
        for field in ("passive", "poses", "residual", "conditioning"):
            assert np.array_equal(getattr(a, field), getattr(b, field), equal_nan=True), field
        checked += int(a.count)
    assert checked >= 40
