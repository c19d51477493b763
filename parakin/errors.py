"""The error hierarchy of parakin: every message names the value that caused it."""

from __future__ import annotations


class ParakinError(Exception):
    """Base class of every error parakin raises on purpose."""


class BadInputError(ParakinError, ValueError):
    """Wrong shape, non-finite values or an unknown name."""


class UnknownMechanismError(BadInputError, KeyError):
    """``parakin.load`` got a name or parameter it does not know; the message lists the valid ones."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0])


class UnreachablePoseError(ParakinError):
    """No inverse-pose branch reaches the pose within the joint limits."""


class SingularConfigurationError(ParakinError):
    """The configuration is (numerically) singular for the requested operation."""


class ConvergenceError(ParakinError):
    """An iterative solver stopped before reaching its tolerance; carries the residual reached."""

    def __init__(self, message: str, residual: float | None = None) -> None:
        super().__init__(message)
        self.residual = residual


class InconsistentInputError(ParakinError):
    """Inputs that no configuration satisfies (for example incompatible locked leg lengths)."""
