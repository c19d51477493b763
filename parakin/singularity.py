"""Distance to singularity: the one measure that ``parakin plot`` labels, ``parakin sweep`` maps
and the MJCF export warns by, and the level below which a configuration is near a singularity.

Both measures are the inverse condition number sigma_min / sigma_max of a matrix of the
configuration (1 far from a singularity, 0 at one; invariant to the matrix's scale):

- ``type II`` (a parallel singularity: the actuators do not hold the platform): the loop-closure
  Jacobian d closure / d passive (``Mechanism.loop_closure``'s ``jacobian``);
- ``type I`` (a serial singularity: the platform cannot move along some twist): the rate model's
  B (A twist = B actuated rates, ``Mechanism.rate_jacobians``), or without a rate model the worst
  of the serial legs' Jacobians (``Mechanism.leg_jacobians``).

The measures are computed for a whole batch of configurations at once (one SVD call per
matrix kind); where the model's matrix is not finite at a configuration (values too large for
doubles, or a model undefined there) its measure is NaN, not an error.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from parakin.errors import BadInputError, ParakinError
from parakin.results import NEAR_SINGULAR, Array, Configuration
from parakin.solvers.linalg import inverse_condition
from parakin.validation import bounded_vector

if TYPE_CHECKING:
    from parakin.solvers.loaded import LoadedMechanism


def _kernel(m: LoadedMechanism, kernel: str, state: Configuration) -> dict[str, Array]:
    """A kernel of the mechanism at ``state`` (checked: a Configuration of finite values, the
    actuated ones inside their ranges), its outputs as computed, finite or not."""
    if not isinstance(state, Configuration):
        raise BadInputError(f"state must be a Configuration (from a solver), got {type(state).__name__}")
    theta = m._actuated(state.actuated)
    passive = bounded_vector(state.passive, "passive", m.passive_names)
    with np.errstate(all="ignore"):
        return m.backend.call(kernel, theta, passive, m.params)


def type_ii_distance(m: LoadedMechanism, state: Configuration) -> Array | None:
    """Distance to a type II (parallel) singularity: 1/cond of the loop-closure Jacobian
    d closure / d passive, per configuration.

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism.
    state : Configuration
        Closed configurations, batch shape (...) (actuated (..., n_a), passive (..., n_p)).

    Returns
    -------
    numpy.ndarray, shape (...), or None
        1 far from, 0 at a type II singularity; NaN where the Jacobian is not finite. None for a
        mechanism without passive joints (no loop to close).

    Raises
    ------
    BadInputError
        ``state`` is not a Configuration, or its values are not finite or outside the actuated ranges.

    Examples
    --------
    >>> import parakin
    >>> from parakin.singularity import type_ii_distance
    >>> import numpy as np
    >>> m = parakin.load("five_bar", backend="numpy")
    >>> home = m.forward_pose(m.home_actuated)
    >>> jacobian = m.loop_closure(home.actuated, home.passive)["jacobian"]
    >>> round(float(type_ii_distance(m, home)), 4), round(float(1 / np.linalg.cond(jacobian)), 4)
    (0.6662, 0.6662)
    """
    if not m.passive_names:
        return None
    return inverse_condition(_kernel(m, "loop_closure", state)["jacobian"])


def type_i_distance(m: LoadedMechanism, state: Configuration) -> Array | None:
    """Distance to a type I (serial) singularity: 1/cond of the rate model's B (A twist = B
    actuated rates), or, without a rate model, the smallest 1/cond of the serial legs' Jacobians.

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism.
    state : Configuration
        Closed configurations, batch shape (...).

    Returns
    -------
    numpy.ndarray, shape (...), or None
        1 far from, 0 at a type I singularity; NaN where a matrix is not finite. None for a
        mechanism with neither a rate model nor serial legs.

    Raises
    ------
    BadInputError
        ``state`` is not a Configuration, or its values are not finite or outside the actuated ranges.

    Examples
    --------
    >>> import parakin
    >>> from parakin.singularity import type_i_distance
    >>> m = parakin.load("sam", backend="numpy")   # two serial legs, no rate model
    >>> round(float(type_i_distance(m, m.forward_pose(m.home_actuated))), 4)
    0.0264
    """
    if m.capabilities.rates is not None:
        return inverse_condition(_kernel(m, "rate_jacobians", state)["b"])
    if m.capabilities.legs:
        legs = _kernel(m, "leg_jacobians", state)
        return np.min([inverse_condition(jacobian) for jacobian in legs.values()], axis=0)
    return None


def singularity_distances(m: LoadedMechanism, state: Configuration) -> dict[str, Array]:
    """Both distances to singularity of a batch of configurations, those the mechanism has.

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism.
    state : Configuration
        Closed configurations, batch shape (...).

    Returns
    -------
    dict of str to numpy.ndarray, each shape (...)
        ``type II`` (``type_ii_distance``) and ``type I`` (``type_i_distance``), in that order;
        a measure the mechanism lacks is left out.

    Raises
    ------
    BadInputError
        ``state`` is not a Configuration, or its values are not finite or outside the actuated ranges.

    Examples
    --------
    >>> import parakin
    >>> from parakin.singularity import singularity_distances
    >>> m = parakin.load("five_bar", backend="numpy")
    >>> modes = m.forward_pose_all(m.home_actuated)
    >>> {name: value.shape for name, value in singularity_distances(m, modes.mode(0)).items()}
    {'type II': (), 'type I': ()}
    """
    out: dict[str, Array] = {}
    for name, measure in (("type II", type_ii_distance), ("type I", type_i_distance)):
        value = measure(m, state)
        if value is not None:
            out[name] = value
    return out


def singularity_distance(m: LoadedMechanism, config: Configuration) -> dict[str, float]:
    """The distances to singularity of one configuration, as numbers for a label: those the
    mechanism has and that are defined there (``singularity_distances``).

    Parameters
    ----------
    m : Mechanism
        A loaded mechanism.
    config : Configuration
        One closed configuration (actuated (n_a,), passive (n_p,)).

    Returns
    -------
    dict of str to float
        ``type II`` and ``type I`` (1 far, 0 singular); a measure the mechanism lacks, or one not
        defined here (a matrix that is not finite), is left out, and so are both for a
        configuration the mechanism refuses (values outside the actuated ranges).

    Raises
    ------
    Nothing
        A configuration the mechanism refuses gives an empty dict: a label, not a check.

    Examples
    --------
    >>> import parakin
    >>> from parakin.singularity import singularity_distance
    >>> m = parakin.load("five_bar", backend="numpy")
    >>> {k: round(v, 4) for k, v in singularity_distance(m, m.forward_pose(m.home_actuated)).items()}
    {'type II': 0.6662, 'type I': 1.0}
    """
    try:
        measures = singularity_distances(m, config)
    except ParakinError:  # a configuration the mechanism refuses: nothing to show
        return {}
    return {name: float(value) for name, value in measures.items() if np.isfinite(value)}


def is_near_singular(distance: Mapping[str, float]) -> bool:
    """Whether a configuration's type II distance (``singularity_distance``) is below
    ``NEAR_SINGULAR``: near a parallel singularity (the actuators barely hold the platform).

    Parameters
    ----------
    distance : mapping of str to float
        A configuration's measures by name, as ``singularity_distance`` returns them.

    Returns
    -------
    bool
        True where ``distance['type II']`` is below ``NEAR_SINGULAR``; False without it.

    Raises
    ------
    Nothing
        A mapping without ``type II`` is not near-singular by this measure.

    Examples
    --------
    >>> from parakin.singularity import is_near_singular
    >>> is_near_singular({"type II": 0.012, "type I": 0.31}), is_near_singular({"type I": 0.001})
    (True, False)
    """
    value = distance.get("type II")
    return value is not None and value < NEAR_SINGULAR


__all__ = [
    "NEAR_SINGULAR",
    "inverse_condition",
    "is_near_singular",
    "singularity_distance",
    "singularity_distances",
    "type_i_distance",
    "type_ii_distance",
]
