"""The calibration's errors, defined with every other named error in ``parakin.errors``."""

from __future__ import annotations

from parakin.errors import CalibrationDataError, CalibrationUnavailableError

__all__ = ["CalibrationDataError", "CalibrationUnavailableError"]
