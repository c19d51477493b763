"""Krawczyk's certificate in C (generator/runtime/krawczyk.h, a package's NAME_certify_roots,
``certify_roots_compiled``) against the NumPy reference ``parakin.solvers.certify.certify_roots``
on the endpoints that ``forward_pose_all`` certifies, and on adversarial systems; candidates that
only the C certifies (its interval enclosures are tighter than the reference's a-priori bound)
are checked by the exact-arithmetic certificate (``certify_root_exactly``)."""

from __future__ import annotations

import ctypes
import re
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import parakin
from parakin.errors import BadInputError
from parakin.packages.compiled import CERTIFY_JOB, CompiledBackend
from parakin.solvers import modes
from parakin.solvers.certify import Certificate, certify_roots, certify_roots_compiled
from parakin.solvers.exact_certify import certify_root_exactly
from parakin.studies.sampling import sample_configurations

GENERATED = Path(__file__).resolve().parent.parent / "generated"


@pytest.fixture(scope="module")
def library() -> Any:
    return parakin.load("planar_3rrr", backend="compiled").backend


#: Dietmaier's leg lengths for the default (his) geometry of the Stewart platform: 40 real
#: assembly modes (Dietmaier 1998; bench/floor.py)
DIETMAIER_LEGS = np.array([1, 0.645275, 1.086284, 1.503439, 1.281933, 0.771071])


def endpoints(
    monkeypatch: pytest.MonkeyPatch, name: str, inputs: int, method: str | None = None, given: Any = None
) -> list[tuple]:
    """The (args, kwargs) of every ``certify_roots`` call ``forward_pose_all`` makes on ``inputs``
    inputs sampled near home (or the ``given`` inputs), one input per call."""
    m = parakin.load(name, backend="compiled")
    calls: list[tuple] = []
    original = modes.certify_roots

    def spy(*args: Any, **kwargs: Any) -> Certificate:
        calls.append((args, kwargs))
        return original(*args, **kwargs)

    monkeypatch.setattr(modes, "certify_roots", spy)

    # the NumPy certificate, whose calls are recorded, in place of the package's C (the default)
    def in_numpy(backend: Any, *args: Any, clusters: bool = True, **kwargs: Any) -> Certificate:
        return spy(*args, **kwargs)  # (the clusters are counted whether asked for or not)

    monkeypatch.setattr(modes, "certify_roots_compiled", in_numpy)
    sample = sample_configurations(m, 3 * inputs, spread=0.05, seed=11).actuated if given is None else given
    extra = {} if method is None else {"method": method}
    for theta in sample[:inputs]:
        m.forward_pose_all(theta, strict=False, **extra)
    monkeypatch.undo()
    return calls


def nested(a: Certificate, b: Certificate) -> np.ndarray:
    """Per candidate: one certified box holds the other (coordinate by coordinate)."""
    gap = abs(a.center - b.center)
    inside = (gap + b.radii <= a.radii * (1 + 1e-12)) | (gap + a.radii <= b.radii * (1 + 1e-12))
    return np.asarray(inside.all(-1))


def compare(library: Any, calls: list[tuple], exact_checks: int = 0) -> dict[str, int]:
    """C against NumPy on every call: where NumPy certifies, C certifies with the same realness
    and a nested box; where only C certifies, the exact certificate agrees (the first
    ``exact_checks`` of them). Returns the counts."""
    counts = {"candidates": 0, "unique": 0, "extra": 0, "exact": 0}
    for args, kwargs in calls:
        reference = certify_roots(*args, **kwargs)
        ours = certify_roots_compiled(library, *args, **kwargs)
        assert ours.unique.shape == reference.unique.shape and ours.center.shape == reference.center.shape
        both = reference.unique
        assert ours.unique[both].all()
        # where the reference decides realness, the same answer; where it leaves it (0), C may decide
        assert ((ours.real == reference.real) | (reference.real == 0))[both].all()
        assert nested(ours, reference)[both].all()
        given = np.isfinite(args[3]).all(-1)
        np.testing.assert_allclose(ours.center[both], reference.center[both], rtol=1e-9, atol=1e-12)
        assert np.isnan(ours.center[~given]).all()
        assert (ours.certified_distinct >= reference.certified_distinct).all()
        extra = ours.unique & ~reference.unique
        counts["candidates"] += int(given.sum())
        counts["unique"] += int(both.sum())
        counts["extra"] += int(extra.sum())
        for index in zip(*np.nonzero(extra), strict=True):
            if counts["exact"] >= exact_checks:
                break
            coefficients = np.broadcast_to(args[0], extra.shape[:-1] + args[0].shape[-1:])[index[:-1]]
            box = certify_root_exactly(
                coefficients, args[1], args[2], ours.center[index], kwargs["homogeneous"] is None
            )
            assert box.unique
            assert (abs(box.center - ours.center[index]) <= box.radius + ours.radii[index]).all()
            assert box.real == 0 or ours.real[index] in (0, box.real)
            counts["exact"] += 1
    return counts


def test_c_certificate_equals_numpy_on_endpoints(library: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    """The affine (planar_3rrr, prs3) and the homogeneous (stewart: the real chart) variants on
    a few inputs each."""
    total = {"candidates": 0, "unique": 0}
    for name, inputs in (("planar_3rrr", 3), ("prs3", 2), ("stewart", 2)):
        counts = compare(library, endpoints(monkeypatch, name, inputs))
        assert counts["unique"] >= 4 * inputs, name
        for key in total:
            total[key] += counts[key]
    assert total["candidates"] >= 100


@pytest.mark.slow
@pytest.mark.parametrize(
    "name, method", [("stewart", None), ("prs3", None), ("planar_3rrr", None), ("rus6", None), ("gough", "automatic")]
)
def test_c_certificate_equals_numpy_on_50_inputs(
    library: Any, monkeypatch: pytest.MonkeyPatch, name: str, method: str | None
) -> None:
    calls = endpoints(monkeypatch, name, 50, method)
    assert len(calls) >= 50
    counts = compare(library, calls, exact_checks=5)
    assert counts["unique"] >= 50


def test_c_certificate_decides_dietmaier_s_forty_real_modes(library: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    """Dietmaier's input has 40 real assembly modes (Dietmaier 1998): the C certificate proves
    all 40 endpoints unique, distinct and real in double precision (the homogeneous chart test);
    the NumPy reference agrees wherever it decides."""
    calls = endpoints(monkeypatch, "stewart", 1, given=DIETMAIER_LEGS[None])
    assert len(calls) == 1
    compare(library, calls)
    ours = certify_roots_compiled(library, *calls[0][0], **calls[0][1])
    assert ours.unique.sum() == 40 and (ours.real == 1).sum() == 40 and (ours.certified_distinct == 40).all()


def test_c_certificate_adversarial(library: Any) -> None:
    """A double root is not unique; a complex pair 1e-7 off the real axis (at 1) is certified
    non-real, never real; roots of size 1e7 are certified in their own scale; as in NumPy."""
    double = ([1, -2, 1], [[2], [1], [0]], [0, 0, 0], [[1 + 1e-9], [1 - 1e-9]])
    pair = ([1, -2, 1 + 1e-14], [[2], [1], [0]], [0, 0, 0], [[1 + 1e-7j], [1 - 1e-7j]])
    # z1^2 + 2e7 z1 - 3e14 = 0 and z2 - 1e-14 z1^2 = 0: the roots (1e7, 1) and (-3e7, 9)
    exponents, equation = [[2, 0], [1, 0], [0, 0], [0, 1], [2, 0]], [0, 0, 0, 1, 1]
    coefficients = [1, 2e7, -3e14, 1, -1e-14]
    roots = [[1e7 * (1 + 1e-12), 1.0], [-3e7, 9.0 + 1e-12]]
    reference = certify_roots(*double)
    ours = certify_roots_compiled(library, *double)
    assert not ours.unique.any() and not reference.unique.any() and not ours.real.any()
    # the pair: NumPy's a-priori rounding bound leaves it undecided, C's enclosure proves it
    # non-real; its boxes hold the closed-form roots 1 +- i sqrt(c - 1) (c as stored, c - 1 exact)
    assert (certify_roots(*pair).real != 1).all()
    ours = certify_roots_compiled(library, *pair)
    assert (ours.real == -1).all()
    closed = 1 + np.array([1, -1]) * 1j * np.sqrt((1 + 1e-14) - 1)
    assert (abs(ours.center[:, 0] - closed) <= ours.radii[:, 0]).all()
    # the equations' scales differ by 1e15: the reference's ||Y|| max_k H_k fails the second root,
    # the row-weighted bound of krawczyk.h certifies both
    reference = certify_roots(coefficients, exponents, equation, roots)
    ours = certify_roots_compiled(library, coefficients, exponents, equation, roots)
    assert ours.unique.all() and (ours.real == 1).all()
    assert (ours.real[reference.unique] == reference.real[reference.unique]).all()
    exact = np.array([[1e7, 1.0], [-3e7, 9.0]])
    assert (abs(ours.center - exact) <= ours.radii).all()
    assert (ours.radii[:, 0] < 1e-5).all()


def test_c_certificate_close_roots_in_double_word(library: Any) -> None:
    """Two simple roots 2^-30 apart (every coefficient exact): double precision's rounding leaves
    both undecided in NumPy; the C's double-word second attempt certifies each in its own box,
    as the exact-arithmetic certificate does."""
    gap = 2.0**-30
    args = ([1, -(2 + gap), 1 + gap], [[2], [1], [0]], [0, 0, 0], [[1.0], [1 + gap]])
    assert not certify_roots(*args).unique.any()
    ours = certify_roots_compiled(library, *args)
    assert ours.unique.all() and (ours.real == 1).all() and ours.certified_distinct == 2
    roots = np.array([1.0, 1 + gap])
    assert (abs(ours.center[:, 0] - roots) <= ours.radii[:, 0]).all() and (ours.radii < gap / 4).all()
    for root in roots:
        box = certify_root_exactly(
            np.array(args[0], complex), np.array(args[1]), np.array(args[2]), np.array([root]), True
        )
        assert box.unique and box.real == 1


def test_c_certificate_decides_rus6_roots_near_infinity(library: Any) -> None:
    """Three of rus6's endpoints near roots of size 5e4..3e6 (near infinity), as forward_pose_all
    handed them to the certificate (tests/fixtures/rus6_near_infinity.npz: the system's 311 terms
    and the candidate): J conditioned ~1e9..1e17 in the scaled chart, the candidates 1e-7..5e-4 of
    their size from the root. The C certificate before issue 33's rus6 work decided none of them
    (|Y| |F| bounded ||Y F||; Newton in double moved them beyond 1e-6; ||I - Y J|| > 1 with the
    double LU); the exact-arithmetic certificate (the oracle, ~20 ms each) proves each non-real:
    the C's box holds the exact box's root, non-real too, and NumPy's reference leaves them."""
    data = np.load(Path(__file__).resolve().parent / "fixtures" / "rus6_near_infinity.npz")
    exponents, equation = data["exponents"].astype(np.int64), data["equation"].astype(np.int64)
    checked = 0
    for coefficients, candidate in zip(data["coefficients"], data["candidates"], strict=True):
        assert not certify_roots(coefficients, exponents, equation, candidate[None]).unique.any()
        ours = certify_roots_compiled(library, coefficients, exponents, equation, candidate[None])
        assert ours.unique.all() and (ours.real == -1).all()
        box = certify_root_exactly(coefficients, exponents, equation, candidate, True)
        assert box.unique and box.real == -1
        assert (abs(box.center - ours.center[0]) <= box.radius + ours.radii[0]).all()
        assert (ours.radii[0] <= 1e-6 * abs(ours.center[0]).max()).all()
        checked += 1
    assert checked == 3


def test_c_certificate_batch_and_errors(library: Any) -> None:
    """A batch of systems broadcast against candidates as in NumPy; bad inputs are the NumPy
    reference's BadInputErrors."""
    c = np.array([[1, 0, -4], [1, 0, -9]], dtype=complex)
    z = np.array([[[2.0], [-2.0]], [[3.0], [np.nan]]])
    ours = certify_roots_compiled(library, c, [[2], [1], [0]], [0, 0, 0], z)
    reference = certify_roots(c, [[2], [1], [0]], [0, 0, 0], z)
    np.testing.assert_array_equal(ours.unique, [[True, True], [True, False]])
    np.testing.assert_array_equal(ours.certified_distinct, reference.certified_distinct)
    with pytest.raises(BadInputError):
        certify_roots_compiled(library, c, [[2], [1], [0]], [0, 0, 5], z)
    with pytest.raises(BadInputError):
        certify_roots_compiled(library, c[:, :2], [[2], [1], [0]], [0, 0, 0], z)
    with pytest.raises(BadInputError, match="homogeneous"):
        certify_roots_compiled(
            library, [1, -4, 1, -1], [[2, 0], [0, 1], [1, 0], [0, 0]], [0, 0, 1, 1], [[2, 1.0]], True, [0, 1], 1
        )


def test_certify_job_layout_is_the_header() -> None:
    """CERTIFY_JOB (the ctypes structure) lists the fields of NAME_certify_job in the generated
    header, in order, with matching kinds."""
    header = (GENERATED / "stewart" / "stewart.h").read_text()
    body = header[header.index("typedef struct {", header.index("Krawczyk")) : header.index("} stewart_certify_job;")]
    fields = re.findall(r"^\s+(?:const )?([a-z ]+\*?) (\w+);", body, re.M)
    assert [name for _, name in fields] == [name for name, _ in CERTIFY_JOB]
    for (kind, _), (_, expected) in zip(fields, CERTIFY_JOB, strict=True):
        assert ("*" in kind) == (expected == "pointer")
    backend = parakin.load("stewart", backend="compiled").backend
    assert isinstance(backend, CompiledBackend)
    assert ctypes.sizeof(backend.CertifyJob) == 8 * len(CERTIFY_JOB)
