"""Calibration of a built mechanism from measured poses (issue 35): ``calibrate`` identifies the
geometric parameters, actuated-joint offsets and unknown instrument frames with analytic
Jacobians and names what the data cannot identify; ``design_poses`` chooses where to measure.
"""

from __future__ import annotations

from parakin.calibration.data import CalibrationData
from parakin.calibration.design import PoseDesign, design_poses
from parakin.calibration.fit import CalibrationResult, calibrate, prediction_covariance
from parakin.calibration.identifiability import Combination
from parakin.errors import CalibrationDataError, CalibrationUnavailableError

__all__ = [
    "CalibrationData",
    "CalibrationDataError",
    "CalibrationResult",
    "CalibrationUnavailableError",
    "Combination",
    "PoseDesign",
    "calibrate",
    "design_poses",
    "prediction_covariance",
]
