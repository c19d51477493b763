"""The error hierarchy of parakin: every message names the value that caused it."""

from __future__ import annotations


class ParakinError(Exception):
    """Base class of every error parakin raises on purpose."""


class BadInputError(ParakinError, ValueError):
    """Wrong shape, non-finite values or an unknown name."""


class UnknownMechanismError(BadInputError, KeyError):
    """``parakin.load`` got a mechanism name (or package folder) it does not know; the message lists
    the valid ones. Unknown parameters and limits are plain BadInputErrors that suggest the closest names."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0])


class UnknownKeywordError(BadInputError, TypeError):
    """A method called with a keyword it does not take (``forward_pose(gues=...)``), or with a
    missing or extra argument: the message names it and the closest keywords. A TypeError too,
    as Python answers a call its signature does not allow."""


class NoSuchModeError(BadInputError, IndexError):
    """An assembly mode (or slot) index outside the result: the message names the count."""


class ArchitectureSingularityWarning(UserWarning):
    """The loaded geometry is singular at every pose (an architecture singularity): unusable."""


class NearSingularModeWarning(UserWarning):
    """The MJCF export (``parakin.mjcf.to_mjcf``) wrote keyframes of assembly modes near a type II
    (parallel) singularity: the message names them and the range of their measure (1/cond of the
    closure Jacobian, below ``parakin.singularity.NEAR_SINGULAR``); each such keyframe's XML comment
    gives its own value. There the actuators barely hold the platform: a simulation from it may
    drift or not come to rest."""


class BrokenPackageError(BadInputError):
    """A package's manifest fails its checks (a missing field, a value of the wrong type, shape or
    range): the message names the field's path and the bad value. Such a package is skipped by
    ``parakin.available()`` with a BrokenPackageWarning."""


class StoreInUseError(ParakinError):
    """Another sweep (another process, or another thread of this one) is writing the sweep store:
    the message names the store and the writer; run again once it has finished to resume."""


class BrokenPackageWarning(UserWarning):
    """A package on the search path whose manifest cannot be read: it is skipped by
    ``parakin.available()`` and ``parakin list``; loading it raises BadInputError."""


class FixedModelError(ParakinError, TypeError):
    """A loaded mechanism's model (its parameters, joint limits and actuator ranges) was assigned
    to: it is fixed when the mechanism is loaded, so that every solver and cached value agrees with
    it. Load another: ``parakin.load(name, d=0.3, limits=...)``."""


class ShadowedPackageWarning(UserWarning):
    """Two folders of the search path hold a package of the same name: loading by that name takes
    the first (the shipped packages, then ``$PARAKIN_PATH`` in order); the message names both. Load
    the other by its folder path, or generate it under a name of its own."""


class BackendFallbackWarning(UserWarning):
    """Backend 'auto' could not use compiled C (no compiler, a failed build, a cache that cannot
    be written) and runs on NumPy instead; the message names the cause."""


class UnsupportedOperationError(ParakinError, NotImplementedError):
    """The mechanism does not have what an operation needs (no closed-form inverse, no forward
    elimination, no rate model, no drawing kernel, ...); its manifest's capabilities say what it has."""


class CompiledUnavailableError(ParakinError):
    """The compiled backend cannot be built or loaded here (backend 'auto' falls back to NumPy)."""


class CompilerUnavailableError(CompiledUnavailableError):
    """No working C compiler for the compiled backend (set CC, or use backend='numpy')."""


class CacheUnavailableError(CompiledUnavailableError):
    """The library cache (``$PARAKIN_CACHE``) cannot be written or its library not loaded."""


class UntrustedCacheError(CacheUnavailableError):
    """The library cache, a folder above it or its library is owned by another user or writable
    by others: a library planted there would run inside this process, so none is loaded from it
    (the message names the file and what to do; backend 'auto' falls back to NumPy)."""


class StaleLibraryError(CacheUnavailableError):
    """A library in the cache under the package's name lacks C symbols the package needs (stale,
    damaged or not built by parakin); the message names it and the symbols: delete it to rebuild."""


class UnreachablePoseError(ParakinError):
    """No inverse-pose branch reaches the pose within the joint limits."""


class SingularConfigurationError(ParakinError):
    """The configuration is (numerically) singular for the requested operation."""


class SelfMotionError(SingularConfigurationError):
    """The inputs leave a positive-dimensional set of poses (e.g. an architecturally singular
    design with locked legs); ``solution_set`` describes it (mechanism-specific, e.g. the
    circuits of a self-motion)."""

    def __init__(self, message: str, solution_set: object) -> None:
        super().__init__(message)
        self.solution_set = solution_set


class ConvergenceError(ParakinError):
    """An iterative solver stopped before reaching its tolerance; carries the residual reached."""

    def __init__(self, message: str, residual: float | None = None) -> None:
        super().__init__(message)
        self.residual = residual


class AssemblyModeChangeError(ParakinError):
    """A tracked solution left its assembly mode: it crossed a type II singularity (the closure
    Jacobian's determinant changed sign) or jumped to another branch. ``index`` is the batch entry
    and ``change`` the kind ('crossed_singularity' or 'jumped_branch')."""

    def __init__(self, message: str, index: int, change: str) -> None:
        super().__init__(message)
        self.index = index
        self.change = change


class InconsistentInputError(ParakinError):
    """Inputs that no configuration satisfies (for example incompatible locked leg lengths)."""


#: status codes of the Newton loops (the generated C driver uses the same numbers)
NEWTON_OK, NEWTON_NONFINITE, NEWTON_NO_CONVERGENCE, NEWTON_SINGULAR, NEWTON_WRONG_BASIN = 0, 1, 2, 3, 4
#: their names in the manifest's ABI (checked when a package is read: the codes are the C enum's)
NEWTON_STATUS_NAMES = ("ok", "nonfinite", "no_convergence", "singular", "wrong_basin")


def first_index(mask: object) -> tuple[int, ...]:
    """The index of the first True entry of a boolean mask (() for a 0-d mask)."""
    import numpy as np

    array = np.asarray(mask)
    return tuple(int(i) for i in np.argwhere(array)[0]) if array.ndim else ()


def at_index(index: tuple[int, ...]) -> str:
    """' at batch index (i, ...)' for messages, or '' for an unbatched input."""
    return f" at batch index {index}" if index else ""


def raise_for_newton_status(
    status: object,
    residual: object,
    iterations: object,
    what: str,
    tolerance: float,
    max_iterations: int,
    guess: object = None,
) -> None:
    """Raise the error of the first failed entry of a Newton batch (arrays of equal shape).
    Callers validate inputs first, so a non-finite status means the loop closure is not defined
    at an iterate: at the guess (``guess`` (..., n_p), named in the message) or later."""
    import numpy as np

    failed = np.asarray(status) != NEWTON_OK
    if not failed.any():
        return
    index = first_index(failed)
    at = at_index(index)
    code = int(np.asarray(status)[index])
    reached = float(np.asarray(residual)[index])
    steps = int(np.asarray(iterations)[index])
    if code == NEWTON_NONFINITE:
        where = "the guess" if steps == 0 else f"iterate {steps} (from the guess)"
        if guess is not None:
            start = np.asarray(guess)
            values = np.broadcast_to(start, np.shape(np.asarray(status)) + start.shape[-1:])[index]
            where += f" {np.array2string(values, precision=6, separator=', ')}"
        raise BadInputError(
            f"{what}{at}: the loop closure is undefined (NaN) at {where}: the model has no value there "
            "(e.g. a zero quaternion); pass another guess"
        )
    if code == NEWTON_SINGULAR:
        raise SingularConfigurationError(
            f"{what}{at}: the loop-closure Jacobian is singular (a type II singularity) after {steps} "
            f"iterations, residual {reached:.3g}"
        )
    if code == NEWTON_WRONG_BASIN:
        raise ConvergenceError(
            f"{what}{at}: the residual vanished ({reached:.3g}) at a false closure (alignment <= 0: "
            "legs a half-turn apart, or a mirror platform); try another guess",
            residual=reached,
        )
    raise ConvergenceError(
        f"{what}{at} did not converge in {max_iterations} iterations: residual {reached:.3g} > "
        f"tolerance {tolerance:g}; try a closer guess",
        residual=reached,
    )


class CalibrationUnavailableError(UnsupportedOperationError):
    """The mechanism's package has no ``parameter_jacobians`` kernel (it was generated before the
    kernel existed): regenerate it (``make regenerate``, or ``parakin generate FILE --out DIR
    --force``) to calibrate it."""


class CalibrationDataError(BadInputError):
    """Measurements that do not fit the mechanism or the measurement kind (wrong shape, a
    non-positive sigma, an unknown parameter name in ``free`` / ``fixed`` / ``prior``); the
    message names the value."""
