"""Independent batched oracle for the forward pose of the 3-RRR spherical parallel manipulator (SPM).

Conventions (base frame; eta_i = 2 pi (i-1)/3, Rz(a) = rotation about z by a; a1 proximal, a2 distal):
    u_i  = Rz(eta_i) [0, sin g, -cos g]                 actuated axes
    e1_i = Rz(eta_i) [0, -cos g, -sin g],  e2_i = u_i x e1_i
    w_i  = cos a1 u_i + sin a1 (cos th_i e1_i + sin th_i e2_i)     intermediate axes
    v_i0 = Rz(eta_i) [0, sin b, cos b],  v_i = R v_i0              platform axes
    leg constraint  w_i . (R v_i0) = cos a2.
With R = R(q) for a quaternion q = (q0, q1, q2, q3) (scalar first), each constraint homogenised with q.q
is a quadric F_i(q) = w_i^T R(q) v_i0 - cos(a2) q.q = q^T Q_i q in P^3 (Bezout number 8; q ~ -q).

Method: total-degree homotopy with the gamma trick in a random complex affine chart q = M (1, y),
H(y, t) = (1 - t) gamma (y_i^2 - 1) + t q^T Q_i q, from the 8 start points y in {+-1}^3. The paths of all
inputs (N x 8) are tracked together with NumPy: RK4 predictor, Newton corrector and adaptive step per path.
Inputs with a failed path (no convergence, divergence or two coinciding endpoints) are re-solved with a new
chart and gamma. A solution is real when q times a phase is real to `real_tol`; it is then polished by
Newton on the real unit sphere. Eight distinct endpoints solving the system are all of its solutions (Bezout),
so the complex count certifies the result. The charts and gammas are drawn from `seed` (deterministic).
Nothing here depends on parakin, the generator or SymPy.

API: forward_rotations, forward_quaternions, complex_solution_count, solve_projective, quadrics, leg_residuals.
"""

from __future__ import annotations

import numpy as np

Scalar = float | np.ndarray  # a geometry angle: scalar or one value per input, shape (N,)
CHUNK = 1024  # inputs tracked together (bounds memory traffic; 8 paths each)
_ETA = 2 * np.pi * np.arange(3) / 3
_START = np.array([[1 - 2 * ((s >> k) & 1) for k in range(3)] for s in range(8)], dtype=complex)


def _rz(x: np.ndarray | float, y: np.ndarray | float, z: np.ndarray | float) -> np.ndarray:
    """Rz(eta_i) [x, y, z] for i = 1..3; x, y, z of shape (N, 1) or scalar -> (N, 3, 3) [input, leg, xyz]."""
    c, s = np.cos(_ETA), np.sin(_ETA)
    x, y, z = np.broadcast_arrays(x, y, z, c)[:3]
    return np.stack([c * x - s * y, s * x + c * y, z], axis=-1)


def _legs(
    alpha1: Scalar, alpha2: Scalar, beta: Scalar, gamma: Scalar, theta: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """w_i (N, 3, 3), v_i0 (N, 3, 3) and cos(alpha2) (N, 1); geometry scalars or (N,) arrays."""
    th = np.atleast_2d(np.asarray(theta, dtype=float))
    a1, a2, b, g = (
        np.broadcast_to(np.asarray(v, dtype=float), (len(th),))[:, None] for v in (alpha1, alpha2, beta, gamma)
    )
    u, e1, v0 = _rz(0.0, np.sin(g), -np.cos(g)), _rz(0.0, -np.cos(g), -np.sin(g)), _rz(0.0, np.sin(b), np.cos(b))
    c, s = np.cos(th)[..., None], np.sin(th)[..., None]
    return np.cos(a1)[..., None] * u + np.sin(a1)[..., None] * (c * e1 + s * np.cross(u, e1)), v0, np.cos(a2)


def quadrics(alpha1: Scalar, alpha2: Scalar, beta: Scalar, gamma: Scalar, theta: np.ndarray) -> np.ndarray:
    """Real symmetric Q of shape (N, 3, 4, 4) with F_i(q) = q^T Q[n, i] q; geometry scalars or (N,) arrays."""
    w, v0, c2 = _legs(alpha1, alpha2, beta, gamma, theta)
    wv = np.einsum("nij,nij->ni", w, v0)
    Q = np.zeros((*wv.shape, 4, 4))
    # R(q) = (q0^2 - |p|^2) I + 2 p p^T + 2 q0 [p]x  with p = (q1, q2, q3)
    Q[..., 0, 0] = wv - c2
    Q[..., 0, 1:] = Q[..., 1:, 0] = np.cross(v0, w)
    Q[..., 1:, 1:] = w[..., :, None] * v0[..., None, :] + v0[..., :, None] * w[..., None, :]
    Q[..., 1:, 1:] -= (wv + c2)[..., None, None] * np.eye(3)
    return Q


def quat_to_rotation(q: np.ndarray) -> np.ndarray:
    """Rotation matrices (..., 3, 3) of unit quaternions (..., 4), scalar first."""
    q0, q1, q2, q3 = np.moveaxis(q, -1, 0)
    return np.stack(
        [
            np.stack([q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3, 2 * (q1 * q2 - q0 * q3), 2 * (q0 * q2 + q1 * q3)], -1),
            np.stack([2 * (q1 * q2 + q0 * q3), q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3, 2 * (q2 * q3 - q0 * q1)], -1),
            np.stack([2 * (q1 * q3 - q0 * q2), 2 * (q0 * q1 + q2 * q3), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3], -1),
        ],
        -2,
    )


def _solve3(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Batched 3x3 solve by cofactors (much faster than LAPACK for tiny systems); nan where singular."""
    C = np.cross(A[:, [1, 2, 0], :], A[:, [2, 0, 1], :])  # rows of the adjugate transposed
    det = np.einsum("pk,pk->p", A[:, 0], C[:, 0])
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.einsum("pik,pi->pk", C, b) / det[:, None]


def _homotopy(Qt: np.ndarray, gam: np.ndarray, y: np.ndarray, t: np.ndarray) -> tuple[np.ndarray, ...]:
    """H, dH/dy and dH/dt at (y, t) for paths p: Qt (P, 3, 4, 4) complex, gam (P,), y (P, 3), t (P,)."""
    z = np.concatenate([np.ones((len(y), 1)), y], axis=1)
    Qz = np.einsum("pikl,pl->pik", Qt, z)
    F, G = np.einsum("pk,pik->pi", z, Qz), gam[:, None] * (y * y - 1)
    s = t[:, None]
    Hy = 2 * s[..., None] * Qz[..., 1:]
    Hy[:, [0, 1, 2], [0, 1, 2]] += 2 * (1 - s) * gam[:, None] * y
    return (1 - s) * G + s * F, Hy, F - G


def _track(Qt: np.ndarray, gam: np.ndarray, tol: float, max_steps: int = 4000) -> tuple[np.ndarray, np.ndarray]:
    """Track the 8 paths of each chart (Qt (K, 3, 4, 4), gam (K,)) from t = 0 to 1; returns y (K, 8, 3), ok."""
    P = 8 * len(Qt)
    Qt, gam = np.repeat(Qt, 8, axis=0), np.repeat(gam, 8)
    y, t = np.tile(_START, (len(Qt) // 8, 1)), np.zeros(P)
    dt, steps, live = np.full(P, 0.05), np.zeros(P, dtype=int), np.ones(P, dtype=bool)

    def dydt(Qa, ga, ya, ta):
        _, Hy, Ht = _homotopy(Qa, ga, ya, ta)
        return -_solve3(Hy, Ht)

    while (act := np.flatnonzero(live & (t < 1))).size:
        Qa, ga, ya, ta = Qt[act], gam[act], y[act], t[act]
        h = np.minimum(dt[act], 1 - ta)
        k1 = dydt(Qa, ga, ya, ta)
        k2 = dydt(Qa, ga, ya + 0.5 * h[:, None] * k1, ta + 0.5 * h)
        k3 = dydt(Qa, ga, ya + 0.5 * h[:, None] * k2, ta + 0.5 * h)
        k4 = dydt(Qa, ga, ya + h[:, None] * k3, ta + h)
        yp, tn = ya + h[:, None] / 6 * (k1 + 2 * k2 + 2 * k3 + k4), np.where(ta + h >= 1 - 1e-12, 1.0, ta + h)
        scale, norms = 1 + np.linalg.norm(yp, axis=1), list[np.ndarray]()
        for _ in range(3):
            Hv, Hy, _ = _homotopy(Qa, ga, yp, tn)
            d = _solve3(Hy, -Hv)
            yp, norms = yp + d, [*norms, np.linalg.norm(d, axis=1)]
        ok = (
            (norms[2] < tol * scale) & ((norms[1] < 0.5 * norms[0]) | (norms[0] < tol * scale)) & np.isfinite(yp).all(1)
        )
        y[act[ok]], t[act[ok]] = yp[ok], tn[ok]
        dt[act] = np.where(ok, np.minimum(np.where(norms[0] < 1e-3 * scale, 2.0, 1.25) * dt[act], 0.1), 0.5 * h)
        steps[act] += 1
        live[act] &= (dt[act] > 1e-13) & (steps[act] < max_steps) & (np.abs(y[act]).max(1) < 1e8)
    for _ in range(4):  # Newton on the target system at t = 1
        Hv, Hy, _ = _homotopy(Qt, gam, y, t)
        d = _solve3(Hy, -Hv)
        y = np.where(np.isfinite(d).all(1, keepdims=True), y + d, y)
    return y.reshape(-1, 8, 3), live.reshape(-1, 8)


def solve_projective(
    Q: np.ndarray, *, tol: float = 1e-9, seed: int = 0, retries: int = 4, info: dict | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """All 8 complex solutions q (N, 8, 4), unit Euclidean norm, of q^T Q[n, i] q = 0, and ok flags (N, 8).

    A path is failed if it did not reach t = 1, if its endpoint is not a solution to 1e-8 or if it coincides
    with another endpoint of the same input; such inputs are re-solved with a new chart and gamma. Eight distinct
    endpoints are all the solutions (Bezout), which certifies the result. `info` receives the retry count."""
    rng = np.random.default_rng(seed)
    N = len(Q)
    q, ok, todo = np.zeros((N, 8, 4), complex), np.zeros((N, 8), dtype=bool), np.arange(N)
    retried = 0
    for attempt in range(retries + 1):
        retried += todo.size if attempt else 0
        M = rng.normal(size=(todo.size, 4, 4)) + 1j * rng.normal(size=(todo.size, 4, 4))
        M /= np.linalg.norm(M, axis=(1, 2), keepdims=True)
        gam = np.exp(2j * np.pi * rng.uniform(size=todo.size))
        Qt = np.einsum("kab,kiac,kcd->kibd", M, Q[todo], M)
        parts = [_track(Qt[c : c + CHUNK], gam[c : c + CHUNK], tol) for c in range(0, todo.size, CHUNK)]
        y, live = np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])
        qk = np.einsum("kab,kpb->kpa", M, np.concatenate([np.ones((*y.shape[:2], 1)), y], axis=2))
        qk /= np.linalg.norm(qk, axis=2, keepdims=True)
        res = np.abs(np.einsum("kpa,kiab,kpb->kpi", qk, Q[todo], qk)).max(2) / (
            1 + np.abs(Q[todo]).max((1, 2, 3))[:, None]
        )
        gram = np.abs(np.einsum("kpa,kra->kpr", qk.conj(), qk)) - 2 * np.eye(8)
        okk = live & (res < 1e-8) & (gram.max(2) < 1 - 1e-10)
        q[todo], ok[todo] = qk, okk
        if (todo := todo[~okk.all(1)]).size == 0:
            break
    if info is not None:
        info["retried_inputs"] = retried
    return q, ok


def _real_polish(Q: np.ndarray, q: np.ndarray, iters: int = 10) -> tuple[np.ndarray, np.ndarray]:
    """Newton on {q^T Q_i q = 0, q.q = 1} for real q (P, 4), Q (P, 3, 4, 4); returns unit q and max |F_i(q)|."""
    for _ in range(iters):
        Qq = np.einsum("piab,pb->pia", Q, q)
        f = np.concatenate([np.einsum("pa,pia->pi", q, Qq), np.einsum("pa,pa->p", q, q)[:, None] - 1], axis=1)
        J = np.concatenate([2 * Qq, 2 * q[:, None, :]], axis=1)
        q = q - np.linalg.solve(J, f[..., None])[..., 0]
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return q, np.abs(np.einsum("pa,piab,pb->pi", q, Q, q)).max(1, initial=0.0)


def forward_quaternions(
    alpha1: Scalar, alpha2: Scalar, beta: Scalar, gamma: Scalar, theta: np.ndarray, *, tol: float = 1e-9,
    real_tol: float = 1e-6, seed: int = 0, info: dict | None = None,
) -> list[np.ndarray]:  # fmt: skip
    """Real unit quaternions (k_n, 4) of every assembly mode (one of q, -q) per input; see forward_rotations."""
    Q = quadrics(alpha1, alpha2, beta, gamma, theta)
    info = {} if info is None else info
    q, ok = solve_projective(Q, tol=tol, seed=seed, info=info)
    k = np.abs(q).argmax(axis=2)[..., None]
    ph = np.take_along_axis(q, k, axis=2)
    qn = q * (ph.conj() / np.abs(ph))  # remove the complex scale
    n_idx, p_idx = np.nonzero(ok & (np.abs(qn.imag).max(axis=2) < real_tol))
    qr, res = _real_polish(Q[n_idx], qn[n_idx, p_idx].real)
    good = res < 1e-12
    qr, n_idx = qr[good], n_idx[good]
    qr *= np.where(np.take_along_axis(qr, np.abs(qr).argmax(1)[:, None], 1) < 0, -1.0, 1.0)
    info.update(path_failures=int((~ok).sum()), complex_counts=ok.sum(axis=1), unpolished_real=int((~good).sum()))
    out = []
    for n in range(len(Q)):
        keep: list[np.ndarray] = []
        for cand in qr[n_idx == n]:
            if all(np.abs(quat_to_rotation(cand) - quat_to_rotation(old)).max() > 1e-8 for old in keep):
                keep.append(cand)
        out.append(np.array(keep).reshape(-1, 4))
    return out


def forward_rotations(
    alpha1: Scalar, alpha2: Scalar, beta: Scalar, gamma: Scalar, theta: np.ndarray, *, tol: float = 1e-9,
    real_tol: float = 1e-6, seed: int = 0, info: dict | None = None,
) -> list[np.ndarray]:  # fmt: skip
    """theta: (N, 3) actuator angles (radians); geometry (radians) scalars or (N,) arrays.

    Returns a list of N arrays, each (k_n, 3, 3): every real rotation R satisfying the three leg constraints,
    deduplicated (q ~ -q) and Newton-polished on the unit sphere. `tol` is the relative corrector tolerance of
    the path tracker, `real_tol` the imaginary-part threshold for a real solution. If `info` is a dict it
    receives path_failures (paths lost after all retries), complex_counts (N,) of distinct finite complex
    solutions (8 generically), retried_inputs and unpolished_real (real candidates whose polished residual
    stayed above 1e-12 and were dropped; only near singular configurations)."""
    qs = forward_quaternions(alpha1, alpha2, beta, gamma, theta, tol=tol, real_tol=real_tol, seed=seed, info=info)
    return [quat_to_rotation(q) for q in qs]


def complex_solution_count(
    alpha1: Scalar, alpha2: Scalar, beta: Scalar, gamma: Scalar, theta: np.ndarray, *, tol: float = 1e-9, seed: int = 0
) -> np.ndarray:
    """Number of distinct finite complex solutions tracked per input (8 for generic data)."""
    return solve_projective(quadrics(alpha1, alpha2, beta, gamma, theta), tol=tol, seed=seed)[1].sum(axis=1)


def leg_residuals(
    alpha1: Scalar, alpha2: Scalar, beta: Scalar, gamma: Scalar, theta: np.ndarray, R: np.ndarray
) -> np.ndarray:
    """w_i . (R v_i0) - cos(alpha2), shape (N, 3), for rotations R (N, 3, 3), by direct substitution."""
    w, v0, c2 = _legs(alpha1, alpha2, beta, gamma, theta)
    return np.einsum("nij,njk,nik->ni", w, R, v0) - c2
