"""forward_pose_all by the polynomial form the generator derives from each loop closure (method
"automatic"), against independent sources: the closed forms written with the mechanisms (same
real modes, poses to 1e-9), the configuration each input was made from (always among the modes),
the trace test's record in the manifest, and the trace test itself failing on an incomplete set."""

from __future__ import annotations

import os
import sys

import numpy as np
import pytest

import parakin
from parakin.studies.sampling import sample_configurations

WITH_LOOPS = [name for name in parakin.available() if parakin.metadata(name).passive]
#: the mechanisms whose derived form got a start system (sam's has no regular start point: it keeps
#: its closed form, and the build says why)
AUTOMATIC = [
    name for name in WITH_LOOPS if "automatic" in parakin.load(name, backend="numpy").capabilities.forward_methods
]


def test_every_mechanism_with_a_loop_has_forward_pose_all() -> None:
    assert len(WITH_LOOPS) >= 10
    assert len(AUTOMATIC) >= len(WITH_LOOPS) - 1
    for name in WITH_LOOPS:
        methods = parakin.load(name, backend="numpy").capabilities.forward_methods
        assert methods, f"{name}: no forward_pose_all method"


#: families with more paths than this are checked on fewer inputs by default (each input tracks
#: every path in NumPy orchestration); ``--run-slow`` checks them on as many as the others
LARGE_FAMILY = 16
RUN_SLOW = "--run-slow" in sys.argv or os.environ.get("PARAKIN_SLOW") == "1"


def _inputs(m: parakin.Mechanism, count: int, seed: int, method: str = "automatic") -> parakin.Configuration:
    """Up to ``count`` closed configurations sampled around the home (at least half of them)."""
    if m.capabilities.forward_methods[method].degree > LARGE_FAMILY and not RUN_SLOW:
        count = max(3, count // 6)
    state = sample_configurations(m, 6 * count, spread=0.08, seed=seed)
    available = min(count, state.actuated.shape[0])
    assert available >= max(count // 2, 3), f"{m.name}: only {state.actuated.shape[0]} closed samples"
    return parakin.Configuration(state.actuated[:available], state.passive[:available], state.pose[:available])


def _pose_distance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(len(a), len(b)) max-abs distance between two sets of 4x4 poses."""
    return np.abs(a[:, None] - b[None]).max(axis=(-2, -1))


@pytest.mark.parametrize("name", AUTOMATIC)
def test_the_root_count_is_proven(name: str) -> None:
    """The manifest's record of the proof is consistent with what it claims: two total-degree
    runs that each found exactly the count, or a closed trace test."""
    m = parakin.load(name, backend="numpy")
    automatic = m.capabilities.forward_methods["automatic"]
    assert automatic.homotopy is not None and automatic.homotopy.root_count is not None
    proof = automatic.homotopy.root_count
    assert proof.count == automatic.degree == automatic.homotopy.start.shape[0]
    if proof.proven and proof.method.startswith("total-degree"):
        exponents, equation = automatic.homotopy.exponents, automatic.homotopy.equation
        bezout = np.prod([exponents[equation == k].sum(1).max() for k in range(exponents.shape[1])])
        assert proof.bezout_paths == bezout >= proof.count
        assert proof.regular_endpoints.count(proof.count) >= 2 and max(proof.regular_endpoints) == proof.count
    elif proof.proven:
        assert proof.method.startswith("trace test")
        assert proof.deviation < proof.tolerance <= 1e-8
        assert proof.witnesses > 0
    else:  # said, not hidden: the manifest and certificate() carry it
        assert "NOT proven" in proof.method


def test_every_family_within_the_total_degree_limit_is_proven() -> None:
    """Every family whose Bezout number the generator can track has its count proven (the
    largest, gough's, rests on the trace test or says it is not proven)."""
    proven = 0
    for name in AUTOMATIC:
        automatic = parakin.load(name, backend="numpy").capabilities.forward_methods["automatic"].homotopy
        exponents, equation = automatic.exponents, automatic.equation
        bezout = np.prod([exponents[equation == k].sum(1).max() for k in range(exponents.shape[1])])
        if bezout <= 10000:
            assert automatic.root_count.proven, f"{name}: {automatic.root_count.method}"
            proven += 1
    assert proven >= 10


@pytest.mark.parametrize("name", AUTOMATIC)
def test_the_generating_pose_is_always_among_the_automatic_modes(name: str) -> None:
    m = parakin.load(name, backend="compiled")
    state = _inputs(m, 24, seed=19)
    modes = m.forward_pose_all(state.actuated, strict=False, method="automatic")
    checked = 0
    for i in range(state.actuated.shape[0]):
        found = modes.poses[i][modes.valid[i]]
        assert found.shape[0] >= 1, f"{name}: input {i} has no mode"
        assert _pose_distance(state.pose[i][None], found).min() < 1e-8, f"{name}: input {i} lost its own pose"
        checked += 1
    assert checked >= min(12, state.actuated.shape[0])


#: the mechanisms with a hand-derived method beside the automatic one (stewart's 40 modes: its own test)
WITH_CLOSED_FORM = [
    name
    for name in AUTOMATIC
    if name != "stewart"
    and {"elimination", "homotopy"} & set(parakin.load(name, backend="numpy").capabilities.forward_methods)
]


@pytest.mark.parametrize("name", WITH_CLOSED_FORM)
def test_automatic_and_closed_form_modes_agree(name: str) -> None:
    m = parakin.load(name, backend="compiled")
    closed = next(method for method in ("elimination", "homotopy") if method in m.capabilities.forward_methods)
    state = _inputs(m, 40, seed=7)
    first = m.forward_pose_all(state.actuated, strict=False, method=closed)
    second = m.forward_pose_all(state.actuated, strict=False, method="automatic")
    compared = 0
    for i in range(state.actuated.shape[0]):
        a, b = first.poses[i][first.valid[i]], second.poses[i][second.valid[i]]
        assert a.shape[0] == b.shape[0], f"{name} input {i}: {closed} {a.shape[0]} modes, automatic {b.shape[0]}"
        if a.shape[0]:
            distance = _pose_distance(a, b)
            assert distance.min(1).max() < 1e-9 and distance.min(0).max() < 1e-9
        compared += 1
    assert compared >= min(20, state.actuated.shape[0])


def test_the_trace_test_rejects_an_incomplete_solution_set() -> None:
    """The generation-time proof closes on the generated start system and fails when one of its
    solutions is withheld."""
    pytest.importorskip("sympy")
    from parakin.generator import start_systems as homotopy
    from parakin.generator.polynomial_form import derive
    from parakin.mechanisms import planar_3rpr

    mechanism = planar_3rpr.build()
    assert mechanism.closure is not None
    residual = list(mechanism.closure.residual)
    form = derive(residual, mechanism.passive, mechanism.actuated, list(mechanism.parameters), mechanism.angular)
    family = homotopy.Family(form, list(form.equations))
    automatic = parakin.load("planar_3rpr", backend="numpy").capabilities.forward_methods["automatic"].homotopy
    assert automatic is not None and automatic.start.shape[0] == 6
    q, found = automatic.start_instance, automatic.start
    assert np.abs(family.value(found, q[None, :])).max() < 1e-12
    complete = homotopy.trace_test("planar_3rpr", family, q, found, np.random.default_rng(4))
    incomplete = homotopy.trace_test("planar_3rpr", family, q, found[:-1], np.random.default_rng(4))
    assert complete["complete"] and complete["deviation"] < 1e-10
    assert not incomplete["complete"] and incomplete["deviation"] > 1e-6


def test_the_total_degree_bound_completes_and_proves_a_partial_set() -> None:
    """Two total-degree runs at the stored start instance find the solutions withheld from it
    (as a component monodromy never reaches would be) and prove the count; a run that lost a
    solution would disagree with the joined set and leave it unproven."""
    pytest.importorskip("sympy")
    from parakin.generator import start_systems as homotopy
    from parakin.generator.polynomial_form import derive
    from parakin.mechanisms import planar_3rpr

    mechanism = planar_3rpr.build()
    assert mechanism.closure is not None
    form = derive(
        list(mechanism.closure.residual), mechanism.passive, mechanism.actuated, list(mechanism.parameters),
        mechanism.angular,
    )  # fmt: skip
    family = homotopy.Family(form, list(form.equations))
    automatic = parakin.load("planar_3rpr", backend="numpy").capabilities.forward_methods["automatic"].homotopy
    q, found = automatic.start_instance, automatic.start
    degrees = [2, 2, 2, 2]
    joined, proof = homotopy._total_degree_bound("planar_3rpr", family, q, found[:2], degrees, [], 2026)
    assert proof["proven"] and proof["regular_endpoints"] == [6, 6] and proof["bezout_paths"] == 16
    assert len(joined) == 6
    # every stored solution is among the joined ones, and the joined ones solve the system
    assert all(np.abs(joined - z).max(-1).min() < 1e-8 for z in found)
    assert np.abs(family.value(joined, q[None, :])).max() < 1e-10
    # runs that each lose a solution (as a failed path would) disagree with the joined set: runs
    # are added up to the limit, and the count is not proven
    one_run = homotopy.total_degree_run
    calls = []

    def losing(*arguments):
        calls.append(1)
        found = one_run(*arguments)
        return found if len(calls) == 1 else found[1:]

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(homotopy, "total_degree_run", losing)
        joined, proof = homotopy._total_degree_bound("planar_3rpr", family, q, found[:2], degrees, [], 2026)
    assert len(joined) == 6 and not proof["proven"]
    assert proof["regular_endpoints"] == [6, 5, 5, 5] and len(calls) == homotopy.TOTAL_DEGREE_MAX_RUNS
    assert "NOT proven" in str(proof["method"])


@pytest.mark.parametrize("name", AUTOMATIC)
def test_generic_inputs_are_certified_complete(name: str) -> None:
    """Every path's endpoint is in a Krawczyk box holding exactly one root, the boxes are
    distinct, and they number the proven root count: no mode can be missing."""
    m = parakin.load(name, backend="compiled")
    state = _inputs(m, 12, seed=5)
    modes = m.forward_pose_all(state.actuated, strict=False, method="automatic")
    certificate = modes.certificate()
    root_count = m.capabilities.forward_methods["automatic"].degree
    assert (certificate["root_count"] == root_count).all()
    assert (certificate["certified_roots"] <= root_count).all()
    complete = np.asarray(certificate["certified_roots"]) == root_count
    assert complete.sum() >= 0.9 * complete.size, f"{name}: {complete.sum()} of {complete.size} certified complete"
    assert (np.asarray(certificate["uncertified_paths"])[complete] == 0).all()
    assert (np.asarray(certificate["complete"]) == (complete & bool(certificate["root_count_proven"].all()))).all()


def test_a_certificate_fails_when_an_endpoint_is_spoiled() -> None:
    """The certificate is not a formality: moving one endpoint off its root leaves that path
    uncertified and the input incomplete."""
    m = parakin.load("planar_3rpr", backend="numpy")
    info = m.capabilities.forward_methods["automatic"]
    state = _inputs(m, 4, seed=8)
    from parakin.solvers.modes import certify, numpy_modes

    out = numpy_modes(m, state.actuated, info)
    good = certify(m, info, state.actuated, out["endpoints"])
    assert (good.certified == info.degree).all() and good.unique.all()
    spoiled = out["endpoints"].copy()
    spoiled[0, 0] += 1e-3
    bad = certify(m, info, state.actuated, spoiled)
    assert bad.certified[0] == info.degree - 1 and not bad.unique[0, 0] and (bad.certified[1:] == info.degree).all()


def test_prs3_has_every_mode_of_the_independent_elimination_without_a_forward_model() -> None:
    """3-PRS (no forward model written): the modes of each input of the mechanism file's table
    (counted there by exact elimination, tests/test_prs3.py) from the derived polynomial form,
    16 complex solutions certified, 16 real modes at the constructed input."""
    from parakin.mechanisms import prs3

    m = parakin.load("prs3", backend="compiled")
    assert set(m.capabilities.forward_methods) == {"automatic"}
    info = m.capabilities.forward
    assert info is not None and info.homotopy is not None and info.homotopy.root_count is not None
    # (p, q) and (p, -q) are the same pose: 16 poses, 32 solutions in the quaternion unknowns
    assert info.homotopy.root_count.count == 32
    for strokes, count in prs3.MODE_COUNTS.values():
        modes = m.forward_pose_all(np.array(strokes))
        certificate = modes.certificate()
        assert int(modes.count) == count
        assert int(certificate["certified_roots"]) == int(certificate["root_count"]), certificate


def test_stewart_automatic_gives_dietmaier_40_modes_certified() -> None:
    m = parakin.load("stewart", backend="compiled")
    example = next(e for e in m.manifest.examples if e.name == "dietmaier_40")
    closed = m.forward_pose_all(np.array(example.actuated))
    automatic = m.forward_pose_all(np.array(example.actuated), method="automatic")
    assert int(closed.count) == int(automatic.count) == 40
    distance = _pose_distance(closed.poses[closed.valid], automatic.poses[automatic.valid])
    assert distance.min(1).max() < 1e-9 and distance.min(0).max() < 1e-9
    for modes in (closed, automatic):
        certificate = modes.certificate()
        assert int(certificate["certified_roots"]) == int(certificate["root_count"])


def test_the_circle_parametrisation_covers_every_real_angle() -> None:
    """u(x) is finite for every real angle (pi included), (C, S, D)(u(x)) is proportional to
    (cos x, sin x, 1) and C^2 + S^2 = D^2 identically."""
    from parakin.solvers.path_tracking import circle_parameter, circle_point

    sympy = pytest.importorskip("sympy")
    from parakin.generator.polynomial_form import MOEBIUS_A, MOEBIUS_B, circle_parametrisation

    u = sympy.Symbol("u")
    c, s, d = circle_parametrisation(u)
    assert sympy.expand(c**2 + s**2 - d**2) == 0
    a, b = complex(MOEBIUS_A), complex(MOEBIUS_B)
    angles = np.concatenate([np.linspace(-np.pi, np.pi, 2001), [np.pi, -np.pi, 0.0]])
    values = circle_parameter(angles, a, b)
    assert np.isfinite(values).all()
    point = circle_point(values, a, b)
    assert np.abs(point[:, 0] / point[:, 2] - np.cos(angles)).max() < 1e-12
    assert np.abs(point[:, 1] / point[:, 2] - np.sin(angles)).max() < 1e-12


def test_the_polynomial_form_keeps_exact_constants_and_clears_roots_and_quotients() -> None:
    sympy = pytest.importorskip("sympy")
    from parakin.generator.polynomial_form import derive

    x, y, phi, theta, length = sympy.symbols("x y phi theta length", real=True)
    residual = [
        sympy.sqrt((x - sympy.sqrt(3) * sympy.cos(theta)) ** 2 + y**2) - length,  # |d| - l: root eliminated
        (x * sympy.cos(phi) + y * sympy.sin(phi) - 1) / length,  # a quotient by a parameter
        x - y * sympy.cos(phi + theta),  # a sum of angles, one of them an input
    ]
    form = derive(residual, [x, y, phi], [theta], [length], [phi, theta])
    names = [str(v) for v in form.unknowns]
    assert names == ["z_x", "z_y", "c_phi", "s_phi"]  # no auxiliary unknown left
    assert len(form.equations) == 4 and len(form.circles) == 1
    text = " ".join(map(str, form.equations))
    assert "sqrt(3)" in text and "sqrt(" not in text.replace("sqrt(3)", "")
    for equation in form.equations:
        sympy.Poly(equation, *form.unknowns)  # polynomial in the unknowns


@pytest.mark.parametrize("threads", ["1", "3"])
def test_certificates_in_chunks_equal_one_pass(monkeypatch, threads: str) -> None:
    """Certification runs in chunks of inputs (bounded memory: 10^4 inputs at once ran out of
    memory), on several threads side by side: chunks of 2 (of 1 on 3 threads) give exactly the
    counts and per-path verdicts of one pass."""
    from parakin.solvers import modes as modes_module

    m = parakin.load("planar_3rpr", backend="numpy")
    info = m.capabilities.forward_methods["automatic"]
    state = _inputs(m, 7, seed=12)
    out = modes_module.numpy_modes(m, state.actuated, info)
    monkeypatch.setenv("PARAKIN_THREADS", "1")
    whole = modes_module.certify(m, info, state.actuated, out["endpoints"])
    monkeypatch.setenv("PARAKIN_THREADS", threads)
    monkeypatch.setattr(modes_module, "CERTIFY_CHUNK", 2)
    chunked = modes_module.certify(m, info, state.actuated, out["endpoints"])
    assert state.actuated.shape[0] >= 5
    for mine, theirs in zip(whole, chunked, strict=True):
        np.testing.assert_array_equal(mine, theirs)
    assert (whole.certified == info.degree).all()
