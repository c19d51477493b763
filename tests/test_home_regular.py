"""A mechanism's default home near a type II (parallel) singularity is reported when the package
is generated (``generator.checks.check_home_regular``), by the measure ``parakin.singularity``
uses: sigma_min / sigma_max of d closure / d passive at the home.

The near-singular layout is a planar 3-RPR with similar base and platform triangles (joints at
90, 210, 330 deg on circles of 0.5 m and 0.2 m): at phi = 0 every leg line passes through the
centre, so the legs exert no moment about it and the platform can turn (Gosselin and Angeles'
type II); at a small phi the lines miss the centre by about r_b r_p sin(phi) / |leg|, so the
measure is first order in phi. Independent checks: the distance in the warning equals what the
generated package's own kernels give at its home (``type_ii_distance``), and halves with phi."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import circle_points, home_from_pose, parameter_fields, planar_pose_values, point_group
from parakin.generator.build import generate_file, load_definition
from parakin.generator.checks import (
    NEAR_SINGULAR_HOME,
    NearSingularHomeWarning,
    check_home_regular,
    home_type_ii_distance,
)
from parakin.generator.model import Citation, Mechanism

import parakin

ROOT = Path(__file__).resolve().parent.parent
ANGLES = [90.0, 210.0, 330.0]

#: the 3-RPR above as a mechanism file, its home at (0, 0, PHI)
NEAR_RPR = '''"""A planar 3-RPR whose leg lines meet at the centre when phi = 0."""
import sympy as sp
from parakin.generator import joints
from parakin.generator.blocks import circle_points, home_from_pose, parameter_fields, planar_pose_values, point_group
from parakin.generator.model import Citation, Mechanism

PHI = {phi!r}
ANGLES = [90.0, 210.0, 330.0]
base = point_group("base", circle_points(0.5, angles_deg=ANGLES, dims=2), "base joint A{{k}}, in {{B}}")
platform = point_group("platform", circle_points(0.2, angles_deg=ANGLES, dims=2), "platform joint c{{k}}, in {{P}}")
lengths = sp.symbols("l1:4", positive=True)
MODEL = joints.DistanceMechanism(
    joints.platform("planar"),
    [joints.prismatic_leg(a, c, n) for a, c, n in zip(base.points, platform.points, lengths, strict=True)],
)
PARAMETERS = parameter_fields(base, platform)


def build() -> Mechanism:
    return Mechanism(
        name="near_rpr",
        title="3-RPR near its type II singularity",
        citation=Citation(("A. User",), "A planar 3-RPR near a singularity", 2026),
        **PARAMETERS,
        **MODEL.fields(),
        home=home_from_pose(MODEL, planar_pose_values(0.0, 0.0, PHI), 0, PARAMETERS["parameters"]),
    )
'''


def _rpr(phi: float) -> tuple[Mechanism, sp.Matrix]:
    """The 3-RPR at home phi and its d closure / d passive, without generating it."""
    base = point_group("base", circle_points(0.5, angles_deg=ANGLES, dims=2), "A{k}")
    platform = point_group("platform", circle_points(0.2, angles_deg=ANGLES, dims=2), "c{k}")
    lengths = sp.symbols("l1:4", positive=True)
    model = joints.DistanceMechanism(
        joints.platform("planar"),
        [joints.prismatic_leg(a, c, n) for a, c, n in zip(base.points, platform.points, lengths, strict=True)],
    )
    fields = parameter_fields(base, platform)
    home = home_from_pose(model, planar_pose_values(0.0, 0.0, phi), 0, fields["parameters"])
    m = Mechanism(
        name="near_rpr", title="t", citation=Citation(("A",), "t", 2026), **fields, **model.fields(), home=home
    )
    assert m.closure is not None
    return m, m.closure.residual.jacobian(m.passive)


def _runtime_home_distance(m: parakin.Mechanism) -> float:
    """sigma_min / sigma_max of the generated loop_closure kernel's Jacobian at the package's home."""
    sigma = np.linalg.svd(np.asarray(m.loop_closure(m.home_actuated, m.home_passive)["jacobian"]), compute_uv=False)
    return float(sigma[-1] / sigma[0])


@pytest.mark.slow  # 3 s: generates a package; test_the_home_distance_... checks the same measure without
def test_a_near_singular_home_warns_at_generation_with_the_packages_own_measure(tmp_path):
    """phi = 1e-4 rad: generation warns (NearSingularHomeWarning) and still writes the package;
    the distance the warning names is the one the generated NumPy kernels give at the package's
    home (an independent evaluation: emitted code, not the generator's SymPy), to the message's
    three digits."""
    source = tmp_path / "near_rpr.py"
    source.write_text(NEAR_RPR.format(phi=1e-4))
    package = tmp_path / "out" / "near_rpr"
    with pytest.warns(NearSingularHomeWarning, match="type II") as caught:
        generate_file(source, package)
    reported = float(re.search(r"d passive at the home = ([0-9.e+-]+)", str(caught[0].message)).group(1))
    assert _runtime_home_distance(parakin.load(str(package), backend="numpy")) == pytest.approx(reported, rel=1e-3)


def test_the_home_distance_is_first_order_in_the_angle_and_shipped_homes_are_clear():
    """Halving phi halves the distance (the leg lines' moment arm about the centre, r_b r_p sin phi
    / |leg|), to 1e-3; at 1e-2 rad the same layout is clear of the level and nothing is warned.
    planar_3rpr, the shipped home nearest a singularity, is above the level with the distance its
    shipped package's kernels give (0.0077)."""
    distances = []
    for phi in (2e-4, 1e-4):
        m, jacobian = _rpr(phi)
        with pytest.warns(NearSingularHomeWarning, match=r"below 0\.001"):
            distances.append(check_home_regular(m, jacobian))
    assert distances[0] == pytest.approx(2 * distances[1], rel=1e-3)
    m, jacobian = _rpr(1e-2)
    with warnings.catch_warnings():
        warnings.simplefilter("error", NearSingularHomeWarning)
        assert check_home_regular(m, jacobian) > NEAR_SINGULAR_HOME
    shipped, _ = load_definition(ROOT / "mechanisms" / "planar_3rpr.py")
    assert shipped.closure is not None
    generator_measure = home_type_ii_distance(shipped, shipped.closure.residual.jacobian(shipped.passive))
    assert generator_measure == pytest.approx(_runtime_home_distance(parakin.load("planar_3rpr")), rel=1e-9)
    assert generator_measure == pytest.approx(0.0077, abs=1e-4) and generator_measure > NEAR_SINGULAR_HOME
