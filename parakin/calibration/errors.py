"""The calibration's own errors, each a subclass of a ``parakin.errors`` base so that callers
catching the base (``UnsupportedOperationError``, ``BadInputError``) also catch these."""

from __future__ import annotations

from parakin.errors import BadInputError, UnsupportedOperationError


class CalibrationUnavailableError(UnsupportedOperationError):
    """The mechanism's package has no ``parameter_jacobians`` kernel (it was generated before the
    kernel existed): regenerate it (``make regenerate``, or ``parakin generate FILE --out DIR
    --force``) to calibrate it."""


class CalibrationDataError(BadInputError):
    """Measurements that do not fit the mechanism or the measurement kind (wrong shape, a
    non-positive sigma, an unknown parameter name in ``free`` / ``fixed`` / ``prior``); the
    message names the value."""
