"""Issue 33: a 3-RRS at its home lost its level home pose on the compiled backend, with "4 certified
roots of undecided realness", while NumPy gave all 8 modes. At that symmetric input the platform's
x and y are 0 at most roots, and the tracker leaves them at 1e-30..1e-15; one path of the C run
ended on another's root, so 18 of the 32 endpoints had y at rounding level and the median that
sets y's typical size (``certify._typical_size``, ``kw_median`` in krawczyk.h) was 2e-15: no box
about those roots could be that narrow in y in double precision. The C certificate (double-word
F, Rump's preconditioner) still proved 4 of them unique, but not real, and the exact test, which
decided them real, was discarded because its polydisc (radius 1e-17 in every coordinate) did not
fit inside a box 8e-31 wide in y.

Fixed: a coordinate at most ``ZERO_SIZE`` times its candidate's largest is a zero to rounding and
sets no typical size (both backends alike), and a unique box of undecided realness that the
exact polydisc does not fit in is replaced by that polydisc with its realness."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import parakin
from parakin.solvers import modes
from parakin.solvers.certify import Certificate, certify_roots, certify_roots_compiled

FIXTURES = Path(__file__).resolve().parent / "fixtures"

# x^2 + y^2 - 1 = 0, (x - 1/2) y = 0: the real roots (1, 0), (-1, 0), (1/2, +-sqrt(3)/2), exactly
EXPONENTS = np.array([[2, 0], [0, 2], [0, 0], [1, 1], [0, 1]])
EQUATION = np.array([0, 0, 0, 1, 1])
COEFFICIENTS = np.array([1, 1, -1, 1, -0.5], dtype=complex)
ROOTS = np.array([[1, 0], [-1, 0], [0.5, np.sqrt(0.75)], [0.5, -np.sqrt(0.75)]], dtype=complex)


def endpoints(noise: float) -> tuple[np.ndarray, np.ndarray]:
    """Five endpoints of the four roots as a tracker leaves them: y at the rounding level ``noise``
    where it is 0, and one path ended on another's root (the C run's path 20 at the 3-RRS's home),
    so that 3 of 5 endpoints have y at rounding level; and the root each endpoint is near."""
    which = np.array([0, 0, 1, 2, 3])
    z = ROOTS[which].copy()
    z[:3, 1] = noise * np.array([1, -1, 1j])
    return z, ROOTS[which]


def assert_certifies_each(cert: Certificate, exact: np.ndarray) -> None:
    """Every endpoint in a box that holds its exact root (the closed form), certified real, and
    the four roots counted distinct."""
    assert cert.unique.all()
    assert (cert.real == 1).all()
    assert (np.abs(cert.center - exact) <= cert.radii).all()
    assert cert.certified_distinct == 4


@pytest.mark.parametrize("noise", [1e-30, 1e-17, 1e-15])
def test_a_coordinate_zero_to_rounding_sets_no_typical_size(noise: float) -> None:
    """NumPy: before the fix, y's typical size was the rounding noise and the three roots at y = 0
    were not certified (unique False, realness 0)."""
    z, exact = endpoints(noise)
    assert_certifies_each(certify_roots(COEFFICIENTS, EXPONENTS, EQUATION, z), exact)


@pytest.mark.parametrize("noise", [1e-30, 1e-15])
def test_the_c_certificate_measures_the_same_typical_size(noise: float) -> None:
    """The package's C (krawczyk.h's KW_ZERO_SIZE, certify.py's ZERO_SIZE): the same verdicts."""
    library: Any = parakin.load("planar_3rrr", backend="compiled").backend
    z, exact = endpoints(noise)
    cert = certify_roots_compiled(library, COEFFICIENTS, EXPONENTS, EQUATION, z)
    assert_certifies_each(cert, exact)
    reference = certify_roots(COEFFICIENTS, EXPONENTS, EQUATION, z)
    assert (cert.real == reference.real).all() and (cert.unique == reference.unique).all()


def test_the_exact_verdict_is_kept_when_its_polydisc_does_not_fit_the_box(monkeypatch: pytest.MonkeyPatch) -> None:
    """A root whose double box is unique but of undecided realness, 1e-20 of its width in one
    coordinate (the C box of the 3-RRS's home root, 8e-31 wide in y): the exact test decides it,
    and its polydisc, which does not fit in that box, becomes the path's box. planar_3rrr at
    theta = (-54, 174, -105) deg: 6 real modes (README), each certified real without the narrowing."""
    m = parakin.load("planar_3rrr", backend="numpy")
    info = m.capabilities.forward_methods["automatic"]
    theta = np.radians([[-54.0, 174.0, -105.0]])
    ends = modes.numpy_modes(m, theta, info)["endpoints"]
    plain = modes.certify_inputs(m, info, theta, ends, exact=True)
    assert plain.certified[0] == 6 and (plain.real == 1).all()
    path = 0
    original = modes._certify_endpoints

    def narrowed(*args: Any, **kwargs: Any) -> Certificate:
        cert = original(*args, **kwargs)
        cert.real[0, path] = 0
        cert.radii[0, path, 1] *= 1e-20
        return cert

    monkeypatch.setattr(modes, "_certify_endpoints", narrowed)
    found = modes.certify_inputs(m, info, theta, ends, exact=True)
    assert found.real[0, path] == 1  # before the fix: 0, the input not complete
    assert found.unique[0, path] and found.certified[0] == 6
    # the box is the exact polydisc (one radius in every coordinate), about the same root
    assert np.ptp(found.radii[0, path]) == 0
    assert (np.abs(found.centre[0, path] - plain.centre[0, path]) <= plain.radii[0, path]).all()


@pytest.mark.slow
@pytest.mark.parametrize("backend", ["compiled", "numpy"])
def test_rrs3_at_its_home_has_every_mode_on_every_backend(tmp_path: Path, backend: str) -> None:
    """The user's 3-RRS (tests/fixtures/rrs3.py) at its home: 8 modes, certified complete, the
    level home pose (z = 0.25 m, identity rotation: the fixture's home) among them, and
    ``forward_pose`` of the home input gives it back; before the fix the compiled backend gave 6
    modes, not complete, and another mode for the home. ~45 s to generate."""
    folder = tmp_path / "rrs3"
    done = subprocess.run(
        [sys.executable, "-m", "parakin", "generate", str(FIXTURES / "rrs3.py"), "--out", str(folder)],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert done.returncode == 0, done.stderr
    m = parakin.load(folder, backend=backend)
    home = np.asarray(m.home_actuated)
    found = m.forward_pose_all(home)
    certificate = found.certificate()
    assert found.count == 8 and certificate["complete"] and certificate["undecided_roots"] == 0
    level = np.eye(4)
    level[2, 3] = 0.25
    poses = np.array([found.mode(k).pose for k in range(found.count)])
    assert (np.abs(poses - level).max((-2, -1)) < 1e-9).sum() == 1
    assert np.abs(m.forward_pose(home).pose - level).max() < 1e-9


def test_the_zero_rule_is_the_same_in_c_and_numpy() -> None:
    """krawczyk.h's KW_ZERO_SIZE is certify.py's ZERO_SIZE (both backends measure alike)."""
    from pathlib import Path

    from parakin.solvers import certify

    text = (Path(__file__).resolve().parent.parent / "generator" / "runtime" / "krawczyk.h").read_text()
    assert certify.ZERO_SIZE == 2.0**-40 and "#define KW_ZERO_SIZE 0x1p-40" in text
