"""Independent batched oracle for the forward pose of the 3(SPS)-S spherical platform.

The leg equations |a_i - R b_ip|^2 = d_i^2 read a_i . R b_ip = c_i with c_i = (|a_i|^2 + |b_ip|^2 - d_i^2) / 2.
With R = R(q) for a quaternion q = (q0, p) (scalar first), R(q) = (q0^2 - |p|^2) I + 2 p p^T + 2 q0 [p]x, each
equation homogenised with q.q is a quadric q^T Q_i q = 0 in P^3 (Bezout number 8; q ~ -q):
    Q_i[0, 0] = a.b - c,  Q_i[0, 1:] = Q_i[1:, 0] = b x a,  Q_i[1:, 1:] = a b^T + b a^T - (a.b + c) I.
All 8 complex solutions are found by the certified total-degree homotopy of ``spm_quaternion.solve_projective``
(the same solver as the SPM oracle: it only sees the quadrics); real ones are polished by Newton on the unit sphere.
Nothing here depends on parakin, the generator, SymPy, Euler angles or the vector method of the paper.
"""

from __future__ import annotations

import numpy as np
from spm_quaternion import _real_polish, quat_to_rotation, solve_projective


def platform_points(b: np.ndarray, b12: float, b23: float, b13: float, chi: float) -> np.ndarray:
    """Rows b_ip from |QB_i| = b (3,) and the distances |B_i B_j|; chi = sign det[b1p b2p b3p]."""
    q12 = (b[0] ** 2 + b[1] ** 2 - b12**2) / (2 * b[0] * b[1])
    q13 = (b[0] ** 2 + b[2] ** 2 - b13**2) / (2 * b[0] * b[2])
    q23 = (b[1] ** 2 + b[2] ** 2 - b23**2) / (2 * b[1] * b[2])
    s = np.sqrt(1 - q12**2)
    gram = 1 - q12**2 - q13**2 - q23**2 + 2 * q12 * q13 * q23
    return np.array(
        [
            [b[0], 0.0, 0.0],
            [b[1] * q12, b[1] * s, 0.0],
            [b[2] * q13, b[2] * (q23 - q12 * q13) / s, b[2] * chi * np.sqrt(max(gram, 0.0)) / s],
        ]
    )


def quadrics(base: np.ndarray, platform: np.ndarray, lengths: np.ndarray) -> np.ndarray:
    """Q (N, 3, 4, 4) for base points (3, 3) rows a_i, platform points (3, 3) rows b_ip, lengths (N, 3)."""
    lengths = np.atleast_2d(lengths)
    ab = np.einsum("ij,ij->i", base, platform)
    c = (np.sum(base**2, 1) + np.sum(platform**2, 1) - lengths**2) / 2
    Q = np.zeros((len(lengths), 3, 4, 4))
    Q[..., 0, 0] = ab - c
    Q[..., 0, 1:] = Q[..., 1:, 0] = np.cross(platform, base)
    outer = base[:, :, None] * platform[:, None, :] + platform[:, :, None] * base[:, None, :]
    Q[..., 1:, 1:] = outer - (ab + c)[..., None, None] * np.eye(3)
    return Q


def forward_rotations(
    base: np.ndarray, platform: np.ndarray, lengths: np.ndarray, *, seed: int = 0, info: dict | None = None
) -> list[np.ndarray]:
    """Every real rotation (k_n, 3, 3) with |a_i - R b_ip| = d_i, per row of lengths (N, 3).

    ``info`` receives complex_counts (N,): distinct finite complex solutions tracked (8 generically; fewer
    means a path was lost, so the real set is not certified for that input)."""
    Q = quadrics(base, platform, lengths)
    q, ok = solve_projective(Q, seed=seed, info=info)
    k = np.abs(q).argmax(axis=2)[..., None]
    phase = np.take_along_axis(q, k, axis=2)
    qn = q * (phase.conj() / np.abs(phase))
    n_idx, p_idx = np.nonzero(ok & (np.abs(qn.imag).max(axis=2) < 1e-6))
    scale = 1 + np.abs(Q).max(axis=(1, 2, 3))
    qr, residual = _real_polish(Q[n_idx] / scale[n_idx, None, None, None], qn[n_idx, p_idx].real)
    good = residual < 1e-12
    qr, n_idx = qr[good], n_idx[good]
    if info is not None:
        info["complex_counts"] = ok.sum(axis=1)
    out = []
    for n in range(len(Q)):
        keep: list[np.ndarray] = []
        for rotation in quat_to_rotation(qr[n_idx == n]):
            if all(np.abs(rotation - old).max() > 1e-8 for old in keep):
                keep.append(rotation)
        out.append(np.array(keep).reshape(-1, 3, 3))
    return out


def leg_lengths(base: np.ndarray, platform: np.ndarray, rotations: np.ndarray) -> np.ndarray:
    """|a_i - R b_ip| (..., 3) by direct substitution."""
    return np.linalg.norm(base - np.einsum("...jk,ik->...ij", rotations, platform), axis=-1)
