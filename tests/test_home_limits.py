"""Angles from the inverse and ``home_at`` in one range, and a home outside its limits refused at
generation (issue 31, item 6).

``DistanceMechanism.home_at`` returned crank angles in (-2 pi, 2 pi] (5.9507 for -0.3325 rad: the
tangent-half-angle form 2 atan2(Y, X)) while ``inverse_pose`` wraps them to (-pi, pi]; and the
generator accepted a home outside the declared limits, so the package's own home was refused by
``plot`` and ``forward_pose_all``. Now the crank inverse is written atan2(2 X Y, X^2 - Y^2), in
(-pi, pi] itself, ``home_at`` wraps what it reads, and ``check_variables`` refuses such a home
naming the value, its unit and the limits.
"""

from __future__ import annotations

import dataclasses
import math
import random
import subprocess
import sys
import textwrap

import numpy as np
import pytest
import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import half_angle_solution
from parakin.generator.build import generate_file
from parakin.generator.checks import check_variables
from parakin.generator.errors import GenerationError
from parakin.generator.model import Mechanism
from parakin.mechanisms import five_bar, planar_3rrr

import parakin


def test_crank_angles_are_in_the_runtime_range_and_solve_the_same_equation():
    """On random E, F, G (reachable: E^2 + F^2 > G^2) and both signs: the angle is in (-pi, pi],
    solves E cos + F sin + G = 0 and equals the tangent-half-angle form modulo 2 pi; among them
    are cases the old form put beyond pi (5.9507 for -0.3325 rad)."""
    e, f, g, sign = sp.symbols("E F G sigma", real=True)
    new, _ = joints.crank_angle(e, f, g, sign)
    old, _ = half_angle_solution(e, f, g, sign)
    new_fn, old_fn = sp.lambdify((e, f, g, sign), new), sp.lambdify((e, f, g, sign), old)
    rng = random.Random(31)
    beyond = 0
    for _ in range(2000):
        ev, fv = rng.uniform(-1, 1), rng.uniform(-1, 1)
        gv = rng.uniform(-1, 1) * math.hypot(ev, fv)
        for s in (1, -1):
            angle, before = new_fn(ev, fv, gv, s), old_fn(ev, fv, gv, s)
            assert -math.pi < angle <= math.pi
            assert abs(ev * math.cos(angle) + fv * math.sin(angle) + gv) < 1e-12
            assert abs(math.remainder(angle - before, 2 * math.pi)) < 1e-12
            beyond += abs(before) > math.pi
    assert beyond > 100


def test_home_at_and_the_inverse_agree_with_the_runtime_range():
    """planar_3rrr's home read by its inverse was theta2 = 4.1262 rad (inverse_pose says -2.1569);
    every crank mechanism's home, from ``home_at`` or the inverse, is now in (-pi, pi], and
    ``home_at`` gives what the runtime's ``inverse_pose`` gives for the same pose and branch."""
    home = planar_3rrr.home()
    assert all(-math.pi < home[t] <= math.pi for t in planar_3rrr.theta)
    assert home[planar_3rrr.theta[1]] == pytest.approx(4.126249442989899 - 2 * math.pi, abs=1e-12)
    pose = sp.Matrix(planar_3rrr.pose_list(0.02, -0.03, 0.4))
    m = parakin.load("planar_3rrr", backend="numpy")
    ik = m.inverse_pose(np.array(pose.tolist(), dtype=float), strict=False)
    for branch in range(len(ik.valid)):
        if not ik.valid[branch]:
            continue
        read = planar_3rrr.MODEL.home_at(pose[:3, :3], pose[:3, 3], branch, planar_3rrr.defaults())
        assert np.allclose([read[t] for t in planar_3rrr.theta], ik.actuated[branch], atol=1e-12, rtol=0)
        assert all(-math.pi < read[t] <= math.pi for t in planar_3rrr.theta)


def test_every_shipped_home_is_within_its_limits_and_angles_in_range():
    for name in parakin.available():
        m = parakin.metadata(name)
        for variable in (*m.actuated, *m.passive):
            if variable.home is None:
                continue
            low, high = variable.limits
            assert (low is None or low <= variable.home) and (high is None or variable.home <= high), (name, variable)
            if variable.revolute:
                assert -math.pi < variable.home <= math.pi, (name, variable.name, variable.home)


def five_bar_with(home: float) -> Mechanism:
    """The five-bar with limits [-pi, pi] on theta1 and ``home`` as its home value."""
    m = five_bar.build()
    theta1 = five_bar.theta[0]
    return dataclasses.replace(m, limits={theta1: (-math.pi, math.pi)}, home={**m.home, theta1: home})


def test_a_home_outside_its_limits_is_refused_with_the_value_and_the_limits():
    with pytest.raises(GenerationError) as refused:
        check_variables(five_bar_with(5.9507))
    message = str(refused.value)
    assert "home value theta1 = 5.9507 rad is outside its limits [-3.1416, 3.1416]" in message
    assert "-0.3325 rad, is inside" in message  # the same angle, as it should be written
    check_variables(five_bar_with(-0.3325))  # inside: accepted
    check_variables(five_bar_with(math.pi))  # on a limit: accepted
    prismatic = dataclasses.replace(five_bar.build(), limits={five_bar.x: (-0.1, 0.1)})
    with pytest.raises(GenerationError, match=r"home value x = 0\.2000 m is outside its limits \[-0\.1000, 0\.1000\]"):
        check_variables(dataclasses.replace(prismatic, home={**prismatic.home, five_bar.x: 0.2}))


MECHANISM_FILE = '''
"""The five-bar with a home outside its limits (a test of parakin generate)."""

import dataclasses
import math

from parakin.mechanisms import five_bar


def build():
    m = five_bar.build()
    theta1 = five_bar.theta[0]
    return dataclasses.replace(
        m, name="my_robot", limits={theta1: (-math.pi, math.pi)}, home={**m.home, theta1: 5.9507}
    )
'''


def test_generate_refuses_a_home_outside_its_limits_before_writing(tmp_path):
    """`parakin generate` names the value and the limits, exits 2, and writes nothing."""
    source = tmp_path / "my_robot.py"
    source.write_text(textwrap.dedent(MECHANISM_FILE))
    with pytest.raises(GenerationError, match=r"home value theta1 = 5\.9507 rad is outside its limits"):
        generate_file(source, tmp_path / "package")
    done = subprocess.run(
        [sys.executable, "-m", "parakin", "generate", str(source), "--out", str(tmp_path / "package")],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2
    assert "home value theta1 = 5.9507 rad is outside its limits [-3.1416, 3.1416]" in done.stderr
    assert not (tmp_path / "package").exists()
