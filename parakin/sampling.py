"""Closed configurations sampled around a mechanism's home configuration, from its manifest alone.

Used by ``make bench``, the contract tests and design studies: the actuated inputs are perturbed
(revolute by ``spread`` rad, prismatic by ``spread`` times their home value) and each
configuration is closed by Newton from the home configuration; the ones that converge are kept.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from parakin.results import Configuration

if TYPE_CHECKING:
    from parakin.mechanism import Mechanism


def sample_configurations(m: Mechanism, count: int, spread: float = 0.05, seed: int = 0) -> Configuration:
    """Up to ``count`` closed configurations near home (a batch; fewer where Newton failed)."""
    rng = np.random.default_rng(seed)
    revolute = np.array([v.revolute for v in m.manifest.actuated])
    scale = np.where(revolute, 1.0, np.maximum(np.abs(m.home_actuated), 1e-3))
    actuated = m.home_actuated + spread * scale * rng.standard_normal((count, m.home_actuated.size))
    guess = np.broadcast_to(m.home_passive, (count, m.home_passive.size))
    solved = m.forward_pose(actuated, guess, strict=False)
    keep = np.asarray(solved.converged)
    return Configuration(actuated[keep], solved.passive[keep], solved.pose[keep])


__all__ = ["sample_configurations"]
